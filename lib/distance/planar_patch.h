#pragma once
// A near-planar patch of F as one member of the convexity (depth) bound. Machined parts tile a
// planar face with many long triangles; the distance to one of them grows across its edges, so
// the triangle-wise bound is loose wherever a cell straddles the shared edges of coplanar
// triangles, and the branch and bound subdivides there down to the tolerance. A patch removes that:
//
// Let U be triangles of F whose vertices w all satisfy |n.w - d| <= eta (a plane {n.x = d}, n the
// stored double vector), and pi the projection along n onto that plane. If pi(K) lies in pi(U) for
// a convex cell K, then for every x of K there is a point p of some triangle of U with x - p
// parallel to n, and
//     dist(x, F) <= |x - p| = |n.x - n.p| / |n| <= (|n.x - d| + eta) / |n|,
// an affine-absolute (convex) function of x: its maximum over K is at a corner, and it may stand
// in the weighted convexity bound (depth_bound.h) in place of U's triangles. Tight on the patch's
// plane wherever the cell is, whatever the tessellation. See doc/distance.md, "Planar patches".
//
// Containment is decided by orientation predicates of the projection along n (the sign of
// det[b - a, n, x - a], in doubles with an error bound; an uncertain sign counts against it):
//   * one corner of K lies strictly inside the projection of a triangle of U, and
//   * no boundary edge of U meets pi(K) (separating-axis test on the segment's line and K's edges);
// an edge is interior when exactly two triangles of U share it (by vertex index) with their third
// vertices strictly on opposite sides. Then pi(K) is covered: the last point of a segment in pi(K)
// that is still covered would lie on the boundary of pi(U), hence on an edge of U; an interior
// edge's points and a vertex whose U-edges are all interior (a closed fan, alternating sides) have
// covered neighbourhoods, so it would lie on a boundary edge.
#include <cstdint>
#include <vector>

#include "core/triangle_mesh.h"
#include "distance/point_triangle_distance.h"

namespace cdbench {

// Sign of det[b - a, n, x - a]: the side of x's projection along n from the projected directed line
// through a and b. +1 or -1 when certain (an error bound valid in any rounding mode), 0 otherwise.
int projected_side(const Vec3& a, const Vec3& b, const Vec3& x, const Vec3& n);

// The triangles `ids` of `mesh`: whether the projection along n onto the plane {n.x = d} of the
// convex hull of the corners provably lies in the union of their projections. The corners: 1 to 3
// points (a flat cell), or the 8 corners of an axis-aligned box (its hull's projected edges are
// parallel to the projected coordinate axes).
bool patch_covers_cell(const TriangleMesh& mesh, const std::vector<std::uint32_t>& ids, const Vec3& n, double d,
                       const Vec3* corners, int n_corners);

// (|n.x - d| + eta) / |n| rounded up: the patch's bound of dist(x, F) at a point x of a covered cell.
double patch_distance_bound(const TrianglePlane& plane, double eta, const Vec3& x);

}  // namespace cdbench
