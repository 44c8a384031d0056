#pragma once
// Rigorous enclosure of the distance between a point and a triangle, in interval arithmetic with
// outward rounding (CGAL::Interval_nt). See doc/distance.md for the case analysis.
#include "core/aabb.h"
#include "core/interval.h"
#include "core/triangle_mesh.h"

#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace cdbench {

// [lo, hi] containing the exact squared Euclidean distance from p to the closed triangle abc
// (a degenerate triangle is treated as the union of its edges).
Interval point_triangle_squared_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// A certified upper bound of the distance from p to abc: the enclosure's upper end, its square root
// (correctly rounded, or rounded up under the upward mode) one ulp up.
inline double point_triangle_distance_upper(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return round_up(std::sqrt(point_triangle_squared_distance(p, a, b, c).hi));
}

// The same for triangle `face` of mesh m.
inline double point_triangle_distance_upper(const Vec3& p, const TriangleMesh& m, std::uint32_t face) {
  const Face& f = m.faces[face];
  return point_triangle_distance_upper(p, m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]);
}

// A certified upper bound of the distance from p to abc in plain doubles, about a quarter of the
// enclosure's cost: |p - q| for q = point_of_triangle_near(p, a, b, c) (a point of the triangle up
// to closest_point_error), with the norm's rounding (a few roundings of at most 2 u each, any
// rounding mode) covered by 1e-14 relative and that error added. At most about 1e-13 max|coordinate|
// above the enclosure's bound. For the depth bounds and clips evaluated at many corners
// (doc/distance.md, "Near-point upper bounds").
// near (optional) receives that q, for a caller that needs it too.
double point_triangle_distance_upper_near(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                          Vec3* near = nullptr);
inline double point_triangle_distance_upper_near(const Vec3& p, const TriangleMesh& m, std::uint32_t face) {
  const Face& f = m.faces[face];
  return point_triangle_distance_upper_near(p, m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]);
}

// A certified upper bound of the largest distance from the points to triangle `face` of m (the
// largest of point_triangle_distance_upper_near, 0 for none). The distance to one triangle is
// convex, so this bounds it over the points' convex hull too, and with it the depth of every hull
// point inside m's solid (the convexity bound of doc/poses.md with one triangle).
inline double max_distance_upper_near(const Vec3* points, int n, const TriangleMesh& m, std::uint32_t face) {
  const Face& f = m.faces[face];
  const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
  double worst = 0.0;
  for (int k = 0; k < n; ++k) worst = std::max(worst, point_triangle_distance_upper_near(points[k], a, b, c));
  return worst;
}

// A rigorous lower bound of the distance from p to abc from any direction u != 0: the triangle lies
// in the half-space {x : (x - p).u >= min_k (v_k - p).u} (a linear function on a triangle is least
// at a vertex), so the distance is at least that minimum over |u| when it is positive (else 0).
// Tight when u points from p to the triangle's closest point. Plain doubles with an explicit error
// bound (valid in any rounding mode): about a third of the certified enclosure's cost.
double point_triangle_distance_lower_bound(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& u);

// A triangle's plane stored once, for the cheapest rigorous lower bound of dist(p, abc): the
// distance to the stored plane {x : n.x = d} less `eps`, a bound of |n.v - d| at the three vertices
// (hence on the whole triangle, n.x - d being affine), divided by |n| rounded up. Degenerate
// triangles get eps = +inf (the bound is then 0). Used to skip a triangle before its closest point
// is estimated: most triangles a deep query visits lie far off their own plane's distance.
struct TrianglePlane {
  Vec3 n = Vec3::Zero();  // about unit
  double d = 0.0;
  double eps = 0.0;
  double norm_up = 1.0;  // >= |n| (exact)
};
TrianglePlane make_triangle_plane(const Vec3& a, const Vec3& b, const Vec3& c);

// n.p - d in plain doubles and a bound of its error against the exact value of the same
// expression, valid in any rounding mode: the value is within gamma_4 T of the exact one (T the sum
// of the absolute terms; doubled for directed rounding), and 2e-15 T covers it with margin.
struct PlaneOffset {
  double value, error;
};
inline PlaneOffset plane_offset(const Vec3& n, double d, const Vec3& p) {
  const double t0 = n[0] * p[0], t1 = n[1] * p[1], t2 = n[2] * p[2];
  return {t0 + t1 + t2 - d, 2e-15 * (std::abs(t0) + std::abs(t1) + std::abs(t2) + std::abs(d))};
}

// Plain doubles with an explicit error bound (any rounding mode), like the slab bound below.
inline double plane_distance_lower_bound(const TrianglePlane& pl, const Vec3& p) {
  const PlaneOffset o = plane_offset(pl.n, pl.d, p);
  const double lo = std::abs(o.value) - o.error - pl.eps - 1e-300;
  return lo > 0.0 ? lo / pl.norm_up * (1.0 - 2e-15) : 0.0;
}

// The least of n.v - d (above) and of d - n.v (below) over x, y, z, each lowered by its error.
struct PlaneMargins {
  double above, below;
};
inline PlaneMargins plane_margins(const TrianglePlane& pl, const Vec3& x, const Vec3& y, const Vec3& z) {
  PlaneMargins m{HUGE_VAL, HUGE_VAL};
  for (const Vec3* v : {&x, &y, &z}) {
    const PlaneOffset o = plane_offset(pl.n, pl.d, *v);
    const double err = o.error + 1e-300;
    m.above = std::min(m.above, o.value - err);
    m.below = std::min(m.below, -o.value - err);
  }
  return m;
}

// The same bound for a second triangle xyz against the plane's triangle: when xyz lies strictly on
// one side (every vertex's n.v - d, less its error, beyond eps), n.(x - y) for x in xyz and y in the
// plane's triangle is at least that least margin (n.x - d is affine: least at a vertex), so the
// two triangles are at least (margin - eps) / |n| apart. 0 when they straddle.
inline double plane_pair_lower_bound(const TrianglePlane& pl, const Vec3& x, const Vec3& y, const Vec3& z) {
  const PlaneMargins m = plane_margins(pl, x, y, z);
  const double lo = std::max(m.above, m.below) - pl.eps;
  return lo > 0.0 ? lo / pl.norm_up * (1.0 - 2e-15) : 0.0;
}

// The box's corners least and greatest along u: u.x over the box lies between their values.
inline std::array<Vec3, 2> extreme_corners(const Vec3& u, const Aabb& b) {
  std::array<Vec3, 2> c;
  for (int k = 0; k < 3; ++k) {
    const bool pos = u[k] >= 0.0;
    c[0][k] = pos ? b.lo[k] : b.hi[k];
    c[1][k] = pos ? b.hi[k] : b.lo[k];
  }
  return c;
}

// A lower bound of the distance between a box and the plane's triangle (0 when nothing is proved):
// the pair margin of the box's corners extreme along n bounds every point of the box. Any rounding
// mode.
inline double box_plane_lower_bound(const TrianglePlane& pl, const Aabb& b) {
  const auto [lo, hi] = extreme_corners(pl.n, b);
  return plane_pair_lower_bound(pl, lo, hi, hi);
}

// The range of u.x over a box or a triangle (u any direction), each end moved outwards by its
// error bound and rounded outwards: it holds the exact range. Any rounding mode. (A box's range is
// at its corners extreme along u, a triangle's at its vertices.)
struct AxisExtent {
  double lo, hi;
};
inline AxisExtent box_extent(const Vec3& u, const Aabb& b) {
  const auto [lo, hi] = extreme_corners(u, b);
  const PlaneOffset bl = plane_offset(u, 0.0, lo), bh = plane_offset(u, 0.0, hi);
  return {round_down(bl.value - bl.error), round_up(bh.value + bh.error)};
}
inline AxisExtent triangle_extent(const Vec3& u, const Vec3& a, const Vec3& b, const Vec3& c) {
  AxisExtent e{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const Vec3* x : {&a, &b, &c}) {
    const PlaneOffset v = plane_offset(u, 0.0, *x);
    e.lo = std::min(e.lo, round_down(v.value - v.error));
    e.hi = std::max(e.hi, round_up(v.value + v.error));
  }
  return e;
}

// A separating axis for boxes against a fixed triangle t: its extent along u (any direction) and
// |u| rounded up, computed once.
struct AxisRange {
  Vec3 u = Vec3::Zero();
  AxisExtent t{0.0, 0.0};
  double norm_up = 1.0;
};
inline AxisRange triangle_axis_range(const Vec3& u, const std::array<Vec3, 3>& t) {
  return {u, triangle_extent(u, t[0], t[1], t[2]), std::sqrt(u.squaredNorm()) * (1.0 + 4e-15) + 1e-300};
}
// A lower bound of the distance between a set whose extent along a.u is e and that triangle, from
// the gap between the extents (0 when they overlap there). Any rounding mode.
inline double axis_gap_lower_bound(const AxisRange& a, const AxisExtent& e) {
  const double gap = std::max(e.lo - a.t.hi, a.t.lo - e.hi);
  return gap > 0.0 ? gap / a.norm_up * (1.0 - 4e-15) : 0.0;
}
// The same for a box.
inline double box_axis_gap_lower_bound(const AxisRange& a, const Aabb& b) {
  return axis_gap_lower_bound(a, box_extent(a.u, b));
}

// The longest edge of abc as a vector (either direction).
inline Vec3 longest_edge(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e0 = b - a, e1 = c - b, e2 = a - c;
  const double l0 = e0.squaredNorm(), l1 = e1.squaredNorm(), l2 = e2.squaredNorm();
  return l0 >= l1 && l0 >= l2 ? e0 : (l1 >= l2 ? e1 : e2);
}

// The same gap along the axis across both triangles' longest edges (ev: xyz's, longest_edge): two
// long slivers crossing at a distance, each cutting the other's plane and side slabs (a finely
// faceted tube's wall against a tilted copy's) are told apart on it, and seldom on any other of the
// separating axes. 0 when the edges are near parallel (the axis then says little) or not finite.
inline double long_edges_gap(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& x, const Vec3& y, const Vec3& z,
                             const Vec3& ev) {
  const Vec3 ef = longest_edge(a, b, c);
  const Vec3 u = ef.cross(ev);
  const double u2 = u.squaredNorm();
  if (!(u2 > 1e-24 * ef.squaredNorm() * ev.squaredNorm()) || !std::isfinite(u2)) return 0.0;
  return axis_gap_lower_bound(triangle_axis_range(u, {x, y, z}), triangle_extent(u, a, b, c));
}

// The same margin as a reach time: xyz moved by s v stays more than r from the plane's triangle
// while s < (margin - eps - r |n|) / (its approach rate along n): n.x - d changes by s n.v at every
// point. 0 when nothing is proved (xyz straddles, or is within r), +inf when it certainly recedes.
// Any rounding mode (explicit error terms, as above).
inline double plane_pair_reach_time_lower_bound(const TrianglePlane& pl, const Vec3& x, const Vec3& y, const Vec3& z,
                                                const Vec3& v, double r) {
  const auto [above, below] = plane_margins(pl, x, y, z);
  const bool up = above > below;
  const double reach = r * pl.norm_up * (1.0 + 1e-15);
  const double room = (up ? above : below) - pl.eps - reach;
  const double room_lo = room - 1e-15 * (std::abs(above) + std::abs(below) + pl.eps + reach) - 1e-300;
  if (!(room_lo > 0.0)) return 0.0;
  const double t0 = pl.n[0] * v[0], t1 = pl.n[1] * v[1], t2 = pl.n[2] * v[2];
  const double nv = t0 + t1 + t2;
  const double rate = (up ? -nv : nv) + 2e-15 * (std::abs(t0) + std::abs(t1) + std::abs(t2)) + 1e-300;
  if (!(rate > 0.0)) return HUGE_VAL;
  return room_lo / rate * (1.0 - 1e-15);
}

// [sqrt(lo), sqrt(hi)] rounded outward.
Interval sqrt_interval(const Interval& squared);

}  // namespace cdbench

namespace cdbench {

// Closest point of triangle abc to p in plain doubles (Ericson's region test). NOT certified:
// used for heuristics and the fast uncertified distance, never as a bound. If `feature` is given
// it receives the closest feature: 0..2 vertex a, b, c; 3..5 edge ab, bc, ca; 6 interior.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int* feature = nullptr);

// A point of the closed triangle abc near its closest point to p, for bounds that need a point
// *of* the triangle: the closest point's barycentrics (beta, gamma) clamped so that beta, gamma >= 0
// and beta + gamma <= 1 hold exactly, then q = a + beta (b - a) + gamma (c - a) in doubles. The
// real point with those barycentrics lies in the triangle, and the computed q is within
// closest_point_error(a, b, c) of it (a handful of roundings, each at most u times a magnitude
// below |a| + |b - a| + |c - a| <= 5 max|coordinate|).
Vec3 point_of_triangle_near(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
double closest_point_error(const Vec3& a, const Vec3& b, const Vec3& c);

// Weights lambda (>= 0, summing to 1) whose combination of the unit vectors g is near the
// min-norm point of their convex hull (Frank-Wolfe with exact line search, starting at g[0]),
// stopping after `iterations` steps or once the duality gap x.(x - g_k) (an upper bound of
// |x|^2/2 minus its least value) is at most `gap`. Heuristic: callers only use the weights in
// bounds that are valid for any weights.
Vec3 min_norm_combination(const std::vector<Vec3>& g, std::vector<double>& lambda, int iterations,
                          double gap = 1e-15);

}  // namespace cdbench
