#include "distance/signed_distance.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "distance/exact_predicates.h"
#include "distance/point_triangle_distance.h"

namespace cdbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Nearest-triangle query: keeps the smallest certified upper bound (prunes with it) and the
// smallest lower bound over visited leaves, which is a lower bound over all triangles (any pruned
// triangle is farther than the final upper bound, see doc/distance.md).
struct NearestPolicy {
  const TriangleMesh& mesh;
  Vec3 p;
  double stop_sq = -1.0;  // stop once best_hi_sq <= stop_sq
  double best_hi_sq = kInf;
  double min_lo_sq = kInf;
  std::uint32_t best_face = 0;

  double bound(const Aabb& box) const { return squared_distance_lower_bound(box, p); }
  double prune_bound() const { return best_hi_sq; }
  bool done() const { return best_hi_sq <= stop_sq; }
  void leaf(std::uint32_t f) {
    const Face& t = mesh.faces[f];
    const Interval d2 = point_triangle_squared_distance(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    if (d2.hi < best_hi_sq) {
      best_hi_sq = d2.hi;
      best_face = f;
    }
    min_lo_sq = std::min(min_lo_sq, d2.lo);
  }
};

// All triangles whose certified lower bound is within the radius.
struct WithinPolicy {
  const TriangleMesh& mesh;
  Vec3 p;
  double radius_sq;
  std::size_t max_count;
  std::vector<std::uint32_t>& out;
  bool overflow = false;
  double bound(const Aabb& box) const { return squared_distance_lower_bound(box, p); }
  double prune_bound() const { return radius_sq; }
  bool done() const { return overflow; }
  void leaf(std::uint32_t f) {
    const Face& t = mesh.faces[f];
    const Interval d2 = point_triangle_squared_distance(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    if (d2.lo <= radius_sq) {
      out.push_back(f);
      overflow = out.size() > max_count;
    }
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

}  // namespace

SignedDistance::SignedDistance(TriangleMesh mesh) : mesh_(std::move(mesh)), bbox_(mesh_.bbox()) {
  // Boxes of double vertices are exact.
  tree_ = build_triangle_bvh<Aabb>(mesh_.vertices, mesh_.faces, [](int n, const auto& p) { return bounding_box(n, p); });
}

Interval SignedDistance::unsigned_distance(const Vec3& p, std::uint32_t* nearest) const {
  NearestPolicy q{mesh_, p};
  traverse_nearest_first(tree_, q);
  if (nearest) *nearest = q.best_face;
  return sqrt_interval({q.min_lo_sq, q.best_hi_sq});
}

std::uint32_t SignedDistance::nearest_face(const Vec3& p) const {
  NearestPolicy q{mesh_, p};
  traverse_nearest_first(tree_, q);
  return q.best_face;
}

bool SignedDistance::distance_at_most(const Vec3& p, double bound, Interval* full) const {
  NearestPolicy q{mesh_, p};
  // bound^2 rounded down: best_hi_sq <= stop_sq then implies dist <= bound in exact arithmetic.
  q.stop_sq = bound > 0.0 ? bound * bound * (1.0 - kRoundingSlack) : -1.0;
  traverse_nearest_first(tree_, q);
  if (q.done()) return true;
  if (full) *full = sqrt_interval({q.min_lo_sq, q.best_hi_sq});
  return false;
}

bool SignedDistance::triangles_within(const Vec3& p, double radius, std::size_t max_count,
                                      std::vector<std::uint32_t>& out) const {
  out.clear();
  // radius^2 rounded up, so that no triangle within the radius is pruned.
  WithinPolicy q{mesh_, p, radius * radius * (1.0 + kRoundingSlack), max_count, out};
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
  const int s = side(p, d);
  if (s == 0) return {0.0, 0.0};
  return s < 0 ? Interval{-d.hi, -d.lo} : d;
}

Interval SignedDistance::signed_distance(const Vec3& p) const { return signed_distance(p, unsigned_distance(p)); }

}  // namespace cdbench
