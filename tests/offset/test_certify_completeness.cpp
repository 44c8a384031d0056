#include <gtest/gtest.h>

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

}  // namespace
}  // namespace cdbench
