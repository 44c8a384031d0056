#pragma once
// Self-intersections of a triangle mesh (exact): the pairs of faces that meet other than in the
// vertex or edge they share. The per-pair test is CGAL's (PMP::self_intersections' "strict"
// test, with CGAL's filtered exact predicates); the candidate pairs come from a grid of face boxes
// searched on every thread, where CGAL's box intersection splits into 16 fixed tasks and ran 1.1-1.4x
// faster on 2 threads than on one (doc/mesh-intake.md, "Self-intersections on every thread").
#include <cstdint>
#include <utility>
#include <vector>

#include "core/triangle_mesh.h"

namespace cdbench {

// Whether faces f and g of `mesh` intersect beyond what they share: sharing two corners (an edge),
// exactly when they are coplanar and fold onto each other (the third corners on the same side of
// the edge); three corners, always; one corner, when the edge opposite it in either face meets
// the other face; none, when the closed triangles meet. Corners are shared by index, not by
// position. Precondition: neither face is degenerate (collinear corners), f != g.
bool faces_intersect(const TriangleMesh& mesh, std::uint32_t f, std::uint32_t g);

// Every pair (f, g), f < g, for which faces_intersect holds, sorted; the same for any thread count.
// Candidates are the pairs whose closed bounding boxes overlap (a pair that meets has overlapping
// boxes), each visited once: in the grid cell holding the least corner of the boxes' overlap.
// Precondition: no degenerate face, finite coordinates.
std::vector<std::pair<std::uint32_t, std::uint32_t>> self_intersecting_faces(const TriangleMesh& mesh);

}  // namespace cdbench
