#pragma once
// Certified signed distance to a closed triangle surface F: for a query point p, an interval
// [lo, hi] that contains s(p) = +-dist(p, F) (negative inside the solid) for the exact real
// geometry given by the doubles. Distances come from an AABB tree in doubles whose pruning bounds
// are rounded down and from interval arithmetic at the leaves; the sign comes from an exact ray or
// segment parity test (CGAL's exact orientation predicates), or from the point's only nearest face
// where the distance query proves one (side_by_nearest). See doc/distance.md.
#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "bvh/bvh.h"
#include "core/aabb.h"
#include "core/interval.h"
#include "core/triangle_mesh.h"
#include "distance/point_triangle_distance.h"

namespace cdbench {

// s from dist(p, F) and p's exact side (-1 inside, 0 on F, +1 outside): [-hi, -lo], [0, 0] or as is.
inline Interval with_side(const Interval& unsigned_dist, int side) {
  if (side == 0) return {0.0, 0.0};
  return side < 0 ? Interval{-unsigned_dist.hi, -unsigned_dist.lo} : unsigned_dist;
}

// How a nearest-triangle query encloses dist(p, F). `enclosed`: both ends from the interval
// enclosures of the nearest triangles (as tight as rounding allows; exact values come out exact).
// `near_points`: the upper end from a point of each nearest triangle near its closest point
// (point_triangle_distance_upper_near) and the lower end from the leaves' rigorous slab bounds, with
// no enclosure: up to about 1e-13 max|coordinate| wider, for the certificates' many queries, whose
// tolerance is far wider (doc/distance.md, "Near-point upper bounds").
enum class DistanceEnds { enclosed, near_points };

class SignedDistance {
 public:
  // The mesh must be closed and free of self-intersections for the sign to be meaningful (it is
  // what validate_mesh certifies); distances are valid for any mesh.
  explicit SignedDistance(TriangleMesh mesh);

  const TriangleMesh& mesh() const { return mesh_; }
  const Aabb& bbox() const { return bbox_; }
  const Bvh<Aabb>& tree() const { return tree_; }
  const std::vector<TrianglePlane>& planes() const { return planes_; }  // per face

  // [lo, hi] containing dist(p, F) >= 0; `nearest` (if given) receives a triangle at the upper end
  // (the least index among those at it). `hint` (optional): a triangle likely to be nearest (e.g. a
  // nearby point's), visited first so that it prunes from the start. It changes the work, not the
  // rigour: the answer is the same but where a triangle pruned in one order and visited in the
  // other has an enclosure reaching below the nearest one's (a few ulps, rigorous either way).
  // ends: see DistanceEnds (the default encloses both ends).
  // unique (if given): set when `nearest` is proven the only triangle at dist(p, F) (every other one
  // lies farther), which side_by_nearest needs; false when that is not proven.
  Interval unsigned_distance(const Vec3& p, std::uint32_t* nearest = nullptr, std::int64_t hint = -1,
                             DistanceEnds ends = DistanceEnds::enclosed, bool* unique = nullptr) const;

  // The same, the triangles searched being `candidates` only: they must include every triangle
  // within dist(p, F) of p (e.g. all within a radius known to exceed it), and then the result is
  // that of unsigned_distance, without a tree traversal.
  Interval unsigned_distance_among(const Vec3& p, const std::vector<std::uint32_t>& candidates,
                                   std::uint32_t* nearest = nullptr, DistanceEnds ends = DistanceEnds::enclosed,
                                   bool* unique = nullptr) const;

  // Rigorous enclosure of the squared distance from p to one face (an upper bound of dist(p, F)^2).
  Interval face_squared_distance(const Vec3& p, std::uint32_t face) const;

  // True when dist(p, F) <= bound is proven; may stop at the first triangle that proves it.
  // False means the full query ran; then `*full` (if given) receives the enclosure of dist(p, F).
  // `nearest` (optional) receives the triangle that proved it, or the nearest one; `hint`, as for
  // unsigned_distance, only orders the search (a triangle near p is tried first); `unique`, when the
  // full query ran, as for unsigned_distance.
  bool distance_at_most(const Vec3& p, double bound, Interval* full = nullptr, std::uint32_t* nearest = nullptr,
                        std::int64_t hint = -1, bool* unique = nullptr) const;

  // A rigorous lower bound of dist(T, F)^2 for the triangle T = (v0, v1, v2), tight up to rounding
  // where T and F are disjoint. F's tree is searched nearest first from T's box; per triangle the
  // cheap bounds first (each triangle's plane against the other's vertices), then the gap of the
  // projections on the estimated closest-point direction, and the certified pair distance (exact
  // intersection test) only where that gap is 0. Stops as soon as the bound is at most `stop_sq`
  // (the default never stops): the value returned is then <= stop_sq but not the minimum.
  // `enough_sq`: a caller that needs no more than this gets min(bound, enough_sq), a valid lower
  // bound found with every node and triangle beyond enough_sq pruned (a disjointness test when
  // small, instead of the distance: far fewer triangles).
  double triangle_squared_distance_lower(const std::array<Vec3, 3>& v, double stop_sq = -1.0,
                                         double enough_sq = std::numeric_limits<double>::infinity()) const;

  // Ids of all triangles of F whose distance to the triangle v may be <= reach (certified superset),
  // F's tree searched from v's box with the bounds of triangle_squared_distance_lower. Returns false,
  // leaving `out` partial, once more than `max_count` qualify.
  bool triangles_near_triangle(const std::array<Vec3, 3>& v, double reach, std::size_t max_count,
                               std::vector<std::uint32_t>& out) const;

  // A lower bound of dist(p, F), at most `enough`: min(dist(p, F), enough) less the bounds' slack.
  // Only what lies within `enough` of p is visited: for a point far from F, where the nearest
  // triangle is found only after every box nearer than it (a point inside a hollow shell meets
  // most of the tree), far cheaper than unsigned_distance. Stops as soon as the bound falls below
  // `stop`, and then returns 0.
  double distance_lower(const Vec3& p, double enough, double stop = 0.0) const;

  // Ids of all triangles whose distance to p may be <= radius (certified superset: every triangle
  // within radius is listed). Returns false, leaving `out` partial, once more than `max_count` qualify.
  bool triangles_within(const Vec3& p, double radius, std::size_t max_count, std::vector<std::uint32_t>& out) const;

  // Ids of all triangles that may meet the closed box (certified superset: their vertices' boxes
  // and planes are not proven apart from it). Returns false, leaving `out` partial, once more than
  // `max_count` qualify.
  bool triangles_meeting_box(const Aabb& box, std::size_t max_count, std::vector<std::uint32_t>& out) const;

  // triangles_within restricted to `candidates`, which must include every triangle within radius
  // of p (then `out` is a certified superset too). No cap.
  void triangles_within_among(const Vec3& p, double radius, const std::vector<std::uint32_t>& candidates,
                              std::vector<std::uint32_t>& out) const;

  // Exact side: -1 strictly inside the solid, 0 on the surface, +1 strictly outside.
  int side(const Vec3& p) const;
  // Same, when dist(p, F) is already enclosed: a positive lower end skips the on-surface test.
  int side(const Vec3& p, const Interval& unsigned_dist) const;

  // The same from a point `ref` off F whose side `ref_side` (+-1) is known: the parity of the
  // segment ref -> p's proper crossings of F (a short segment meets far fewer boxes than a ray out
  // of the bounding box), or the ray test when that segment meets F degenerately.
  int side(const Vec3& p, const Interval& unsigned_dist, const Vec3& ref, int ref_side) const;
  // The same, the segment's crossings counted among `candidates` only: they must include every
  // triangle the segment ref -> p may meet (e.g. all within |p - ref| of ref).
  int side_among(const Vec3& p, const Interval& unsigned_dist, const Vec3& ref, int ref_side,
                 const std::vector<std::uint32_t>& candidates) const;

  // p's side from its distance query (unsigned_dist, its `nearest` triangle and `unique`): where
  // that triangle is p's only nearest one, p's closest point lies inside it (a point of its
  // boundary is on a neighbour too), so p lies on the side of F that the face's side towards p
  // faces, the same over the whole face; that side is learnt once per face and then read with one
  // exact orientation test (doc/distance.md, "Side from the nearest face"). Otherwise, and to learn
  // it, side(p, ud, ref, ref_side): side_among with `candidates` (which must then hold every
  // triangle the segment ref -> p may meet), the ray when ref_side is not +-1.
  int side_by_nearest(const Vec3& p, const Interval& unsigned_dist, std::uint32_t nearest, bool unique,
                      const Vec3& ref, int ref_side, const std::vector<std::uint32_t>* candidates = nullptr) const;

  // [lo, hi] containing the signed distance s(p) (negative inside); the side by side_by_nearest
  // where p has one nearest triangle, else by the ray.
  Interval signed_distance(const Vec3& p) const;

  // Same, when dist(p, F) is already enclosed by `unsigned_dist`.
  Interval signed_distance(const Vec3& p, const Interval& unsigned_dist) const;

 private:
  bool on_surface(const Vec3& p) const;
  int side_off_surface(const Vec3& p) const;  // ray parity; p must not lie on F
  // side(p, ud, ref, ref_side) over F's tree (candidates null) or over `candidates` (side_among).
  int segment_side(const Vec3& p, const Interval& unsigned_dist, const Vec3& ref, int ref_side,
                   const std::vector<std::uint32_t>* candidates) const;

  TriangleMesh mesh_;
  Aabb bbox_;
  Bvh<Aabb> tree_;
  std::vector<TrianglePlane> planes_;  // per face: skips a visited triangle before its closest point
  // Per face, the side of F (+-1) that the side its normal points to faces; 0 while unknown
  // (side_by_nearest). Learnt as needed by any thread; shared by copies (the same mesh).
  std::shared_ptr<std::atomic<std::int8_t>[]> face_outward_;
};

}  // namespace cdbench
