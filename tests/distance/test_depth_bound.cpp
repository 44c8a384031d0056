// The translated depth bound (distance/depth_bound.h) against exact rational distances: for random
// cells in and around closed meshes and random translations, no point of the translated cell is
// farther from the surface than the bound; a bound with the translation's sign flipped fails the
// same check; and along a face's normal the bound is exact, along the face it grows more slowly
// than the shifted Lipschitz bound.
#include <gtest/gtest.h>

#include <iomanip>
#include <random>

#include "distance/depth_bound.h"
#include "distance/point_triangle_distance.h"
#include "exact_reference.h"
#include "mesh/shapes.h"

namespace cdbench {
namespace {

using testing::Epeck;
using testing::exact_squared_distance;

// Whether sqrt(exact_sq) <= bound, decided exactly.
bool within(const Epeck::FT& exact_sq, double bound) { return bound >= 0 && exact_sq <= Epeck::FT(bound) * Epeck::FT(bound); }

// Points of the triangle abc: corners, edge midpoints, centroid and a few interior points.
std::vector<Vec3> samples(const std::array<Vec3, 3>& v) {
  std::vector<Vec3> out;
  const double w[][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {.5, .5, 0}, {0, .5, .5}, {.5, 0, .5}, {1. / 3, 1. / 3, 1. / 3},
                         {.7, .2, .1}, {.1, .7, .2}, {.2, .1, .7}};
  for (const auto& c : w) out.push_back(c[0] * v[0] + c[1] * v[1] + c[2] * v[2]);
  return out;
}

struct Checked {
  int cells = 0, points = 0, violations = 0;
};

// Random small triangles (cells) around a mesh, each with its bound from depth_upper_bound, then
// translated by random D; every sampled point of the translated cell must be within the bound of
// the surface. `flip` evaluates the bound at -D instead (a wrong bound, which must be caught).
Checked check_mesh(const TriangleMesh& m, std::uint64_t seed, int cells, bool flip) {
  const SignedDistance sdf(m);
  const Aabb box = m.bbox();
  const double diag = box.diagonal();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  std::vector<std::uint32_t> scratch;
  Checked r;
  while (r.cells < cells) {
    const Vec3 c = box.lo + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.extent());
    const double size = diag * (0.002 + 0.05 * u(rng));
    std::array<Vec3, 3> v;
    for (Vec3& x : v) x = c + size * Vec3(s(rng), s(rng), s(rng));
    const Vec3 centre = (v[0] + v[1] + v[2]) / 3.0;
    double radius = 0;
    for (const Vec3& x : v) radius = std::max(radius, (x - centre).norm());
    const Interval ud = sdf.unsigned_distance(centre);
    TranslatedDepthBound b;
    const double depth = depth_upper_bound(sdf, centre, ud.hi + 2 * radius, v.data(), 3, scratch, nullptr, nullptr,
                                           nullptr, &b);
    if (!(depth < HUGE_VAL) || b.n != 3) continue;
    ++r.cells;
    // At D = 0 the moments bound is never below the bound it extends (Jensen).
    EXPECT_GE(translated_depth(b, Vec3::Zero()), depth * (1 - 1e-9));  // up to their rounding margins
    for (int k = 0; k < 4; ++k) {
      // Translations from tiny to a tenth of the diagonal, any direction.
      const Vec3 D = std::pow(10.0, -4.0 + 3.0 * u(rng)) * diag * Vec3(s(rng), s(rng), s(rng)).normalized();
      const double bound = translated_depth(b, flip ? Vec3(-D) : D);
      for (const Vec3& x : samples(v)) {
        ++r.points;
        const Vec3 p = x + D;
        if (!within(exact_squared_distance(p, m), bound)) {
          ++r.violations;
          if (!flip)
            ADD_FAILURE() << std::setprecision(17) << "point (" << p.x() << ", " << p.y() << ", " << p.z()
                          << ") is farther than the bound " << bound;
        }
      }
    }
  }
  return r;
}

TEST(TranslatedDepth, BoundsEveryPointOfTheTranslatedCellExactly) {
  for (const auto& [name, m] : std::vector<std::pair<std::string, TriangleMesh>>{
           {"torus", make_torus(2.0, 0.6, 24, 12)},
           {"sphere", make_icosphere(1.0, 2)},
           {"box", make_box(Vec3(0, 0, 0), Vec3(2, 1, 0.5))}}) {
    SCOPED_TRACE(name);
    const Checked r = check_mesh(m, 5, 200, false);
    EXPECT_EQ(r.cells, 200);
    EXPECT_EQ(r.violations, 0) << "of " << r.points;
  }
}

TEST(TranslatedDepth, AWrongBoundIsCaught) {
  // Evaluating at -D (the sign of W.D flipped) must fail somewhere: the check above has power.
  const Checked r = check_mesh(make_torus(2.0, 0.6, 24, 12), 5, 60, true);
  EXPECT_GT(r.violations, 0);
}

TEST(TranslatedDepth, ExactAlongTheNormalSlowerThanLipschitzAlongTheFace) {
  // A cell 0.2 above the bottom face (z = 0) of a box, well inside one of its two triangles (the
  // diagonal is x + y = 4), which is then the only one within reach.
  const TriangleMesh m = make_box(Vec3(0, 0, 0), Vec3(4, 4, 2));
  const SignedDistance sdf(m);
  const std::array<Vec3, 3> v{Vec3(0.9, 0.9, 0.2), Vec3(1.1, 0.9, 0.2), Vec3(1.0, 1.1, 0.2)};
  const Vec3 centre = (v[0] + v[1] + v[2]) / 3.0;
  std::vector<std::uint32_t> scratch;
  TranslatedDepthBound b;
  const double depth = depth_upper_bound(sdf, centre, 0.6, v.data(), 3, scratch, nullptr, nullptr, nullptr, &b);
  ASSERT_EQ(b.n, 3);
  EXPECT_NEAR(depth, 0.2, 1e-12);
  EXPECT_NEAR(translated_depth(b, Vec3::Zero()), 0.2, 1e-12);
  // Deeper along the normal: exact.
  EXPECT_NEAR(translated_depth(b, Vec3(0, 0, 0.3)), 0.5, 1e-12);
  // Along the face the depth stays 0.2; the bound grows like sqrt(0.2^2 + |D|^2), not 0.2 + |D|.
  const double along = translated_depth(b, Vec3(0.1, 0, 0));
  EXPECT_GE(along, 0.2);
  EXPECT_NEAR(along, std::sqrt(0.2 * 0.2 + 0.1 * 0.1), 1e-12);
  EXPECT_LT(along, 0.2 + 0.1 - 0.07);
}

TEST(PointOfTriangleNear, LiesInTheTriangleWithinItsErrorBound) {
  // Random, sliver, degenerate and far-off triangles at several scales: the computed point is within
  // closest_point_error of the closed triangle (exact distance), and as near to p as the closest point.
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int n = 0;
  for (double scale : {1e-3, 1.0, 1e4}) {
    for (int k = 0; k < 3000; ++k) {
      const Vec3 off = scale * 10 * Vec3(u(rng), u(rng), u(rng));
      Vec3 a = off + scale * Vec3(u(rng), u(rng), u(rng)), b = off + scale * Vec3(u(rng), u(rng), u(rng));
      Vec3 c = off + scale * Vec3(u(rng), u(rng), u(rng));
      if (k % 3 == 1) c = a + (b - a) * u(rng) + 1e-9 * scale * Vec3(u(rng), u(rng), u(rng));  // sliver
      if (k % 3 == 2) c = b;                                                                  // degenerate
      const Vec3 p = off + 3 * scale * Vec3(u(rng), u(rng), u(rng));
      const Vec3 q = point_of_triangle_near(p, a, b, c);
      ASSERT_TRUE(within(testing::exact_squared_distance(q, a, b, c), closest_point_error(a, b, c)))
          << std::setprecision(17) << "q (" << q.x() << ", " << q.y() << ", " << q.z() << ")";
      EXPECT_LE((p - q).norm(), (p - closest_point_on_triangle(p, a, b, c)).norm() * (1 + 1e-9) + 1e-12 * scale);
      ++n;
    }
  }
  EXPECT_EQ(n, 9000);
}

}  // namespace
}  // namespace cdbench
