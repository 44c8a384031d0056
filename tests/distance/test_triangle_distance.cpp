#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <random>

#include "distance/exact_predicates.h"
#include "distance/point_triangle_distance.h"
#include "distance/triangle_distance.h"
#include "exact_reference.h"
#include "test_scale.h"

namespace cdbench {
namespace {

using testing::Epeck;
using testing::exact_point;

void expect_encloses(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e, const Vec3& f) {
  const Interval r = triangle_triangle_squared_distance(a, b, c, d, e, f);
  const Epeck::FT exact = CGAL::squared_distance(Epeck::Triangle_3(exact_point(a), exact_point(b), exact_point(c)),
                                                 Epeck::Triangle_3(exact_point(d), exact_point(e), exact_point(f)));
  EXPECT_TRUE(Epeck::FT(r.lo) <= exact && exact <= Epeck::FT(r.hi))
      << std::setprecision(17) << "a=(" << a.transpose() << ") b=(" << b.transpose() << ") c=(" << c.transpose()
      << ") d=(" << d.transpose() << ") e=(" << e.transpose() << ") f=(" << f.transpose() << ") [" << r.lo << ", "
      << r.hi << "] exact " << CGAL::to_double(exact);
  const double scale = (a - d).squaredNorm() + (b - a).squaredNorm() + (e - d).squaredNorm() + 1e-300;
  EXPECT_LE(r.hi - r.lo, 1e-11 * scale);
}

TEST(TriangleDistance, RandomPairsAgainstExactRationals) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 shift = (k % 3 == 0) ? Vec3{u(rng), u(rng), u(rng)} : Vec3(2.5 * u(rng), 0, 0);
    const std::array<Vec3, 6> v{Vec3{u(rng), u(rng), u(rng)},         Vec3{u(rng), u(rng), u(rng)},
                                Vec3{u(rng), u(rng), u(rng)},         shift + Vec3{u(rng), u(rng), u(rng)},
                                shift + Vec3{u(rng), u(rng), u(rng)}, shift + Vec3{u(rng), u(rng), u(rng)}};
    expect_encloses(v[0], v[1], v[2], v[3], v[4], v[5]);
  }
}

TEST(TriangleDistance, HandBuiltCases) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // Parallel, stacked: distance 1 (face-face).
  expect_encloses(a, b, c, Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(0, 1, 1));
  // Crossing edges (edge-edge closest pair inside both).
  expect_encloses(a, b, c, Vec3(0.25, -1, 0.5), Vec3(0.25, 1, 0.5), Vec3(0.25, 0, 3));
  // Sharing a vertex, sharing an edge, coplanar overlap, touching at a point: distance 0.
  expect_encloses(a, b, c, a, Vec3(-1, 0, 0), Vec3(0, -1, 1));
  expect_encloses(a, b, c, a, b, Vec3(0, -1, 0));
  expect_encloses(a, b, c, Vec3(0.1, 0.1, 0), Vec3(2, 0.1, 0), Vec3(0.1, 2, 0));
  expect_encloses(a, b, c, Vec3(0.25, 0.25, 0), Vec3(0.25, 0.25, 1), Vec3(1, 1, 1));
  // Coplanar, disjoint: edge-edge in the plane.
  expect_encloses(a, b, c, Vec3(1, 1, 0), Vec3(2, 1, 0), Vec3(1, 2, 0));
  // Parallel edges.
  expect_encloses(a, b, c, Vec3(0, 0, 2), Vec3(1, 0, 2), Vec3(0.5, -1, 2));
  EXPECT_EQ(triangle_triangle_squared_distance(a, b, c, a, b, Vec3(0, -1, 0)).hi, 0.0);
}

TEST(SegmentDistance, AgainstExactRationals) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 3000; ++k) {
    const Vec3 p0{u(rng), u(rng), u(rng)}, p1{u(rng), u(rng), u(rng)}, q0{u(rng), u(rng), u(rng)};
    const Vec3 q1 = (k % 4 == 0) ? q0 + (p1 - p0) * 0.5 : Vec3{u(rng), u(rng), u(rng)};  // some parallel
    const Interval r = segment_segment_squared_distance(p0, p1, q0, q1);
    const Epeck::FT exact = CGAL::squared_distance(Epeck::Segment_3(exact_point(p0), exact_point(p1)),
                                                   Epeck::Segment_3(exact_point(q0), exact_point(q1)));
    EXPECT_TRUE(Epeck::FT(r.lo) <= exact && exact <= Epeck::FT(r.hi)) << k;
  }
}

// The projection lower bound: never above the exact distance (exact rationals), whatever the
// direction; and, along the estimated closest-point direction, tight for disjoint triangles.
TEST(TriangleDistance, ProjectionLowerBoundAgainstExactRationals) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1, 1);
  int tight = 0;
  for (int k = 0; k < 3000; ++k) {
    const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
    const Vec3 shift = 1.5 * Vec3{u(rng), u(rng), u(rng)};
    const Vec3 d = Vec3{u(rng), u(rng), u(rng)} + shift, e = Vec3{u(rng), u(rng), u(rng)} + shift,
               f = Vec3{u(rng), u(rng), u(rng)} + shift;
    const Epeck::FT exact = CGAL::squared_distance(Epeck::Triangle_3(exact_point(a), exact_point(b), exact_point(c)),
                                                   Epeck::Triangle_3(exact_point(d), exact_point(e), exact_point(f)));
    Vec3 p, q;
    const double est = triangle_triangle_closest_points(a, b, c, d, e, f, &p, &q);
    for (const Vec3& dir : {Vec3(q - p), Vec3{u(rng), u(rng), u(rng)}}) {
      const double lb = triangle_distance_lower_bound(a, b, c, d, e, f, dir);
      ASSERT_GE(lb, 0.0);
      EXPECT_TRUE(Epeck::FT(lb) * Epeck::FT(lb) <= exact) << k;
    }
    if (est > 1e-6) {
      const double lb = triangle_distance_lower_bound(a, b, c, d, e, f, q - p);
      EXPECT_NEAR(lb * lb, CGAL::to_double(exact), 1e-12 * (1 + est)) << k;
      ++tight;
    }
  }
  EXPECT_GT(tight, 1000);
}

// The stored-plane bound for a pair (it lets the pair-distance path skip pairs before their closest
// points) never exceeds the exact distance: random pairs, some with the second triangle just above
// the first's plane (where it is tight), some straddling (bound 0), slivers, at two offsets from the
// origin; its control without eps exceeds the exact distance somewhere.
TEST(TriangleDistance, PlanePairLowerBoundAgainstExactRationals) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1, 1), w(0, 1);
  int positive = 0, over_without_eps = 0;
  for (double offset : {0.0, 1e3}) {
    const Vec3 o(offset, 0.5 * offset, -offset);
    for (int k = 0; k < test_scale::cases(3000); ++k) {
      const Vec3 a = o + Vec3{u(rng), u(rng), u(rng)}, b = o + Vec3{u(rng), u(rng), u(rng)};
      const double along = k % 10 == 3 ? w(rng) : 0.0;
      const Vec3 c = k % 10 == 3 ? Vec3(a + along * (b - a) + 1e-10 * Vec3{u(rng), u(rng), u(rng)})
                                 : Vec3(o + Vec3{u(rng), u(rng), u(rng)});
      const TrianglePlane pl = make_triangle_plane(a, b, c);
      const Vec3 n = (b - a).cross(c - a).normalized();
      const double h = k % 2 ? std::ldexp(1.0, -static_cast<int>(w(rng) * 40)) : u(rng);
      const Vec3 base = a + 0.3 * (b - a) + 0.3 * (c - a) + h * n;
      const Vec3 d = base + 0.5 * Vec3{u(rng), u(rng), u(rng)}.cross(n), e = base + 0.5 * Vec3{u(rng), u(rng), u(rng)}.cross(n),
                 f0 = base + 0.5 * Vec3{u(rng), u(rng), u(rng)}.cross(n);
      const Vec3 f = f0 + 0.01 * u(rng) * n;
      const Epeck::FT exact = CGAL::squared_distance(Epeck::Triangle_3(exact_point(a), exact_point(b), exact_point(c)),
                                                     Epeck::Triangle_3(exact_point(d), exact_point(e), exact_point(f)));
      const double lb = plane_pair_lower_bound(pl, d, e, f);
      ASSERT_GE(lb, 0.0);
      ASSERT_TRUE(Epeck::FT(lb) * Epeck::FT(lb) <= exact)
          << std::setprecision(17) << "a=(" << a.transpose() << ") b=(" << b.transpose() << ") c=(" << c.transpose()
          << ") d=(" << d.transpose() << ") e=(" << e.transpose() << ") f=(" << f.transpose() << ") bound " << lb;
      positive += lb > 0.0;
      TrianglePlane no_eps = pl;
      no_eps.eps = -1e-300;
      no_eps.norm_up = std::sqrt(pl.n.squaredNorm());
      const double wrong = plane_pair_lower_bound(no_eps, d, e, f) / (1.0 - 2e-15);
      if (pl.eps < HUGE_VAL && !(Epeck::FT(wrong) * Epeck::FT(wrong) <= exact)) ++over_without_eps;
    }
  }
  EXPECT_GT(positive, test_scale::cases(1000));
  EXPECT_GT(over_without_eps, test_scale::cases(10));
}


// The gap along the axis across two triangles' longest edges (long_edges_gap) is a lower bound of
// their distance (exact rationals): slivers 1-4 long and a thousandth as wide, skew or near
// parallel (angles down to 1e-13), apart by 2^-40 ... 1 along the axis or crossing, at the origin
// and 1e3 away; positive on most skew pairs apart, 0 for near-parallel edges.
TEST(TriangleDistance, LongEdgesGapAgainstExactRationals) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(-1, 1), w(0, 1);
  int positive = 0, skew_apart = 0, tight = 0;
  for (double offset : {0.0, 1e3}) {
    const Vec3 o(offset, -0.5 * offset, 0.25 * offset);
    for (int k = 0; k < test_scale::cases(3000); ++k) {
      const auto unit = [&] { return Vec3{u(rng), u(rng), u(rng)}.normalized(); };
      const Vec3 da = unit();
      // Near parallel one time in five: the second direction tilted from the first by 1e-13 ... 1e-3.
      const bool parallel = k % 5 == 0;
      const double tilt = parallel ? std::pow(10.0, -3.0 - 10.0 * w(rng)) : 0.0;
      const Vec3 db = parallel ? Vec3((da + tilt * unit()).normalized()) : unit();
      const double la = 1.0 + 3.0 * w(rng), lb = 1.0 + 3.0 * w(rng);
      const Vec3 across = da.cross(db).squaredNorm() > 1e-20 ? Vec3(da.cross(db).normalized()) : unit();
      const double h = k % 3 == 0 ? 0.0 : std::ldexp(1.0, -static_cast<int>(w(rng) * 40));
      // The two long edges' midpoints h apart along the common normal, shifted along the edges.
      const double sa = u(rng), sb = u(rng);
      const Vec3 ma = o, mb = o + h * across + 0.5 * la * sa * da + 0.5 * lb * sb * db;
      const Vec3 wa = 1e-3 * la * da.cross(unit()), wb = 1e-3 * lb * db.cross(unit());
      const Vec3 a = ma - 0.5 * la * da, b = ma + 0.5 * la * da, c = ma + 0.3 * la * u(rng) * da + wa;
      const Vec3 d = mb - 0.5 * lb * db, e = mb + 0.5 * lb * db, f = mb + 0.3 * lb * u(rng) * db + wb;
      const Epeck::FT exact = CGAL::squared_distance(Epeck::Triangle_3(exact_point(a), exact_point(b), exact_point(c)),
                                                     Epeck::Triangle_3(exact_point(d), exact_point(e), exact_point(f)));
      const double g = long_edges_gap(a, b, c, d, e, f, longest_edge(d, e, f));
      ASSERT_GE(g, 0.0);
      ASSERT_TRUE(Epeck::FT(g) * Epeck::FT(g) <= exact)
          << std::setprecision(17) << "a=(" << a.transpose() << ") b=(" << b.transpose() << ") c=(" << c.transpose()
          << ") d=(" << d.transpose() << ") e=(" << e.transpose() << ") f=(" << f.transpose() << ") gap " << g
          << " exact " << std::sqrt(CGAL::to_double(exact));
      positive += g > 0.0;
      if (parallel) {
        // The axis is ill-conditioned there: no claim (and none expected below 1e-12 radians).
        continue;
      }
      if (h > 0.01) {
        ++skew_apart;
        tight += g > 0.5 * h;
      }
    }
  }
  EXPECT_GT(positive, test_scale::cases(1500));
  // Skew slivers apart along their common normal: that axis shows most of the distance.
  EXPECT_GT(tight, skew_apart * 3 / 4);
}

// The reach time (the conservative-advancement bound of the separated advance): at every s up to
// the bound, the exact distance between abc and def + s v (rational arithmetic) is at least r;
// for a vertex coming straight at a face along the normal direction the bound is the exact time
// (H - r) / |v.n|. Random pairs with the estimated closest-point direction and a random one, random
// motions, reaches from 0 to the current distance.
TEST(TriangleDistance, ReachTimeLowerBoundAgainstExactRationals) {
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<double> u(-1, 1), w(0, 1);
  int finite = 0, infinite = 0;
  const auto moved = [](const Vec3& x, const Vec3& v, const Epeck::FT& s) {
    const Epeck::Point_3 p = exact_point(x);
    return Epeck::Point_3(p.x() + s * v.x(), p.y() + s * v.y(), p.z() + s * v.z());
  };
  for (int k = 0; k < test_scale::cases(2000); ++k) {
    const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
    const Vec3 shift = 2.0 * Vec3{u(rng), u(rng), u(rng)};
    const Vec3 d = Vec3{u(rng), u(rng), u(rng)} + shift, e = Vec3{u(rng), u(rng), u(rng)} + shift,
               f = Vec3{u(rng), u(rng), u(rng)} + shift;
    Vec3 p, q;
    const double est = triangle_triangle_closest_points(a, b, c, d, e, f, &p, &q);
    if (!(est > 1e-6)) continue;
    // Mostly towards abc, sometimes sideways or away.
    const Vec3 v = (k % 4 ? Vec3(p - q).normalized() + 0.7 * Vec3{u(rng), u(rng), u(rng)} : Vec3{u(rng), u(rng), u(rng)});
    const Epeck::Triangle_3 A(exact_point(a), exact_point(b), exact_point(c));
    // The estimate ignores intersections: r from the exact distance (0 when they intersect).
    const double r = w(rng) * std::sqrt(CGAL::to_double(CGAL::squared_distance(
                                  A, Epeck::Triangle_3(exact_point(d), exact_point(e), exact_point(f))))) * (1 - 1e-9);
    const TrianglePlane pl = make_triangle_plane(a, b, c);
    for (int kind = 0; kind < 3; ++kind) {
      const Vec3 dir = kind == 0 ? Vec3(q - p) : Vec3{u(rng), u(rng), u(rng)};
      // kind 2: the stored-plane form (point_triangle_distance.h).
      const double s = kind == 2 ? plane_pair_reach_time_lower_bound(pl, d, e, f, v, r)
                                 : triangle_reach_time_lower_bound(a, b, c, d, e, f, dir, v, r);
      ASSERT_GE(s, 0.0);
      const bool inf = !(s < HUGE_VAL);
      (inf ? infinite : finite) += 1;
      for (double at : {1.0, 0.5, w(rng)}) {
        const Epeck::FT sx = inf ? Epeck::FT(at * 50.0) : Epeck::FT(s) * Epeck::FT(at);
        const Epeck::FT dist2 = CGAL::squared_distance(A, Epeck::Triangle_3(moved(d, v, sx), moved(e, v, sx), moved(f, v, sx)));
        ASSERT_TRUE(dist2 >= Epeck::FT(r) * Epeck::FT(r))
            << std::setprecision(17) << "a=(" << a.transpose() << ") b=(" << b.transpose() << ") c=(" << c.transpose()
            << ") d=(" << d.transpose() << ") e=(" << e.transpose() << ") f=(" << f.transpose() << ") u=("
            << dir.transpose() << ") v=(" << v.transpose() << ") r=" << r << " s=" << s << " at " << at;
      }
    }
  }
  EXPECT_GT(finite, test_scale::pick(1500, 750));  // of 3 x the cases
  EXPECT_GT(infinite, test_scale::pick(100, 50));
  // A vertex at height H above the middle of a large face, coming down along v with a sideways part.
  for (double H : {1.0, 1e-3, 37.5}) {
    const Vec3 a(-100, -100, 0), b(100, -100, 0), c(0, 100, 0);
    const Vec3 d(0.1, 0.2, H), e(0.5, 0.2, H + 1), f(0.1, 0.7, H + 2);
    const Vec3 v(0.3, -0.2, -0.8);
    const double r = 0.25 * H;
    const double s = triangle_reach_time_lower_bound(a, b, c, d, e, f, Vec3(0, 0, 1), v, r);
    EXPECT_NEAR(s, (H - r) / 0.8, 1e-14 * H) << H;
    EXPECT_LE(s, (H - r) / 0.8) << H;
    const double sp = plane_pair_reach_time_lower_bound(make_triangle_plane(a, b, c), d, e, f, v, r);
    EXPECT_NEAR(sp, (H - r) / 0.8, 1e-12 * H + 1e-13) << H;  // the plane's error terms scale with the face (100)
    EXPECT_LE(sp, (H - r) / 0.8) << H;
  }
}

// The one exact triangle-triangle intersection test, degenerate triangles included (a zero-area
// triangle is its edges): the certified distance is exactly 0 for every intersecting pair,
// including a segment that pierces a triangle's interior, which no vertex or edge pair sees.
TEST(TriangleDistance, IntersectionTestWithDegenerateTriangles) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const Vec3 up(0.25, 0.25, 1), down(0.25, 0.25, -1), mid(0.25, 0.25, 0);
  struct Case {
    Vec3 d, e, f;
    bool hit;
  };
  const Case cases[] = {
      {up, down, Vec3(0.25, 0.25, 0.5), true},       // a segment (collinear corners) through the interior
      {up, Vec3(0.25, 0.25, 0.5), up, false},        // a segment above the triangle
      {mid, mid, mid, true},                         // a point in the interior
      {Vec3(0.5, 0.5, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0.5, 0), true},  // a point on the hypotenuse
      {Vec3(0.5, 0.5 + 1e-15, 0), Vec3(0.5, 0.5 + 1e-15, 0), Vec3(0.5, 0.5 + 1e-15, 0), false},  // just beside it
      {Vec3(0, 0, 1), Vec3(0, 0, 1), a, true},       // a segment ending at a corner
      {Vec3(-1, 0, 0), Vec3(2, 0, 0), Vec3(0.5, 0, 0), true},  // along an edge
      {Vec3(2, 0, 0), Vec3(3, 0, 0), Vec3(2.5, 0, 0), false},  // on the edge's line, beyond it
      {Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1), Vec3(1, 1, 1), true},  // a proper triangle through it
      {Vec3(0, 0, 1e-300), Vec3(1, 0, 1e-300), Vec3(0, 1, 1e-300), false},  // parallel, a hair above
  };
  for (const Case& k : cases) {
    EXPECT_EQ(triangles_intersect(a, b, c, k.d, k.e, k.f), k.hit) << k.d.transpose() << " / " << k.e.transpose();
    EXPECT_EQ(triangles_intersect(k.d, k.e, k.f, a, b, c), k.hit);
    const Interval d2 = triangle_triangle_squared_distance(a, b, c, k.d, k.e, k.f);
    if (k.hit) {
      EXPECT_EQ(d2.lo, 0.0);
      EXPECT_EQ(d2.hi, 0.0);
    } else {
      EXPECT_GT(d2.hi, 0.0);
    }
  }
  // Two degenerate triangles: overlapping and disjoint collinear segments, crossing segments.
  EXPECT_TRUE(triangles_intersect(a, b, b, Vec3(0.5, 0, 0), Vec3(2, 0, 0), Vec3(2, 0, 0)));
  EXPECT_FALSE(triangles_intersect(a, b, b, Vec3(1.5, 0, 0), Vec3(2, 0, 0), Vec3(2, 0, 0)));
  EXPECT_TRUE(triangles_intersect(a, b, b, Vec3(0.5, -1, 0), Vec3(0.5, 1, 0), Vec3(0.5, 1, 0)));
  EXPECT_FALSE(triangles_intersect(a, b, b, Vec3(0.5, -1, 1e-9), Vec3(0.5, 1, 1e-9), Vec3(0.5, 1, 1e-9)));
}

}  // namespace
}  // namespace cdbench
