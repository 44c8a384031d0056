#include <CGAL/Interval_nt.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <optional>
#include <random>
#include <sstream>
#include <vector>

#include "distance/point_triangle_distance.h"
#include "exact_reference.h"
#include "test_scale.h"

namespace cdbench {
namespace {

using testing::Epeck;
using testing::Epick;
using testing::exact_squared_distance;

void expect_encloses(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Interval d2 = point_triangle_squared_distance(p, a, b, c);
  const Epeck::FT exact = exact_squared_distance(p, a, b, c);
  EXPECT_TRUE(Epeck::FT(d2.lo) <= exact && exact <= Epeck::FT(d2.hi))
      << std::setprecision(17) << "p=(" << p.transpose() << ") a=(" << a.transpose() << ") b=(" << b.transpose()
      << ") c=(" << c.transpose() << ") interval [" << d2.lo << ", " << d2.hi << "] exact "
      << CGAL::to_double(exact);
  // Tight: relative width near machine precision (absolute near zero).
  const double scale = (p - a).squaredNorm() + (b - a).squaredNorm() + (c - a).squaredNorm();
  EXPECT_LE(d2.hi - d2.lo, 1e-12 * scale + 1e-300);
}

TEST(PointTriangleDistance, RandomPointsAndTrianglesAtManyScales) {
  std::mt19937_64 rng(42);
  for (double scale : {1e-3, 1.0, 1e3}) {
    std::uniform_real_distribution<double> u(-scale, scale);
    for (int k = 0; k < 3000; ++k) {
      const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
      expect_encloses(Vec3{u(rng), u(rng), u(rng)}, a, b, c);
    }
  }
}

TEST(PointTriangleDistance, NearTheTrianglePlane) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1), w(0, 1);
  for (int k = 0; k < 3000; ++k) {
    const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
    double s = w(rng), t = w(rng);
    if (s + t > 1.2) s = 1.2 - s;  // some outside, most inside
    const Vec3 n = (b - a).cross(c - a).normalized();
    const double h = std::ldexp(1.0, -static_cast<int>(w(rng) * 60));
    expect_encloses(a + s * (b - a) + t * (c - a) + ((k % 2) ? h : -h) * n, a, b, c);
  }
}

// Random triangles at three scales, about the origin and 10^3 scales from it, every tenth a sliver
// and every fiftieth degenerate (two equal vertices): f(a, b, c, o, scale, k) for each, o the
// centre and k its index at that scale and centre.
template <class F>
void for_random_triangles(std::mt19937_64& rng, F&& f) {
  std::uniform_real_distribution<double> w(0, 1);
  for (double scale : {1e-3, 1.0, 1e3}) {
    for (double offset : {0.0, 1e3 * scale, 1e7 * scale}) {  // 1e7: rounding a fair part of the distances
      std::uniform_real_distribution<double> u(-scale, scale);
      const Vec3 o(offset, -0.5 * offset, 0.25 * offset);
      for (int k = 0; k < 3000; ++k) {
        Vec3 a = o + Vec3{u(rng), u(rng), u(rng)}, b = o + Vec3{u(rng), u(rng), u(rng)}, c = o + Vec3{u(rng), u(rng), u(rng)};
        if (k % 10 == 1) {  // sliver
          const double along = w(rng);
          c = a + along * (b - a) + 1e-9 * Vec3{u(rng), u(rng), u(rng)};
        }
        if (k % 50 == 2) c = b;                                                           // degenerate
        f(a, b, c, o, scale, k);
      }
    }
  }
}

// The slab bound (used by the fast nearest query) never exceeds the exact distance, for any
// direction, at many scales and near the plane; along the normal it is tight where the projection
// falls inside the triangle.
TEST(PointTriangleDistance, SlabLowerBoundNeverExceedsTheExactDistance) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> w(0, 1);
  int tight_checked = 0;
  for (double scale : {1e-3, 1.0, 1e3}) {
    std::uniform_real_distribution<double> u(-scale, scale);
    for (int k = 0; k < 3000; ++k) {
      const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
      const Vec3 n = (b - a).cross(c - a);
      Vec3 p{u(rng), u(rng), u(rng)};
      const bool near_plane = k % 3 == 0;
      double s = w(rng), t = w(rng);
      if (near_plane && s + t < 1.0 && n.norm() > 0.0)  // a point just off the plane, projection inside
        p = a + s * (b - a) + t * (c - a) + std::ldexp(scale, -static_cast<int>(w(rng) * 40)) * n.normalized();
      const Epeck::FT exact = exact_squared_distance(p, a, b, c);
      const Vec3 q = closest_point_on_triangle(p, a, b, c) - p;
      const std::array<Vec3, 5> dirs{q, n, Vec3(-n), Vec3{u(rng), u(rng), u(rng)}, Vec3(q + 1e-3 * n)};
      for (const Vec3& dir : dirs) {
        if (dir.squaredNorm() == 0.0) continue;
        const double lb = point_triangle_distance_lower_bound(p, a, b, c, dir);
        ASSERT_GE(lb, 0.0);
        EXPECT_TRUE(Epeck::FT(lb) * Epeck::FT(lb) <= exact)
            << std::setprecision(17) << "p=(" << p.transpose() << ") a=(" << a.transpose() << ") b=("
            << b.transpose() << ") c=(" << c.transpose() << ") u=(" << dir.transpose() << ") bound " << lb
            << " exact^2 " << CGAL::to_double(exact);
      }
      if (near_plane && s + t < 1.0 && n.norm() > 0.0) {
        const Vec3 side = n.dot(p - a) > 0.0 ? -n : n;  // from p towards the plane
        const double lb = point_triangle_distance_lower_bound(p, a, b, c, side);
        const double d = std::sqrt(CGAL::to_double(exact));
        EXPECT_GE(lb, d - 1e-13 * scale) << std::setprecision(17) << "exact " << d << " bound " << lb;
        ++tight_checked;
      }
    }
  }
  EXPECT_GT(tight_checked, 1000);
}

// The stored-plane bound (it lets nearest queries skip most triangles before their closest point)
// never exceeds the exact distance: random triangles at many scales and offsets from the origin,
// slivers and degenerate ones, points near and far; it is tight (to 1e-12 relative) above the
// interior, and a version without its vertex term eps would exceed the exact distance somewhere
// (the control: the test can fail).
TEST(PointTriangleDistance, PlaneLowerBoundNeverExceedsTheExactDistance) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> w(0, 1);
  int tight = 0, over_without_eps = 0, degenerate = 0;
  for_random_triangles(rng, [&](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& o, double scale, int k) {
    std::uniform_real_distribution<double> u(-scale, scale);
    const double offset = o.x();
    const TrianglePlane pl = make_triangle_plane(a, b, c);
    if (!(pl.eps < std::numeric_limits<double>::infinity())) ++degenerate;
    const Vec3 n = (b - a).cross(c - a);
    double s = w(rng), t = w(rng);
    const bool above = k % 2 == 0 && s + t < 1.0 && n.norm() > 0.0;
    Vec3 p = o + Vec3{u(rng), u(rng), u(rng)};
    if (above) p = a + s * (b - a) + t * (c - a) + std::ldexp(scale, -static_cast<int>(w(rng) * 30)) * n.normalized();
    const double lb = plane_distance_lower_bound(pl, p);
    const Epeck::FT exact = exact_squared_distance(p, a, b, c);
    ASSERT_GE(lb, 0.0);
    ASSERT_TRUE(Epeck::FT(lb) * Epeck::FT(lb) <= exact)
        << std::setprecision(17) << "p=(" << p.transpose() << ") a=(" << a.transpose() << ") b=(" << b.transpose()
        << ") c=(" << c.transpose() << ") bound " << lb << " exact^2 " << CGAL::to_double(exact);
    if (above && offset == 0.0 && k % 10 != 1) {
      const double d = std::sqrt(CGAL::to_double(exact));
      EXPECT_GE(lb, d * (1.0 - 1e-12) - 1e-13 * scale);
      ++tight;
    }
    TrianglePlane no_eps = pl;
    no_eps.eps = 0.0;
    no_eps.norm_up = std::sqrt(pl.n.squaredNorm());
    const double s0 = pl.n.dot(p) - pl.d;
    if (pl.eps < std::numeric_limits<double>::infinity() && std::abs(s0) > 0.0 &&
        !(Epeck::FT(std::abs(s0) / no_eps.norm_up) * Epeck::FT(std::abs(s0) / no_eps.norm_up) <= exact))
      ++over_without_eps;
  });
  EXPECT_GT(tight, 1500);
  EXPECT_GT(degenerate, 100);
  EXPECT_GT(over_without_eps, 10);
}

// The squared distance between a box and triangle abc in kernel K (CGAL's rationals: exact): 0 when
// they meet, else the least over the pairs where two disjoint convex polytopes come nearest (a
// vertex of one and a face of the other, an edge of each).
template <class K>
typename K::FT box_triangle_squared_distance(const Aabb& box, const Vec3& a, const Vec3& b, const Vec3& c) {
  const auto P = [](const Vec3& v) { return typename K::Point_3(v.x(), v.y(), v.z()); };
  const typename K::Iso_cuboid_3 cube(P(box.lo), P(box.hi));
  const typename K::Triangle_3 tri(P(a), P(b), P(c));
  if (!tri.is_degenerate()) {
    if (CGAL::do_intersect(cube, tri)) return 0;
  } else {  // collinear: the union of its edges (or a point)
    for (const auto& [x, y] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
      if (x == y ? !cube.has_on_unbounded_side(P(x)) : CGAL::do_intersect(cube, typename K::Segment_3(P(x), P(y))))
        return 0;
  }
  const std::array<Vec3, 8> k = box.corners();
  // The box's 12 edges and its faces as 12 triangles (corner i has bit j set when its coordinate j
  // is the upper one, as Aabb::corners orders them).
  std::vector<std::array<int, 2>> edges;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 3; ++j)
      if (!(i & (1 << j))) edges.push_back({i, i | (1 << j)});
  std::vector<std::array<int, 3>> faces;
  for (int j = 0; j < 3; ++j)
    for (int side = 0; side < 2; ++side) {
      std::vector<int> q;
      for (int i = 0; i < 8; ++i)
        if (((i >> j) & 1) == side) q.push_back(i);
      // q holds the face's four corners in bit order: 0-1-3-2 goes round it.
      faces.push_back({q[0], q[1], q[3]});
      faces.push_back({q[0], q[3], q[2]});
    }
  const std::array<Vec3, 3> t{a, b, c};
  typename K::FT best = -1;
  const auto offer = [&](const typename K::FT& d) {
    if (best < 0 || d < best) best = d;
  };
  const auto point_triangle = [&](const Vec3& p, const Vec3& x, const Vec3& y, const Vec3& z) {
    return CGAL::squared_distance(P(p), typename K::Triangle_3(P(x), P(y), P(z)));
  };
  for (const Vec3& v : t)
    for (const auto& f : faces) offer(point_triangle(v, k[f[0]], k[f[1]], k[f[2]]));
  for (const Vec3& x : k) offer(point_triangle(x, a, b, c));
  for (const auto& e : edges)
    for (int i = 0; i < 3; ++i)
      offer(CGAL::squared_distance(typename K::Segment_3(P(k[e[0]]), P(k[e[1]])),
                                   typename K::Segment_3(P(t[i]), P(t[(i + 1) % 3]))));
  return best;
}

// The box bounds of a triangle's distance (its plane; its range along an axis: the disjointness
// test's node bounds, distance/signed_distance.cpp) never exceed the exact distance: random
// triangles (slivers, degenerate ones, far from the origin) against boxes beside them and boxes
// with a corner on the triangle's plane or on one of its edges' in-plane normals, where only the
// error terms keep the bounds below the exact distance; the same bounds without them exceed it
// somewhere (the control: the test can fail). Where the box lies clear of the triangle's plane
// above its interior, the plane bound is the distance.
TEST(PointTriangleDistance, BoxBoundsNeverExceedTheExactDistance) {
  std::mt19937_64 rng(57);
  std::uniform_real_distribution<double> w(0, 1);
  int checked = 0, tight = 0, positive_axis = 0, over_without_errors = 0;
  // A third of the slivers, the degenerate ones, some others; a fifth of those under the
  // sanitizers (exact rationals cost 10-20x there).
  const int thin = test_scale::pick(1, 5);
  for_random_triangles(rng, [&](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& o, double scale, int k) {
    if (k % (18 * thin) != 0 && k % (30 * thin) != 1 && k % (50 * thin) != 2) return;
    std::uniform_real_distribution<double> u(-scale, scale);
    const std::array<Vec3, 3> t{a, b, c};
    const Vec3 n = (b - a).cross(c - a);
    const TrianglePlane pl = make_triangle_plane(a, b, c);
    const double s = 0.5 * w(rng), r = 0.5 * w(rng);
    const Vec3 inside = a + s * (b - a) + r * (c - a);
    const int edge = k % 3;
    const Vec3 side = (t[(edge + 1) % 3] - t[edge]).cross(n);
    const Vec3 on_edge = t[edge] + w(rng) * (t[(edge + 1) % 3] - t[edge]);
    const double size = std::ldexp(scale, -static_cast<int>(w(rng) * 20));
    // The corner of a box of that size nearest along `dir` placed at `x`: the box lies on dir's side.
    const auto box_from = [&](const Vec3& x, const Vec3& dir) {
      Aabb box;
      box.extend(x);
      Vec3 far = x;
      for (int j = 0; j < 3; ++j) far[j] += (dir[j] >= 0.0 ? 1.0 : -1.0) * size * (0.2 + w(rng));
      box.extend(far);
      return box;
    };
    const double lift = std::ldexp(scale, -static_cast<int>(w(rng) * 40));
    const Vec3 corner = o + Vec3{u(rng), u(rng), u(rng)}, extent{u(rng), u(rng), u(rng)};
    const std::array<Aabb, 4> boxes{box_from(corner, extent),
                                    box_from(inside + (k % 4 == 0 ? lift : 0.0) * n.normalized(), n),
                                    box_from(on_edge + (k % 4 == 0 ? lift : 0.0) * side.normalized(), side),
                                    box_from(inside, -n)};
    for (const Aabb& box : boxes) {
      // Exact where doubles cannot tell: a bound clearly below the distance in doubles (by far more
      // than their rounding) is below the exact one.
      const double approx = box_triangle_squared_distance<Epick>(box, a, b, c);
      const double margin = 1e-12 * std::pow(scale + o.cwiseAbs().maxCoeff(), 2);
      std::optional<Epeck::FT> exact_value;
      const auto exact = [&]() -> const Epeck::FT& {
        if (!exact_value) exact_value = box_triangle_squared_distance<Epeck>(box, a, b, c);
        return *exact_value;
      };
      const auto below = [&](double bound) {
        return bound * bound <= approx * (1.0 - 1e-6) - margin || Epeck::FT(bound) * Epeck::FT(bound) <= exact();
      };
      const auto where = [&] {
        std::ostringstream os;
        os << std::setprecision(17) << "a=(" << a.transpose() << ") b=(" << b.transpose() << ") c=(" << c.transpose()
           << ") box (" << box.lo.transpose() << ") (" << box.hi.transpose() << ") exact^2 " << CGAL::to_double(exact());
        return os.str();
      };
      const double lp = box_plane_lower_bound(pl, box);
      ASSERT_GE(lp, 0.0);
      ASSERT_TRUE(below(lp)) << where() << " plane bound " << lp;
      for (int i = 0; i < 3; ++i) {
        const Vec3 axis = (t[(i + 1) % 3] - t[i]).cross(n);
        const double la = box_axis_gap_lower_bound(triangle_axis_range(axis, t), box);
        ASSERT_GE(la, 0.0);
        ASSERT_TRUE(below(la)) << where() << " axis " << i << " bound " << la;
        if (la > 0.0) ++positive_axis;
        // Without the error terms: the gap of the rounded projections over the rounded |axis|.
        const auto [lo, hi] = extreme_corners(axis, box);
        double tlo = HUGE_VAL, thi = -HUGE_VAL;
        for (const Vec3& x : t) tlo = std::min(tlo, axis.dot(x)), thi = std::max(thi, axis.dot(x));
        const double gap0 = std::max(axis.dot(lo) - thi, tlo - axis.dot(hi)) / axis.norm();
        if (gap0 > 0.0 && !below(gap0)) ++over_without_errors;
      }
      ++checked;
    }
    // Above the interior, clear of the plane by more than the box's rounding: the plane bound is
    // the distance.
    const Aabb& above = boxes[1];
    if (k % 4 == 0 && k % 10 != 1 && k % 50 != 2 && lift > 1e-9 * scale) {
      const double d = std::sqrt(CGAL::to_double(box_triangle_squared_distance<Epeck>(above, a, b, c)));
      EXPECT_GE(box_plane_lower_bound(pl, above), d * (1.0 - 1e-9) - 1e-12 * (scale + o.norm()));
      ++tight;
    }
  });
  EXPECT_GT(checked, 6000 / thin);
  EXPECT_GT(tight, 200 / thin);
  EXPECT_GT(positive_axis, 2000 / thin);
  EXPECT_GT(over_without_errors, 20 / thin);
}

// The near-point upper bound is never below the exact distance (random and nearly coplanar points,
// slivers and degenerate triangles, far from the origin too), and at most about 1e-13 of the
// coordinates' magnitude above it; without its error term it falls below the exact distance
// somewhere (the control: the test can fail).
TEST(PointTriangleDistance, NearPointUpperBoundEnclosesTheExactDistance) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> w(0, 1);
  int below_without_error = 0;
  for_random_triangles(rng, [&](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& o, double scale, int k) {
    std::uniform_real_distribution<double> u(-scale, scale);
    Vec3 p = o + Vec3{u(rng), u(rng), u(rng)};
    const Vec3 n = (b - a).cross(c - a);
    if (k % 2 == 0 && n.norm() > 0.0) {  // on or just off the plane, inside or outside
      const double s = w(rng), t = 1.2 * w(rng) * (1.0 - s);
      p = a + s * (b - a) + t * (c - a) + ((k % 4) ? 1.0 : 0.0) * std::ldexp(scale, -static_cast<int>(w(rng) * 50)) *
                                              n.normalized();
    }
    const double up = point_triangle_distance_upper_near(p, a, b, c);
    const Epeck::FT exact = exact_squared_distance(p, a, b, c);
    ASSERT_TRUE(up >= 0.0 && exact <= Epeck::FT(up) * Epeck::FT(up))
        << std::setprecision(17) << "p=(" << p.transpose() << ") a=(" << a.transpose() << ") b=(" << b.transpose()
        << ") c=(" << c.transpose() << ") bound " << up << " exact^2 " << CGAL::to_double(exact);
    const double m = std::max({a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff(), c.cwiseAbs().maxCoeff()});
    // Within about closest_point_error (2e-14 m since session 69; 1e-13 m before) of the exact one.
    EXPECT_LE(up, std::sqrt(CGAL::to_double(exact)) * (1.0 + 1e-13) + 4e-14 * m);
    const double bare = (p - point_of_triangle_near(p, a, b, c)).norm();
    if (Epeck::FT(bare) * Epeck::FT(bare) < exact) ++below_without_error;
  });
  EXPECT_GT(below_without_error, 10);
}

// The largest near-point upper bound over a few points bounds the exact distance at each of them
// and, the distance to one triangle being convex, at every point of their hull (exact rational
// combinations of the computed points); and it is the largest point's bound, not a smaller one
// (the control: the hull's farthest corner reaches it within 4e-14 of the magnitude).
TEST(PointTriangleDistance, LargestNearPointBoundHoldsOverTheHull) {
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> w(0, 1);
  int reached = 0, cases = 0;
  for_random_triangles(rng, [&](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& o, double scale, int) {
    TriangleMesh m;
    m.vertices = {a, b, c};
    m.faces = {{0, 1, 2}};
    std::uniform_real_distribution<double> u(-scale, scale);
    std::array<Vec3, 4> pts;
    for (Vec3& q : pts) q = o + Vec3{u(rng), u(rng), u(rng)};
    const int n = 3 + static_cast<int>(w(rng) * 2);  // 3 or 4 points
    const double bound = max_distance_upper_near(pts.data(), n, m, 0);
    const Epeck::FT b2 = Epeck::FT(bound) * Epeck::FT(bound);
    double worst = 0.0;
    for (int k = 0; k < n; ++k) {
      const Epeck::FT e = exact_squared_distance(pts[k], a, b, c);
      ASSERT_LE(e, b2) << std::setprecision(17) << "point " << k << " (" << pts[k].transpose() << ") bound " << bound;
      worst = std::max(worst, std::sqrt(CGAL::to_double(e)));
    }
    // An exact point of the hull: a rational combination of the points, its distance by the exact
    // kernel on the combination's coordinates (no rounding).
    std::array<double, 4> lambda{};
    double sum = 0.0;
    for (int k = 0; k < n; ++k) sum += (lambda[k] = w(rng) + 1e-3);
    Epeck::FT x[3] = {0, 0, 0};
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < 3; ++i) x[i] += Epeck::FT(lambda[k]) / Epeck::FT(sum) * Epeck::FT(pts[k][i]);
    const Epeck::Point_3 q(x[0], x[1], x[2]);
    const Epeck::Triangle_3 t(Epeck::Point_3(a[0], a[1], a[2]), Epeck::Point_3(b[0], b[1], b[2]),
                              Epeck::Point_3(c[0], c[1], c[2]));
    if (!t.is_degenerate()) {
      ASSERT_LE(CGAL::squared_distance(q, t), b2) << std::setprecision(17) << "bound " << bound;
    }
    const double mag = std::max({a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff(), c.cwiseAbs().maxCoeff(),
                                 o.cwiseAbs().maxCoeff() + scale});
    ++cases;
    if (bound <= worst * (1.0 + 1e-13) + 4e-14 * mag) ++reached;
  });
  EXPECT_EQ(reached, cases);
  EXPECT_GT(cases, 1000);
}

TEST(PointTriangleDistance, HandBuiltDegenerateAndBoundaryCases) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const std::vector<Vec3> points = {
      a, b, c,                                    // vertices: distance exactly 0
      {0.25, 0, 0}, {0.5, 0.5, 0}, {0, 0.75, 0},  // on the edges
      {0.25, 0.25, 0},                            // inside
      {0.25, 0, 5}, {0.5, 0.5, -3}, {0, 0.25, 2}, // projection exactly on an edge
      {0, 0, 1}, {1, 0, -1}, {0, 1, 7},           // projection exactly on a vertex
      {2, 2, 0}, {-1, -1, 0}, {3, -1, 0},         // in the plane, outside
      {-0.5, 0.25, 0}, {0.25, -1e-300, 0},        // in the plane, just outside an edge
      {0.25, 0.25, 1e-300}, {0.25, 0.25, -4.9e-324},
      {1e100, 1e100, 1e100}, {-1e-310, 1e-310, 0}};
  for (const Vec3& p : points) expect_encloses(p, a, b, c);
  // Degenerate triangles: collinear corners, a repeated corner, all corners equal.
  for (const Vec3& p : points) {
    expect_encloses(p, a, b, Vec3(2, 0, 0));
    expect_encloses(p, a, b, b);
    expect_encloses(p, a, a, a);
  }
  EXPECT_EQ(point_triangle_squared_distance(Vec3(0.25, 0.25, 0), a, b, c).lo, 0.0);
  EXPECT_EQ(point_triangle_squared_distance(b, a, b, c).hi, 0.0);
}

TEST(PointTriangleDistance, SqrtIsRoundedOutward) {
  const Interval s = sqrt_interval({2.0, 2.0});
  EXPECT_LT(s.lo * s.lo, 2.0 + 1e-15);
  EXPECT_LE(s.lo, std::sqrt(2.0));
  EXPECT_GE(s.hi, std::sqrt(2.0));
  EXPECT_LE(s.hi - s.lo, 4.5e-16);
}

// sqrt_interval's fast path (one sqrt and one fma per end, no change of rounding mode) gives the
// same doubles as CGAL's interval square root, which it replaced: random magnitudes over the whole
// range, perfect squares, squares of random doubles and their neighbours (the residual's sign
// decides there), subnormals, zero; under the default rounding and under upward rounding (the
// branch and bound's traversals call it inside CGAL::Protect_FPU_rounding).
TEST(SqrtInterval, SameDoublesAsCgalIntervalSqrt) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mant(1.0, 2.0);
  std::uniform_int_distribution<int> expo(-1074, 1023);
  std::vector<double> xs{0.0, 4.9e-324, 1e-310, 0x1p-600, 0x1p600, 1.0, 2.0, 4.0, 0.25, 1.7976931348623157e308};
  for (int i = 0; i < 200000; ++i) {
    const double m = mant(rng);
    xs.push_back(std::ldexp(m, expo(rng)));
    const double mr = mant(rng);
    const double r = std::ldexp(mr, expo(rng) / 2);
    const double sq = r * r;
    xs.push_back(sq);
    xs.push_back(std::nextafter(sq, 0.0));
    xs.push_back(std::nextafter(sq, HUGE_VAL));
    const double k = static_cast<double>(rng() % 100000000);
    xs.push_back(k * k);
  }
  const auto reference = [](double lo, double hi) {
    CGAL::Protect_FPU_rounding<true> guard;
    const CGAL::Interval_nt<false> s = CGAL::sqrt(CGAL::Interval_nt<false>(lo, hi));
    return Interval{s.inf(), s.sup()};
  };
  for (int mode = 0; mode < 2; ++mode) {
    std::size_t differ = 0;
    for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
      const double lo = std::min(xs[i], xs[i + 1]), hi = std::max(xs[i], xs[i + 1]);
      for (const Interval& x : {Interval{lo, hi}, Interval{lo, lo}, Interval{hi, hi}}) {
        Interval got;
        if (mode == 0) {
          got = sqrt_interval(x);
        } else {
          CGAL::Protect_FPU_rounding<true> guard;
          got = sqrt_interval(x);
        }
        const Interval want = reference(x.lo, x.hi);
        if (got.lo != want.lo || got.hi != want.hi) {
          if (++differ <= 5)
            ADD_FAILURE() << std::setprecision(17) << "mode " << mode << " [" << x.lo << ", " << x.hi << "]: got ["
                          << got.lo << ", " << got.hi << "], CGAL [" << want.lo << ", " << want.hi << "]";
        }
      }
    }
    EXPECT_EQ(differ, 0u) << "mode " << mode;
  }
}

}  // namespace
}  // namespace cdbench
