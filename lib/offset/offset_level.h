#pragma once
// One certified offset level: empty, the original surface, or a mesh of {s = d} built by CGAL's
// surface mesher and certified by (a) validation, (b) the band and (c) completeness, with
// re-seeding of missed components and finer criteria until the band meets the tolerance.
#include <functional>
#include <string>
#include <vector>

#include "distance/max_penetration.h"
#include "mesh/validate_mesh.h"
#include "offset/certify_band.h"
#include "offset/offset_status.h"

namespace cdbench {

struct OffsetOptions {
  double tolerance_relative = 1e-3;   // band tolerance, relative to the input's bbox diagonal
  double radius_relative = 0.01;      // mesher: largest surface Delaunay ball radius, x diagonal
  // mesher: distance bound at the first attempt, x tolerance. 0.7 leaves the band above the tolerance
  // on 0.5-4 % of the faces, which the local repair splits: 2-3x fewer faces than 0.3 (doc/offsets.md).
  double distance_over_tolerance = 0.7;
  int max_attempts = 4;
  // A candidate whose band misses the tolerance on few faces is first split locally there
  // (refine_offset.h) before a whole re-mesh with a finer distance bound.
  bool local_repair = true;
  // Where that repair stalls or folds faces, it runs once more with new vertices on the level set's
  // creases and folds mended where they are, before the re-mesh (doc/offsets.md).
  bool repair_creases = true;
  int seeds = 64;
  // Regions of the level set that a candidate missed are first meshed alone and added to it (an
  // island no seed reached), before a re-mesh of the whole level from the candidate's vertices.
  bool mesh_missed_regions_alone = true;
  // The candidate mesher: Surface_mesher (one thread, reproducible) or Mesh_3 in parallel mode.
  bool parallel_mesher = false;
  // Called with a line per attempt and phase (what was done, how long, the outcome); may be empty.
  std::function<void(const std::string&)> log;
};

struct OffsetLevel {
  double d = 0.0;
  OffsetStatus status = OffsetStatus::Failed;
  std::string message;        // why it failed, or a note
  TriangleMesh mesh;          // empty for Empty
  MeshReport report;          // validation of `mesh`
  double epsilon = 0.0;       // certified band (b); completeness (c) holds for the same epsilon
  bool complete = false;
  int attempts = 0;
  int repairs = 0;              // attempts whose band was brought under the tolerance by local splits
  double distance_bound = 0.0;  // mesher criterion of the accepted attempt (absolute)
  std::size_t band_pieces = 0;
  std::uint64_t completeness_cells = 0;
  double seconds_mesh = 0.0, seconds_band = 0.0, seconds_completeness = 0.0;
};

// The candidate mesher's name, as offset manifests and pose sets record it: "surface-mesher" or
// "mesh3-parallel".
inline const char* mesher_name(const OffsetOptions& options) {
  return options.parallel_mesher ? "mesh3-parallel" : "surface-mesher";
}

// The band certificate's options for a level of tolerance `tol` (absolute): faces are split only
// as far as acceptance needs, with a margin, and a few loose faces get a second, deeper pass.
BandOptions offset_band_options(double tol);

OffsetLevel compute_offset_level(const SignedDistance& sdf, const MaxPenetrationResult& max_penetration, double d,
                                 const OffsetOptions& options);

}  // namespace cdbench
