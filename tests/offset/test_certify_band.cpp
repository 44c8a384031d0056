#include <gtest/gtest.h>

#include <random>

#include "mesh/shapes.h"
#include "offset/certify_band.h"
#include "offset/fast_signed_distance.h"
#include "offset/mesh_level_set.h"

namespace cdbench {
namespace {

TriangleMesh offset_of(const SignedDistance& sdf, double d, double distance_bound) {
  const FastSignedDistance fast(sdf);
  const std::function<double(const Vec3&)> f = [&](const Vec3& p) { return fast(p) - d; };
  const double radius = 3.0 + std::max(d, 0.0);
  LevelSetMeshOptions o;
  o.radius_bound = 0.25;
  o.distance_bound = distance_bound;
  return mesh_level_set(f, Vec3::Zero(), radius, level_set_seeds(f, Vec3::Zero(), radius, 32), o);
}

// Independent dense check: certified signed distances at many points of every face lie in the band.
void expect_samples_inside_band(const SignedDistance& sdf, const TriangleMesh& m, double d, const BandResult& band) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::size_t i = 0; i < m.faces.size(); ++i) {
    const Face& f = m.faces[i];
    for (int k = 0; k < 6; ++k) {
      double s = u(rng), t = u(rng);
      if (s + t > 1) { s = 1 - s; t = 1 - t; }
      const Vec3 p = m.vertices[f[0]] + s * (m.vertices[f[1]] - m.vertices[f[0]]) + t * (m.vertices[f[2]] - m.vertices[f[0]]);
      const Interval sd = sdf.signed_distance(p);
      ASSERT_GE(sd.lo, d - band.face_epsilon[i]) << "face " << i;
      ASSERT_LE(sd.hi, d + band.face_epsilon[i]) << "face " << i;
    }
  }
}

TEST(CertifyBand, SphereOffsetsBothWays) {
  const SignedDistance sdf(make_icosphere(1.0, 2));
  for (double d : {-0.4, 0.3}) {
    const TriangleMesh m = offset_of(sdf, d, 0.01);
    BandOptions o;
    o.target = 0.001;
    const BandResult band = certify_band(sdf, m, d, o);
    EXPECT_EQ(band.faces_touching, 0u);
    EXPECT_LT(band.epsilon, 0.02);
    EXPECT_GT(band.epsilon, 0.0);
    expect_samples_inside_band(sdf, m, d, band);
    // A deeper second pass on the widest faces never widens a band and stays rigorous.
    o.second_pass_above = 0.8 * band.epsilon;
    const BandResult deeper = certify_band(sdf, m, d, o);
    EXPECT_LE(deeper.epsilon, band.epsilon);
    for (std::size_t i = 0; i < m.faces.size(); ++i) EXPECT_LE(deeper.face_epsilon[i], band.face_epsilon[i]);
    expect_samples_inside_band(sdf, m, d, deeper);
  }
}

TEST(CertifyBand, DisplacedVertexWidensTheBand) {
  const SignedDistance sdf(make_icosphere(1.0, 2));
  TriangleMesh m = offset_of(sdf, 0.3, 0.01);
  BandOptions o;
  o.target = 0.001;
  const double before = certify_band(sdf, m, 0.3, o).epsilon;
  m.vertices[0] *= 1.05;  // about 0.065 off the level
  const BandResult after = certify_band(sdf, m, 0.3, o);
  EXPECT_GT(after.epsilon, 0.06);
  EXPECT_GT(after.epsilon, before);
}

TEST(CertifyBand, FaceCrossingTheSurfaceIsFlagged) {
  const SignedDistance sdf(make_icosphere(1.0, 2));
  TriangleMesh m = make_box(Vec3(-0.5, -0.5, -0.5), Vec3(2, 2, 2));  // crosses the sphere
  const BandResult band = certify_band(sdf, m, 0.1, BandOptions{});
  EXPECT_GT(band.faces_touching, 0u);
}

}  // namespace
}  // namespace cdbench
