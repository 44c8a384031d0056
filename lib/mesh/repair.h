#pragma once
// Repair of inputs that are not valid closed solids, exact when possible.
//
// 1. Weld (exact, or within a tolerance if asked) and validate: a valid solid is returned as is.
// 2. Exact union: many models (robot links, CAD assemblies) are unions of closed parts that overlap
//    or touch. The input is split into parts — first by the file's own connectivity (faces sharing
//    vertex indices), else by the welded surface's manifold edges (faces joined across edges with
//    exactly two faces) — and if every part is a valid closed solid, the parts are united with
//    CGAL's exact corefinement (Polygon_mesh_processing::corefine_and_compute_union, exact kernel).
//    Every point of the result lies on the input surface, up to the rounding of new intersection
//    vertices to doubles; the rounded result is validated again (exact self-intersection test).
// 3. Otherwise CGAL's alpha wrap (mesh/alpha_wrap.h), which moves the surface by about `offset`.
// The caller measures how far the result is from the input (distance/hausdorff.h).
#include <string>

#include "core/triangle_mesh.h"
#include "mesh/alpha_wrap.h"
#include "mesh/validate_mesh.h"

namespace cdbench {

enum class RepairMethod { Unchanged, ExactUnion, AlphaWrap };
const char* to_string(RepairMethod m);

struct RepairOptions {
  double weld_tolerance = 0.0;  // > 0: weld vertices closer than this (reported)
  bool allow_wrap = true;       // false: fail (method Unchanged, invalid report) rather than wrap
  AlphaWrapOptions wrap;
};

struct RepairResult {
  RepairMethod method = RepairMethod::Unchanged;
  ValidatedMesh result;          // the output and its validation report (valid unless the repair failed)
  MeshReport input_report;       // what was wrong with the input
  std::size_t parts = 0;         // closed parts united (ExactUnion)
  std::string exact_note;        // why the exact union was not used, when it was not
  double alpha = 0.0, offset = 0.0;  // AlphaWrap parameters used
  double seconds = 0.0;
};

RepairResult repair_mesh(const PolygonSoup& soup, const RepairOptions& options = {});

// The union of closed, outward, self-intersection-free parts by exact corefinement, rounded to
// doubles. Returns false with a reason when CGAL cannot produce a manifold union.
bool exact_union(const std::vector<TriangleMesh>& parts, TriangleMesh& out, std::string& reason);

// Polygons fanned into triangles (for distances to a soup); vertices unchanged.
TriangleMesh fan_triangulation(const PolygonSoup& soup);

}  // namespace cdbench
