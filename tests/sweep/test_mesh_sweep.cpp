// The sphere-tree first-contact query must give exactly the brute-force time (all triangle pairs).
#include <gtest/gtest.h>

#include <iomanip>

#include <Eigen/Geometry>
#include <random>

#include "distance/triangle_distance.h"
#include "mesh/shapes.h"
#include "placed_sweep_mesh.h"
#include "sweep/mesh_sweep.h"
#include "test_scale.h"

namespace cdbench {
namespace {

using test::placed;

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
      for (int k = 0; k < test_scale::cases(12); ++k) {  // 4 aligned and 2 generic under the sanitizers
        // Axis-aligned cases (identity rotation, axis directions) create coplanar and parallel
        // contacts; the others are generic.
        const bool aligned = k < 4;
        Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
        if (!aligned) R = Eigen::Quaterniond(Eigen::Vector4d{u(rng), u(rng), u(rng), u(rng)}.normalized()).toRotationMatrix();
        Vec3 v = aligned ? Vec3::Unit(k % 3) * (k == 3 ? -1.0 : 1.0) : Vec3{u(rng), u(rng), u(rng)};
        const Vec3 offset = aligned ? Vec3(0.125 * k, 0.0, 0.0) : 0.5 * Vec3{u(rng), u(rng), u(rng)};
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
    const Vec3 c = Vec3{u(rng), u(rng), u(rng)} * 10.0;
    f.extend(c);
    f.extend(c + Vec3{1 + u(rng), 1 + u(rng), 1 + u(rng)});
    Vec3 d{u(rng), u(rng), u(rng)};
    if (k % 3 == 0) d[k % 2] = 0.0;            // touching faces on some axis
    const Vec3 mc = f.hi + d;
    m.extend(mc);
    m.extend(mc + Vec3{0.5 + u(rng) * 0.4, 0.5 + u(rng) * 0.4, 0.5 + u(rng) * 0.4});
    Vec3 v{-1.0 + 0.1 * u(rng), u(rng), u(rng)};
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
    Sphere f{Vec3{u(rng), u(rng), u(rng)} * 10.0, 1.0 + u(rng) * 0.5};
    Sphere m{f.center + Vec3{5 + u(rng), u(rng), u(rng)}, 0.5 + u(rng) * 0.25};
    const Vec3 v{-1.0, u(rng) * 1e-3, u(rng) * 1e-3};
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


// The oriented boxes' bound against the exact first contact of the triangles they contain: fitted
// to one or a few random triangles each (long, thin and tilted ones included), the bound never
// exceeds the exact contact time of any contained pair (line_contact, exact), and is infinite only
// when no pair ever meets. It must also be finite, and later than the axis-aligned boxes' bound,
// in many cases (else it would prune nothing).
TEST(MeshSweep, ObbEntryBoundNeverPassesAContainedContact) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto random_triangle = [&](const Vec3& at, bool needle) {
    const Vec3 axis = Vec3{u(rng), u(rng), u(rng)}.normalized();
    Triangle T;
    for (Vec3& p : T) {
      const double along = needle ? 2.0 * u(rng) : 0.0;
      p = at + (needle ? along * axis + 0.05 * Vec3{u(rng), u(rng), u(rng)} : Vec3{u(rng), u(rng), u(rng)});
    }
    return T;
  };
  int finite = 0, infinite = 0, later_than_boxes = 0, pairs_checked = 0;
  for (int k = 0; k < 3000; ++k) {
    const int nf = 1 + static_cast<int>(rng() % 3), nm = 1 + static_cast<int>(rng() % 3);
    const bool needle = k % 2 == 0;
    std::vector<Triangle> F, M;
    for (int i = 0; i < nf; ++i) F.push_back(random_triangle(Vec3(0, 0, 0) + 0.3 * Vec3{u(rng), u(rng), u(rng)}, needle));
    const Vec3 start = 4.0 * Vec3{u(rng), u(rng), u(rng)};
    for (int i = 0; i < nm; ++i) M.push_back(random_triangle(start + 0.3 * Vec3{u(rng), u(rng), u(rng)}, needle));
    // Towards the fixed set, off by a random lateral amount (many lines miss).
    const Vec3 aim = -start + 1.5 * Vec3{u(rng), u(rng), u(rng)};
    Vec3 v = aim * (0.1 + std::abs(u(rng)));
    if (k % 7 == 0) v[k % 3] = 0.0;
    const auto fit = [](const std::vector<Triangle>& T) {
      return fit_obb(static_cast<int>(3 * T.size()), [&](int i) -> const Vec3& { return T[i / 3][i % 3]; });
    };
    const auto box = [](const std::vector<Triangle>& T) {
      Aabb b;
      for (const Triangle& t : T)
        for (const Vec3& p : t) b.extend(p);
      return b;
    };
    const double b = obb_entry_time_lower_bound(fit(F), fit(M), v);
    bool any = false;
    for (const Triangle& A : F)
      for (const Triangle& B : M) {
        const LineContact c = line_contact(A, B, v);
        ++pairs_checked;
        if (!c.hit) continue;
        any = true;
        ASSERT_LE(b, c.t_in.lo) << std::setprecision(17) << "case " << k;
      }
    if (std::isinf(b)) {
      ++infinite;
      EXPECT_FALSE(any) << "case " << k;
      continue;
    }
    ++finite;
    if (b > box_entry_time_lower_bound(box(F), box(M), v) + 1e-9) ++later_than_boxes;
  }
  EXPECT_GT(finite, 300);
  EXPECT_GT(infinite, 300);
  EXPECT_GT(later_than_boxes, 200);
  std::printf("oriented boxes: %d finite, %d infinite, %d later than the axis-aligned bound (%d pairs)\n", finite,
              infinite, later_than_boxes, pairs_checked);
}

// The oriented boxes' distance bound never exceeds the certified distance of two triangles they
// contain (each box fitted to one random triangle, needles among them, near and far apart, some
// with a pad), and it is positive in most separated cases.
TEST(MeshSweep, ObbDistanceBoundNeverExceedsTheTrianglesDistance) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int positive = 0, separated = 0;
  for (int k = 0; k < 20000; ++k) {
    const bool needle = k % 2 == 0;
    const auto triangle = [&](const Vec3& at) {
      const Vec3 axis = Vec3{u(rng), u(rng), u(rng)}.normalized();
      Triangle T;
      for (Vec3& p : T) {
        const double along = needle ? 2.0 * u(rng) : 0.0;
        p = at + (needle ? along * axis + 0.02 * Vec3{u(rng), u(rng), u(rng)} : Vec3{u(rng), u(rng), u(rng)});
      }
      return T;
    };
    const Triangle A = triangle(Vec3::Zero());
    const double apart = 0.5 + 2.0 * std::abs(u(rng));
    const Triangle B = triangle(apart * Vec3{u(rng), u(rng), u(rng)});
    const auto fit = [](const Triangle& T) { return fit_obb(3, [&](int i) -> const Vec3& { return T[i]; }); };
    Obb a = fit(A), b = fit(B);
    if (k % 3 == 0) b.pad = 0.01 * std::abs(u(rng));  // a pad only makes the bound smaller
    const double bound = obb_squared_distance_lower_bound(a, b);
    const Interval d2 = triangle_triangle_squared_distance(A[0], A[1], A[2], B[0], B[1], B[2]);
    ASSERT_LE(bound, d2.hi) << std::setprecision(17) << "case " << k;
    if (d2.lo > 0.0) {
      ++separated;
      positive += bound > 0.0;
    }
  }
  EXPECT_GT(separated, 10000);
  EXPECT_GT(positive, separated / 2);
}

// A mover's own tree carried to a placed mover (placed_sweep_mesh): every placed vertex lies in
// each of its nodes' sphere and box (exactly, in rationals) and within the pad of its oriented box
// (a point of the box found from the exact coordinates, in rationals), for rotations exactly
// orthonormal or not (perturbed by 1e-9) and large translations; the first contacts equal the
// rebuilt tree's and the brute force's.
TEST(MeshSweep, CarriedTreeContainsThePlacedMoverAndFindsTheSameContacts) {
  const TriangleMesh torus = make_torus(1.0, 0.3, 12, 5);
  const TriangleMesh box = make_box(Vec3(-1.5, -0.2, -0.1), Vec3(1.5, 0.2, 0.1));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto q = [](double x) { return mpq_class(x); };
  for (const TriangleMesh* mesh : {&torus, &box}) {
    const SweepMesh own = make_sweep_mesh(mesh->vertices, mesh->faces);
    const SweepMesh fixed = make_sweep_mesh(mesh->vertices, mesh->faces);
    for (int k = 0; k < 12; ++k) {
      Eigen::Matrix3d R = Eigen::Quaterniond(Eigen::Vector4d{u(rng), u(rng), u(rng), u(rng)}.normalized()).toRotationMatrix();
      if (k % 3 == 1) R += 1e-9 * Eigen::Matrix3d::Random();
      const Vec3 t = (k % 4 == 0 ? 1e6 : 2.0) * Vec3{u(rng), u(rng), u(rng)};
      std::vector<Vec3> placed;
      Vec3 abs_max = Vec3::Zero();
      for (const Vec3& x : mesh->vertices) {
        const Vec3 r(R(0, 0) * x[0] + R(0, 1) * x[1] + R(0, 2) * x[2], R(1, 0) * x[0] + R(1, 1) * x[1] + R(1, 2) * x[2],
                     R(2, 0) * x[0] + R(2, 1) * x[1] + R(2, 2) * x[2]);
        placed.push_back(Vec3(r[0] + t[0], r[1] + t[1], r[2] + t[2]));
        abs_max = abs_max.cwiseMax(R.cwiseAbs() * x.cwiseAbs());
      }
      // MoverOrientation::transform_error's bound (gamma_4 (|R| |x| + |t|), Euclidean).
      const double err = (4.5e-16 * (abs_max + t.cwiseAbs())).norm() * (1.0 + 1e-10);
      const SweepMesh carried = placed_sweep_mesh(own, R, t, placed, err);
      SCOPED_TRACE("case " + std::to_string(k));
      // Every node's vertices, through the leaves below it.
      std::vector<std::vector<std::uint32_t>> below(carried.tree.nodes.size());
      for (std::size_t n = carried.tree.nodes.size(); n-- > 0;) {
        const auto& node = carried.tree.nodes[n];
        if (node.count > 0) {
          for (std::uint32_t i = 0; i < node.count; ++i)
            for (std::uint32_t v : mesh->faces[carried.tree.order[node.first + i]]) below[n].push_back(v);
        } else {
          for (std::uint32_t c : {node.first, node.first + 1}) below[n].insert(below[n].end(), below[c].begin(), below[c].end());
        }
      }
      for (std::size_t n = 0; n < carried.tree.nodes.size(); ++n) {
        const SweepVolume& w = carried.tree.nodes[n].bv;
        Eigen::Matrix<mpq_class, 3, 3> A, Ai;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) A(i, j) = q(w.obb.axes(i, j));
        // The exact inverse by cofactors.
        const mpq_class det = A(0, 0) * (A(1, 1) * A(2, 2) - A(1, 2) * A(2, 1)) -
                              A(0, 1) * (A(1, 0) * A(2, 2) - A(1, 2) * A(2, 0)) +
                              A(0, 2) * (A(1, 0) * A(2, 1) - A(1, 1) * A(2, 0));
        ASSERT_NE(det, 0);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            const int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
            Ai(i, j) = (A(i1, j1) * A(i2, j2) - A(i1, j2) * A(i2, j1)) / det;
          }
        for (std::uint32_t v : below[n]) {
          const Vec3& y = placed[v];
          for (int i = 0; i < 3; ++i) {
            ASSERT_LE(w.box.lo[i], y[i]);
            ASSERT_GE(w.box.hi[i], y[i]);
          }
          mpq_class d2 = 0;
          for (int i = 0; i < 3; ++i) d2 += (q(y[i]) - q(w.sphere.center[i])) * (q(y[i]) - q(w.sphere.center[i]));
          ASSERT_LE(d2, q(w.sphere.radius) * q(w.sphere.radius));
          std::array<mpq_class, 3> a, p;
          for (int i = 0; i < 3; ++i) {
            a[i] = 0;
            for (int j = 0; j < 3; ++j) a[i] += Ai(i, j) * (q(y[j]) - q(w.obb.center[j]));
            const mpq_class h = q(w.obb.half[i]);
            if (a[i] > h) a[i] = h;
            if (a[i] < -h) a[i] = -h;
          }
          mpq_class e2 = 0;
          for (int i = 0; i < 3; ++i) {
            p[i] = q(w.obb.center[i]);
            for (int j = 0; j < 3; ++j) p[i] += A(i, j) * a[j];
            e2 += (q(y[i]) - p[i]) * (q(y[i]) - p[i]);
          }
          ASSERT_LE(e2, q(w.obb.pad) * q(w.obb.pad)) << "node " << n << " vertex " << v;
        }
      }
      if (k % 4 == 0) continue;  // far away: no contact to compare
      const SweepMesh rebuilt = make_sweep_mesh(placed, mesh->faces);
      for (int d = 0; d < 4; ++d) {
        const Vec3 v = Vec3{u(rng), u(rng), u(rng)};
        const MeshContact a = first_contact_along_line(fixed, carried, v);
        const MeshContact b = first_contact_along_line(fixed, rebuilt, v);
        const MeshContact c = first_contact_brute_force(fixed, carried, v);
        ASSERT_EQ(a.hit, c.hit);
        ASSERT_EQ(b.hit, c.hit);
        if (!c.hit) continue;
        EXPECT_EQ(a.t.lo, c.t.lo);
        EXPECT_EQ(a.t.hi, c.t.hi);
        EXPECT_EQ(b.t.lo, c.t.lo);
        EXPECT_EQ(a.fixed_face, c.fixed_face);
        EXPECT_EQ(a.moving_face, c.moving_face);
      }
    }
  }
}

// The rule that keeps the oriented test in a pair traversal (a heuristic: only the work depends on
// it): off after a window of kTrial tested pairs with fewer than a quarter pruned, on again for a
// new window after kRetrial skipped pairs, and kept while a window prunes a quarter or more.
TEST(MeshSweep, ObbTrialTurnsOffAfterAPoorWindowAndTriesAgainLater) {
  ObbTrial t;
  EXPECT_TRUE(t.paid());  // nothing judged yet
  for (int i = 0; i < ObbTrial::kTrial; ++i) {
    ASSERT_TRUE(t.on) << i;
    t.record(i % 8 == 0);  // an eighth pruned
  }
  EXPECT_FALSE(t.on);
  EXPECT_FALSE(t.paid());
  for (int i = 0; i + 1 < ObbTrial::kRetrial; ++i) t.skip();
  EXPECT_FALSE(t.on);
  t.skip();
  EXPECT_TRUE(t.on);  // a new window
  for (int i = 0; i + 1 < ObbTrial::kTrial; ++i) t.record(i % 4 == 0);
  EXPECT_FALSE(t.paid());  // not judged yet: the last judgment stands
  t.record(false);         // a quarter pruned: kept
  EXPECT_TRUE(t.on);
  EXPECT_TRUE(t.paid());
  for (int i = 0; i < 10 * ObbTrial::kTrial; ++i) t.record(false);  // decided: not judged again
  EXPECT_TRUE(t.on);
}

}  // namespace
}  // namespace cdbench
