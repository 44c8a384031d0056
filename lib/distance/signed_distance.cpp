#include "distance/signed_distance.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "distance/exact_predicates.h"
#include "distance/point_triangle_distance.h"
#include "distance/triangle_distance.h"
#include "util/least_key.h"

namespace cdbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Nearest-triangle query: keeps the smallest certified upper bound (prunes with it) and the
// smallest lower bound over visited leaves, which is a lower bound over all triangles (any pruned
// triangle is farther than the final upper bound, see doc/distance.md).
struct NearestPolicy {
  const TriangleMesh& mesh;
  Vec3 p;
  LeastKey best{};  // (upper end squared, face); ties to the least index, whatever the visiting order
  double min_lo_sq = kInf;

  double best_hi_sq() const { return best.key; }
  std::uint32_t best_face() const { return best.index; }
  double bound(const Aabb& box) const { return squared_distance_lower_bound(box, p); }
  double prune_bound() const { return best.key; }
  bool done() const { return false; }
  void leaf(std::uint32_t f) {
    const Face& t = mesh.faces[f];
    const Interval d2 = point_triangle_squared_distance(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    best.offer(d2.hi, f);
    min_lo_sq = std::min(min_lo_sq, d2.lo);
  }
};

// The slab lower bound of dist(p, abc)^2 (point_triangle_distance_lower_bound, rounded down) along
// the direction of the estimated closest point; *e2 receives the estimate's squared distance.
// An error of angle theta in the direction costs about theta times the triangle's size, so it is
// taken from exact features where the estimate would tilt it: the face normal for the interior,
// the estimate made orthogonal to the edge for an edge, the estimate itself for a vertex.
double slab_lower_bound_sq(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double* e2_out) {
  int feature = 6;
  const Vec3 e = closest_point_on_triangle(p, a, b, c, &feature) - p;
  const double e2 = e.squaredNorm();
  *e2_out = e2;
  if (!(e2 > 0.0)) return 0.0;
  Vec3 u = e;
  if (feature == 6) {
    u = (b - a).cross(c - a);
    if (u.dot(e) < 0.0) u = -u;
  } else if (feature >= 3) {
    const Vec3& v0 = feature == 3 ? a : feature == 4 ? b : c;
    const Vec3& v1 = feature == 3 ? b : feature == 4 ? c : a;
    const Vec3 t = v1 - v0;
    const double tt = t.squaredNorm();
    if (tt > 0.0) u = e - (e.dot(t) / tt) * t;
  }
  const double lb = point_triangle_distance_lower_bound(p, a, b, c, u);
  return lb > 0.0 ? round_down(lb * lb) : 0.0;
}

// The same query at about half the cost: a leaf costs a double closest-point estimate and a rigorous
// slab lower bound along the estimated direction (slab_lower_bound_sq); pruning uses the estimated
// best with a margin. Afterwards the caller encloses
// the best triangle rigorously (hi): if hi lies at or below the final pruning threshold, every
// pruned subtree is beyond the minimum, and so is every leaf whose slab bound is at least hi; the
// lower end is the least certified lower end among the best and the leaves kept in `near` (slab
// bound below hi; usually the few sharing the nearest feature), so the interval is as tight as
// NearestPolicy's. Otherwise the query is redone with NearestPolicy.
struct FastNearestPolicy {
  const TriangleMesh& mesh;
  const std::vector<TrianglePlane>& planes;
  Vec3 p;
  double margin_sq;
  std::vector<std::pair<double, std::uint32_t>>& near;  // (slab bound squared, face) below the threshold
  LeastKey best{};  // (estimate squared, face)
  double best_lb_sq = 0.0;  // the best triangle's slab bound squared
  double threshold_sq = kInf;

  double bound(const Aabb& box) const { return squared_distance_lower_bound(box, p); }
  double prune_bound() const { return threshold_sq; }
  bool done() const { return false; }
  void leaf(std::uint32_t f) {
    // Farther than the threshold by its plane alone: neither the best nor near it (see the caller).
    const double pl = plane_distance_lower_bound(planes[f], p);
    if (pl > 0.0 && round_down(pl * pl) >= threshold_sq) return;
    const Face& t = mesh.faces[f];
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    double e2 = 0.0;
    const double lb_sq = slab_lower_bound_sq(p, a, b, c, &e2);
    if (best.offer(e2, f)) {
      threshold_sq = e2 * (1.0 + 1e-6) + margin_sq;
      best_lb_sq = lb_sq;
    }
    if (lb_sq < threshold_sq) near.emplace_back(lb_sq, f);
  }
};

// A lower bound of dist(p, F)^2, at most enough_sq: the least of the visited triangles' bounds
// and enough_sq (a node or triangle beyond the running least is pruned: it cannot lower it). Each
// triangle by its plane first, then by the slab bound. Stops once the bound is below stop_sq.
struct LowerPolicy {
  const TriangleMesh& mesh;
  const std::vector<TrianglePlane>& planes;
  Vec3 p;
  double stop_sq;
  double lo_sq;
  double bound(const Aabb& box) const { return squared_distance_lower_bound(box, p); }
  double prune_bound() const { return lo_sq; }
  bool done() const { return lo_sq < stop_sq; }
  void leaf(std::uint32_t f) {
    const double pl = plane_distance_lower_bound(planes[f], p);
    if (pl > 0.0 && round_down(pl * pl) >= lo_sq) return;
    const Face& t = mesh.faces[f];
    double e2 = 0.0;
    lo_sq = std::min(lo_sq, slab_lower_bound_sq(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]], &e2));
  }
};

// Whether some triangle is proven within sqrt(stop_sq) of p, nearest boxes first: a triangle is
// enclosed rigorously only when the double estimate of its distance is about the bound or below
// (most visited ones are not: an enclosure costs several estimates), and the first whose upper end
// is at most stop_sq ends the search. Boxes beyond the bound cannot prove it and are pruned.
struct AtMostPolicy {
  const SignedDistance& sd;
  Vec3 p;
  double stop_sq;
  bool proven = false;
  std::uint32_t face = 0;  // the triangle that proved it
  double bound(const Aabb& box) const { return squared_distance_lower_bound(box, p); }
  double prune_bound() const { return stop_sq; }
  bool done() const { return proven; }
  void leaf(std::uint32_t f) {
    if (proven) return;
    const Face& t = sd.mesh().faces[f];
    const auto& v = sd.mesh().vertices;
    const double e2 = (closest_point_on_triangle(p, v[t[0]], v[t[1]], v[t[2]]) - p).squaredNorm();
    if (e2 <= stop_sq * (1.0 + 1e-9) && sd.face_squared_distance(p, f).hi <= stop_sq) {
      proven = true;
      face = f;
    }
  }
};

// All triangles whose rigorous slab lower bound is within the radius: a certified superset of those
// within it (a few more than the certified enclosures would keep, never fewer), at a third of the
// cost of enclosing each.
struct WithinPolicy {
  const TriangleMesh& mesh;
  const std::vector<TrianglePlane>& planes;
  Vec3 p;
  double radius_sq;
  std::size_t max_count;
  std::vector<std::uint32_t>& out;
  bool overflow = false;
  double bound(const Aabb& box) const { return squared_distance_lower_bound(box, p); }
  double prune_bound() const { return radius_sq; }
  bool done() const { return overflow; }
  void leaf(std::uint32_t f) {
    const double pl = plane_distance_lower_bound(planes[f], p);
    if (pl > 0.0 && round_down(pl * pl) > radius_sq) return;
    const Face& t = mesh.faces[f];
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    // Every vertex within the radius: so is the triangle (the distance to p is convex), and the
    // slab bound, below its distance, would keep it; it is kept at a third of the cost. The sums
    // of three squared differences are within 5 u of the exact ones; kRoundingSlack covers that.
    const double far_sq = std::max({(a - p).squaredNorm(), (b - p).squaredNorm(), (c - p).squaredNorm()});
    if (!(far_sq * (1.0 + kRoundingSlack) + 1e-300 <= radius_sq)) {
      double e2 = 0.0;
      if (slab_lower_bound_sq(p, a, b, c, &e2) > radius_sq) return;
    }
    out.push_back(f);
    overflow = out.size() > max_count;
  }
};

// Triangles that may meet a closed box: those whose vertices' box and plane are not proven apart
// from it (the tree's boxes hold their triangles' vertices exactly: a node apart is skipped).
struct MeetingBoxPolicy {
  const TriangleMesh& mesh;
  const std::vector<TrianglePlane>& planes;
  Aabb box;
  std::size_t max_count;
  std::vector<std::uint32_t>& out;
  bool overflow = false;
  double bound(const Aabb& b) const { return b.apart(box) ? kInf : 0.0; }
  double prune_bound() const { return 0.0; }
  bool done() const { return overflow; }
  void leaf(std::uint32_t f) {
    const Face& t = mesh.faces[f];
    if (bounding_box(3, [&](int k) { return mesh.vertices[t[k]]; }).apart(box)) return;
    if (std::isfinite(planes[f].eps) && box_plane_lower_bound(planes[f], box) > 0.0) return;
    out.push_back(f);
    overflow = out.size() > max_count;
  }
};

// Candidates for an exact test: triangles whose box holds p (bound 0) are visited, others skipped.
struct BoxContainsPolicy {
  const TriangleMesh& mesh;
  Vec3 p;
  bool found = false;
  double bound(const Aabb& box) const { return box.contains(p) ? 0.0 : kInf; }
  double prune_bound() const { return 0.0; }
  bool done() const { return found; }
  void leaf(std::uint32_t f) {
    const Face& t = mesh.faces[f];
    if (point_on_triangle(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]])) found = true;
  }
};

// Ray parity along the segment p -> q, q outside the bounding box.
struct ParityPolicy {
  const TriangleMesh& mesh;
  Vec3 p, q;
  double margin;
  int crossings = 0;
  bool degenerate = false;
  double bound(const Aabb& box) const { return segment_may_hit(box, p, q, margin) ? 0.0 : kInf; }
  double prune_bound() const { return 0.0; }
  bool done() const { return degenerate; }
  void leaf(std::uint32_t f) {
    const Face& t = mesh.faces[f];
    switch (segment_crosses_triangle(p, q, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]])) {
      case SegmentCrossing::None: break;
      case SegmentCrossing::Proper: ++crossings; break;
      case SegmentCrossing::Degenerate: degenerate = true; break;
    }
  }
};

// Pruning on the running minimum of the lower bounds is rigorous: a node is skipped only when a
// lower bound of its distance to v exceeds that minimum, so none of its triangles could lower it.
// Lower bounds of the squared distance from a node of F's tree to a triangle v: the boxes'
// distance; for a node smaller than v's box, also its distance to v's plane, its gaps to v along
// v's in-plane edge normals (a long, tilted cell of a machined part has a box that holds many of
// F's nodes its plane and sides keep far from it) and along v's longest edge times each coordinate
// axis (a box's separating axes from a segment: a sliver across a faceted wall). Nodes at least as
// large as v's box seldom lie beyond those, so they are not asked: on rounded meshes the extra
// bounds would cost more than they prune. `limit_sq`: the caller's pruning bound (the extra bounds
// are skipped past it).
struct TriangleNodeBound {
  const std::array<Vec3, 3>& v;
  TrianglePlane plane;              // of v
  std::array<AxisRange, 3> sides;   // v's range along each edge's in-plane normal
  std::array<AxisRange, 3> across;  // along its longest edge times each coordinate axis
  Aabb box;                         // of v
  double box_diagonal_sq;
  Vec3 long_edge;                   // v's longest edge (long_edges_gap)
  explicit TriangleNodeBound(const std::array<Vec3, 3>& t)
      : v(t), plane(make_triangle_plane(t[0], t[1], t[2])), long_edge(longest_edge(t[0], t[1], t[2])) {
    for (const Vec3& x : t) box.extend(x);
    box_diagonal_sq = (box.hi - box.lo).squaredNorm();
    const Vec3 normal = (t[1] - t[0]).cross(t[2] - t[0]);
    for (int k = 0; k < 3; ++k) sides[k] = triangle_axis_range((t[(k + 1) % 3] - t[k]).cross(normal), t);
    // (An axis near 0, the edge along a coordinate axis, is left out: its gap is then 0.)
    const double long2 = long_edge.squaredNorm();
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = long_edge.cross(Vec3::Unit(k));
      if (u.squaredNorm() > 1e-24 * long2) across[k] = triangle_axis_range(u, t);
    }
  }
  double operator()(const Aabb& b, double limit_sq) const {
    const double boxes = squared_distance_lower_bound(b, box);
    if (boxes >= limit_sq || (b.hi - b.lo).squaredNorm() >= box_diagonal_sq) return boxes;
    double lb = box_plane_lower_bound(plane, b);
    for (int k = 0; lb * lb < limit_sq && k < 3; ++k) lb = std::max(lb, box_axis_gap_lower_bound(sides[k], b));
    for (int k = 0; lb * lb < limit_sq && k < 3; ++k) lb = std::max(lb, box_axis_gap_lower_bound(across[k], b));
    return lb > 0.0 ? std::max(boxes, round_down(lb * lb)) : boxes;
  }
  // A rigorous lower bound of the distance from F's triangle (a, b, c) to v, from the two planes
  // alone (each triangle's plane against the other's vertices).
  double planes_lower(const TrianglePlane& fp, const Vec3& a, const Vec3& b, const Vec3& c) const {
    return std::max(plane_pair_lower_bound(fp, v[0], v[1], v[2]), plane_pair_lower_bound(plane, a, b, c));
  }
  // True when a cheap bound proves F's triangle (a, b, c) at least sqrt(limit_sq) from v: the two
  // planes, then the axis across both longest edges. (A tube's 4-long wall slivers against a
  // tilted copy's: of the triangles the planes kept, 90 % lay 0.1 or more from the cell, and the
  // long-edge axis set aside 99.7 % of them; doc/performance.md, "Slivers across slivers".)
  bool cheaply_beyond(const TrianglePlane& fp, const Vec3& a, const Vec3& b, const Vec3& c, double limit_sq) const {
    const double lb = planes_lower(fp, a, b, c);
    if (round_down(lb * lb) >= limit_sq) return true;
    const double g = long_edges_gap(a, b, c, v[0], v[1], v[2], long_edge);
    return round_down(g * g) >= limit_sq;
  }
};

struct TriangleLowerPolicy {
  const TriangleMesh& mesh;
  const std::vector<TrianglePlane>& planes;
  const TriangleNodeBound& nb;
  double stop_sq;
  double d2lo;  // starts at the caller's enough_sq: nothing beyond it is looked at
  double bound(const Aabb& b) const { return nb(b, d2lo); }
  double prune_bound() const { return d2lo; }
  bool done() const { return d2lo <= stop_sq; }
  void leaf(std::uint32_t j) {
    const Face& g = mesh.faces[j];
    const Vec3 &a = mesh.vertices[g[0]], &b = mesh.vertices[g[1]], &c = mesh.vertices[g[2]];
    const auto& v = nb.v;
    if (nb.cheaply_beyond(planes[j], a, b, c, d2lo)) return;  // cannot lower the minimum
    Vec3 p, q;
    const double e2 = triangle_triangle_closest_points(a, b, c, v[0], v[1], v[2], &p, &q);
    const double gap = e2 > 0.0 ? triangle_distance_lower_bound(a, b, c, v[0], v[1], v[2], q - p) : 0.0;
    d2lo = std::min(d2lo, gap > 0.0 ? round_down(gap * gap)
                                    : triangle_triangle_squared_distance(a, b, c, v[0], v[1], v[2]).lo);
  }
};

// Every triangle of F that may lie within sqrt(reach_sq) of v: a triangle is left out only when a
// rigorous lower bound of its distance (the planes, then the projection gap) exceeds it.
struct TriangleWithinPolicy {
  const TriangleMesh& mesh;
  const std::vector<TrianglePlane>& planes;
  const TriangleNodeBound& nb;
  double reach_sq;
  std::size_t max_count;
  std::vector<std::uint32_t>& out;
  bool overflow = false;
  double bound(const Aabb& b) const { return nb(b, reach_sq); }
  double prune_bound() const { return reach_sq; }
  bool done() const { return overflow; }
  void leaf(std::uint32_t j) {
    const Face& g = mesh.faces[j];
    const Vec3 &a = mesh.vertices[g[0]], &b = mesh.vertices[g[1]], &c = mesh.vertices[g[2]];
    const auto& v = nb.v;
    // (Strictly beyond: one at exactly reach is listed.)
    if (nb.cheaply_beyond(planes[j], a, b, c, round_up(reach_sq))) return;
    Vec3 p, q;
    if (triangle_triangle_closest_points(a, b, c, v[0], v[1], v[2], &p, &q) > 0.0) {
      const double gap = triangle_distance_lower_bound(a, b, c, v[0], v[1], v[2], q - p);
      if (round_down(gap * gap) > reach_sq) return;
    }
    out.push_back(j);
    overflow = out.size() > max_count;
  }
};

}  // namespace

double SignedDistance::triangle_squared_distance_lower(const std::array<Vec3, 3>& v, double stop_sq,
                                                       double enough_sq) const {
  // Starting the running minimum at enough_sq prunes what lies beyond it, and the result is the
  // minimum of the visited triangles' bounds and enough_sq: every skipped node or triangle lies
  // at or beyond that minimum.
  const TriangleNodeBound nb(v);
  TriangleLowerPolicy policy{mesh_, planes_, nb, stop_sq, enough_sq};
  traverse_nearest_first(tree_, policy);
  return policy.d2lo;
}

bool SignedDistance::triangles_near_triangle(const std::array<Vec3, 3>& v, double reach, std::size_t max_count,
                                             std::vector<std::uint32_t>& out) const {
  out.clear();
  const TriangleNodeBound nb(v);
  // reach^2 rounded up, so that no triangle within reach is pruned.
  TriangleWithinPolicy q{mesh_, planes_, nb, round_up(reach * reach * (1.0 + kRoundingSlack)), max_count, out};
  traverse_nearest_first(tree_, q);
  return !q.overflow;
}

SignedDistance::SignedDistance(TriangleMesh mesh)
    : mesh_(std::move(mesh)), bbox_(mesh_.bbox()), face_outward_(new std::atomic<std::int8_t>[mesh_.faces.size()]()) {
  // Boxes of double vertices are exact. The faces' planes beside the tree, on all threads (at
  // 832,000 faces a serial loop that other threads waited for). Split by surface area: CAD parts'
  // long faces beside small ones made median boxes that overlap, and every distance query visited
  // more nodes (doc/performance.md, "Distance trees split by surface area").
  tbb::parallel_invoke(
      [&] {
        tree_ = build_triangle_bvh<Aabb>(
            mesh_.vertices, mesh_.faces, [](int n, const auto& p) { return bounding_box(n, p); },
            BvhBuildOptions{1, BvhSplit::surface_area});
      },
      [&] {
        planes_.resize(mesh_.faces.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, planes_.size(), 16384), [&](const auto& r) {
          for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const Face& f = mesh_.faces[i];
            planes_[i] = make_triangle_plane(mesh_.vertices[f[0]], mesh_.vertices[f[1]], mesh_.vertices[f[2]]);
          }
        });
      });
}

namespace {

// The fast query's result from the leaves it visited (tree or candidate list): the best triangle
// enclosed rigorously, and the lower end from the leaves kept near it (enclosed too, or with
// DistanceEnds::near_points their slab bounds and near-point upper ends). False when the best does
// not lie at or below the final pruning threshold (the caller then runs the rigorous query).
bool finish_fast(const SignedDistance& sd, const FastNearestPolicy& fast,
                 const std::vector<std::pair<double, std::uint32_t>>& near, Interval* out, std::uint32_t* nearest,
                 DistanceEnds ends, bool* unique) {
  if (!(fast.best.key < kInf)) return false;
  // A triangle's squared distance enclosed (`enclosed`), or between its slab bound and the square of
  // its near-point upper bound (`near_points`: no enclosure).
  const auto enclose = [&](std::uint32_t f, double lb_sq) {
    if (ends == DistanceEnds::enclosed) return sd.face_squared_distance(fast.p, f);
    const double h = point_triangle_distance_upper_near(fast.p, sd.mesh(), f);
    return Interval{lb_sq, round_up(h * h)};
  };
  const Interval best = enclose(fast.best.index, fast.best_lb_sq);
  if (!(best.hi <= fast.threshold_sq)) return false;
  double lo = best.lo;
  LeastKey upper{best.hi, fast.best.index};  // ties: the least index, whatever the order of `near`
  // (lower end squared, face) of the best and of `near`, for `unique` only.
  thread_local std::vector<std::pair<double, std::uint32_t>> lows;
  lows.clear();
  if (unique) lows.emplace_back(best.lo, fast.best.index);
  for (const auto& [lb_sq, f] : near)
    if (lb_sq < best.hi && f != fast.best.index) {
      const Interval x = enclose(f, lb_sq);
      lo = std::min(lo, x.lo);
      upper.offer(x.hi, f);
      if (unique) lows.emplace_back(x.lo, f);
    } else if (unique) {
      lows.emplace_back(lb_sq, f);
    }
  if (nearest) *nearest = upper.index;
  *out = sqrt_interval({lo, upper.key});
  if (unique) {
    // The nearest triangle is the only one at dist(p, F) when every other lies farther than its
    // upper end: those left out of `near` or pruned lie at or beyond the final threshold (it only
    // falls), those in it beyond their lower ends.
    bool u = upper.key < fast.threshold_sq;
    for (std::size_t i = 0; u && i < lows.size(); ++i) u = lows[i].second == upper.index || lows[i].first > upper.key;
    *unique = u;
  }
  return true;
}

// The nearest-triangle query over the leaves `visit` hands to a policy (the tree's, or a list's):
// the fast policy first, the rigorous one when the fast result cannot be confirmed.
template <class Visit>
Interval nearest_distance(const SignedDistance& sd, const Vec3& p, const Visit& visit, std::uint32_t* nearest,
                          DistanceEnds ends, bool* unique) {
  // Margin of the estimate: far above its rounding near the surface (scale: the box and p).
  const double scale = sd.bbox().lo.cwiseAbs().maxCoeff() + sd.bbox().hi.cwiseAbs().maxCoeff() + p.cwiseAbs().maxCoeff();
  thread_local std::vector<std::pair<double, std::uint32_t>> near;
  near.clear();
  FastNearestPolicy fast{sd.mesh(), sd.planes(), p, (1e-10 * scale) * (1e-10 * scale), near};
  visit(fast);
  Interval d;
  if (finish_fast(sd, fast, near, &d, nearest, ends, unique)) return d;
  if (unique) *unique = false;  // not asked of the rigorous query (rare)
  NearestPolicy q{sd.mesh(), p};
  visit(q);
  if (nearest) *nearest = q.best_face();
  return sqrt_interval({q.min_lo_sq, q.best_hi_sq()});
}

}  // namespace

Interval SignedDistance::unsigned_distance(const Vec3& p, std::uint32_t* nearest, std::int64_t hint,
                                           DistanceEnds ends, bool* unique) const {
  const bool hinted = hint >= 0 && static_cast<std::size_t>(hint) < mesh_.faces.size();
  return nearest_distance(
      *this, p,
      [&](auto& policy) {
        // A leaf visited once more is harmless: every policy takes the least over its leaves.
        if (hinted) policy.leaf(static_cast<std::uint32_t>(hint));
        traverse_nearest_first(tree_, policy);
      },
      nearest, ends, unique);
}

Interval SignedDistance::unsigned_distance_among(const Vec3& p, const std::vector<std::uint32_t>& candidates,
                                                 std::uint32_t* nearest, DistanceEnds ends, bool* unique) const {
  // The same leaves as the tree query, without the tree: every triangle left out is farther than
  // the nearest, as a pruned subtree is.
  return nearest_distance(
      *this, p, [&](auto& policy) { for (std::uint32_t f : candidates) policy.leaf(f); }, nearest, ends, unique);
}

void SignedDistance::triangles_within_among(const Vec3& p, double radius, const std::vector<std::uint32_t>& candidates,
                                            std::vector<std::uint32_t>& out) const {
  out.clear();
  WithinPolicy q{mesh_, planes_, p, radius * radius * (1.0 + kRoundingSlack), candidates.size(), out};
  for (std::uint32_t f : candidates) q.leaf(f);
}

Interval SignedDistance::face_squared_distance(const Vec3& p, std::uint32_t f) const {
  const Face& t = mesh_.faces[f];
  return point_triangle_squared_distance(p, mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]]);
}

bool SignedDistance::distance_at_most(const Vec3& p, double bound, Interval* full, std::uint32_t* nearest,
                                      std::int64_t hint, bool* unique) const {
  const bool hinted = hint >= 0 && static_cast<std::size_t>(hint) < mesh_.faces.size();
  if (bound > 0.0) {
    // bound^2 rounded down: an upper end <= stop_sq then implies dist <= bound in exact arithmetic.
    AtMostPolicy q{*this, p, bound * bound * (1.0 - kRoundingSlack)};
    if (hinted) q.leaf(static_cast<std::uint32_t>(hint));
    if (!q.proven) traverse_nearest_first(tree_, q);
    if (q.proven) {
      if (nearest) *nearest = q.face;
      return true;
    }
  }
  std::uint32_t face = 0;
  const Interval d = unsigned_distance(p, &face, hint, DistanceEnds::enclosed, unique);
  if (full) *full = d;
  if (nearest) *nearest = face;
  return false;
}

double SignedDistance::distance_lower(const Vec3& p, double enough, double stop) const {
  if (!(enough > 0.0)) return 0.0;
  if (mesh_.faces.empty()) return enough;  // no triangle: dist(p, F) is infinite
  // enough^2 rounded down and the result's root rounded down: a lower bound either way.
  LowerPolicy q{mesh_, planes_, p, stop > 0.0 ? round_up(stop * stop) : -1.0, round_down(enough * enough)};
  traverse_nearest_first(tree_, q);
  if (q.done()) return 0.0;  // stopped: the leaves not visited may be nearer than the bound so far
  return q.lo_sq > 0.0 ? round_down(std::sqrt(q.lo_sq)) : 0.0;
}

bool SignedDistance::triangles_within(const Vec3& p, double radius, std::size_t max_count,
                                      std::vector<std::uint32_t>& out) const {
  out.clear();
  // radius^2 rounded up, so that no triangle within the radius is pruned.
  WithinPolicy q{mesh_, planes_, p, radius * radius * (1.0 + kRoundingSlack), max_count, out};
  traverse_nearest_first(tree_, q);
  return !q.overflow;
}

bool SignedDistance::triangles_meeting_box(const Aabb& box, std::size_t max_count, std::vector<std::uint32_t>& out) const {
  out.clear();
  MeetingBoxPolicy q{mesh_, planes_, box, max_count, out};
  traverse_nearest_first(tree_, q);
  return !q.overflow;
}

bool SignedDistance::on_surface(const Vec3& p) const {
  BoxContainsPolicy q{mesh_, p};
  traverse_nearest_first(tree_, q);
  return q.found;
}

int SignedDistance::side(const Vec3& p) const { return on_surface(p) ? 0 : side_off_surface(p); }

int SignedDistance::side(const Vec3& p, const Interval& unsigned_dist) const {
  return unsigned_dist.lo > 0.0 ? side_off_surface(p) : side(p);
}

int SignedDistance::side(const Vec3& p, const Interval& unsigned_dist, const Vec3& ref, int ref_side) const {
  return segment_side(p, unsigned_dist, ref, ref_side, nullptr);
}

int SignedDistance::side_among(const Vec3& p, const Interval& unsigned_dist, const Vec3& ref, int ref_side,
                               const std::vector<std::uint32_t>& candidates) const {
  return segment_side(p, unsigned_dist, ref, ref_side, &candidates);
}

int SignedDistance::segment_side(const Vec3& p, const Interval& unsigned_dist, const Vec3& ref, int ref_side,
                                 const std::vector<std::uint32_t>* candidates) const {
  if (!(unsigned_dist.lo > 0.0) || (ref_side != 1 && ref_side != -1)) return side(p, unsigned_dist);
  // Both ends off F: each proper crossing flips the side (Jordan-Brouwer, as for the ray).
  const double margin = 1e-9 * (bbox_.diagonal() + (p - bbox_.center()).norm() + (p - ref).norm()) + 1e-300;
  ParityPolicy parity{mesh_, ref, p, margin};
  if (candidates) {
    for (const std::uint32_t f : *candidates) {
      parity.leaf(f);
      if (parity.done()) break;
    }
  } else {
    traverse_nearest_first(tree_, parity);
  }
  if (parity.degenerate) return side_off_surface(p);
  return parity.crossings % 2 == 1 ? -ref_side : ref_side;
}

int SignedDistance::side_by_nearest(const Vec3& p, const Interval& unsigned_dist, std::uint32_t nearest,
                                    bool unique, const Vec3& ref, int ref_side,
                                    const std::vector<std::uint32_t>* candidates) const {
  const auto slow = [&] {
    return ref_side == 1 || ref_side == -1 ? segment_side(p, unsigned_dist, ref, ref_side, candidates)
                                           : side(p, unsigned_dist);
  };
  if (!unique || !(unsigned_dist.lo > 0.0)) return slow();
  const Face& t = mesh_.faces[nearest];
  const int o = orientation_sign(mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]], p);
  if (o == 0) return slow();  // a degenerate face (p, off F, is never in a proper face's plane here)
  std::atomic<std::int8_t>& known = face_outward_[nearest];
  const int sigma = known.load(std::memory_order_relaxed);
  if (sigma != 0) return sigma * o;
  const int s = slow();
  if (s != 0) known.store(static_cast<std::int8_t>(s * o), std::memory_order_relaxed);
  return s;
}

int SignedDistance::side_off_surface(const Vec3& p) const {
  const Vec3 center = bbox_.center();
  const double reach = 2.0 * (bbox_.diagonal() + (p - center).norm()) + 1.0;
  const double margin = 1e-9 * (bbox_.diagonal() + (p - center).norm()) + 1e-300;
  // Deterministic, well-spread directions; a degenerate hit (edge, vertex, coplanar) tries the next.
  const double golden = 0.5 * (1.0 + std::sqrt(5.0));
  for (int k = 0; k < 200; ++k) {
    const double z = 1.0 - 2.0 * (k + 0.5) / 200.0;
    const double phi = 2.0 * M_PI * std::fmod((k + 0.37) * golden, 1.0);
    const Vec3 dir(std::sqrt(1.0 - z * z) * std::cos(phi), std::sqrt(1.0 - z * z) * std::sin(phi), z);
    Vec3 q = p + reach * dir;
    if (bbox_.contains(q)) continue;
    ParityPolicy parity{mesh_, p, q, margin};
    traverse_nearest_first(tree_, parity);
    if (!parity.degenerate) return (parity.crossings % 2 == 1) ? -1 : 1;
  }
  throw std::logic_error("side(): every ray direction hit the surface degenerately");
}

Interval SignedDistance::signed_distance(const Vec3& p, const Interval& d) const {
  return with_side(d, side(p, d));
}

Interval SignedDistance::signed_distance(const Vec3& p) const {
  std::uint32_t face = 0;
  bool unique = false;
  const Interval d = unsigned_distance(p, &face, -1, DistanceEnds::enclosed, &unique);
  return with_side(d, side_by_nearest(p, d, face, unique, p, 0));
}

}  // namespace cdbench
