// F's supporting planes (distance/support_planes.h): the planes found support F (checked in exact
// rationals), convex solids have one per distinct face plane, and each triangle's weighted plane
// bound holds along the whole line (against certified signed distances at dense samples), is tight
// inside a convex F, and is not tight where a control says it should not be.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <random>

#include "distance/signed_distance.h"
#include "distance/support_planes.h"
#include "exact_reference.h"
#include "mesh/shapes.h"

namespace cdbench {
namespace {

using testing::Epeck;

TriangleMesh tetrahedron() {
  TriangleMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

// Every vertex of F satisfies n.v - d <= e exactly: the plane supports F.
void expect_supporting(const TriangleMesh& F, const SupportPlanes& S) {
  for (const SupportPlane& p : S.planes()) {
    const Epeck::FT e(p.e);
    for (const Vec3& v : F.vertices) {
      const Epeck::FT value = Epeck::FT(p.n[0]) * v[0] + Epeck::FT(p.n[1]) * v[1] + Epeck::FT(p.n[2]) * v[2] - p.d;
      ASSERT_TRUE(value <= e) << std::setprecision(17) << "n " << p.n.transpose() << " d " << p.d << " e " << p.e
                              << " vertex " << v.transpose();
    }
    ASSERT_GT(p.norm_up, 0.0);
    const Epeck::FT nn = Epeck::FT(p.n[0]) * p.n[0] + Epeck::FT(p.n[1]) * p.n[1] + Epeck::FT(p.n[2]) * p.n[2];
    EXPECT_TRUE(Epeck::FT(p.norm_lo) * p.norm_lo <= nn && nn <= Epeck::FT(p.norm_up) * p.norm_up);
  }
}

TEST(SupportPlanes, ConvexSolidsHaveOnePlanePerFacePlane) {
  const TriangleMesh box = make_box(Vec3(-1, -2, -0.5), Vec3(1, 0.5, 3));
  const SupportPlanes b = SupportPlanes::build(box);
  EXPECT_TRUE(b.convex());
  EXPECT_EQ(b.planes().size(), 6u);  // 12 triangles, 6 distinct planes
  expect_supporting(box, b);
  const TriangleMesh tet = tetrahedron();
  const SupportPlanes t = SupportPlanes::build(tet);
  EXPECT_TRUE(t.convex());
  EXPECT_EQ(t.planes().size(), 4u);
  expect_supporting(tet, t);
  const TriangleMesh ico = make_icosphere(1.0, 1);
  const SupportPlanes i = SupportPlanes::build(ico);
  EXPECT_TRUE(i.convex());
  EXPECT_EQ(i.planes().size(), ico.faces.size());
  expect_supporting(ico, i);
  // A torus: no face supports it from the hole's side, some do from outside.
  const TriangleMesh torus = make_torus(1.0, 0.35, 24, 12);
  const SupportPlanes r = SupportPlanes::build(torus);
  EXPECT_FALSE(r.convex());
  EXPECT_LT(r.planes().size(), torus.faces.size() / 2);
  expect_supporting(torus, r);
  // Beyond the work budget nothing is searched.
  EXPECT_TRUE(SupportPlanes::build(ico, 10.0).empty());
}

struct LineCheck {
  int triangles = 0, points = 0, violations = 0, inside = 0;
  double worst_gap = 0.0;  // inside a convex F: largest (least sampled s) - lower at mu = 0
};

// Random triangles in and around F, random directions: at each sample point x of the triangle and
// each mu, the certified s(x - mu d) must reach lower - mu rate.
LineCheck check_lines(const TriangleMesh& F, std::uint64_t seed, int n, double rate_factor = 1.0) {
  const SignedDistance sd(F);
  const SupportPlanes S = SupportPlanes::build(F);
  std::mt19937_64 rng(seed);
  const Aabb box = F.bbox();
  const double diag = box.diagonal();
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  LineCheck out;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& v : F.vertices) mean += v / static_cast<double>(F.vertices.size());
  for (int k = 0; k < n; ++k) {
    // Every other triangle about the vertices' mean (inside a convex F), the others anywhere around.
    const Vec3 c = k % 2 ? Vec3(mean + 0.05 * diag * Vec3{s(rng), s(rng), s(rng)}) : Vec3{box.lo[0] + (box.hi[0] - box.lo[0]) * (1.4 * u(rng) - 0.2),
                 box.lo[1] + (box.hi[1] - box.lo[1]) * (1.4 * u(rng) - 0.2),
                 box.lo[2] + (box.hi[2] - box.lo[2]) * (1.4 * u(rng) - 0.2)};
    const double size = diag * (k % 2 ? 0.05 : k % 3 == 0 ? 0.02 : 0.15) * (0.2 + u(rng));
    const std::array<Vec3, 3> v{c + size * Vec3{s(rng), s(rng), s(rng)}, c + size * Vec3{s(rng), s(rng), s(rng)},
                                c + size * Vec3{s(rng), s(rng), s(rng)}};
    const Vec3 d = Vec3{s(rng), s(rng), s(rng)}.normalized();
    const HalfspaceBound b = halfspace_bound(S, v.data(), 3, d);
    // The same over the triangle's bounding box (8 corners, as for the mover's tree nodes).
    Vec3 lo = v[0].cwiseMin(v[1]).cwiseMin(v[2]), hi = v[0].cwiseMax(v[1]).cwiseMax(v[2]);
    std::array<Vec3, 8> corners;
    for (int q = 0; q < 8; ++q)
      for (int a = 0; a < 3; ++a) corners[q][a] = (q >> a) & 1 ? hi[a] : lo[a];
    const HalfspaceBound bb = halfspace_bound(S, corners.data(), 8, d);
    for (int q = 0; q < 27; ++q) {
      const Vec3 y = lo + Vec3((q % 3) / 2.0, (q / 3 % 3) / 2.0, (q / 9) / 2.0).cwiseProduct(hi - lo);
      for (double mu : {0.0, 0.1 * diag, 0.5 * diag}) {
        ++out.points;
        if (sd.signed_distance(y - mu * d).hi < bb.lower - mu * bb.rate * rate_factor) {
          if (rate_factor == 1.0) ADD_FAILURE() << std::setprecision(17) << "box " << lo.transpose() << " / " << hi.transpose() << " mu " << mu;
          ++out.violations;
        }
      }
    }
    ++out.triangles;
    double least = HUGE_VAL;
    bool inside = true;
    for (int i = 0; i <= 6; ++i)
      for (int j = 0; i + j <= 6; ++j) {
        const Vec3 x = v[0] + (i / 6.0) * (v[1] - v[0]) + (j / 6.0) * (v[2] - v[0]);
        for (double mu : {0.0, 0.05 * diag, 0.2 * diag, 0.6 * diag}) {
          const Interval sx = sd.signed_distance(x - mu * d);
          ++out.points;
          if (sx.hi < b.lower - mu * b.rate * rate_factor) {
            if (rate_factor == 1.0)
              ADD_FAILURE() << std::setprecision(17) << "triangle " << v[0].transpose() << " / " << v[1].transpose()
                            << " / " << v[2].transpose() << " d " << d.transpose() << " mu " << mu << ": s <= "
                            << sx.hi << " < " << b.lower << " - mu " << b.rate;
            ++out.violations;
          }
          if (mu == 0.0) {
            least = std::min(least, sx.hi);
            inside = inside && sx.hi < 0.0;
          }
        }
      }
    if (inside && S.convex()) {
      // The samples are 1/6 of the edges apart: the least s over the triangle is within that of
      // the least sample (s is 1-Lipschitz), and the bound is exact for a convex F.
      ++out.inside;
      double edge = 0.0;
      for (int e = 0; e < 3; ++e) edge = std::max(edge, (v[e] - v[(e + 1) % 3]).norm());
      out.worst_gap = std::max(out.worst_gap, (least - b.lower) - edge / 6.0);
    }
  }
  return out;
}

TEST(SupportPlanes, TriangleBoundHoldsAlongTheLine) {
  for (const TriangleMesh& F : {tetrahedron(), make_box(Vec3(0, 0, 0), Vec3(2, 1, 0.5)), make_icosphere(1.0, 1),
                                make_torus(1.0, 0.35, 24, 12)}) {
    const LineCheck c = check_lines(F, 7, 150);
    EXPECT_EQ(c.violations, 0);
    EXPECT_GT(c.points, 10000);
    // Tight inside a convex F (up to the sampling): the weights of the linear program.
    EXPECT_LE(c.worst_gap, 1e-9 * F.bbox().diagonal());
    if (SupportPlanes::build(F).convex()) {
      EXPECT_GT(c.inside, 5);
    }
  }
}

// A sliver of a long rod's side (10 long, 6e-4 wide) across another rod of 500 sides (radius
// 0.05), 0.0025 deep: the planes highest at the sliver's centroid are not those active where it is
// deepest, and the column generation must bring the right ones in for the bound to be exact (with
// four rounds it was 3e-4 below the least s, and the rods' penetrating certificates fell back to
// the branch and bound: 1-3 s each). The least s, sampled every 1e-5 along the crossing, is within
// that of the bound.
TEST(SupportPlanes, ExactForASliverAcrossAFinelyFacetedRod) {
  const TriangleMesh F = make_cylinder(0.05, 10.0, 500);
  const SupportPlanes S = SupportPlanes::build(F);
  ASSERT_TRUE(S.convex());
  const SignedDistance sd(F);
  const double y0 = 0.0475;
  const std::array<Vec3, 3> v{Vec3(-5.0, y0, 5.0), Vec3(5.0, y0 + 1e-4, 5.0), Vec3(5.0, y0 + 7e-4, 5.0003)};
  const HalfspaceBound b = halfspace_bound(S, v.data(), 3, Vec3(0, 1, 0));
  double least = HUGE_VAL;
  for (int i = 0; i <= 20000; ++i) {
    const Vec3 x = v[0] + (0.49 + 0.02 * i / 20000.0) * (v[1] - v[0]);  // x from -0.1 to 0.1
    least = std::min(least, sd.signed_distance(x).hi);
  }
  EXPECT_LT(least, -0.002);
  EXPECT_LE(b.lower, least) << std::setprecision(17) << b.lower << " " << least;
  EXPECT_GE(b.lower, least - 1.5e-5) << std::setprecision(17) << b.lower << " " << least;
}

// A non-convex F (a faceted tube): the outer wall's faces and the ends' support it, the bore's do
// not; each face maps to a plane at least as tight as its own (plane_of), and the planes found
// support F exactly. The tube's ends (one plane each, many triangles) map unscanned.
TEST(SupportPlanes, TubeOuterWallAndEndsSupportItTheBoreDoesNot) {
  const int n = 48;
  const TriangleMesh F = make_tube(0.9, 1.0, 2.0, n);
  const SupportPlanes S = SupportPlanes::build(F);
  EXPECT_FALSE(S.convex());
  expect_supporting(F, S);
  EXPECT_EQ(S.planes().size(), static_cast<std::size_t>(n + 2));  // n quads' planes and the two ends
  int outer = 0, bore = 0;
  for (std::uint32_t f = 0; f < F.faces.size(); ++f) {
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < 3; ++k) c += F.vertices[F.faces[f][k]] / 3.0;
    const double rho = std::hypot(c[0], c[1]);
    const bool end = std::abs(F.vertices[F.faces[f][0]][2] - F.vertices[F.faces[f][1]][2]) < 1e-12 &&
                     std::abs(F.vertices[F.faces[f][0]][2] - F.vertices[F.faces[f][2]][2]) < 1e-12;
    const std::int32_t p = S.plane_of(f);
    if (!end && rho < 0.95) {
      EXPECT_EQ(p, -1) << "bore face " << f;
      ++bore;
      continue;
    }
    ASSERT_GE(p, 0) << "face " << f;
    ++outer;
    // The mapped plane is the face's own within the merging tolerance: its vertices on it.
    const SupportPlane& q = S.planes()[static_cast<std::size_t>(p)];
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(q.n.dot(F.vertices[F.faces[f][k]]) - q.d, 0.0, 1e-9) << "face " << f;
  }
  EXPECT_EQ(bore, 2 * n);
  EXPECT_EQ(outer, static_cast<int>(F.faces.size()) - 2 * n);
  EXPECT_EQ(S.plane_of(static_cast<std::uint32_t>(F.faces.size())), -1);
}

// The bound from chosen planes (halfspace_bound_among) on the tube: cells along the wall, across
// the outer facets' long edges and partly inside the wall, sampled densely against certified
// signed distances: never above them, and within the sampling's reach of the least where the
// cell's deepest points lie under the outer wall (there s is the least plane distance).
TEST(SupportPlanes, ChosenPlanesBoundANonConvexTubesWall) {
  const int n = 48;
  const TriangleMesh F = make_tube(0.9, 1.0, 2.0, n);
  const SupportPlanes S = SupportPlanes::build(F);
  const SignedDistance sd(F);
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst_gap = 0.0;
  for (int k = 0; k < 40; ++k) {
    // A sliver along z at angle phi, 0.002-0.02 deep, a little tilted, about one facet wide.
    const double phi = 3.14159 * u(rng), depth = 0.011 + 0.009 * u(rng), w = 2 * 3.14159 / n * (1.0 + 0.5 * u(rng));
    const double r0 = 1.0 - depth;
    const auto at = [&](double a, double rho, double z) { return Vec3(rho * std::cos(a), rho * std::sin(a), z); };
    const double turn = u(rng), lift = u(rng);
    const std::array<Vec3, 3> v{at(phi, r0, 0.3), at(phi + 0.1 * w * turn, r0 + 0.002 * lift, 1.7),
                                at(phi + w, r0, 0.3 + 0.2 * u(rng))};
    // The planes of the faces nearest the cell's centroid (as the branch and bound gathers them).
    std::vector<std::uint32_t> ids;
    sd.triangles_within((v[0] + v[1] + v[2]) / 3.0, 0.9, 16, ids);
    std::vector<std::int32_t> members;
    for (const std::uint32_t f : ids)
      if (S.plane_of(f) >= 0 && std::find(members.begin(), members.end(), S.plane_of(f)) == members.end())
        members.push_back(S.plane_of(f));
    ASSERT_FALSE(members.empty());
    const HalfspaceBound b =
        halfspace_bound_among(S, members.data(), static_cast<int>(members.size()), v.data(), 3, Vec3(0, 0, 1));
    double least = HUGE_VAL;
    for (int i = 0; i <= 60; ++i)
      for (int j = 0; i + j <= 60; ++j) {
        const Vec3 x = v[0] + (i / 60.0) * (v[1] - v[0]) + (j / 60.0) * (v[2] - v[0]);
        const double sx = sd.signed_distance(x).hi;
        ASSERT_LE(b.lower, sx) << std::setprecision(17) << "cell " << k << " at " << x.transpose();
        least = std::min(least, sx);
      }
    double edge = 0.0;
    for (int e = 0; e < 3; ++e) edge = std::max(edge, (v[e] - v[(e + 1) % 3]).norm());
    worst_gap = std::max(worst_gap, (least - b.lower) - edge / 60.0);
  }
  EXPECT_LE(worst_gap, 1e-9);  // exact up to the sampling: s there is the least outer plane's
  // The control: the bore's side has no plane, and an empty list bounds nothing.
  EXPECT_EQ(halfspace_bound_among(S, nullptr, 0, nullptr, 3, Vec3(0, 0, 1)).lower,
            -std::numeric_limits<double>::infinity());
}

// The control: with the rate halved the same check fails (it has teeth: along the line the bound
// follows s closely, not merely from below).
// The planes highest at a point (highest) and the highest above a floor outside a set
// (highest_above) are found from groups of planes by their normals: the same planes, in the same
// order, as a scan of every plane, on convex and non-convex solids, near and far from F, with
// floors at planes' own values (ties) and members skipped.
TEST(SupportPlanes, GroupedSearchMatchesAScanOfEveryPlane) {
  TriangleMesh far_rod = make_cylinder(0.05, 10.0, 500);
  for (Vec3& v : far_rod.vertices) v = Vec3(v[2] + 1e3, v[0] - 250.0, v[1]);  // along x, far from 0
  const std::vector<TriangleMesh> solids{make_cylinder(0.05, 10.0, 500), far_rod, make_icosphere(1.0, 3),
                                         make_tube(0.98, 1.0, 4.0, 256), make_box(Vec3(0, 0, 0), Vec3(1, 2, 3))};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const TriangleMesh& F : solids) {
    const SupportPlanes S = SupportPlanes::build(F);
    const std::vector<SupportPlane>& P = S.planes();
    ASSERT_FALSE(P.empty());
    const Aabb box = F.bbox();
    const Vec3 mid = 0.5 * (box.lo + box.hi), half = 0.5 * (box.hi - box.lo);
    for (int trial = 0; trial < 400; ++trial) {
      const double reach = trial % 4 == 0 ? 1e-3 : trial % 4 == 1 ? 1.0 : trial % 4 == 2 ? 3.0 : 1e4;
      Vec3 g = trial == 0 ? mid : Vec3{mid[0] + reach * half[0] * u(rng), mid[1] + reach * half[1] * u(rng),
                                        mid[2] + reach * half[2] * u(rng)};
      std::vector<std::pair<double, std::uint32_t>> all(P.size());
      for (std::size_t j = 0; j < P.size(); ++j) all[j] = {P[j].n.dot(g) - P[j].d, static_cast<std::uint32_t>(j)};
      std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
        return a.first > b.first || (a.first == b.first && a.second < b.second);
      });
      for (int k : {1, 6, 16}) {
        std::array<std::pair<double, std::uint32_t>, 16> got;
        S.highest(g, k, got.data());
        for (int i = 0; i < std::min<int>(k, static_cast<int>(P.size())); ++i)
          ASSERT_EQ(got[i].second, all[i].second) << std::setprecision(17) << "rank " << i << " of " << k << " at "
                                                  << g.transpose();
      }
      // Skip the first few found, floor at the value of a plane further down (it must not be
      // chosen: the floor is exceeded strictly).
      std::vector<std::uint32_t> skip;
      for (int i = 0; i < trial % 5 && i < static_cast<int>(P.size()); ++i) skip.push_back(all[i].second);
      const std::size_t at = std::min<std::size_t>(P.size() - 1, static_cast<std::size_t>(trial % 7));
      const double floor = P[all[at].second].n.dot(g) - P[all[at].second].d - P[all[at].second].e;
      for (const double f : {floor, -HUGE_VAL, floor - 1e-9}) {
        std::int64_t want = -1;
        double best = f;
        for (std::uint32_t j = 0; j < P.size(); ++j) {
          const double h = P[j].n.dot(g) - P[j].d - P[j].e;
          if (h > best && std::find(skip.begin(), skip.end(), j) == skip.end()) {
            best = h;
            want = j;
          }
        }
        ASSERT_EQ(S.highest_above(g, f, skip.data(), static_cast<int>(skip.size())), want)
            << std::setprecision(17) << "floor " << f << " at " << g.transpose();
      }
    }
  }
}

// A seed (planes a nearby bound weighted) changes only the members: the bound stays below the
// certified signed distance along a sliver across a rod and as tight as without one, whatever the
// seed (the previous pose's, planes far from the sliver, an index out of range); it returns the
// planes it weighted.
TEST(SupportPlanes, SeedsChangeOnlyTheWork) {
  const TriangleMesh F = make_cylinder(0.05, 10.0, 500);
  const SupportPlanes S = SupportPlanes::build(F);
  ASSERT_TRUE(S.convex());
  const SignedDistance sd(F);
  HalfspaceSeed carried;  // over the steps, as an advance carries it
  for (int step = 0; step < 6; ++step) {
    const double y0 = 0.046 - 0.0004 * step;
    const std::array<Vec3, 3> v{Vec3(-5.0, y0, 5.0), Vec3(5.0, y0 + 1e-4, 5.0), Vec3(5.0, y0 + 7e-4, 5.0003)};
    double least = HUGE_VAL;
    for (int i = 0; i <= 4000; ++i)
      least = std::min(least, sd.signed_distance(v[0] + (0.49 + 0.02 * i / 4000.0) * (v[1] - v[0])).hi);
    const HalfspaceBound cold = halfspace_bound(S, v.data(), 3, Vec3(0, 1, 0));
    HalfspaceSeed far;  // planes of the rod's far side and its caps
    far.idx = {0, 1, static_cast<std::uint32_t>(S.planes().size() - 1), 1u << 30};
    far.n = 4;
    const HalfspaceSeed before = carried;
    const HalfspaceBound warm = halfspace_bound(S, v.data(), 3, Vec3(0, 1, 0), 6, &carried);
    const HalfspaceBound odd = halfspace_bound(S, v.data(), 3, Vec3(0, 1, 0), 6, &far);
    for (const HalfspaceBound& b : {cold, warm, odd}) {
      EXPECT_LE(b.lower, least) << std::setprecision(17) << "step " << step;
      EXPECT_GE(b.lower, least - 1.5e-5) << std::setprecision(17) << "step " << step << " seeded with "
                                         << before.n;
    }
    EXPECT_NEAR(warm.lower, cold.lower, 1e-12);
    EXPECT_GT(carried.n, 0);
    for (int j = 0; j < carried.n; ++j) EXPECT_LT(carried.idx[j], S.planes().size());
  }
}

// A box of 6,912 triangles (each side a 24 x 24 grid) beside a sphere, faces shuffled: the scans
// run in blocks of faces, in parallel, so coplanar faces fall in many blocks. The set is the same
// on one thread and on all; it has 5 of the box's planes and the sphere's supporting faces; a face
// maps to a plane of its own (within the merging tolerance) exactly when no vertex lies beyond it.
TEST(SupportPlanes, SameSetOnAnyThreadCountFromBlocksOfFaces) {
  TriangleMesh box;
  const int N = 24;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const std::uint32_t base = static_cast<std::uint32_t>(box.vertices.size());
      for (int i = 0; i <= N; ++i)
        for (int j = 0; j <= N; ++j) {
          Vec3 p;
          p[axis] = side;
          p[(axis + 1) % 3] = static_cast<double>(i) / N;
          p[(axis + 2) % 3] = static_cast<double>(j) / N;
          box.vertices.push_back(p);
        }
      const auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(i * (N + 1) + j); };
      for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) {
          // Outward on side 1, flipped on side 0 (only the planes matter here, not the orientation).
          if (side == 1) {
            box.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            box.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
          } else {
            box.faces.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
            box.faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
          }
        }
    }
  TriangleMesh F = merge_meshes(box, make_icosphere(0.4, 3, Vec3(2.0, 0.5, 0.5)));
  std::mt19937_64 rng(7);
  std::shuffle(F.faces.begin(), F.faces.end(), rng);
  SupportPlanes one, all;
  tbb::task_arena(1).execute([&] { one = SupportPlanes::build(F); });
  all = SupportPlanes::build(F);
  ASSERT_FALSE(one.empty());
  EXPECT_FALSE(one.convex());
  ASSERT_EQ(one.planes().size(), all.planes().size());
  for (std::size_t k = 0; k < one.planes().size(); ++k) {
    const SupportPlane &a = one.planes()[k], &b = all.planes()[k];
    EXPECT_TRUE(a.n == b.n && a.d == b.d && a.e == b.e) << "plane " << k;
  }
  expect_supporting(F, one);
  const double slack = 1e-9 * F.bbox().diagonal();
  std::size_t box_planes = 0, sphere_planes = 0;
  for (const SupportPlane& p : one.planes())
    ((p.n.cwiseAbs().array() > 0.0).count() == 1 ? box_planes : sphere_planes) += 1;
  EXPECT_EQ(box_planes, 5u);  // not x = 1: the sphere lies beyond it
  EXPECT_GT(sphere_planes, 0u);
  for (std::uint32_t f = 0; f < F.faces.size(); ++f) {
    ASSERT_EQ(one.plane_of(f), all.plane_of(f)) << "face " << f;
    const TrianglePlane pl =
        make_triangle_plane(F.vertices[F.faces[f][0]], F.vertices[F.faces[f][1]], F.vertices[F.faces[f][2]]);
    double beyond = -HUGE_VAL;  // the farthest vertex beyond the face's plane, rounded down
    for (const Vec3& v : F.vertices) {
      const PlaneOffset o = plane_offset(pl.n, pl.d, v);
      beyond = std::max(beyond, o.value - o.error);
    }
    if (one.plane_of(f) < 0) {
      EXPECT_GT(beyond, slack) << "face " << f << " has no plane but supports F";
    } else {
      const SupportPlane& q = one.planes()[static_cast<std::size_t>(one.plane_of(f))];
      EXPECT_LE((q.n - pl.n).cwiseAbs().maxCoeff(), 2e-9) << "face " << f;
      EXPECT_LE(beyond, q.e + 1e-8) << "face " << f;
    }
  }
  // The budget: beyond it, the same (empty) answer on any number of threads.
  tbb::task_arena(1).execute([&] { one = SupportPlanes::build(F, 1e3); });
  all = SupportPlanes::build(F, 1e3);
  EXPECT_TRUE(one.empty());
  EXPECT_TRUE(all.empty());
}

// What a scan of every vertex gives as a plane's e: the largest rounded-up offset.
double scanned_offset(const TriangleMesh& F, const Vec3& n, double d) {
  double e = -HUGE_VAL;
  for (const Vec3& v : F.vertices) {
    const PlaneOffset o = plane_offset(n, d, v);
    e = std::max(e, round_up(o.value + o.error));
  }
  return e;
}

// The planes are searched by a box tree over F's vertices: each plane's e is exactly what a scan
// of every vertex gives (the largest rounded-up offset), and a face has a plane exactly when a scan
// finds no vertex beyond it. A 2,500-sided thin tube's 2,502 planes are found within the default
// budget (a scan of every vertex passed it: 2,500 outer faces x 10,000 vertices).
TEST(SupportPlanes, TreeSearchGivesAScansPlanesAndOffsets) {
  std::mt19937_64 rng(11);
  TriangleMesh bumpy = make_icosphere(1.0, 3);
  std::uniform_real_distribution<double> u(0.97, 1.03);
  for (Vec3& v : bumpy.vertices) v *= u(rng);
  const TriangleMesh meshes[] = {make_tube(0.98, 1.0, 4.0, 2500), make_torus(1.0, 0.35, 24, 12), bumpy,
                                 make_icosphere(1.0, 2, Vec3(1e5, -2e5, 3e5))};
  for (const TriangleMesh& F : meshes) {
    const SupportPlanes S = SupportPlanes::build(F);
    ASSERT_FALSE(S.empty()) << F.faces.size() << " faces";
    for (const SupportPlane& p : S.planes())
      ASSERT_EQ(p.e, scanned_offset(F, p.n, p.d)) << std::setprecision(17) << "n " << p.n.transpose() << " d " << p.d;
    const double slack = 1e-9 * F.bbox().diagonal();
    const std::uint32_t stride = F.faces.size() > 5000 ? 7 : 1;  // the tube: every 7th face
    for (std::uint32_t f = 0; f < F.faces.size(); f += stride) {
      const TrianglePlane pl =
          make_triangle_plane(F.vertices[F.faces[f][0]], F.vertices[F.faces[f][1]], F.vertices[F.faces[f][2]]);
      ASSERT_EQ(S.plane_of(f) >= 0, scanned_offset(F, pl.n, pl.d) <= slack) << "face " << f << " of " << F.faces.size();
    }
  }
  EXPECT_EQ(SupportPlanes::build(meshes[0]).planes().size(), 2502u);
}

TEST(SupportPlanes, HalvedRateFailsTheCheck) {
  const LineCheck c = check_lines(tetrahedron(), 11, 150, 0.5);
  EXPECT_GT(c.violations, 0);
}

}  // namespace
}  // namespace cdbench
