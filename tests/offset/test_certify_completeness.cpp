#include <gtest/gtest.h>

#include <iomanip>
#include <random>

#include "mesh/shapes.h"
#include "offset/certify_band.h"
#include "offset/certify_completeness.h"
#include "offset/fast_signed_distance.h"
#include "offset/mesh_level_set.h"

namespace cdbench {
namespace {

TriangleMesh offset_near(const SignedDistance& sdf, const Vec3& center, double radius, double d) {
  const FastSignedDistance fast(sdf);
  const std::function<double(const Vec3&)> f = [&](const Vec3& p) { return fast(p) - d; };
  LevelSetMeshOptions o;
  o.radius_bound = 0.25;
  o.distance_bound = 0.01;
  return mesh_level_set(f, center, radius, level_set_seeds(f, center, radius, 32), o);
}

TEST(CertifyCompleteness, SphereOffsetsAreComplete) {
  const SignedDistance sdf(make_icosphere(1.0, 2));
  for (double d : {-0.4, 0.3}) {
    const TriangleMesh m = offset_near(sdf, Vec3::Zero(), 3.0, d);
    const double eps = certify_band(sdf, m, d, BandOptions{}).epsilon;
    const CompletenessResult r = certify_completeness(sdf, m, d, eps);
    EXPECT_TRUE(r.complete) << "missed " << r.missed.size() << ", unresolved " << r.unresolved.size();
  }
}

TEST(CertifyCompleteness, DroppedComponentIsFound) {
  // Two balls; an offset mesh of only the first must be reported incomplete, near the second.
  const TriangleMesh two = merge_meshes(make_icosphere(1.0, 2), make_icosphere(0.6, 2, Vec3(4, 0, 0)));
  const SignedDistance sdf(two);
  const double d = -0.2;
  const TriangleMesh first = offset_near(sdf, Vec3::Zero(), 1.5, d);
  const double eps = certify_band(sdf, first, d, BandOptions{}).epsilon;
  const CompletenessResult r = certify_completeness(sdf, first, d, eps);
  EXPECT_FALSE(r.complete);
  ASSERT_FALSE(r.missed.empty());
  EXPECT_NEAR(r.missed[0].x(), 4.0, 0.6);
  // With both components meshed it is complete.
  TriangleMesh both = merge_meshes(first, offset_near(sdf, Vec3(4, 0, 0), 1.0, d));
  const double eps2 = certify_band(sdf, both, d, BandOptions{}).epsilon;
  EXPECT_TRUE(certify_completeness(sdf, both, d, eps2).complete);
}

TEST(CertifyCompleteness, EmptyLevels) {
  const SignedDistance sdf(make_box(Vec3(0, 0, 0), Vec3(2, 2, 2)));  // max penetration 1
  EXPECT_TRUE(certify_completeness(sdf, TriangleMesh{}, -1.2, 0.01).complete);   // below the deepest point
  const CompletenessResult r = certify_completeness(sdf, TriangleMesh{}, -0.5, 0.01);  // not empty
  EXPECT_FALSE(r.complete);
  EXPECT_FALSE(r.missed.empty());
}

// The bound on w.(p - c) over the part of a triangle within rho of c never falls below the largest
// value at densely sampled points of that part (random, long, sliver and far triangles, balls that
// cut or miss the plane), and for a long triangle it is the disc's value, far below the vertices'.
TEST(MaxTowards, BoundsTheTrianglePartInTheBallFromAbove) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.0, 1.0);
  int sampled = 0;
  for (int k = 0; k < 400; ++k) {
    const double scale = k % 4 == 0 ? 50.0 : 1.0;  // long triangles, far wider than the ball
    const Vec3 a = scale * Vec3(u(rng), u(rng), u(rng)), b = scale * Vec3(u(rng), u(rng), u(rng));
    Vec3 q = scale * Vec3(u(rng), u(rng), u(rng));
    if (k % 4 == 1) q = a + (b - a) * pos(rng) + 1e-6 * Vec3(u(rng), u(rng), u(rng));  // sliver
    const Vec3 c = Vec3(u(rng), u(rng), u(rng)), w = Vec3(u(rng), u(rng), u(rng)).normalized();
    const double rho = 0.2 + 1.5 * pos(rng);
    const double bound = max_towards(w, c, rho, a, b, q);
    double best = -HUGE_VAL;
    const int n = 300;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 p = a + (double(i) / n) * (b - a) + (double(j) / n) * (q - a);
        if ((p - c).norm() <= rho) best = std::max(best, w.dot(p - c));
      }
    if (best > -HUGE_VAL) ++sampled;
    // The samples are rounded points of the triangle: 1e-12 x scale covers that, far below a real miss.
    ASSERT_LE(best, bound + 1e-12 * scale) << std::setprecision(17) << "case " << k << " rho " << rho << " best " << best << " bound " << bound;
  }
  EXPECT_GT(sampled, 100);
  // A long triangle in z = 0, a ball of radius 2 about (0, 0, 1): along x the part in the ball
  // reaches sqrt(3), its vertices 100.
  const double disc = max_towards(Vec3(1, 0, 0), Vec3(0, 0, 1), 2.0, Vec3(-100, -100, 0), Vec3(100, -100, 0),
                                  Vec3(0, 100, 0));
  EXPECT_GE(disc, std::sqrt(3.0));
  EXPECT_LT(disc, std::sqrt(3.0) + 1e-9);
  // A ball that misses the plane holds no point of the triangle.
  EXPECT_EQ(max_towards(Vec3(1, 0, 0), Vec3(0, 0, 3), 2.0, Vec3(-100, -100, 0), Vec3(100, -100, 0), Vec3(0, 100, 0)),
            -HUGE_VAL);
}

}  // namespace
}  // namespace cdbench
