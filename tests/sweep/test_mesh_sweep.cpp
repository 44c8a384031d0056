// The sphere-tree first-contact query must give exactly the brute-force time (all triangle pairs).
#include <gtest/gtest.h>

#include <iomanip>

#include <Eigen/Geometry>
#include <random>

#include "mesh/shapes.h"
#include "sweep/mesh_sweep.h"

namespace cdbench {
namespace {

SweepMesh placed(const TriangleMesh& m, const Eigen::Matrix3d& R, const Vec3& t) {
  std::vector<Vec3> v;
  for (const Vec3& p : m.vertices) v.push_back(R * p + t);
  return make_sweep_mesh(v, m.faces);
}

struct Shape {
  const char* name;
  TriangleMesh mesh;
};

TEST(MeshSweep, SphereTreeMatchesBruteForceExactly) {
  const std::vector<Shape> shapes = {{"icosphere", make_icosphere(1.0, 1)},
                                     {"torus", make_torus(1.0, 0.35, 10, 6)},
                                     {"box", make_box(Vec3(-1, -0.5, -0.25), Vec3(1, 0.5, 0.25))}};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int cases = 0, hits = 0;
  std::uint64_t tree_sweeps = 0, brute_sweeps = 0;
  for (const Shape& fixed_shape : shapes) {
    const SweepMesh fixed = make_sweep_mesh(fixed_shape.mesh.vertices, fixed_shape.mesh.faces);
    for (const Shape& mover : shapes) {
      for (int k = 0; k < 12; ++k) {
        // Axis-aligned cases (identity rotation, axis directions) create coplanar and parallel
        // contacts; the others are generic.
        const bool aligned = k < 4;
        Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
        if (!aligned) R = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
        Vec3 v = aligned ? Vec3::Unit(k % 3) * (k == 3 ? -1.0 : 1.0) : Vec3(u(rng), u(rng), u(rng));
        const Vec3 offset = aligned ? Vec3(0.125 * k, 0.0, 0.0) : 0.5 * Vec3(u(rng), u(rng), u(rng));
        const SweepMesh moving = placed(mover.mesh, R, offset);
        SCOPED_TRACE(std::string(fixed_shape.name) + " vs " + mover.name + " case " + std::to_string(k));
        const MeshContact tree = first_contact_along_line(fixed, moving, v);
        const MeshContact brute = first_contact_brute_force(fixed, moving, v);
        ++cases;
        tree_sweeps += tree.triangle_sweeps;
        brute_sweeps += brute.triangle_sweeps;
        ASSERT_EQ(tree.hit, brute.hit);
        if (!tree.hit) continue;
        ++hits;
        EXPECT_EQ(exact_contact_time(fixed, moving, v, tree), exact_contact_time(fixed, moving, v, brute));
        EXPECT_EQ(tree.t.lo, brute.t.lo);
        EXPECT_EQ(tree.t.hi, brute.t.hi);
      }
    }
  }
  EXPECT_EQ(hits, cases);  // every line through overlapping meshes meets them
  // The traversal must actually prune.
  EXPECT_LT(tree_sweeps * 5, brute_sweeps);
  std::printf("cases %d, triangle sweeps: tree %llu, brute force %llu\n", cases,
              static_cast<unsigned long long>(tree_sweeps), static_cast<unsigned long long>(brute_sweeps));
}

TEST(MeshSweep, MissingLineAndTranslationInvariance) {
  const TriangleMesh s = make_icosphere(1.0, 2);
  const SweepMesh fixed = make_sweep_mesh(s.vertices, s.faces);
  // A mover passing far to the side never touches.
  const SweepMesh far = placed(s, Eigen::Matrix3d::Identity(), Vec3(0, 5, 0));
  EXPECT_FALSE(first_contact_along_line(fixed, far, Vec3(1, 0, 0)).hit);
  EXPECT_FALSE(first_contact_brute_force(fixed, far, Vec3(1, 0, 0)).hit);
  // Two unit spheres on the x axis, the mover 10 to the left moving right: contact when the gap
  // closes, t = 10 - 2 minus the faceting (an inscribed polyhedron touches later: t >= 8).
  const SweepMesh left = placed(s, Eigen::Matrix3d::Identity(), Vec3(-10, 0, 0));
  const MeshContact c = first_contact_along_line(fixed, left, Vec3(1, 0, 0));
  ASSERT_TRUE(c.hit);
  EXPECT_GE(c.t.lo, 8.0);
  EXPECT_LE(c.t.hi, 8.2);
  // Moving the mover by a multiple of v shifts the time by exactly that multiple.
  const SweepMesh left2 = placed(s, Eigen::Matrix3d::Identity(), Vec3(-12, 0, 0));
  const MeshContact c2 = first_contact_along_line(fixed, left2, Vec3(1, 0, 0));
  EXPECT_EQ(exact_contact_time(fixed, left2, Vec3(1, 0, 0), c2) - exact_contact_time(fixed, left, Vec3(1, 0, 0), c), 2);
}

}  // namespace
}  // namespace cdbench

namespace cdbench {
namespace {

// The box pruning bound against exact rationals: the exact meeting interval of the moving box
// (+ t v) with the fixed one is the intersection of the three axes' intervals; a finite bound is
// at most its start, an infinite bound only when it is empty. Boxes that just touch, velocities
// with zero and tiny components, and near-empty intersections are the hard cases.
TEST(MeshSweep, BoxEntryBoundIsRigorous) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int finite = 0, infinite = 0;
  const auto q = [](double x) { return mpq_class(x); };
  for (int k = 0; k < 20000; ++k) {
    Aabb f, m;
    const Vec3 c = Vec3(u(rng), u(rng), u(rng)) * 10.0;
    f.extend(c);
    f.extend(c + Vec3(1 + u(rng), 1 + u(rng), 1 + u(rng)));
    Vec3 d(u(rng), u(rng), u(rng));
    if (k % 3 == 0) d[k % 2] = 0.0;            // touching faces on some axis
    const Vec3 mc = f.hi + d;
    m.extend(mc);
    m.extend(mc + Vec3(0.5 + u(rng) * 0.4, 0.5 + u(rng) * 0.4, 0.5 + u(rng) * 0.4));
    Vec3 v(-1.0 + 0.1 * u(rng), u(rng), u(rng));
    if (k % 5 == 0) v[1] = 0.0;
    if (k % 7 == 0) v[2] = 1e-300 * u(rng);
    const double b = box_entry_time_lower_bound(f, m, v);
    // The exact interval of t, or empty.
    bool empty = false, has_lo = false, has_hi = false;
    mpq_class lo, hi;
    for (int a = 0; a < 3; ++a) {
      if (v[a] == 0.0) {
        if (m.hi[a] < f.lo[a] || f.hi[a] < m.lo[a]) empty = true;
        continue;
      }
      mpq_class x = (q(f.lo[a]) - q(m.hi[a])) / q(v[a]), y = (q(f.hi[a]) - q(m.lo[a])) / q(v[a]);
      if (v[a] < 0) std::swap(x, y);
      if (!has_lo || x > lo) lo = x;
      if (!has_hi || y < hi) hi = y;
      has_lo = has_hi = true;
    }
    if (has_lo && lo > hi) empty = true;
    if (std::isinf(b)) {
      ++infinite;
      EXPECT_TRUE(empty) << std::setprecision(17) << "case " << k;
      continue;
    }
    ++finite;
    if (!empty && has_lo) {
      EXPECT_LE(q(b), lo) << std::setprecision(17) << "case " << k;
    }
  }
  EXPECT_GT(finite, 1000);
  EXPECT_GT(infinite, 1000);
}

// The pruning bound against exact rational arithmetic: at t = bound the spheres are still apart or
// touching (|w + t v|^2 >= R^2) and t is before the closest approach, so t <= the entry time; an
// infinite bound means the exact discriminant is negative. Near-tangent lines are the hard cases.
TEST(MeshSweep, SphereEntryBoundIsRigorous) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int finite = 0, infinite = 0;
  for (int k = 0; k < 20000; ++k) {
    Sphere f{Vec3(u(rng), u(rng), u(rng)) * 10.0, 1.0 + u(rng) * 0.5};
    Sphere m{f.center + Vec3(5 + u(rng), u(rng), u(rng)), 0.5 + u(rng) * 0.25};
    const Vec3 v(-1.0, u(rng) * 1e-3, u(rng) * 1e-3);
    // Make the line nearly tangent: the perpendicular offset of the centres about R.
    const Vec3 side = v.cross(Vec3(0, 0, 1)).normalized();
    const double R = f.radius + m.radius;
    m.center = f.center + Vec3(5, 0, 0) + side * (R * (1.0 + u(rng) * 1e-12));
    const double b = sphere_entry_time_lower_bound(f, m, v);
    const auto q = [](double x) { return mpq_class(x); };
    mpq_class wx = q(m.center.x()) - q(f.center.x()), wy = q(m.center.y()) - q(f.center.y()),
              wz = q(m.center.z()) - q(f.center.z());
    const mpq_class Rq = q(f.radius) + q(m.radius);
    const mpq_class wv = wx * q(v.x()) + wy * q(v.y()) + wz * q(v.z());
    const mpq_class vv = q(v.x()) * q(v.x()) + q(v.y()) * q(v.y()) + q(v.z()) * q(v.z());
    const mpq_class ww = wx * wx + wy * wy + wz * wz;
    const mpq_class disc = wv * wv - vv * (ww - Rq * Rq);
    if (std::isinf(b)) {
      ++infinite;
      EXPECT_LT(disc, 0);
      continue;
    }
    ++finite;
    const mpq_class t = q(b);
    const mpq_class fx = wx + t * q(v.x()), fy = wy + t * q(v.y()), fz = wz + t * q(v.z());
    EXPECT_GE(fx * fx + fy * fy + fz * fz, Rq * Rq);
    EXPECT_LE(t * vv, -wv);
  }
  EXPECT_GT(finite, 1000);
  EXPECT_GT(infinite, 1000);
}

}  // namespace
}  // namespace cdbench
