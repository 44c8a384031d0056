#pragma once
// Turning a polygon soup into a validated, outward-oriented triangle mesh, with a report that names
// every problem found (what, how many, one example with indices and coordinates).
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "core/triangle_mesh.h"

namespace cdbench {

struct MeshProblem {
  std::string kind;     // short identifier: "boundary", "non-manifold-edge", "self-intersection", ...
  std::size_t count = 0;
  std::string message;  // full sentence with the count and one example
};

struct MeshReport {
  std::size_t input_vertices = 0;
  std::size_t input_polygons = 0;
  std::vector<MeshProblem> errors;   // any error makes the mesh unusable as a solid
  std::vector<std::string> notices;  // changes made or facts worth knowing (triangulation, orientation fixed, ...)
  bool self_intersections_checked = false;
  // Topology and geometry of the resulting mesh.
  std::size_t components = 0;
  bool closed = false;
  long genus = -1;           // sum over components (closed, manifold meshes only), else -1
  double volume_lo = 0.0, volume_hi = 0.0;  // rigorous enclosure of the enclosed volume (closed meshes)
  double seconds_self_intersections = 0.0;
  // The pairs of faces that intersect (indices of the mesh as validated, the lesser first, sorted):
  // for callers that repair their own meshes locally (offset/offset_level.cpp).
  std::vector<std::pair<std::size_t, std::size_t>> intersecting_faces;

  bool valid() const { return errors.empty(); }
  bool has(const std::string& kind) const;
};

struct ValidatedMesh {
  TriangleMesh mesh;
  MeshReport report;
};

// The supported scale (see validate_mesh.cpp): larger coordinates or a smaller extent are an
// error of kind "coordinate-range". Scaling by a power of two is exact.
constexpr double kMaxCoordinate = 1e40;
constexpr double kMinDiagonal = 1e-40;

struct ValidateOptions {
  bool check_self_intersections = true;
  bool fix_orientation = true;
  bool weld = true;             // merge vertices with exactly equal coordinates first (mesh/weld.h)
  double weld_tolerance = 0.0;  // > 0: also merge vertices closer than this (moves them; reported)
};

// Welds vertices at equal positions (a notice with the count), triangulates polygons, drops unreferenced vertices, and checks: degenerate faces (exact),
// boundary edges, non-manifold edges and vertices, orientability, self-intersections (exact: mesh/self_intersections.h),
// and outward orientation (reversed automatically when closed and valid, with a notice).
// By value: a caller done with its soup moves it in (832K polygons are 832K allocations to copy).
ValidatedMesh validate_mesh(PolygonSoup soup, const ValidateOptions& options = {});

// Convenience: validation of an already triangulated mesh.
ValidatedMesh validate_mesh(const TriangleMesh& mesh, const ValidateOptions& options = {});

}  // namespace cdbench
