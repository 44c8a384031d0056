#pragma once
// Supporting planes of F: a plane n.x = d with every vertex of F on its inner side, n.v - d <= e,
// bounds the signed distance from below everywhere:
//   s(x) >= (n.x - d - e) / |n|.
// The solid lies in the convex hull of F's vertices, hence in the half-space n.x <= d + e. Outside
// the solid, s(x) = dist(x, solid) >= the distance to that half-space; inside, the ray from x along
// n leaves the half-space after (d + e - n.x) / |n| and the solid no later, so F is that near. A
// convex F has one such plane per face, and then s = max over them wherever s < 0: the signed
// distance inside a convex polyhedron is the largest of its faces' signed plane distances.
//
// For a triangle of the mover and weights w >= 0 on the planes, the weighted mean of the plane
// bounds is affine in x, so its least value over the triangle is at a corner, and it falls at a
// known rate when the triangle is translated: one linear lower bound of c along a whole line of
// poses, exact where the deepest point of a convex F's penetration lies on the triangle (the
// weights of a small linear program make it so, by linear-programming duality). See
// doc/poses.md, "Supporting planes".
#include <array>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/triangle_mesh.h"

namespace cdbench {

struct SupportPlane {
  Vec3 n = Vec3::Zero();     // about unit
  double d = 0.0;
  double e = 0.0;            // >= max over F's vertices of the exact n.v - d (rounded up)
  double norm_lo = 1.0, norm_up = 1.0;  // enclose |n|
};

class SupportPlanes {
 public:
  SupportPlanes() = default;
  // The planes of F's faces that support F within `relative_slack` times its bounding-box diagonal
  // (near-duplicates merged). Each face's plane is tested against F's vertices, by a box tree over
  // them, until one lies beyond it (a supporting face visits the vertices near its plane and the
  // nodes above them; a face that does not support F mostly stops at the vertex that refuted the
  // face before): when that has cost more than max_work vertex tests and node bounds, and for a
  // mesh no face of which supports it, the set is empty (only speed depends on it: every use has
  // another bound).
  static SupportPlanes build(const TriangleMesh& F, double max_work = 2e7, double relative_slack = 1e-9);
  const std::vector<SupportPlane>& planes() const { return planes_; }
  bool empty() const { return planes_.empty(); }
  // The index in planes() of a plane at least as tight as face f's own (within the merging
  // tolerance), or -1 when f's plane does not support F.
  std::int32_t plane_of(std::uint32_t f) const { return f < face_plane_.size() ? face_plane_[f] : -1; }
  // Every face of F supports it: F is convex (then the bound below is exact where s < 0).
  bool convex() const { return convex_; }

  // The `k` planes highest at g, by the computed n.g - d, highest first (ties: the lesser index),
  // into `out` (value, index); k <= 16. The same as sorting every plane's value, from a tree of the
  // planes by their normals that skips groups provably lower (a finely faceted rod's 502 planes:
  // a few dozen evaluated).
  void highest(const Vec3& g, int k, std::pair<double, std::uint32_t>* out) const;
  // The plane with the greatest computed n.y - d - e above `floor`, not among `skip[0..n_skip)`
  // (ties: the lesser index), or -1: what a scan of every plane keeping a strictly greater value
  // finds.
  std::int64_t highest_above(const Vec3& y, double floor, const std::uint32_t* skip, int n_skip) const;

 private:
  // Groups of planes for highest(): a node's planes are order_[first, first + count) at a leaf
  // (count > 0), else its children are nodes first and first + 1. Every plane's n lies in [lo, hi]
  // and n.c - d (c: centre_) is at most top, n.c - d - e at most top_e (both as computed).
  struct Group {
    Vec3 lo, hi;
    double top, top_e;
    std::uint32_t first, count;
  };
  void build_groups(const Vec3& centre);
  // Above every computed value (n.y - d, or n.y - d - e with `with_e`) of the group's planes.
  double group_bound(const Group& g, const Vec3& y, bool with_e) const;
  template <class Leaf>
  void walk(const Vec3& y, bool with_e, const double& floor, const Leaf& leaf) const;

  std::vector<SupportPlane> planes_;
  std::vector<std::int32_t> face_plane_;
  bool convex_ = false;
  std::vector<Group> groups_;
  std::vector<std::uint32_t> order_;
  Vec3 centre_ = Vec3::Zero();
  double magnitude_ = 0.0;  // |centre|_1 + max |d| + max e + 1: the groups' rounding scale
};

// For the convex hull of the points x[0..n) (n <= 8: a triangle's corners, a box's) and a direction
// d: for every point y of the hull and every mu >= 0,
//   s(y - mu d) >= lower - mu rate   (rigorous; rate may be negative: the bound then rises).
// The weights come from a small linear program over the `max_members` planes highest at the
// points' centroid, for a triangle extended by column generation (any weights are valid; these
// make the bound tight at mu = 0). For a triangle, `beta, gamma`: barycentrics of a point where
// the weighted planes' maximum is least (a guess of the deepest point, for an upper end; not part
// of the bound). lower = -inf when the set is empty.
struct HalfspaceBound {
  double lower = 0.0, rate = 0.0;
  double beta = 1.0 / 3, gamma = 1.0 / 3;
};
// `seed` (a triangle's, optional): planes a previous bound of the same triangle weighted (a nearby
// pose of the mover), which join first; on return the planes this bound weights. Only the members,
// hence the work and the weights, depend on it: the bound is rigorous for any.
struct HalfspaceSeed {
  std::array<std::uint32_t, 4> idx{};
  int n = 0;
};
HalfspaceBound halfspace_bound(const SupportPlanes& S, const Vec3* x, int n, const Vec3& d, int max_members = 6,
                               HalfspaceSeed* seed = nullptr);
// Seeds of a mover's triangles by face index, kept over the poses of one advance.
using HalfspaceSeeds = std::unordered_map<std::uint32_t, HalfspaceSeed>;

// The same bound from the given planes only (indices into S.planes(), at most 16 used; no column
// generation): for a cell of a mover triangle near faces of F that support F (a non-convex F's
// outer walls), the planes of those faces. lower = -inf when `members` is empty.
HalfspaceBound halfspace_bound_among(const SupportPlanes& S, const std::int32_t* members, int n_members,
                                     const Vec3* x, int n, const Vec3& d);

}  // namespace cdbench
