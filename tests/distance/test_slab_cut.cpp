#include "distance/slab_cut.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

namespace cdbench {
namespace {

// The property the slab bounds rely on: the hull of the cut's points, widened by err, holds every
// point of the cell within the slab. Checked with convex functions (linear ones and distances to a
// point): their value at a sampled point of the cut cell never exceeds their largest value over the
// cut's points plus err. Boxes and triangles, random slabs, one plane or two, planes through
// corners (ends within their error of a plane).
template <class F>
double max_over(const SlabCut& cut, const F& f) {
  double m = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < cut.n; ++k) m = std::max(m, f(cut.q[static_cast<std::size_t>(k)]));
  return m;
}

void check_cut(const Vec3* v, int n_corners, const std::array<int, 2>* edges, int n_edges, const Vec3& n, double hs,
               double ls, std::mt19937_64& rng, const std::function<Vec3(std::mt19937_64&)>& sample) {
  std::array<PlaneOffset, 8> ov;
  for (int k = 0; k < n_corners; ++k) ov[static_cast<std::size_t>(k)] = plane_offset(n, 0.0, v[k]);
  SlabCut cut;
  ASSERT_TRUE(cut_by_slab(v, ov.data(), n_corners, edges, n_edges, hs, ls, cut));
  std::uniform_real_distribution<double> u(-1, 1);
  for (int f = 0; f < 20; ++f) {
    const Vec3 a{u(rng), u(rng), u(rng)}, p{3 * u(rng), 3 * u(rng), 3 * u(rng)};
    const auto linear = [&](const Vec3& x) { return a.dot(x); };
    const auto dist = [&](const Vec3& x) { return (x - p).norm(); };
    const double lin_max = max_over(cut, linear) + a.norm() * cut.err + 1e-12;
    const double dist_max = max_over(cut, dist) + cut.err + 1e-12;
    for (int s = 0; s < 200; ++s) {
      const Vec3 x = sample(rng);
      const double t = n.dot(x);
      if (t > hs || t < ls) continue;
      EXPECT_LE(linear(x), lin_max);
      EXPECT_LE(dist(x), dist_max);
    }
  }
}

TEST(SlabCut, BoxCutCoversItsPartWithinTheSlab) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  const double inf = std::numeric_limits<double>::infinity();
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 c{u(rng), u(rng), u(rng)};
    const double half = 0.1 + 0.5 * (u(rng) + 1);
    std::array<Vec3, 8> v;
    for (int k = 0; k < 8; ++k) v[k] = c + Vec3(k & 1 ? half : -half, k & 2 ? half : -half, k & 4 ? half : -half);
    Vec3 n{u(rng), u(rng), u(rng)};
    if (trial % 5 == 0) n = Vec3(0, 0, 1);  // planes parallel to faces
    const double mid = n.dot(c) + half * u(rng), thick = 0.3 * half * (u(rng) + 1);
    double hs = mid + thick, ls = mid - thick;
    if (trial % 7 == 1) hs = n.dot(v[trial % 8]);  // through a corner
    if (trial % 3 == 2) ls = -inf;                  // one plane
    check_cut(v.data(), 8, kBoxEdges.data(), 12, n, hs, ls, rng, [&](std::mt19937_64& g) {
      return Vec3{c.x() + half * u(g), c.y() + half * u(g), c.z() + half * u(g)};
    });
  }
}

TEST(SlabCut, TriangleCutCoversItsPartWithinTheSlab) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1, 1), w(0, 1);
  const std::array<std::array<int, 2>, 3> edges{{{0, 1}, {1, 2}, {2, 0}}};
  for (int trial = 0; trial < 200; ++trial) {
    const std::array<Vec3, 3> v{Vec3{u(rng), u(rng), u(rng)}, Vec3{u(rng), u(rng), u(rng)}, Vec3{u(rng), u(rng), u(rng)}};
    const Vec3 n{u(rng), u(rng), u(rng)};
    const double a = n.dot(v[0]), b = n.dot(v[1]);
    const double hs = std::max(a, b) - 0.2 * std::abs(a - b) * w(rng), ls = std::min(a, b) + 0.2 * std::abs(a - b) * w(rng);
    check_cut(v.data(), 3, edges.data(), 3, n, hs, ls, rng, [&](std::mt19937_64& g) {
      double s = w(g), t = w(g);
      if (s + t > 1) s = 1 - s, t = 1 - t;
      return v[0] + s * (v[1] - v[0]) + t * (v[2] - v[0]);
    });
  }
}

TEST(SlabCut, NothingLeftWhenTheSlabMissesTheCell) {
  std::array<Vec3, 8> v;
  for (int k = 0; k < 8; ++k) v[k] = Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
  std::array<PlaneOffset, 8> ov;
  const Vec3 n(0, 0, 1);
  for (int k = 0; k < 8; ++k) ov[k] = plane_offset(n, 0.0, v[k]);
  SlabCut cut;
  ASSERT_TRUE(cut_by_slab(v.data(), ov.data(), 8, kBoxEdges.data(), 12, 3.0, 2.0, cut));
  EXPECT_EQ(cut.n, 0);
  // A slab through the middle: the four crossings of each plane, no corner.
  ASSERT_TRUE(cut_by_slab(v.data(), ov.data(), 8, kBoxEdges.data(), 12, 0.75, 0.25, cut));
  EXPECT_EQ(cut.n, 8);
  for (int k = 0; k < cut.n; ++k) EXPECT_EQ(cut.corner_of[k], -1);
}

// triangles_span_in_box: every sampled point of the triangles within the box has n.y in [l, h]
// (long double products), on random triangles from small to long ones crossing the box, axes of
// the triangles' own normals and random ones; and a long triangle counts by its part in the box.
TEST(SlabCut, TrianglesSpanInABoxHoldsTheirPointsInIt) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1, 1), w(0, 1);
  int inside = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 c{u(rng), u(rng), u(rng)};
    const double hk = 0.05 + 0.5 * w(rng), reach = trial % 3 == 0 ? 100.0 : 2.0;
    TriangleMesh m;
    std::vector<std::uint32_t> ids;
    for (std::uint32_t j = 0; j < 4; ++j) {
      const Vec3 p = c + hk * Vec3{u(rng), u(rng), u(rng)};  // a point of the box on each triangle
      const Vec3 a = p + reach * Vec3{u(rng), u(rng), u(rng)}, b = p + reach * Vec3{u(rng), u(rng), u(rng)};
      const double wa = w(rng), wb = w(rng);
      const Vec3 q = p + (p - a) * wa + (p - b) * wb;  // p inside (for most draws)
      m.vertices.insert(m.vertices.end(), {a, b, q});
      m.faces.push_back({3 * j, 3 * j + 1, 3 * j + 2});
      ids.push_back(j);
    }
    std::vector<TrianglePlane> planes;
    for (const Face& f : m.faces) planes.push_back(make_triangle_plane(m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]));
    const Vec3 n = trial % 2 ? planes[0].n : Vec3{u(rng), u(rng), u(rng)};
    const Interval s = triangles_span_in_box(m, planes, ids, n, c, hk);
    for (const Face& f : m.faces)
      for (int k = 0; k < 2000; ++k) {
        double x = w(rng), y = w(rng);
        if (x + y > 1) x = 1 - x, y = 1 - y;
        const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &q = m.vertices[f[2]];
        const Vec3 pt = a + x * (b - a) + y * (q - a);
        if (((pt - c).cwiseAbs().array() > hk).any()) continue;
        ++inside;
        const long double t = static_cast<long double>(n[0]) * pt[0] + static_cast<long double>(n[1]) * pt[1] +
                              static_cast<long double>(n[2]) * pt[2];
        EXPECT_LE(t, s.hi) << trial;
        EXPECT_GE(t, s.lo) << trial;
      }
  }
  EXPECT_GT(inside, 10000);
  // A long tilted triangle through a small box: its vertices span 200 along n, its part in the box
  // about the box's size.
  TriangleMesh m;
  m.vertices = {Vec3(-100, -100, -50), Vec3(100, -100, 50), Vec3(0, 100, 0)};
  m.faces = {{0, 1, 2}};
  const std::vector<TrianglePlane> planes{make_triangle_plane(m.vertices[0], m.vertices[1], m.vertices[2])};
  const Interval s = triangles_span_in_box(m, planes, {0}, Vec3(0, 0, 1), Vec3(0, 0, 0), 0.01);
  EXPECT_LT(s.hi - s.lo, 0.1);
  EXPECT_GE(s.hi, 0.005);  // the box holds points of the plane z = x / 2 up to z = 0.005
  EXPECT_LE(s.lo, -0.005);
}

}  // namespace
}  // namespace cdbench
