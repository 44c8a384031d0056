#include <gtest/gtest.h>

#include <random>

#include "distance/signed_distance.h"
#include "mesh/shapes.h"
#include "mesh/validate_mesh.h"
#include "offset/fast_signed_distance.h"
#include "offset/level_list.h"
#include "offset/mesh_level_set.h"
#include "util/error.h"

namespace cdbench {
namespace {

TEST(LevelList, AbsolutePercentAndRanges) {
  const auto l = parse_level_list("-0.5, 0.2,-80%,-25%:25%:25%");
  ASSERT_EQ(l.size(), 6u);
  EXPECT_EQ(l[0].value, -0.5);
  EXPECT_FALSE(l[0].percent);
  EXPECT_EQ(l[2].value, -80.0);
  EXPECT_TRUE(l[2].percent);
  EXPECT_EQ(l[3].value, -25.0);
  EXPECT_EQ(l[4].value, 0.0);
  EXPECT_EQ(l[5].value, 25.0);
  EXPECT_DOUBLE_EQ(level_distance(l[2], 2.0), -1.6);
  EXPECT_EQ(parse_level_list("0:1:0.1").size(), 11u);  // rounding must not drop the end point
}

TEST(LevelList, ErrorsNameTheItem) {
  for (const char* bad : {"", "abc", "1,,2", "1:2", "1%:2:1", "2:1:0.5", "0:1:0", "0:1e9:1", "nan", "5%%"}) {
    try {
      parse_level_list(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--levels"), std::string::npos);
    }
  }
}

TEST(FastSignedDistance, AgreesWithTheCertifiedOne) {
  for (const TriangleMesh& m : {make_icosphere(1.0, 3), make_torus(2.0, 0.5, 32, 16)}) {
    const SignedDistance sdf(m);
    const FastSignedDistance fast(sdf);
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(-3, 3);
    for (int k = 0; k < 3000; ++k) {
      const Vec3 p(u(rng), u(rng), u(rng));
      const Interval s = sdf.signed_distance(p);
      const double f = fast(p);
      EXPECT_GE(f, s.lo - 1e-12);
      EXPECT_LE(f, s.hi + 1e-12);
    }
  }
}

TEST(MeshLevelSet, SphereOffsetsAreValidAndNearTheLevel) {
  const TriangleMesh sphere = make_icosphere(1.0, 2);
  const SignedDistance sdf(sphere);
  const FastSignedDistance fast(sdf);
  for (double d : {-0.5, 0.3}) {
    const std::function<double(const Vec3&)> f = [&](const Vec3& p) { return fast(p) - d; };
    const std::vector<Vec3> seeds = level_set_seeds(f, Vec3::Zero(), 2.0 + d, 16);
    ASSERT_EQ(seeds.size(), 16u);
    for (const Vec3& p : seeds) EXPECT_NEAR(f(p), 0.0, 1e-12);
    LevelSetMeshOptions o;
    o.radius_bound = 0.1;
    o.distance_bound = 0.01;
    const TriangleMesh m = mesh_level_set(f, Vec3::Zero(), 2.0 + d, seeds, o);
    const ValidatedMesh v = validate_mesh(m);
    EXPECT_TRUE(v.report.valid());
    EXPECT_EQ(v.report.genus, 0);
    EXPECT_GT(m.faces.size(), 100u);
    for (const Vec3& p : m.vertices) EXPECT_NEAR(fast(p), d, 1e-6);
  }
}

}  // namespace
}  // namespace cdbench
