#pragma once
// A set of certified offset levels written to a directory with manifest.json and timings.json,
// reusing levels of an earlier run with the same input, distance and options (cdbench offset, and
// the offsets/ of a pose set).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/mesh_source.h"
#include "core/triangle_mesh.h"
#include "distance/max_penetration.h"
#include "offset/offset_level.h"

namespace cdbench {

struct OffsetSetRequest {
  MeshSource source;
  const SignedDistance* sdf = nullptr;
  const MaxPenetrationResult* max_penetration = nullptr;
  double max_penetration_tolerance = 1e-6;
  double seconds_max_penetration = 0.0;
  std::string mesh_path, input_sha, out_dir;
  std::vector<std::string> names;   // level names as the user wrote them (file names derive from them)
  std::vector<double> distances;    // absolute signed distances
  OffsetOptions options;
  bool verbose = false;
  const char* log_prefix = "cdbench offset: ";
};

// A level of the set, typed for the callers (the pose-set builder decides its starts from it).
struct OffsetSetLevel {
  OffsetStatus status = OffsetStatus::Failed;
  std::string file;      // in out_dir; empty when the level has no mesh
  double epsilon = 0.0;  // the certified band; NaN when there is none
  std::size_t faces = 0;
  bool reused = false;   // taken over from an earlier run's manifest
  double seconds = 0.0;  // this run's time on it (0 when reused)
};

struct OffsetSetResult {
  nlohmann::json manifest;  // also written to out_dir/manifest.json
  std::vector<OffsetSetLevel> levels;
};

OffsetSetResult write_offset_set(const OffsetSetRequest& request);

// The certified maximum penetration (what every offset set needs first), with its duration.
MaxPenetrationResult timed_max_penetration(const SignedDistance& sdf, double relative_tolerance, double* seconds);

// A request for the offsets of `source` (whose signed distance and max penetration are given),
// with the levels still to be filled in.
// (`source` is copied; its mesh must outlive the request.)
OffsetSetRequest make_offset_request(const MeshSource& source, const SignedDistance& sdf,
                                     const MaxPenetrationResult& max_penetration, double max_penetration_tolerance,
                                     double seconds_max_penetration, const std::string& input_sha,
                                     const std::string& out_dir);

}  // namespace cdbench
