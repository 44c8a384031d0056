#include "offset/fast_signed_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "core/interval.h"
#include "distance/point_triangle_distance.h"

namespace cdbench {
namespace {

struct FastNearest {
  const TriangleMesh& mesh;
  const std::vector<Vec3>& normal;  // unit face normals
  Vec3 p;
  double best_sq;
  std::uint32_t best_face;
  Vec3 best_point;
  int best_feature = 6;
  double bound(const Aabb& box) const { return squared_distance_lower_bound(box, p); }
  double prune_bound() const { return best_sq; }
  bool done() const { return false; }
  void leaf(std::uint32_t f) {
    const Face& t = mesh.faces[f];
    // A triangle is no nearer than its plane. Skipped only when the plane is beyond the best by a
    // margin far above the rounding of either distance, so that no tie or near-tie is decided by
    // the skip: the result stays independent of the warm start.
    const Vec3 w = p - mesh.vertices[t[0]];
    const double scale = p.cwiseAbs().maxCoeff() + mesh.vertices[t[0]].cwiseAbs().maxCoeff();
    const double plane = std::abs(normal[f].dot(w)) - 1e-12 * scale;
    if (plane > 0.0 && plane * plane > best_sq * (1.0 + 1e-9)) return;
    int feature = 6;
    const Vec3 q = closest_point_on_triangle(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]], &feature);
    const double d2 = (p - q).squaredNorm();
    // The minimum with ties to the smaller index, so that the result (down to the last bit, and
    // the sign's feature) does not depend on the warm start, i.e. on thread history: the mesher's
    // output must be reproducible.
    if (d2 < best_sq || (d2 == best_sq && f < best_face)) {
      best_sq = d2;
      best_face = f;
      best_point = q;
      best_feature = feature;
    }
  }
};

}  // namespace

FastSignedDistance::FastSignedDistance(const SignedDistance& exact) : exact_(exact) {
  const TriangleMesh& m = exact.mesh();
  face_normal_.resize(m.faces.size());
  vertex_normal_.assign(m.vertices.size(), Vec3::Zero());
  edge_normal_.resize(m.faces.size());
  std::map<std::pair<std::uint32_t, std::uint32_t>, Vec3> edge_sum;
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    const Face& t = m.faces[f];
    const Vec3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).normalized();
    face_normal_[f] = n;
    for (int k = 0; k < 3; ++k) {
      const Vec3 e1 = (m.vertices[t[(k + 1) % 3]] - m.vertices[t[k]]).normalized();
      const Vec3 e2 = (m.vertices[t[(k + 2) % 3]] - m.vertices[t[k]]).normalized();
      vertex_normal_[t[k]] += std::acos(std::clamp(e1.dot(e2), -1.0, 1.0)) * n;
      const auto key = std::minmax(t[k], t[(k + 1) % 3]);
      // try_emplace with an explicit zero: Eigen's default constructor leaves the vector uninitialised.
      edge_sum.try_emplace({key.first, key.second}, Vec3::Zero()).first->second += n;
    }
  }
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    const Face& t = m.faces[f];
    for (int k = 0; k < 3; ++k) {
      const auto key = std::minmax(t[k], t[(k + 1) % 3]);
      edge_normal_[f][k] = edge_sum[{key.first, key.second}];
    }
  }
}

double FastSignedDistance::operator()(const Vec3& p) const {
  Vec3 unused;
  return value_and_gradient(p, unused);
}

double FastSignedDistance::value_and_gradient(const Vec3& p, Vec3& gradient) const {
  const TriangleMesh& m = exact_.mesh();
  // Warm start from this thread's previous nearest face: consecutive mesher queries are close.
  thread_local const FastSignedDistance* owner = nullptr;
  thread_local std::uint32_t hint = 0;
  if (owner != this || hint >= m.faces.size()) {
    owner = this;
    hint = 0;
  }
  FastNearest q{m, face_normal_, p, std::numeric_limits<double>::infinity(), hint, p};
  q.leaf(hint);
  // Prune with a bound one ulp above the hint's distance: every triangle at least as near as the
  // hint is still visited (node bounds are rounded down), so the tie-break above decides.
  q.best_sq = round_up(q.best_sq);
  q.best_face = std::numeric_limits<std::uint32_t>::max();
  traverse_nearest_first(exact_.tree(), q);
  hint = q.best_face;
  const Vec3 diff = p - q.best_point;
  const double dist = diff.norm();
  const Face& t = m.faces[q.best_face];
  Vec3 normal;
  if (q.best_feature == 6) normal = face_normal_[q.best_face];
  else if (q.best_feature < 3) normal = vertex_normal_[t[q.best_feature]];
  else normal = edge_normal_[q.best_face][q.best_feature - 3];
  // Outside the bounding box of a closed surface is outside the solid. Far out every triangle is
  // nearest within rounding, and the winning feature's pseudo-normal may point either way.
  const Aabb& box = exact_.bbox();
  const bool outside_box = (p.array() < box.lo.array()).any() || (p.array() > box.hi.array()).any();
  const double sign = !outside_box && diff.dot(normal) < 0 ? -1.0 : 1.0;
  gradient = dist > 0 ? Vec3(sign * diff / dist) : Vec3(normal.normalized());
  return sign * dist;
}

namespace {

// Bisection of the segment from a (fast - d of the sign of fa) to b (the other sign) down to
// adjacent doubles; the end on b's side.
Vec3 bisect_to_level(const FastSignedDistance& fast, double d, Vec3 a, Vec3 b, double fa) {
  for (int it = 0; it < 200; ++it) {
    const Vec3 m = 0.5 * (a + b);
    if (m == a || m == b) break;
    ((fast(m) - d < 0) == (fa < 0) ? a : b) = m;
  }
  return b;
}

}  // namespace

bool point_on_level_near(const FastSignedDistance& fast, double d, const Vec3& x, Vec3& on) {
  Vec3 g;
  const double fx = fast.value_and_gradient(x, g) - d;
  for (double scale : {1.5, 3.0, 6.0}) {
    const Vec3 y = x - scale * fx * g;
    const double fy = fast(y) - d;
    if ((fx < 0) == (fy < 0)) continue;
    on = bisect_to_level(fast, d, x, y, fx);
    return true;
  }
  return false;
}

bool point_on_level_close(const FastSignedDistance& fast, double d, const Vec3& x, Vec3& on, int max_doublings) {
  if (point_on_level_near(fast, d, x, on)) return true;
  std::vector<Vec3> ring;
  points_on_level_around(fast, d, x, ring, max_doublings);
  if (ring.empty()) return false;
  // The first of equally near points, so that the choice does not depend on anything but x.
  on = *std::min_element(ring.begin(), ring.end(),
                         [&](const Vec3& p, const Vec3& q) { return (p - x).squaredNorm() < (q - x).squaredNorm(); });
  return true;
}

bool point_on_level_along(const FastSignedDistance& fast, double d, const Vec3& x, const Vec3& u, double max_length,
                          Vec3& on) {
  const double fx = fast(x) - d;
  if (!std::isfinite(fx)) return false;
  if (fx == 0.0) {
    on = x;
    return true;
  }
  Vec3 last = x;
  double t = 0.0, ft = fx;
  for (int it = 0; it < 100; ++it) {
    t += 1.5 * std::abs(ft);
    if (!(t <= max_length)) return false;
    const Vec3 y = x + t * u;
    ft = fast(y) - d;
    if ((ft < 0) != (fx < 0)) {
      on = bisect_to_level(fast, d, last, y, fx);
      return true;
    }
    last = y;
  }
  return false;
}

bool point_on_crease_across(const FastSignedDistance& fast, double d, const Vec3& a, const Vec3& b, Vec3& on,
                            double crease_cos) {
  Vec3 ga, gb;
  fast.value_and_gradient(a, ga);
  fast.value_and_gradient(b, gb);
  if (!(ga.dot(gb) < crease_cos)) return false;
  Vec3 u = ga + gb;
  const double len = u.norm();
  if (!(len > 1e-3)) return false;
  u /= len;
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 40; ++it) {
    const double t = 0.5 * (lo + hi);
    Vec3 g;
    fast.value_and_gradient(a + t * (b - a), g);
    (g.dot(ga) >= g.dot(gb) ? lo : hi) = t;
  }
  const Vec3 m = a + (0.5 * (lo + hi)) * (b - a);
  // fast grows along both gradients: towards the level from a point below it, away from above.
  const double fm = fast(m) - d;
  return point_on_level_along(fast, d, m, fm < 0 ? u : Vec3(-u), (b - a).norm(), on);
}

void points_on_level_around(const FastSignedDistance& fast, double d, const Vec3& x, std::vector<Vec3>& out,
                            int max_doublings) {
  const double fx = fast(x) - d;
  if (!(fx != 0.0) || !std::isfinite(fx)) return;
  for (int k = 0; k < 14; ++k) {
    Vec3 u = Vec3::Zero();
    if (k < 6) u[k / 2] = k % 2 ? -1.0 : 1.0;
    else u = Vec3(k & 1 ? -1.0 : 1.0, k & 2 ? -1.0 : 1.0, k & 4 ? -1.0 : 1.0).normalized();
    for (int j = 1; j <= max_doublings; ++j) {
      const Vec3 y = x + std::ldexp(std::abs(fx), j) * u;
      if ((fast(y) - d < 0) == (fx < 0)) continue;
      out.push_back(bisect_to_level(fast, d, x, y, fx));
      break;
    }
  }
}

}  // namespace cdbench
