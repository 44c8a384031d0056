#include "distance/triangle_distance.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interval_nt.h>

#include <algorithm>

#include "distance/point_triangle_distance.h"

namespace cdbench {
namespace {

using I = CGAL::Interval_nt<false>;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

struct V {
  I x, y, z;
};
inline V vec(const Vec3& p) { return {I(p.x()), I(p.y()), I(p.z())}; }
inline V sub(const V& a, const V& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline I dot(const V& a, const V& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V cross(const V& a, const V& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

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
  const auto P = [](const Vec3& v) { return K::Point_3(v.x(), v.y(), v.z()); };
  const K::Triangle_3 t1(P(a), P(b), P(c)), t2(P(d), P(e), P(f));
  if (!t1.is_degenerate() && !t2.is_degenerate() && CGAL::do_intersect(t1, t2)) return {0.0, 0.0};
  Interval r{HUGE_VAL, HUGE_VAL};
  for (const Vec3* p : {&a, &b, &c}) take(r, point_triangle_squared_distance(*p, d, e, f));
  for (const Vec3* p : {&d, &e, &f}) take(r, point_triangle_squared_distance(*p, a, b, c));
  const Vec3* s1[3][2] = {{&a, &b}, {&b, &c}, {&c, &a}};
  const Vec3* s2[3][2] = {{&d, &e}, {&e, &f}, {&f, &d}};
  for (auto& x : s1)
    for (auto& y : s2) take(r, segment_segment_squared_distance(*x[0], *x[1], *y[0], *y[1]));
  // A zero-area triangle may cross the other's interior without any of the pairs above seeing it:
  // no positive lower bound is claimed then.
  if (t1.is_degenerate() || t2.is_degenerate()) r.lo = 0.0;
  return r;
}

}  // namespace cdbench
