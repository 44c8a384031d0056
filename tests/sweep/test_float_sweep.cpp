// The float twins of the sweeps (the float pipeline's placement) against the exact ones, and the
// translated sphere tree against a rebuilt one.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "mesh/shapes.h"
#include "placed_sweep_mesh.h"
#include "sweep/mesh_sweep.h"
#include "sweep/triangle_sweep.h"

namespace cdbench {
namespace {

using test::placed;

// Random generic pairs: the float sweep finds the same contacts, at the same times up to rounding
// (relative 1e-9 of the scale). Disagreements on whether a pair touches come from configurations
// within rounding of a cell boundary; in generic random pairs they must be rare (documented band).
TEST(FloatSweep, AgreesWithTheExactSweepOnRandomPairs) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0, disagree = 0, far_times = 0;
  const int n = 100000;
  for (int k = 0; k < n; ++k) {
    Triangle A, B;
    for (int i = 0; i < 3; ++i) {
      A[i] = Vec3{u(rng), u(rng), u(rng)};
      B[i] = Vec3{u(rng), u(rng), u(rng)} + Vec3(0.5, 0.0, 0.0);
    }
    const Vec3 v{u(rng), u(rng), u(rng)};
    if (v.norm() < 1e-3) continue;
    const LineContact e = line_contact(A, B, v);
    const FloatLineContact f = line_contact_float(A, B, v);
    if (e.hit != f.hit) {
      ++disagree;
      continue;
    }
    if (!e.hit) continue;
    ++hits;
    const double scale = 1.0 + std::abs(e.t_in.lo) + std::abs(e.t_out.lo);
    if (std::abs(f.t_in - e.t_in.lo) > 1e-9 * scale || std::abs(f.t_out - e.t_out.lo) > 1e-9 * scale) ++far_times;
  }
  EXPECT_GT(hits, n / 10);
  EXPECT_LE(disagree, n / 10000) << "hit/miss disagreements";
  EXPECT_LE(far_times, hits / 10000) << "times beyond the rounding band";
  std::printf("float vs exact sweeps: %d contacts, %d hit/miss disagreements, %d times off\n", hits, disagree, far_times);
}

// Small-integer inputs make every product exact in doubles, so the float twin must decide exactly
// as the exact sweep, degenerate contacts included (coplanar faces, parallel edges, vertex on
// vertex are frequent here), and its times are the correctly rounded exact ones.
TEST(FloatSweep, ExactOnSmallIntegerInputsIncludingDegenerateOnes) {
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> c(-2, 2);
  const auto coordinate = [&] { return static_cast<double>(c(rng)); };
  int hits = 0;
  for (int k = 0; k < 100000; ++k) {
    Triangle A, B;
    for (int i = 0; i < 3; ++i) {
      A[i] = Vec3{coordinate(), coordinate(), coordinate()};
      B[i] = Vec3{coordinate(), coordinate(), coordinate()};
    }
    const Vec3 v{coordinate(), coordinate(), coordinate()};
    if (v == Vec3::Zero()) continue;
    const LineContact e = line_contact(A, B, v);
    const FloatLineContact f = line_contact_float(A, B, v);
    ASSERT_EQ(e.hit, f.hit) << "case " << k;
    if (!e.hit) continue;
    ++hits;
    EXPECT_GE(f.t_in, e.t_in.lo);
    EXPECT_LE(f.t_in, e.t_in.hi);
    EXPECT_GE(f.t_out, e.t_out.lo);
    EXPECT_LE(f.t_out, e.t_out.hi);
  }
  EXPECT_GT(hits, 10000);
}

// Whole meshes: the float traversal returns the exact first-contact time up to rounding.
TEST(FloatSweep, MeshFirstContactMatchesExact) {
  const TriangleMesh torus = make_torus(1.0, 0.35, 24, 12), sphere = make_icosphere(0.5, 2);
  const SweepMesh fixed = make_sweep_mesh(torus.vertices, torus.faces);
  const SweepMesh fixed8 = make_sweep_mesh(torus.vertices, torus.faces, {8});  // as the float pipeline builds
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Matrix3d R = Eigen::Quaterniond(Eigen::Vector4d{u(rng), u(rng), u(rng), u(rng)}.normalized()).toRotationMatrix();
    const SweepMesh moving = placed(sphere, R, 0.6 * Vec3{u(rng), u(rng), u(rng)});
    const Vec3 v{u(rng), u(rng), u(rng)};
    const MeshContact e = first_contact_along_line(fixed, moving, v);
    const FloatMeshContact f = first_contact_along_line_float(fixed, moving, v);
    const FloatMeshContact f8 = first_contact_along_line_float(fixed8, moving, v);
    ASSERT_EQ(e.hit, f.hit) << "case " << k;
    // The answer does not depend on the tree's shape (the earliest time, ties by face pair).
    ASSERT_EQ(f.hit, f8.hit) << "case " << k;
    EXPECT_EQ(f.t, f8.t) << "case " << k;
    EXPECT_EQ(f.fixed_face, f8.fixed_face) << "case " << k;
    if (!e.hit) continue;
    ++hits;
    EXPECT_NEAR(f.t, e.t.lo, 1e-9 * (1.0 + std::abs(e.t.lo))) << "case " << k;
  }
  EXPECT_GT(hits, 100);
}

// A translated tree is a valid sphere tree of the moved mesh: the exact query gives the same time
// as on a tree rebuilt from the moved vertices (the same doubles).
TEST(FloatSweep, TranslatedSweepMeshGivesTheRebuiltTreesContact) {
  const TriangleMesh bunny = make_torus(1.0, 0.3, 20, 10), fixed_mesh = make_icosphere(1.0, 2);
  const SweepMesh fixed = make_sweep_mesh(fixed_mesh.vertices, fixed_mesh.faces);
  const Eigen::Matrix3d R = Eigen::Quaterniond(0.3, -0.2, 0.9, 0.1).normalized().toRotationMatrix();
  const SweepMesh rotated = placed(bunny, R, Vec3::Zero());
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 50; ++k) {
    const Vec3 t = 3.0 * Vec3{u(rng), u(rng), u(rng)} + Vec3(1e3 * (k % 2), 0, 0);  // large |t| too
    const SweepMesh moved = translated_sweep_mesh(rotated, t);
    std::vector<Vec3> v;
    for (const Vec3& p : rotated.vertices) v.push_back(Vec3(p[0] + t[0], p[1] + t[1], p[2] + t[2]));
    ASSERT_EQ(moved.vertices, v);
    const SweepMesh rebuilt = make_sweep_mesh(v, bunny.faces);
    const Vec3 dir = -(t - Vec3{0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng)});
    const MeshContact a = first_contact_along_line(fixed, moved, dir), b = first_contact_along_line(fixed, rebuilt, dir);
    ASSERT_EQ(a.hit, b.hit);
    if (a.hit) {
      EXPECT_EQ(exact_contact_time(fixed, moved, dir, a), exact_contact_time(fixed, rebuilt, dir, b));
    }
    // Every vertex lies in its leaf's sphere and box.
    for (const auto& node : moved.tree.nodes) {
      if (node.count == 0) continue;
      for (std::uint32_t j = 0; j < node.count; ++j) {
        const Face& f = moved.faces[moved.tree.order[node.first + j]];
        for (int c = 0; c < 3; ++c) {
          EXPECT_LE((moved.vertices[f[c]] - node.bv.sphere.center).norm(), node.bv.sphere.radius);
          EXPECT_TRUE(node.bv.box.contains(moved.vertices[f[c]]));
        }
      }
    }
  }
}

}  // namespace
}  // namespace cdbench
