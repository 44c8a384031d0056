#pragma once
// A convex cell cut by the planes of a slab {ls <= n.x <= hs}, as points whose convex hull, widened
// by `err`, holds the cut cell. Used where a cell across a thin wall of F is bounded by its part
// between the planes of the faces it crosses: the pose certificates' mover faces
// (placement/clearance.cpp, slab_lower) and the maximum penetration's cubes
// (distance/max_penetration.cpp). See doc/distance.md, "Cubes across a thin wall".
//
// The cut cell is a convex polytope; its vertices are the cell's corners within the slab and the
// crossings of its edges with the two planes (three facets meet at a vertex, and the slab's
// planes are parallel). A corner whose side of a plane is uncertain is kept; an edge whose end
// lies on a plane within its error gives both ends (the crossing may be anywhere on it); otherwise
// the crossing's parameter t = A / (A - B) is enclosed from the enclosures of A = n.a - H and
// B = n.b - H, and the point a + t (b - a) at its midpoint is within
//   (t_hi - t_lo) |b - a| + 4e-15 (|a| + |b|)   (max norms)
// of the exact crossing, in any rounding mode: err is the largest such term.
#include <array>
#include <cstdint>
#include <vector>

#include "core/interval.h"
#include "core/triangle_mesh.h"
#include "distance/point_triangle_distance.h"

namespace cdbench {

struct SlabCut {
  static constexpr int kCapacity = 32;
  std::array<Vec3, kCapacity> q;
  std::array<int, kCapacity> corner_of;  // the corner of the cell a point is, or -1 (a crossing)
  int n = 0;
  double err = 0.0;
  // Per edge and plane (0: hs, 1: ls): the crossing's parameter from the edge's first end, or -1.
  std::array<std::array<double, 2>, 12> cross_t;
};

// corners[k] with offsets[k] = plane_offset(n, 0, corners[k]); edges: pairs of corner indices (at
// most 12). A plane at +-inf does not cut. False when more than `capacity` (at most kCapacity)
// points would be needed.
bool cut_by_slab(const Vec3* corners, const PlaneOffset* offsets, int n_corners, const std::array<int, 2>* edges,
                 int n_edges, double hs, double ls, SlabCut& out, int capacity = SlabCut::kCapacity);

// [l, h] holding n.y for every point y of the triangles `ids` that lies in the box c +- hk
// (rigorous), for the slab's planes: each triangle j by its vertices and, where tighter, by the
// box's points on its plane's slab {|n_j.y - d_j| <= eps_j} (planes[j]): with z = y - c and
// e = n - mu n_j for any mu,
//   n.y = n.c + e.z + mu n_j.z <= n.c + hk |e|_1 + mu (d_j - n_j.c) + |mu| eps_j,
// likewise from below (mu = n.n_j / |n_j|^2; the doubles' rounding covered by 1e-13 of the terms'
// sizes): a long triangle crossing the box at a seam counts by its part in the box, not by its far
// vertices. Empty (lo > hi) without triangles.
Interval triangles_span_in_box(const TriangleMesh& mesh, const std::vector<TrianglePlane>& planes,
                               const std::vector<std::uint32_t>& ids, const Vec3& n, const Vec3& c, double hk);
// The same for the one triangle j (its points in the box: [lo, hi]; lo > hi never, but the range
// may be wider than the triangle's part in the box, which can be empty).
Interval triangle_span_in_box(const TriangleMesh& mesh, const std::vector<TrianglePlane>& planes, std::uint32_t j,
                              const Vec3& n, const Vec3& c, double hk);
// The same for the box c +- hk with a half side per axis (hk_k; |e|_1 hk becomes sum |e_k| hk_k).
Interval triangle_span_in_box(const TriangleMesh& mesh, const std::vector<TrianglePlane>& planes, std::uint32_t j,
                              const Vec3& n, const Vec3& c, const Vec3& hk);

// The 12 edges of a box whose corner k is (k & 1 ? hi : lo, k & 2 ? ..., k & 4 ? ...).
extern const std::array<std::array<int, 2>, 12> kBoxEdges;

}  // namespace cdbench
