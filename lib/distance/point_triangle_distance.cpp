#include "distance/point_triangle_distance.h"

#include <CGAL/Interval_nt.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace cdbench {
namespace {

using I = CGAL::Interval_nt<false>;  // needs the rounding mode set upward (done by the caller's guard)

struct V {
  I x, y, z;
};
inline V vec(const Vec3& p) { return {I(p.x()), I(p.y()), I(p.z())}; }
inline V sub(const V& a, const V& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline I dot(const V& a, const V& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V cross(const V& a, const V& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline I norm2(const V& a) { return CGAL::square(a.x) + CGAL::square(a.y) + CGAL::square(a.z); }

// Squared distance from p to segment uv. The distance to the supporting line is always a lower
// bound and each endpoint distance an upper bound; where the sign of the projection parameter is
// certain, the exact case applies.
Interval segment(const V& p, const V& u, const V& v) {
  const V f = sub(v, u), g = sub(p, u), h = sub(p, v);
  const I ff = norm2(f), gf = dot(g, f), gg = norm2(g), hh = norm2(h);
  if (gf.sup() <= 0.0) return {gg.inf(), gg.sup()};            // projection before u
  if (gf.inf() >= ff.sup()) return {hh.inf(), hh.sup()};       // projection after v
  const double ends = std::min(gg.sup(), hh.sup());
  if (!(ff.inf() > 0.0)) return {std::min(gg.inf(), hh.inf()), ends};
  const I line = norm2(cross(g, f)) / ff;
  if (gf.inf() > 0.0 && gf.sup() < ff.inf()) return {line.inf(), std::min(line.sup(), ends)};
  return {line.inf(), ends};
}

}  // namespace

double point_triangle_distance_lower_bound(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& u) {
  // Each s_k = sum_i fl(v_i - p_i) u_i is within 6u T_k of the exact (v - p).u, T_k the sum of the
  // absolute terms (gamma_3 for the sum of products, u for the differences; doubled for directed
  // rounding): 2e-15 T_k covers it with margin.
  double lo = std::numeric_limits<double>::infinity();
  for (const Vec3* v : {&a, &b, &c}) {
    const double d0 = (*v)[0] - p[0], d1 = (*v)[1] - p[1], d2 = (*v)[2] - p[2];
    const double s = d0 * u[0] + d1 * u[1] + d2 * u[2];
    const double t = std::abs(d0 * u[0]) + std::abs(d1 * u[1]) + std::abs(d2 * u[2]);
    lo = std::min(lo, s - 2e-15 * t - 1e-300);  // (and any underflow)
  }
  if (!(lo > 0.0)) return 0.0;
  const double len = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) * (1.0 + 2e-15);
  return lo / len * (1.0 - 2e-15);
}

TrianglePlane make_triangle_plane(const Vec3& a, const Vec3& b, const Vec3& c) {
  TrianglePlane pl;
  const Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  if (!(len > 0.0) || !std::isfinite(len)) {
    pl.eps = std::numeric_limits<double>::infinity();
    return pl;
  }
  pl.n = n / len;  // any direction is valid; the closer to the true normal, the tighter
  pl.d = pl.n.dot(a);
  double eps = 0.0;
  for (const Vec3* v : {&a, &b, &c}) {
    const PlaneOffset o = plane_offset(pl.n, pl.d, *v);  // |exact n.v - d| <= |value| + error
    eps = std::max(eps, std::abs(o.value) + o.error);
  }
  pl.eps = eps * (1.0 + 2e-15) + 1e-300;
  pl.norm_up = std::sqrt(pl.n.squaredNorm()) * (1.0 + 4e-15);
  return pl;
}

Interval point_triangle_squared_distance(const Vec3& pd, const Vec3& ad, const Vec3& bd, const Vec3& cd) {
  CGAL::Protect_FPU_rounding<true> guard;  // round upward for the interval operations below
  const V p = vec(pd), a = vec(ad), b = vec(bd), c = vec(cd);
  const V n = cross(sub(b, a), sub(c, a));
  const I nn = norm2(n);
  const auto edges = [&](bool e0, bool e1, bool e2, double* lo, double* hi) {
    *lo = *hi = std::numeric_limits<double>::infinity();
    const auto take = [&](const Interval& e) {
      *lo = std::min(*lo, e.lo);
      *hi = std::min(*hi, e.hi);
    };
    if (e0) take(segment(p, a, b));
    if (e1) take(segment(p, b, c));
    if (e2) take(segment(p, c, a));
  };
  double edges_lo, edges_hi;
  if (!(nn.inf() > 0.0)) {  // degenerate: the triangle is its edges
    edges(true, true, true, &edges_lo, &edges_hi);
    return {edges_lo, edges_hi};
  }
  const I plane = CGAL::square(dot(n, sub(p, a))) / nn;
  // Signs of the projection against each edge's inner side (all >= 0: projection inside).
  const I s0 = dot(n, cross(sub(b, a), sub(p, a)));
  const I s1 = dot(n, cross(sub(c, b), sub(p, b)));
  const I s2 = dot(n, cross(sub(a, c), sub(p, c)));
  // Projection inside: the distance is the plane's.
  if (s0.inf() >= 0.0 && s1.inf() >= 0.0 && s2.inf() >= 0.0) return {plane.inf(), plane.sup()};
  if (s0.sup() < 0.0 || s1.sup() < 0.0 || s2.sup() < 0.0) {
    // Projection outside: the nearest point lies on an edge whose outer side holds the projection
    // (the in-plane vector from the nearest point to the projection is an outward normal there),
    // so only edges with a possibly negative sign are needed.
    edges(s0.inf() < 0.0, s1.inf() < 0.0, s2.inf() < 0.0, &edges_lo, &edges_hi);
    return {std::max(edges_lo, plane.inf()), edges_hi};
  }
  // Projection within rounding of the boundary: the plane distance is a lower bound, edges an upper.
  edges(true, true, true, &edges_lo, &edges_hi);
  return {plane.inf(), edges_hi};
}

namespace {

// The square root of x rounded down (up = false) or up, without changing the rounding mode: s =
// sqrt(x) is correctly rounded in the current mode (IEEE 754), so within one ulp of the root, and
// the sign of the exact residual s^2 - x (one fma, whose rounding keeps a nonzero value's sign as
// long as it does not underflow) says on which side of the root s lies; the neighbour of s is on
// the other side. For x in [2^-600, 2^600] a nonzero residual is at least 2^-704 in magnitude (a
// multiple of ulp(s)^2), far from underflow; 0 is exact; other x take CGAL's interval square root.
// The same doubles as CGAL::sqrt on Interval_nt (which switches the rounding mode four times):
// test_distance's SqrtInterval.* compare the two.
bool directed_sqrt(double x, bool up, double* out) {
  if (x == 0.0) {
    *out = 0.0;
    return true;
  }
  if (!(x >= 0x1p-600 && x <= 0x1p600)) return false;
  const double s = std::sqrt(x);
  const double r = std::fma(s, s, -x);
  *out = up ? (r < 0.0 ? round_up(s) : s) : (r > 0.0 ? round_down(s) : s);
  return true;
}

}  // namespace

Interval sqrt_interval(const Interval& squared) {
  const double lo = std::max(0.0, squared.lo), hi = std::max(0.0, squared.hi);
  Interval out;
  if (directed_sqrt(lo, false, &out.lo) && directed_sqrt(hi, true, &out.hi)) return out;
  CGAL::Protect_FPU_rounding<true> guard;
  const I s = CGAL::sqrt(I(lo, hi));
  return {s.inf(), s.sup()};
}

}  // namespace cdbench

namespace cdbench {

namespace {

// Ericson's region test; `bary` receives the closest point's (beta, gamma) with respect to (a, b, c).
Vec3 closest_point(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int& f, std::array<double, 2>& bary) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) { f = 0; bary = {0.0, 0.0}; return a; }
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) { f = 1; bary = {1.0, 0.0}; return b; }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    f = 3;
    const double t = d1 / (d1 - d3);
    bary = {t, 0.0};
    return a + t * ab;
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) { f = 2; bary = {0.0, 1.0}; return c; }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    f = 5;
    const double t = d2 / (d2 - d6);
    bary = {0.0, t};
    return a + t * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    f = 4;
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    bary = {1.0 - t, t};
    return b + t * (c - b);
  }
  f = 6;
  const double denom = 1.0 / (va + vb + vc);
  bary = {vb * denom, vc * denom};
  return a + ab * bary[0] + ac * bary[1];
}

}  // namespace

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int* feature) {
  int unused;
  std::array<double, 2> bary;
  return closest_point(p, a, b, c, feature ? *feature : unused, bary);
}

Vec3 point_of_triangle_near(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  int f;
  std::array<double, 2> bary;
  closest_point(p, a, b, c, f, bary);
  // NaN-safe clamps: beta in [0, 1], then gamma in [0, 1 - beta] with 1 - beta rounded down (inline:
  // std::nextafter's library call was 1.6 % of a penetrating level's instructions).
  const double beta = bary[0] >= 0.0 ? std::min(bary[0], 1.0) : 0.0;
  double gamma = bary[1] >= 0.0 ? std::min(bary[1], round_down(1.0 - beta)) : 0.0;
  if (!(gamma >= 0.0)) gamma = 0.0;
  return a + beta * (b - a) + gamma * (c - a);
}

double point_triangle_distance_upper_near(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3* near) {
  const Vec3 q = point_of_triangle_near(p, a, b, c);
  if (near) *near = q;
  const double d = (p - q).norm();
  return round_up(round_up(d * (1.0 + 1e-14)) + closest_point_error(a, b, c));
}

double closest_point_error(const Vec3& a, const Vec3& b, const Vec3& c) {
  // q = fl(fl(a + fl(beta fl(b - a))) + fl(gamma fl(c - a))), each rounding at most v = 2u relative
  // in any rounding mode (u = 2^-53); beta, gamma in [0, 1], so |b - a|, |c - a| <= 2M and the
  // partial sums a + beta (b - a) and q lie in the triangle (<= M) per coordinate: each product is
  // within 4.0002 v M, the first sum within 5.0003 v M, q within 10.001 v M = 20.002 u M of the
  // exact point per coordinate, 34.7 u M = 3.9e-15 M in norm. 2e-14 M covers it five times (it
  // was 1e-13 M until session 69: at 10^7 from the origin that alone was 10^-6, wider than the
  // default tolerance of a unit part there, and the certificates split to their cell budget).
  const double m = std::max({a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff(), c.cwiseAbs().maxCoeff()});
  return 2e-14 * m + 1e-300;
}

Vec3 min_norm_combination(const std::vector<Vec3>& g, std::vector<double>& lambda, int iterations, double gap) {
  lambda.assign(g.size(), 0.0);
  if (g.empty()) return Vec3::Zero();
  lambda[0] = 1.0;
  Vec3 x = g[0];
  for (int it = 0; it < iterations; ++it) {
    std::size_t k = 0;
    for (std::size_t j = 1; j < g.size(); ++j)
      if (g[j].dot(x) < g[k].dot(x)) k = j;
    const Vec3 d = x - g[k];
    const double dd = d.squaredNorm();
    if (!(x.dot(d) > gap) || !(dd > 0.0)) break;
    const double step = std::min(1.0, x.dot(d) / dd);
    x -= step * d;
    for (double& l : lambda) l *= 1.0 - step;
    lambda[k] += step;
  }
  return x;
}

}  // namespace cdbench
