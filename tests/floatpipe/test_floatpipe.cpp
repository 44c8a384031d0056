// The float pipeline against analytic answers: grid offsets of a sphere, first contacts of a
// sphere with a sphere's and a torus's offsets (including a line through the torus's hole), and
// the pose-set builder's bundle (statuses, determinism).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "floatpipe/float_poseset.h"
#include "distance/signed_distance.h"
#include "floatpipe/grid_offsets.h"
#include "mesh/shapes.h"
#include "mesh/write_mesh.h"
#include "poseset/pose_csv.h"
#include "util/error.h"
#include "test_scale.h"

namespace cdbench {
namespace {

double signed_volume(const TriangleMesh& m) {
  double v = 0.0;
  for (const Face& f : m.faces) v += m.vertices[f[0]].dot(m.vertices[f[1]].cross(m.vertices[f[2]])) / 6.0;
  return v;
}

TEST(GridOffsets, SphereLevelsAreSpheresWithinAVoxel) {
  const TriangleMesh s = make_icosphere(1.0, 4);  // inscribed: faces within 1e-3 of the sphere
  const GridSdf grid(s, {voxel_for_grid(s, 128), 0.3});
  const double h = grid.voxel();
  EXPECT_NEAR(h, 2.0 / 128, 1e-12);
  EXPECT_NEAR(grid.max_depth(), 1.0, h + 2e-3);
  for (double d : {-0.5, 0.0, 0.25}) {
    const TriangleMesh iso = grid.isosurface(d);
    ASSERT_GT(iso.faces.size(), 1000u) << d;
    double worst = 0.0;
    for (const Vec3& p : iso.vertices) worst = std::max(worst, std::abs(p.norm() - (1.0 + d)));
    EXPECT_LT(worst, 0.5 * h + 2e-3) << "level " << d;
    const double r = 1.0 + d;
    const double V = 4.0 / 3.0 * M_PI * r * r * r;  // dV/V = 3 dr/r
    EXPECT_NEAR(signed_volume(iso), V, 3.0 * (0.5 * h + 2e-3) / r * V) << "outward, closed: level " << d;
  }
  EXPECT_TRUE(grid.isosurface(-1.5).faces.empty());  // deeper than the max depth
}

// The pruned search must find exactly the deepest lattice point a brute-force scan of the whole
// fine lattice finds (same distance function), on shapes with a point, ring and sheet of maxima.
TEST(GridOffsets, DeepestLatticePointMatchesBruteForce) {
  const std::vector<TriangleMesh> shapes = {make_icosphere(1.0, 3), make_torus(1.0, 0.3, 48, 24),
                                            make_box(Vec3(-1.0, -0.7, -0.13), Vec3(1.1, 0.6, 0.17))};
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const TriangleMesh& m = shapes[k];
    const SignedDistance sdf(m);
    const auto dist = [&](const Vec3& p) { return sdf.unsigned_distance(p).mid(); };
    const auto inside = [&](const Vec3& p) { return sdf.side(p) < 0; };
    const double h = voxel_for_grid(m, 64);
    const GridSdf coarse(m, {4.0 * h, 0.0});
    const LatticeDepth found = deepest_lattice_point(coarse, h, dist, inside);
    double brute = 0.0;
    std::size_t interior = 0;
    const Vec3 lo = m.bbox().lo / h, hi = m.bbox().hi / h;
    for (double i = std::floor(lo.x()); i <= hi.x(); ++i)
      for (double j = std::floor(lo.y()); j <= hi.y(); ++j)
        for (double l = std::floor(lo.z()); l <= hi.z(); ++l) {
          const Vec3 p = Vec3(i, j, l) * h;
          const double d = dist(p);
          if (!inside(p)) continue;
          ++interior;
          brute = std::max(brute, d);
        }
    EXPECT_EQ(found.depth, brute) << "shape " << k;
    EXPECT_EQ(dist(found.point), found.depth) << "shape " << k;
    // Fewer evaluations than the interior's lattice points: 156, 3,064 and 8,929 of 136,015,
    // 26,232 and 23,040 measured (a point, a ring and a sheet of maxima; on a sheet every point of
    // the deepest layer ties and none can be pruned).
    EXPECT_LT(found.evaluations, interior / 2) << "shape " << k << ", " << interior << " interior points";
  }
}

// A band that reaches only as deep as the deepest level must give the same iso-surfaces as the
// whole interior.
TEST(GridOffsets, NarrowInteriorBandKeepsTheLevels) {
  const TriangleMesh s = make_icosphere(1.0, 4);
  const double h = voxel_for_grid(s, 96);
  const GridSdf full(s, {h, 0.1}), narrow(s, {h, 0.1, 0.3});
  for (double d : {-0.3, -0.1, 0.0, 0.1}) {
    const TriangleMesh a = full.isosurface(d), b = narrow.isosurface(d);
    ASSERT_GT(a.faces.size(), 1000u) << d;
    EXPECT_EQ(a.faces.size(), b.faces.size()) << d;
    EXPECT_NEAR(signed_volume(a), signed_volume(b), 1e-6 * std::abs(signed_volume(a))) << d;
  }
}

TEST(FloatPlacement, SphereOnSphereOffsets) {
  const TriangleMesh fixed = make_icosphere(1.0, 4), mover = make_icosphere(0.5, 4);
  const GridSdf grid(fixed, {voxel_for_grid(fixed, test_scale::pick(128, 64)), 0.3});  // tolerances in voxels
  const SweepMesh swept = make_sweep_mesh(mover.vertices, mover.faces);  // centres together: t0 = 0
  for (double d : {-0.3, 0.0, 0.25}) {
    const TriangleMesh iso = grid.isosurface(d);
    const SweepMesh level = make_sweep_mesh(iso.vertices, iso.faces);
    for (const Vec3& dir : {Vec3(0, 0, 1), Vec3(1, 1, 1).normalized(), Vec3(-0.3, 0.8, -0.52).normalized()}) {
      double lambda = 0.0;
      ASSERT_TRUE(float_first_contact(level, swept, dir, &lambda));
      // Centres 1 + d + 0.5 apart at contact; grid (half a voxel) and faceting (1e-3 each).
      EXPECT_NEAR(lambda, 1.5 + d, 0.5 * grid.voxel() + 3e-3) << "level " << d;
    }
  }
}

TEST(FloatPlacement, SphereThroughATorus) {
  // Torus R = 1, r = 0.3 around z; a sphere of radius 0.2 coming down the z axis touches the
  // level-d offset (a tube of radius 0.3 + d) where sqrt(1 + z^2) = 0.5 + d, or passes through
  // the hole when 0.5 + d < 1.
  const TriangleMesh torus = make_torus(1.0, 0.3, 96, 48), ball = make_icosphere(0.2, 4);
  const GridSdf grid(torus, {voxel_for_grid(torus, test_scale::pick(160, 80)), 0.7});  // tolerances in voxels
  const SweepMesh swept = make_sweep_mesh(ball.vertices, ball.faces);
  const Vec3 dir(0, 0, 1);
  for (double d : {0.1, 0.45}) {
    const TriangleMesh iso = grid.isosurface(d);
    double lambda = 0.0;
    EXPECT_FALSE(float_first_contact(make_sweep_mesh(iso.vertices, iso.faces), swept, dir, &lambda)) << "level " << d;
  }
  for (double d : {0.55, 0.6}) {
    const TriangleMesh iso = grid.isosurface(d);
    double lambda = 0.0;
    ASSERT_TRUE(float_first_contact(make_sweep_mesh(iso.vertices, iso.faces), swept, dir, &lambda)) << "level " << d;
    const double rho = 0.5 + d, z = std::sqrt(rho * rho - 1.0);
    // dz / d(rho) = rho / z amplifies the grid's and the faceting's error.
    EXPECT_NEAR(lambda, z, rho / z * (0.5 * grid.voxel() + 4e-3)) << "level " << d;
  }
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(FloatPoseSet, BundleOfASphere) {
  const std::string dir = testing::TempDir() + "/float_poseset_test";
  const TriangleMesh s = make_icosphere(1.0, 3);
  std::filesystem::create_directories(dir);
  write_off(s, dir + "/sphere.off");
  FloatPoseSetRequest rq;
  rq.fixed = {dir + "/sphere.off", &s};
  rq.levels = "-20%,0,0.1";
  rq.directions = 6;
  rq.orientations = 3;
  rq.grid = 96;
  rq.out = dir + "/a";
  const FloatPoseSetResult a = build_float_poseset(rq);
  EXPECT_EQ(a.placed, 54u);
  EXPECT_NEAR(a.max_depth, 1.0, a.voxel + 0.01);
  EXPECT_EQ(a.poseset["pipeline"], "float");
  EXPECT_EQ(a.poseset["grid"]["voxel"].get<double>(), a.voxel);
  std::ifstream in(rq.out + "/poses.csv");
  const std::vector<PoseRow> rows = read_pose_csv(in, "poses.csv");
  ASSERT_EQ(rows.size(), 54u);
  for (const PoseRow& r : rows) {
    EXPECT_EQ(r.status, PoseStatus::Float);
    EXPECT_TRUE(std::isnan(r.clearance_lo));
    // Sphere on itself: the centres 2 + d apart, whatever the orientation (faceting 4e-3 each).
    EXPECT_NEAR((r.t - Vec3::Zero()).norm(), 2.0 + r.target, 0.5 * a.voxel + 1e-2) << "pose " << r.pose;
    EXPECT_NEAR(r.t.normalized().dot(r.dir), 1.0, 1e-9);
  }
  EXPECT_DOUBLE_EQ(rows[1].target, 0.0);
  EXPECT_DOUBLE_EQ(rows[2].target, 0.1);
  // Deterministic: the same request gives the same bytes.
  rq.out = dir + "/b";
  build_float_poseset(rq);
  EXPECT_EQ(slurp(dir + "/a/poses.csv"), slurp(dir + "/b/poses.csv"));
  // Option errors name the option.
  rq.grid = 2;
  EXPECT_THROW(check_float_poseset_request(rq), std::exception);
  const auto message = [&](FloatPoseSetRequest r) -> std::string {
    try {
      build_float_poseset(r);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  // A voxel finer than the grid's limit of 4096 cells (OpenVDB threw its own exception at 1e-9).
  FloatPoseSetRequest fine = rq;
  fine.voxel = 1e-9;
  fine.out = dir + "/fine";
  EXPECT_NE(message(fine).find("--voxel: 1e-09 gives"), std::string::npos) << message(fine);
  // A plate between the lattice's planes z = 0.25 and 0.5: no lattice point inside, so no scale for
  // percentage levels (every one lay at d = 0); absolute levels still work.
  const TriangleMesh plate = make_box(Vec3(-1, -1, 0.3), Vec3(1, 1, 0.31));
  write_off(plate, dir + "/plate.off");
  FloatPoseSetRequest coarse = rq;
  coarse.fixed = {dir + "/plate.off", &plate};
  coarse.voxel = 0.25;
  coarse.out = dir + "/coarse";
  EXPECT_NE(message(coarse).find("percentage levels need the grid's maximum depth"), std::string::npos)
      << message(coarse);
  coarse.levels = "-0.002,0,0.1";
  EXPECT_EQ(message(coarse), "");
}

}  // namespace
}  // namespace cdbench
