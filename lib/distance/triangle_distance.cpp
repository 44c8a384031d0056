#include "distance/triangle_distance.h"

#include <CGAL/Interval_nt.h>

#include <algorithm>
#include <limits>

#include "distance/exact_predicates.h"
#include "distance/point_triangle_distance.h"

namespace cdbench {
namespace {

using I = CGAL::Interval_nt<false>;

struct V {
  I x, y, z;
};
inline V vec(const Vec3& p) { return {I(p.x()), I(p.y()), I(p.z())}; }
inline V sub(const V& a, const V& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline I dot(const V& a, const V& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V cross(const V& a, const V& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

// Lower bounds of the gaps between the projections of abc and def on U: def above abc (min def -
// max abc) and def below it (min abc - max def); at most one is positive. Under upward rounding,
// -(y - x) is x - y rounded down.
struct ProjectionGaps {
  double up, down;
};
ProjectionGaps projection_gaps(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e,
                               const Vec3& f, const V& U) {
  const I pa = dot(vec(a), U), pb = dot(vec(b), U), pc = dot(vec(c), U);
  const I pd = dot(vec(d), U), pe = dot(vec(e), U), pf = dot(vec(f), U);
  return {-(std::max({pa.sup(), pb.sup(), pc.sup()}) - std::min({pd.inf(), pe.inf(), pf.inf()})),
          -(std::max({pd.sup(), pe.sup(), pf.sup()}) - std::min({pa.inf(), pb.inf(), pc.inf()}))};
}

inline void take(Interval& acc, const Interval& x) {
  acc.lo = std::min(acc.lo, x.lo);
  acc.hi = std::min(acc.hi, x.hi);
}

}  // namespace

Interval segment_segment_squared_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  // The minimum is at an endpoint (point-segment distances, a segment being a degenerate triangle)
  // or at the lines' common perpendicular when its feet lie inside both segments.
  Interval r{HUGE_VAL, HUGE_VAL};
  take(r, point_triangle_squared_distance(p0, q0, q1, q1));
  take(r, point_triangle_squared_distance(p1, q0, q1, q1));
  take(r, point_triangle_squared_distance(q0, p0, p1, p1));
  take(r, point_triangle_squared_distance(q1, p0, p1, p1));
  CGAL::Protect_FPU_rounding<true> guard;
  const V P0 = vec(p0), Q0 = vec(q0);
  const V u = sub(vec(p1), P0), v = sub(vec(q1), Q0), w = sub(Q0, P0);
  const V n = cross(u, v);
  const I nn = dot(n, n);
  if (!(nn.inf() > 0.0)) return r;  // (nearly) parallel: the endpoint cases hold the minimum
  const I s = dot(cross(w, v), n) / nn, t = dot(cross(w, u), n) / nn;
  const bool maybe_inside = s.sup() >= 0.0 && s.inf() <= 1.0 && t.sup() >= 0.0 && t.inf() <= 1.0;
  if (!maybe_inside) return r;
  const I line = CGAL::square(dot(w, n)) / nn;  // never more than the segment distance
  r.lo = std::min(r.lo, line.inf());
  const bool surely_inside = s.inf() >= 0.0 && s.sup() <= 1.0 && t.inf() >= 0.0 && t.sup() <= 1.0;
  if (surely_inside) r.hi = std::min(r.hi, line.sup());
  return r;
}

Interval triangle_triangle_squared_distance(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                            const Vec3& e, const Vec3& f) {
  if (triangles_intersect(a, b, c, d, e, f)) return {0.0, 0.0};
  Interval r{HUGE_VAL, HUGE_VAL};
  for (const Vec3* p : {&a, &b, &c}) take(r, point_triangle_squared_distance(*p, d, e, f));
  for (const Vec3* p : {&d, &e, &f}) take(r, point_triangle_squared_distance(*p, a, b, c));
  const Vec3* s1[3][2] = {{&a, &b}, {&b, &c}, {&c, &a}};
  const Vec3* s2[3][2] = {{&d, &e}, {&e, &f}, {&f, &d}};
  for (auto& x : s1)
    for (auto& y : s2) take(r, segment_segment_squared_distance(*x[0], *x[1], *y[0], *y[1]));
  // No positive lower bound is claimed for a zero-area triangle. The vertex and edge pairs alone
  // miss a segment through the other's interior; the exact test above now rules that out, but the
  // bound stays as conservative as it was.
  if (corners_collinear(a, b, c) || corners_collinear(d, e, f)) r.lo = 0.0;
  return r;
}

namespace {

// Closest points of segments p0p1 and q0q1 in doubles (clamped parameters).
double segment_closest(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, Vec3* cp, Vec3* cq) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 0.0 && e <= 0.0) {
    s = t = 0.0;
  } else if (a <= 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  *cp = p0 + s * d1;
  *cq = q0 + t * d2;
  return (*cp - *cq).squaredNorm();
}

}  // namespace

double triangle_triangle_closest_points(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e,
                                        const Vec3& f, Vec3* p, Vec3* q) {
  double best = HUGE_VAL;
  const auto offer = [&](const Vec3& x, const Vec3& y) {
    const double d2 = (x - y).squaredNorm();
    if (d2 < best) {
      best = d2;
      *p = x;
      *q = y;
    }
  };
  for (const Vec3* v : {&d, &e, &f}) offer(closest_point_on_triangle(*v, a, b, c), *v);
  for (const Vec3* v : {&a, &b, &c}) offer(*v, closest_point_on_triangle(*v, d, e, f));
  const Vec3* s1[3][2] = {{&a, &b}, {&b, &c}, {&c, &a}};
  const Vec3* s2[3][2] = {{&d, &e}, {&e, &f}, {&f, &d}};
  for (auto& x : s1)
    for (auto& y : s2) {
      Vec3 cp, cq;
      segment_closest(*x[0], *x[1], *y[0], *y[1], &cp, &cq);
      offer(cp, cq);
    }
  return best;
}

double triangle_distance_lower_bound(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e,
                                     const Vec3& f, const Vec3& u) {
  CGAL::Protect_FPU_rounding<true> guard;
  const V U = vec(u);
  const ProjectionGaps g = projection_gaps(a, b, c, d, e, f, U);
  const double gap = std::max(g.up, g.down);
  if (!(gap > 0.0)) return 0.0;
  const I len = CGAL::sqrt(dot(U, U));
  // gap / |u| rounded down: divide the negated value under upward rounding.
  return -((-gap) / len.sup());
}

double triangle_reach_time_lower_bound(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e,
                                       const Vec3& f, const Vec3& u, const Vec3& v, double r) {
  CGAL::Protect_FPU_rounding<true> guard;
  const V U = vec(u);
  // def above abc along u: that gap shrinks at the rate -u.v; def below abc: at the rate u.v.
  const ProjectionGaps g = projection_gaps(a, b, c, d, e, f, U);
  const bool up = g.up > 0.0;
  if (!up && !(g.down > 0.0)) return 0.0;
  const I uv = dot(U, vec(v));
  const I len = CGAL::sqrt(dot(U, U));
  const I room = I(up ? g.up : g.down) - I(r) * len;  // gap left before the distance can reach r
  if (!(room.inf() > 0.0)) return 0.0;
  const I rate = up ? -uv : uv;  // how fast that gap shrinks per unit of s
  if (!(rate.sup() > 0.0)) return std::numeric_limits<double>::infinity();
  // room / rate rounded down: the negated quotient of the lower room and the upper rate, rounded up.
  return -((-room.inf()) / I(rate.sup())).sup();
}

}  // namespace cdbench
