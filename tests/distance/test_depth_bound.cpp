// The translated depth bound (distance/depth_bound.h) against exact rational distances: for random
// cells in and around closed meshes and random translations, no point of the translated cell is
// farther from the surface than the bound; a bound with the translation's sign flipped fails the
// same check; and along a face's normal the bound is exact, along the face it grows more slowly
// than the shifted Lipschitz bound.
#include <gtest/gtest.h>

#include <iomanip>
#include <map>
#include <random>

#include "distance/depth_bound.h"
#include "distance/planar_patch.h"
#include "distance/point_triangle_distance.h"
#include "exact_reference.h"
#include "mesh/shapes.h"
#include "test_scale.h"

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

// The solids of the moved-cell checks: curved (a torus, a sphere) and flat (a box).
std::vector<std::pair<std::string, TriangleMesh>> three_solids() {
  return {{"torus", make_torus(2.0, 0.6, 24, 12)},
          {"sphere", make_icosphere(1.0, 2)},
          {"box", make_box(Vec3(0, 0, 0), Vec3(2, 1, 0.5))}};
}

// Random small triangles (cells) in and around a mesh's box, with the reach of their depth
// candidates (dist(centre, F) + 2 radius), and random moves of them (10^-4 to 10^-1 of the
// diagonal, any direction): the inputs of the moved-cell checks below.
struct RandomCells {
  RandomCells(const TriangleMesh& m, std::uint64_t seed) : box(m.bbox()), diag(box.diagonal()), rng(seed) {}
  struct Cell {
    std::array<Vec3, 3> v;
    Vec3 centre;
    double reach;
  };
  Cell next(const SignedDistance& sdf) {
    Cell k;
    const Vec3 c = box.lo + Vec3{u(rng), u(rng), u(rng)}.cwiseProduct(box.extent());
    const double size = diag * (0.002 + 0.05 * u(rng));
    for (Vec3& x : k.v) x = c + size * Vec3{s(rng), s(rng), s(rng)};
    k.centre = (k.v[0] + k.v[1] + k.v[2]) / 3.0;
    double radius = 0;
    for (const Vec3& x : k.v) radius = std::max(radius, (x - k.centre).norm());
    k.reach = sdf.unsigned_distance(k.centre).hi + 2 * radius;
    return k;
  }
  Vec3 move() { return std::pow(10.0, -4.0 + 3.0 * u(rng)) * diag * Vec3{s(rng), s(rng), s(rng)}.normalized(); }
  Aabb box;
  double diag;
  std::mt19937_64 rng;
  std::uniform_real_distribution<double> u{0.0, 1.0}, s{-1.0, 1.0};
};

// Counts the sampled points of the moved cell (corners v moved by D) farther from m's surface than
// `bound` (exact rationals); reported as failures unless `expected` (a control).
void check_points(const TriangleMesh& m, const std::array<Vec3, 3>& v, const Vec3& D, double bound, bool expected,
                  Checked& r) {
  std::array<Vec3, 3> moved;
  for (int j = 0; j < 3; ++j) moved[j] = v[j] + D;
  for (const Vec3& p : samples(moved)) {
    ++r.points;
    if (within(exact_squared_distance(p, m), bound)) continue;
    ++r.violations;
    if (!expected)
      ADD_FAILURE() << std::setprecision(17) << "point (" << p.x() << ", " << p.y() << ", " << p.z()
                    << ") is farther than the bound " << bound;
  }
}

// Random small triangles (cells) around a mesh, each with its bound from depth_upper_bound, then
// translated by random D; every sampled point of the translated cell must be within the bound of
// the surface. `flip` evaluates the bound at -D instead (a wrong bound, which must be caught).
Checked check_mesh(const TriangleMesh& m, std::uint64_t seed, int cells, bool flip,
                   DepthWeights weights = DepthWeights::converged) {
  const SignedDistance sdf(m);
  RandomCells gen(m, seed);
  std::vector<std::uint32_t> scratch;
  Checked r;
  while (r.cells < cells) {
    const RandomCells::Cell k = gen.next(sdf);
    TranslatedDepthBound b;
    const double depth = depth_upper_bound(sdf, k.centre, k.reach, k.v.data(), 3, scratch, nullptr, nullptr, nullptr,
                                           &b, 0.0, weights);
    if (!(depth < HUGE_VAL) || b.n != 3) continue;
    ++r.cells;
    // At D = 0 the moments bound is never below the bound it extends (Jensen).
    EXPECT_GE(translated_depth(b, Vec3::Zero()), depth * (1 - 1e-9));  // up to their rounding margins
    for (int i = 0; i < 4; ++i) {
      const Vec3 D = gen.move();
      check_points(m, k.v, D, translated_depth(b, flip ? Vec3(-D) : D), flip, r);
    }
  }
  return r;
}

TEST(TranslatedDepth, BoundsEveryPointOfTheTranslatedCellExactly) {
  for (const auto& [name, m] : three_solids()) {
    SCOPED_TRACE(name);
    for (const DepthWeights w : {DepthWeights::converged, DepthWeights::sparse}) {
      const Checked r = check_mesh(m, 5, test_scale::cases(200), false, w);
      EXPECT_EQ(r.cells, test_scale::cases(200));
      EXPECT_EQ(r.violations, 0) << "of " << r.points;
    }
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
      const Vec3 off = scale * 10 * Vec3{u(rng), u(rng), u(rng)};
      Vec3 a = off + scale * Vec3{u(rng), u(rng), u(rng)}, b = off + scale * Vec3{u(rng), u(rng), u(rng)};
      Vec3 c = off + scale * Vec3{u(rng), u(rng), u(rng)};
      if (k % 3 == 1) {  // sliver
        const double along = u(rng);
        c = a + (b - a) * along + 1e-9 * scale * Vec3{u(rng), u(rng), u(rng)};
      }
      if (k % 3 == 2) c = b;                                                                  // degenerate
      const Vec3 p = off + 3 * scale * Vec3{u(rng), u(rng), u(rng)};
      const Vec3 q = point_of_triangle_near(p, a, b, c);
      ASSERT_TRUE(within(testing::exact_squared_distance(q, a, b, c), closest_point_error(a, b, c)))
          << std::setprecision(17) << "q (" << q.x() << ", " << q.y() << ", " << q.z() << ")";
      EXPECT_LE((p - q).norm(), (p - closest_point_on_triangle(p, a, b, c)).norm() * (1 + 1e-9) + 1e-12 * scale);
      ++n;
    }
  }
  EXPECT_EQ(n, 9000);
}


// A solid made of unit cubes (cells (i, j, k)), its boundary squares split into two triangles each:
// large planar faces tiled by many coplanar triangles, a non-convex face, convex and concave
// creases. Vertices are rotated by R (identity: exactly coplanar; otherwise coplanar up to rounding).
TriangleMesh make_cube_solid(const std::vector<std::array<int, 3>>& cells, const Eigen::Matrix3d& R) {
  std::map<std::array<int, 3>, bool> filled;
  for (const auto& c : cells) filled[c] = true;
  TriangleMesh m;
  std::map<std::array<int, 3>, std::uint32_t> index;
  const auto vertex = [&](std::array<int, 3> p) {
    const auto it = index.find(p);
    if (it != index.end()) return it->second;
    const std::uint32_t i = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back(R * Vec3(p[0], p[1], p[2]));
    index[p] = i;
    return i;
  };
  for (const auto& c : cells)
    for (int axis = 0; axis < 3; ++axis)
      for (int dir : {-1, 1}) {
        std::array<int, 3> nb = c;
        nb[axis] += dir;
        if (filled.count(nb)) continue;
        // The square on that side, counter-clockwise seen from outside.
        const int u = (axis + 1) % 3, w = (axis + 2) % 3;
        std::array<int, 3> base = c;
        if (dir > 0) base[axis] += 1;
        std::array<std::array<int, 3>, 4> q{base, base, base, base};
        q[1][u] += 1;
        q[2][u] += 1;
        q[2][w] += 1;
        q[3][w] += 1;
        if (dir < 0) std::swap(q[1], q[3]);
        const std::uint32_t a = vertex(q[0]), b = vertex(q[1]), cc = vertex(q[2]), d = vertex(q[3]);
        m.faces.push_back({a, b, cc});
        m.faces.push_back({a, cc, d});
      }
  return m;
}

// An L-shaped slab, 3 x 3 x 1 cubes with one corner cube missing: its top and bottom faces are
// non-convex planar regions of 16 triangles each.
std::vector<std::array<int, 3>> l_slab() {
  std::vector<std::array<int, 3>> cells;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!(i == 2 && j == 2)) cells.push_back({i, j, 0});
  return cells;
}

// The pose certificates' sparse weights (a Frank-Wolfe stopped at duality gap 1/2) still cancel
// the two opposite nearest faces of a thin wall: the bound on a cell deep inside it is its
// half-width, as with converged weights (either face alone gives its deepest corner). At a box
// corner (three nearest faces, no two opposite) the sparse bound stays valid and within the
// cell's size of the converged one.
TEST(DepthWeights, SparseWeightsKeepAThinWallsPlateauExact) {
  const TriangleMesh m = make_box(Vec3(0, 0, 0), Vec3(4, 4, 0.2));
  const SignedDistance sdf(m);
  std::vector<std::uint32_t> scratch;
  // Tilted across the mid-plane: one face alone would bound it by 0.125 (its deepest corner).
  const std::array<Vec3, 3> v{Vec3(1.7, 1.2, 0.075), Vec3(2.2, 1.3, 0.1), Vec3(1.9, 1.8, 0.125)};
  const Vec3 centre = (v[0] + v[1] + v[2]) / 3.0;
  for (const DepthWeights w : {DepthWeights::converged, DepthWeights::sparse}) {
    const double depth = depth_upper_bound(sdf, centre, 1.0, v.data(), 3, scratch, nullptr, nullptr, nullptr, nullptr,
                                           0.0, w);
    EXPECT_NEAR(depth, 0.1, 1e-12);
  }
  const std::array<Vec3, 3> corner{Vec3(0.05, 0.06, 0.04), Vec3(0.07, 0.05, 0.05), Vec3(0.06, 0.07, 0.06)};
  const Vec3 cc = (corner[0] + corner[1] + corner[2]) / 3.0;
  const double converged = depth_upper_bound(sdf, cc, 0.3, corner.data(), 3, scratch);
  const double sparse = depth_upper_bound(sdf, cc, 0.3, corner.data(), 3, scratch, nullptr, nullptr, nullptr, nullptr,
                                          0.0, DepthWeights::sparse);
  for (const Vec3& x : samples(corner)) {
    EXPECT_TRUE(within(exact_squared_distance(x, m), sparse));
    EXPECT_TRUE(within(exact_squared_distance(x, m), converged));
  }
  EXPECT_LT(sparse, converged + 0.03);
}

// The witness of a depth bound (its four largest weights), evaluated at a cell's corners moved by
// a random D: every sampled point of the moved cell lies within that bound of the surface (exact
// rationals). `stale`: the witness evaluated at the unmoved corners instead (a wrong bound for the
// moved cell, which must be caught). Minimax weights are checked as well as min-norm ones.
Checked check_witness(const TriangleMesh& m, std::uint64_t seed, int cells, bool stale) {
  const SignedDistance sdf(m);
  RandomCells gen(m, seed);
  std::vector<std::uint32_t> ids;
  Checked r;
  while (r.cells < cells) {
    const RandomCells::Cell k = gen.next(sdf);
    DepthWitness w, mm;
    const double depth = depth_upper_bound(sdf, k.centre, k.reach, k.v.data(), 3, ids, nullptr, nullptr, nullptr,
                                           nullptr, 0.0, DepthWeights::sparse, &w);
    if (!(depth < HUGE_VAL) || w.n == 0) continue;
    minimax_depth_bound(sdf, ids, k.v.data(), 3, 4, &mm);
    ++r.cells;
    for (int i = 0; i < 4; ++i) {
      const Vec3 D = gen.move();
      std::array<Vec3, 3> moved;
      for (int j = 0; j < 3; ++j) moved[j] = k.v[j] + D;
      for (const DepthWitness* x : {&w, &mm})
        if (x->n > 0) check_points(m, k.v, D, witness_depth_bound(sdf, *x, stale ? k.v.data() : moved.data(), 3), stale, r);
    }
  }
  return r;
}

TEST(DepthWitness, BoundsEveryPointOfTheMovedCellExactly) {
  for (const auto& [name, m] : three_solids()) {
    SCOPED_TRACE(name);
    const Checked r = check_witness(m, 7, test_scale::cases(200), false);
    EXPECT_EQ(r.cells, test_scale::cases(200));
    EXPECT_EQ(r.violations, 0) << "of " << r.points;
  }
}

TEST(DepthWitness, AStaleBoundIsCaught) {
  // The witness at the corners where the cell was, for the cell moved: must fail somewhere.
  const Checked r = check_witness(make_torus(2.0, 0.6, 24, 12), 7, 60, true);
  EXPECT_GT(r.violations, 0);
}

TEST(DepthWitness, ExactOnAThinWallsPlateauWhereverTheCellSlides) {
  // A cell across the mid-plane of a plate 0.2 thick: its witness weighs the two faces, so the
  // bound is the half-thickness wherever the cell slides along them (one face alone: 0.125).
  const TriangleMesh m = make_box(Vec3(0, 0, 0), Vec3(4, 4, 0.2));
  const SignedDistance sdf(m);
  std::vector<std::uint32_t> ids;
  const std::array<Vec3, 3> v{Vec3(1.7, 1.2, 0.075), Vec3(2.2, 1.3, 0.1), Vec3(1.9, 1.8, 0.125)};
  const Vec3 centre = (v[0] + v[1] + v[2]) / 3.0;
  DepthWitness w;
  const double depth = depth_upper_bound(sdf, centre, 1.0, v.data(), 3, ids, nullptr, nullptr, nullptr, nullptr, 0.0,
                                         DepthWeights::sparse, &w);
  EXPECT_NEAR(depth, 0.1, 1e-12);
  ASSERT_GE(w.n, 2);
  // Slides that keep the cell over the same two triangles (each face is split along x + y = 4):
  // beyond them the old triangles' distances grow and the bound with them (valid, not exact).
  for (const Vec3& D : {Vec3(0.3, 0, 0), Vec3(-0.5, 0.4, 0), Vec3(-1.0, -0.8, 0)}) {
    std::array<Vec3, 3> moved;
    for (int j = 0; j < 3; ++j) moved[j] = v[j] + D;
    EXPECT_NEAR(witness_depth_bound(sdf, w, moved.data(), 3), 0.1, 1e-6);
  }
}

Eigen::Matrix3d some_rotation() {
  return (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()) * Eigen::AngleAxisd(0.3, Vec3(0, 1, 0))).toRotationMatrix();
}

// Random cells near the surface (often straddling the shared edges of coplanar triangles): the
// bound with planar patches must hold at every sampled point (exact rationals). Returns how often
// patches made the bound tighter than without.
int check_patch_bounds(const TriangleMesh& m, std::uint64_t seed, int cells, double slack,
                       DepthWeights weights = DepthWeights::converged) {
  const SignedDistance sdf(m);
  const double diag = m.bbox().diagonal();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  std::vector<std::uint32_t> scratch;
  int tighter = 0, done = 0;
  while (done < cells) {
    // Near a random point of a random face: within the jitter of it, or a little inside or outside;
    // flat or tilted.
    const Face& f = m.faces[rng() % m.faces.size()];
    double b = u(rng), g = u(rng);
    if (b + g > 1) b = 1 - b, g = 1 - g;
    const Vec3 n = (m.vertices[f[1]] - m.vertices[f[0]]).cross(m.vertices[f[2]] - m.vertices[f[0]]).normalized();
    const Vec3 on = m.vertices[f[0]] + b * (m.vertices[f[1]] - m.vertices[f[0]]) + g * (m.vertices[f[2]] - m.vertices[f[0]]);
    const Vec3 c = on - n * diag * (u(rng) < 0.3 ? 1e-9 * s(rng) : 0.05 * (u(rng) - 0.2));
    const double size = diag * std::pow(10.0, -6 + 5 * u(rng));
    std::array<Vec3, 3> v;
    const double tilt = u(rng) < 0.5 ? 0.0 : 1.0;
    for (Vec3& x : v) {
      Vec3 d{s(rng), s(rng), s(rng)};
      d -= (1 - tilt) * d.dot(n) * n;
      x = c + size * d;
    }
    const Vec3 centre = (v[0] + v[1] + v[2]) / 3.0;
    double radius = 0;
    for (const Vec3& x : v) radius = std::max(radius, (x - centre).norm());
    const Interval ud = sdf.unsigned_distance(centre);
    Vec3 normal = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
    const double plain = depth_upper_bound(sdf, centre, ud.hi + 2 * radius, v.data(), 3, scratch, nullptr, &normal,
                                           nullptr, nullptr, 0.0, weights);
    const double bound = depth_upper_bound(sdf, centre, ud.hi + 2 * radius, v.data(), 3, scratch, nullptr, &normal,
                                           nullptr, nullptr, slack, weights);
    if (!(bound < HUGE_VAL)) continue;
    ++done;
    EXPECT_LE(bound, plain);
    if (bound < plain * (1 - 1e-9)) ++tighter;
    // A sample is computed from the corners in doubles: within a few ulps of the cell, not in it.
    const double rounding = 1e-15 * std::max({v[0].cwiseAbs().maxCoeff(), v[1].cwiseAbs().maxCoeff(),
                                              v[2].cwiseAbs().maxCoeff()});
    for (const Vec3& x : samples(v))
      EXPECT_TRUE(within(exact_squared_distance(x, m), bound + rounding))
          << std::setprecision(17) << "point (" << x.x() << ", " << x.y() << ", " << x.z() << ") is farther than "
          << bound << "; cell (" << v[0].transpose() << ") (" << v[1].transpose() << ") (" << v[2].transpose() << ")";
  }
  return tighter;
}

TEST(PlanarPatch, BoundsEveryPointOfTheCellExactly) {
  // Exactly coplanar, coplanar up to rounding, and off their planes by up to 1e-9 (within the
  // slack: the patch's eta must carry it).
  TriangleMesh jittered = make_cube_solid(l_slab(), some_rotation());
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> s(-1.0, 1.0);
  for (Vec3& x : jittered.vertices) x += 1e-9 * Vec3{s(rng), s(rng), s(rng)};
  for (const auto& [name, m] : std::vector<std::pair<std::string, TriangleMesh>>{
           {"axis-aligned", make_cube_solid(l_slab(), Eigen::Matrix3d::Identity())},
           {"rotated", make_cube_solid(l_slab(), some_rotation())},
           {"jittered", jittered}}) {
    SCOPED_TRACE(name);
    const int tighter = check_patch_bounds(m, 3, 400, 1e-9 * 3 * m.bbox().diagonal());
    EXPECT_GT(tighter, 30) << "of 400";  // the patches matter on many of these cells (45-58)
    check_patch_bounds(m, 3, 400, 1e-9 * 3 * m.bbox().diagonal(), DepthWeights::sparse);
  }
}

TEST(PlanarPatch, ExactOnThePlaneAcrossSharedEdges) {
  // A flat cell 0.25 below the top face of the L slab (z = 1), across the shared edges of four of
  // its triangles: the depth there is 0.25 everywhere; triangle by triangle the bound is looser.
  const TriangleMesh m = make_cube_solid(l_slab(), Eigen::Matrix3d::Identity());
  const SignedDistance sdf(m);
  const std::array<Vec3, 3> v{Vec3(0.8, 0.7, 0.75), Vec3(1.3, 0.8, 0.75), Vec3(0.9, 1.3, 0.75)};
  const Vec3 centre = (v[0] + v[1] + v[2]) / 3.0;
  const Vec3 normal(0, 0, 1);
  std::vector<std::uint32_t> scratch;
  const double plain = depth_upper_bound(sdf, centre, 1.0, v.data(), 3, scratch, nullptr, &normal);
  const double patched = depth_upper_bound(sdf, centre, 1.0, v.data(), 3, scratch, nullptr, &normal, nullptr, nullptr,
                                           1e-12);
  EXPECT_NEAR(patched, 0.25, 1e-12);
  EXPECT_GT(plain, 0.26);
  // Over the L's missing corner (x, y > 2) the top face does not cover the cell: no patch there.
  const std::array<Vec3, 3> w{Vec3(1.8, 1.8, 0.75), Vec3(2.3, 1.9, 0.75), Vec3(1.9, 2.3, 0.75)};
  std::vector<std::uint32_t> top;
  for (std::uint32_t i = 0; i < m.faces.size(); ++i) {
    bool up = true;
    for (std::uint32_t k : m.faces[i]) up = up && m.vertices[k].z() == 1.0;
    if (up) top.push_back(i);
  }
  ASSERT_EQ(top.size(), 16u);
  EXPECT_TRUE(patch_covers_cell(m, top, normal, 1.0, v.data(), 3));
  EXPECT_FALSE(patch_covers_cell(m, top, normal, 1.0, w.data(), 3));
}

// A flat cell lying on F (a mover face resting on the L slab's top, z = 1), its centre exactly on
// one of F's triangles, where that triangle's distance has no gradient: the depth there is 0, and
// the bound must say so, within one triangle and, with planar patches, across shared edges. Before
// session 93 it gave no bound at all (+inf), and the branch and bound split such cells down to the
// tolerance (a cube resting face-on on a step was not certified within the work limit).
TEST(PlanarPatch, ACellLyingOnFKeepsItsBound) {
  const TriangleMesh m = make_cube_solid(l_slab(), Eigen::Matrix3d::Identity());
  const SignedDistance sdf(m);
  const Vec3 normal(0, 0, 1);
  std::vector<std::uint32_t> scratch;
  // Within one triangle of the square [0, 1]^2 (either diagonal): the triangle alone is exact.
  const std::array<Vec3, 3> inside{Vec3(0.375, 0.0625, 1), Vec3(0.625, 0.0625, 1), Vec3(0.5, 0.25, 1)};
  const Vec3 c(0.5, 0.125, 1);  // the centroid, exactly
  EXPECT_LE(depth_upper_bound(sdf, c, 1.0, inside.data(), 3, scratch, nullptr, &normal), 1e-12);
  // Across the shared edges of four top triangles (ExactOnThePlaneAcrossSharedEdges's cell, lifted
  // onto the face): the patch is exact.
  const std::array<Vec3, 3> across{Vec3(0.8, 0.7, 1), Vec3(1.3, 0.8, 1), Vec3(0.9, 1.3, 1)};
  const Vec3 on(0.96875, 0.9375, 1);  // a point of the cell, on F
  EXPECT_LE(depth_upper_bound(sdf, on, 1.0, across.data(), 3, scratch, nullptr, &normal, nullptr, nullptr, 1e-12),
            1e-12);
  // Still a bound where the cell leaves F's top: over the missing corner (x, y > 2) every point of
  // the cell is within the bound of F (checked exactly at sampled points).
  const std::array<Vec3, 3> off{Vec3(1.75, 1.5, 1), Vec3(2.5, 1.75, 1), Vec3(1.5, 2.5, 1)};
  const Vec3 at(1.75, 1.75, 1);
  const double b = depth_upper_bound(sdf, at, 2.0, off.data(), 3, scratch, nullptr, &normal, nullptr, nullptr, 1e-12);
  ASSERT_LT(b, 1.0);
  for (const Vec3& x : samples(off)) EXPECT_TRUE(within(exact_squared_distance(x, m), b)) << x.transpose();
}

// patch_covers_cell against dense sampling: random cells over the top face of the L slab with
// random triangles removed (holes and notches); whenever it claims coverage, every sampled point's
// projection lies in a remaining triangle (exact 2-D predicates). It must claim it often.
TEST(PlanarPatch, CoverageClaimsHoldUnderSampling) {
  const TriangleMesh m = make_cube_solid(l_slab(), Eigen::Matrix3d::Identity());
  std::vector<std::uint32_t> top;
  for (std::uint32_t i = 0; i < m.faces.size(); ++i) {
    bool up = true;
    for (std::uint32_t k : m.faces[i]) up = up && m.vertices[k].z() == 1.0;
    if (up) top.push_back(i);
  }
  using P2 = testing::Epick::Point_2;
  const auto in_union = [&](const std::vector<std::uint32_t>& ids, const Vec3& x) {
    const P2 p(x.x(), x.y());
    for (std::uint32_t j : ids) {
      const auto& f = m.faces[j];
      const P2 a(m.vertices[f[0]].x(), m.vertices[f[0]].y()), b(m.vertices[f[1]].x(), m.vertices[f[1]].y()),
          c(m.vertices[f[2]].x(), m.vertices[f[2]].y());
      const auto o = CGAL::orientation(a, b, c);
      if (CGAL::orientation(a, b, p) != -o && CGAL::orientation(b, c, p) != -o && CGAL::orientation(c, a, p) != -o)
        return true;
    }
    return false;
  };
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  const Vec3 n(0, 0, 1);
  int claimed = 0;
  for (int k = 0; k < 3000; ++k) {
    std::vector<std::uint32_t> ids = top;
    const int removed = static_cast<int>(rng() % 3);
    for (int r = 0; r < removed; ++r) ids.erase(ids.begin() + static_cast<long>(rng() % ids.size()));
    const Vec3 c{3 * u(rng), 3 * u(rng), 1 + s(rng)};
    const double size = 0.05 + 0.6 * u(rng);
    std::array<Vec3, 3> v;
    for (Vec3& x : v) x = c + size * Vec3{s(rng), s(rng), s(rng)};
    if (!patch_covers_cell(m, ids, n, 1.0, v.data(), 3)) continue;
    ++claimed;
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; i + j <= 20; ++j) {
        const Vec3 x = v[0] + (i / 20.0) * (v[1] - v[0]) + (j / 20.0) * (v[2] - v[0]);
        ASSERT_TRUE(in_union(ids, x)) << std::setprecision(17) << "cell (" << v[0].transpose() << ") ("
                                      << v[1].transpose() << ") (" << v[2].transpose() << "), point " << x.transpose();
      }
  }
  EXPECT_GT(claimed, 300);
}

// The same for axis-aligned cubes (the maximum penetration's cells) over the top face of a rotated
// L slab (tilted normal: the projected cube is a hexagon): whenever coverage is claimed, every
// sampled point of the cube projects into a triangle of the face, decided exactly (the sign of
// det[b - a, n, x - a] in rationals, for the stored n).
TEST(PlanarPatch, BoxCoverageClaimsHoldUnderSampling) {
  const Eigen::Matrix3d R = some_rotation();
  const TriangleMesh m = make_cube_solid(l_slab(), R);
  const Vec3 up = R * Vec3(0, 0, 1);
  const SignedDistance sdf(m);
  std::vector<std::uint32_t> top;
  for (std::uint32_t i = 0; i < m.faces.size(); ++i) {
    const TrianglePlane& pl = sdf.planes()[i];
    if (pl.n.dot(up) > 0.999 && std::abs(pl.d - up.dot(R * Vec3(0, 0, 1))) < 1e-9) top.push_back(i);
  }
  ASSERT_EQ(top.size(), 16u);
  const TrianglePlane& pl = sdf.planes()[top[0]];
  using FT = Epeck::FT;
  const auto det = [&](const Vec3& a, const Vec3& b, const Vec3& x) {
    const FT e0 = FT(b.x()) - a.x(), e1 = FT(b.y()) - a.y(), e2 = FT(b.z()) - a.z();
    const FT f0 = FT(x.x()) - a.x(), f1 = FT(x.y()) - a.y(), f2 = FT(x.z()) - a.z();
    const FT n0 = pl.n.x(), n1 = pl.n.y(), n2 = pl.n.z();
    return CGAL::sign((e1 * n2 - e2 * n1) * f0 + (e2 * n0 - e0 * n2) * f1 + (e0 * n1 - e1 * n0) * f2);
  };
  const auto in_union = [&](const Vec3& x) {
    for (std::uint32_t j : top) {
      const Face& f = m.faces[j];
      const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
      const auto o = det(a, b, c);
      if (det(a, b, x) != -o && det(b, c, x) != -o && det(c, a, x) != -o) return true;
    }
    return false;
  };
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  int claimed = 0;
  for (int k = 0; k < test_scale::cases(600); ++k) {
    const Vec3 c = R * Vec3{3 * u(rng), 3 * u(rng), 1 + 0.5 * s(rng)};
    const double h = 0.02 + 0.4 * u(rng);
    std::array<Vec3, 8> v;
    for (int q = 0; q < 8; ++q) v[q] = c + Vec3((q & 1) ? h : -h, (q & 2) ? h : -h, (q & 4) ? h : -h);
    if (!patch_covers_cell(m, top, pl.n, pl.d, v.data(), 8)) continue;
    ++claimed;
    for (int i = 0; i <= 4; ++i)
      for (int j = 0; j <= 4; ++j)
        for (int l = 0; l <= 4; ++l) {
          const Vec3 x = c + h * Vec3(i / 2.0 - 1, j / 2.0 - 1, l / 2.0 - 1);
          ASSERT_TRUE(in_union(x)) << std::setprecision(17) << "cube centre " << c.transpose() << " half side " << h
                                   << ", point " << x.transpose();
        }
  }
  EXPECT_GT(claimed, test_scale::cases(60)) << "of " << test_scale::cases(600);
}

}  // namespace
}  // namespace cdbench

namespace cdbench {
namespace {

// Random cubes in and around closed meshes: the minimax bound (weights from a linear program) bounds
// the exact distance to the surface of every point of a 5 x 5 x 5 grid of the cube.
TEST(MinimaxDepthBound, BoundsEveryPointOfTheCubeExactly) {
  for (const auto& [name, m] : std::vector<std::pair<std::string, TriangleMesh>>{
           {"torus", make_torus(2.0, 0.6, 24, 12)},
           {"tube", make_tube(0.17, 0.31, 1.0, 20)},
           {"box", make_box(Vec3(0, 0, 0), Vec3(2, 1, 0.5))}}) {
    SCOPED_TRACE(name);
    const SignedDistance sdf(m);
    const Aabb box = m.bbox();
    std::mt19937_64 rng(31);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<std::uint32_t> ids;
    int cells = 0, finite = 0;
    while (cells < test_scale::cases(150)) {
      const Vec3 c = box.lo + Vec3{u(rng), u(rng), u(rng)}.cwiseProduct(box.extent());
      const double h = box.diagonal() * (0.001 + 0.03 * u(rng));
      std::array<Vec3, 8> v;
      for (int q = 0; q < 8; ++q) v[q] = c + Vec3((q & 1) ? h : -h, (q & 2) ? h : -h, (q & 4) ? h : -h);
      const Interval ud = sdf.unsigned_distance(c);
      depth_upper_bound(sdf, c, ud.hi + 2 * std::sqrt(3.0) * h, v.data(), 8, ids);  // ids: nearest first
      ++cells;
      const double bound = minimax_depth_bound(sdf, ids, v.data(), 8);
      if (!(bound < HUGE_VAL)) continue;
      ++finite;
      for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j)
          for (int l = 0; l <= 4; ++l) {
            const Vec3 x = c + h * Vec3(i / 2.0 - 1, j / 2.0 - 1, l / 2.0 - 1);
            ASSERT_TRUE(within(exact_squared_distance(x, m), bound))
                << std::setprecision(17) << "cube centre " << c.transpose() << " half side " << h << ", point "
                << x.transpose() << ", bound " << bound;
          }
    }
    EXPECT_GT(finite, test_scale::cases(150) - 10);
  }
}

// Across a seam of a faceted tube's wall (a cube about the bisector of two outer facets, where the
// deepest points lie), the min-norm weights balance one facet against the facing one and miss the
// seam; the program's weights take both outer facets and the inner edge.
TEST(MinimaxDepthBound, TighterThanMinNormWeightsAcrossATubesSeam) {
  const TriangleMesh m = make_tube(0.17, 0.31, 1.0, 40);
  const SignedDistance sdf(m);
  std::vector<std::uint32_t> ids;
  int tighter = 0;
  for (double h : {0.02, 0.01, 0.005, 0.0025}) {
    const Vec3 c(0.24, 0.001, 0.5);  // beside the bisector of the facets meeting at angle 0
    std::array<Vec3, 8> v;
    for (int q = 0; q < 8; ++q) v[q] = c + Vec3((q & 1) ? h : -h, (q & 2) ? h : -h, (q & 4) ? h : -h);
    const Interval ud = sdf.unsigned_distance(c);
    const double min_norm = depth_upper_bound(sdf, c, ud.hi + 2 * std::sqrt(3.0) * h, v.data(), 8, ids);
    const double minimax = minimax_depth_bound(sdf, ids, v.data(), 8);
    // No weights give less than the largest distance of a cube point (sampled: a little below it);
    // the program's excess over it is under half the min-norm weights' (measured 0.22-0.39).
    double deepest = 0.0;
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j)
        for (int l = 0; l <= 8; ++l)
          deepest = std::max(deepest, sdf.unsigned_distance(c + h * Vec3(i / 4.0 - 1, j / 4.0 - 1, l / 4.0 - 1)).lo);
    EXPECT_GE(minimax, deepest);
    EXPECT_LE(minimax, min_norm);
    if (minimax - deepest < 0.5 * (min_norm - deepest)) ++tighter;
    else
      ADD_FAILURE() << std::setprecision(17) << "h " << h << ": deepest sample " << deepest << ", min-norm "
                    << min_norm << ", minimax " << minimax;
  }
  EXPECT_EQ(tighter, 4);
}

}  // namespace
}  // namespace cdbench
