#include "distance/depth_bound.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "distance/point_triangle_distance.h"

namespace cdbench {

double translated_depth(const TranslatedDepthBound& b, const Vec3& D) {
  if (b.n == 0) return std::numeric_limits<double>::infinity();
  const double d2 = D.squaredNorm(), dn = std::sqrt(d2);
  double worst = 0.0;
  for (int k = 0; k < b.n; ++k) {
    const CornerMoments& m = b.corners[k];
    // The computed A and W are within (n + 5) u (n <= 48 weights) of the exact means of the
    // computed w: 1e-13 relative for A, 1e-13 sqrt(A) for W (|W| <= sqrt(A) by Cauchy-Schwarz).
    // The sum then rounds by a few u times (sqrt(A) + |D|)^2; 1e-12 of it covers that.
    const double sa = std::sqrt(m.a);
    double g = m.a * (1.0 + 1e-13) + 2.0 * m.w.dot(D) + 2e-13 * sa * dn + d2;
    g += 1e-12 * (sa + dn) * (sa + dn);
    worst = std::max(worst, g);
  }
  return round_up(round_up(std::sqrt(worst)) + b.err);
}

namespace {
// The most triangles a bound combines: a partial set is still valid, and the nearest ones make it
// tight (the first found by the tree's nearest-first order, or the nearest of a candidate list).
constexpr std::size_t kMaxTriangles = 49;
}  // namespace

double depth_upper_bound(const SignedDistance& sdf, const Vec3& c, double radius, const Vec3* corners, int n_corners,
                         std::vector<std::uint32_t>& ids, Vec3* candidate, const Vec3* plane_normal, int* worst_corner,
                         TranslatedDepthBound* moments) {
  sdf.triangles_within(c, radius, kMaxTriangles - 1, ids);  // stops after kMaxTriangles
  return depth_upper_bound_among(sdf, c, ids, corners, n_corners, candidate, plane_normal, worst_corner, moments);
}

double depth_upper_bound_among(const SignedDistance& sdf, const Vec3& c, std::vector<std::uint32_t>& ids,
                               const Vec3* corners, int n_corners, Vec3* candidate, const Vec3* plane_normal,
                               int* worst_corner, TranslatedDepthBound* moments) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (moments) moments->n = 0;
  if (ids.empty()) return kInf;
  const TriangleMesh& m = sdf.mesh();
  std::size_t n = ids.size();
  // Per-thread scratch: this runs for every deep cell of every branch and bound.
  thread_local std::vector<Vec3> g, nearest, points;
  thread_local std::vector<std::pair<double, std::uint32_t>> order;
  g.resize(n);
  nearest.resize(n);
  points.resize(n);
  order.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Face& f = m.faces[ids[j]];
    points[j] = closest_point_on_triangle(c, m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]);
    order[j] = {(c - points[j]).squaredNorm(), static_cast<std::uint32_t>(j)};
  }
  // Nearest first (ties by id): the search below then prefers, among triangles of one face, the one
  // holding the projection, whose gradient is the exact face normal.
  std::sort(order.begin(), order.end(), [&](const auto& x, const auto& y) {
    return x.first < y.first || (x.first == y.first && ids[x.second] < ids[y.second]);
  });
  n = std::min(n, kMaxTriangles);
  g.resize(n);
  for (std::size_t j = 0; j < n; ++j) nearest[j] = points[order[j].second];
  for (std::size_t j = 0; j < n; ++j) order[j].second = ids[order[j].second];
  ids.resize(n);
  for (std::size_t j = 0; j < n; ++j) ids[j] = order[j].second;
  for (std::size_t j = 0; j < n; ++j) {
    const Vec3 v = c - nearest[j];
    const double len = v.norm();
    if (!(len > 0.0)) return kInf;
    g[j] = v / len;
  }
  // Weights near the min-norm point of conv{g_j} (heuristic: only tightness depends on them).
  thread_local std::vector<double> lambda;
  if (plane_normal)
    for (Vec3& x : g) x -= x.dot(*plane_normal) * *plane_normal;
  min_norm_combination(g, lambda, 100);
  if (candidate) {
    *candidate = Vec3::Zero();
    for (std::size_t j = 0; j < n; ++j) *candidate += lambda[j] * nearest[j];
  }
  double worst = 0.0;
  if (moments) moments->err = 0.0;
  const bool with_moments = moments && n_corners <= static_cast<int>(moments->corners.size());
  for (int corner = 0; corner < n_corners; ++corner) {
    const Vec3& v = corners[corner];
    double sum = 0.0, weights = 0.0;
    CornerMoments cm;
    for (std::size_t j = 0; j < n; ++j) {
      if (lambda[j] <= 0.0) continue;
      const Face& f = m.faces[ids[j]];
      const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &cc = m.vertices[f[2]];
      const Interval d2 = point_triangle_squared_distance(v, a, b, cc);
      sum += lambda[j] * round_up(std::sqrt(d2.hi));  // sqrt is correctly rounded: one ulp up bounds it
      weights += lambda[j];
      if (with_moments) {
        const Vec3 w = v - point_of_triangle_near(v, a, b, cc);
        cm.a += lambda[j] * w.squaredNorm();
        cm.w += lambda[j] * w;
        // q's distance to the triangle, and fl(v - q) within 2 u |w| (norm) of v - q.
        moments->err = std::max(moments->err, closest_point_error(a, b, cc) + 1e-15 * w.norm());
      }
    }
    if (with_moments && weights > 0.0) {
      cm.a /= weights;
      cm.w /= weights;
      moments->corners[moments->n++] = cm;
    }
    // Positive terms only: the relative rounding error of at most ~50 additions and one product each
    // is below 1e-13; the factor covers it with margin.
    const double bound = sum * (1.0 + 1e-12) / (weights * (1.0 - 1e-12));
    if (bound > worst || corner == 0) {
      worst = std::max(worst, bound);
      if (worst_corner) *worst_corner = corner;
    }
  }
  if (moments && moments->n != n_corners) moments->n = 0;  // every corner or none
  return round_up(worst);
}

}  // namespace cdbench
