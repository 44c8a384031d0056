// Deep-zone jumps (PoseOptions::deep_cover and deep_zone_cubes, deep_cover_contact,
// deep_zone_contact; doc/poses.md, "Deep-zone jumps"): beyond the mover's first contact with the
// cover its clearance is above the target (checked by certificates), the octree grown about the
// mover's path finds the built cover's contact, and a jump never passes the first crossing (poses
// with and without jumps agree within the tolerance), while it crosses a plateau in one step.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iomanip>
#include <limits>
#include <random>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "distance/deep_cover.h"
#include "distance/point_triangle_distance.h"
#include "mesh/shapes.h"
#include "placement/advance.h"
#include "placement/clearance.h"
#include "placement/place_pose.h"
#include "scene.h"

namespace cdbench {
namespace {

// A thin plate (0.04 thick, deepest point 0.02) then, past a gap, a thick block: at -0.05 the
// mover slides through the plate on a plateau (c about -0.02) before it reaches the block.
TriangleMesh plate_and_block(double half_thickness = 0.02, double half_width = 0.5) {
  return merge_meshes(make_box(Vec3(0, -half_width, -half_thickness), Vec3(1, half_width, half_thickness)),
                      make_box(Vec3(1.2, -0.5, -0.5), Vec3(2, 0.5, 0.5)));
}

using testing::random_direction;
using testing::random_rotation;
using testing::Scene;

// The two scenes of the zone's tests (shape 0, 1): a sphere through the plate and block, at a
// target beyond the plate's depth, and through a torus, at a target under a third of its tube.
Scene zone_scene(int shape) {
  return Scene(shape == 0 ? plate_and_block() : make_torus(1.0, 0.4, 24, 12), make_icosphere(0.15, 1));
}
double zone_target(int shape) { return shape == 0 ? -0.05 : -0.12; }

// A level's options point into its zone (cover, memo): taking them from a temporary zone, whose
// cover and memo die with it, does not compile (a test of session 85 did so, and its poses read
// freed memory).
template <class Z, class = void>
struct OptionsFrom : std::false_type {};
template <class Z>
struct OptionsFrom<Z, std::void_t<decltype(std::declval<Z>().options(PoseOptions{}))>> : std::true_type {};
static_assert(OptionsFrom<const LevelDeepZone&>::value, "a kept zone gives its options");
static_assert(!OptionsFrom<LevelDeepZone>::value, "a temporary zone must not give options");

TEST(DeepJumps, OctreeBudgetDoublesAndTriesTheCapOnce) {
  PoseOptions o;
  o.deep_zone_cubes = 4000000;
  o.deep_zone_cubes_per_cell = 4.0;
  o.deep_zone_min_cubes = 2000;
  EXPECT_EQ(deep_zone_query_budget(o, 400, 0), 0u);        // 1,600 cubes: below the least query
  EXPECT_EQ(deep_zone_query_budget(o, 1000, 0), 4000u);    // the first: 4 x the cells
  EXPECT_EQ(deep_zone_query_budget(o, 1500, 4000), 0u);    // 6,000: not yet double the last
  EXPECT_EQ(deep_zone_query_budget(o, 2000, 4000), 8000u);  // double: tried again
  // The doubling would skip the cap (2.15 M ran out; 4.3 M is above it): one last query at it.
  EXPECT_EQ(deep_zone_query_budget(o, 1000000, 2150000), 4000000u);
  EXPECT_EQ(deep_zone_query_budget(o, 3000000, 4000000), 0u);  // that ran out too: none more
  EXPECT_EQ(deep_zone_query_budget(o, 600000, 2150000), 0u);   // 2.4 M: not double, not the cap
  // On a plateau a pose gets the least query before its work reaches it, and more by its work.
  o.deep_zone_min_cubes = 20000;
  EXPECT_EQ(deep_zone_query_budget(o, 1000, 0), 0u);
  EXPECT_EQ(deep_zone_query_budget(o, 1000, 0, ZonePlateau::plateau), 20000u);
  EXPECT_EQ(deep_zone_query_budget(o, 1000, 20000, ZonePlateau::plateau), 0u);  // that ran out: not yet double
  EXPECT_EQ(deep_zone_query_budget(o, 10000, 20000, ZonePlateau::plateau), 40000u);
  // On a long plateau its own cubes a cell: 16 x 10,000 (4 x 10,000 on a plateau, above).
  o.deep_zone_long_plateau_cubes_per_cell = 16.0;
  EXPECT_EQ(deep_zone_query_budget(o, 1000, 0, ZonePlateau::long_plateau), 20000u);  // the least
  EXPECT_EQ(deep_zone_query_budget(o, 10000, 20000, ZonePlateau::long_plateau), 160000u);
  EXPECT_EQ(deep_zone_query_budget(o, 10000, 100000, ZonePlateau::long_plateau), 0u);  // not double
  o.deep_zone_cubes = 0;
  EXPECT_EQ(deep_zone_query_budget(o, 1000000, 0), 0u);  // no octree
}

TEST(DeepJumps, CoverBudgetFollowsTheRequest) {
  // 1,000 cubes per approach of the level, at most 150,000; without a request size, the cap.
  EXPECT_EQ(deep_cover_options(-0.1, 40).max_cells, 40000u);
  EXPECT_EQ(deep_cover_options(-0.1, 149).max_cells, 149000u);
  EXPECT_EQ(deep_cover_options(-0.1, 150).max_cells, 150000u);
  EXPECT_EQ(deep_cover_options(-0.1, 5000).max_cells, 150000u);
  EXPECT_EQ(deep_cover_options(-0.1).max_cells, 150000u);
  EXPECT_EQ(deep_cover_options(-0.1, 0).max_cells, 0u);
  EXPECT_DOUBLE_EQ(deep_cover_options(-0.1, 40).cell_size, 0.05);
}

TEST(DeepJumps, CrossThePlateauInOneJump) {
  const Scene w(plate_and_block(), make_icosphere(0.1, 1));
  ApproachSetup setup = w.attached();
  setup.fixed_ref = Vec3(0, 0, 0);  // the mover's centre at (-lambda, 0, 0): through the plate's mid-plane
  const OrientationFrame frame = make_orientation_frame(setup, Eigen::Matrix3d::Identity());
  const double target = -0.05;
  const LazyDeepCover cover(w.fixed, target, deep_cover_options(target));
  PoseOptions opt;
  opt.tolerance = 1e-7;
  opt.start = PoseStart::Surface;
  opt.deep_zone_cubes = 0;  // no jumps
  const Vec3 dir(-1, 0, 0);
  const PoseOutcome plain = place_pose(setup, frame, &w.surface, dir, target, opt);
  opt.deep_cover = &cover;
  const PoseOutcome jumped = place_pose(setup, frame, &w.surface, dir, target, opt);
  // With a cover over its budget, the octree about the mover's path (a budget of its own, not
  // tied to the pose's certificates on so small a mesh).
  DeepCoverOptions tiny = deep_cover_options(target);
  tiny.max_cells = 10;
  const LazyDeepCover over_budget(w.fixed, target, tiny);
  PoseOptions grown = opt;
  grown.deep_cover = &over_budget;
  grown.deep_zone_cubes = 100000;
  grown.deep_zone_cubes_per_cell = 1e9;
  const PoseOutcome lazy = place_pose(setup, frame, &w.surface, dir, target, grown);
  ASSERT_TRUE(lazy.contact && lazy.on_target && lazy.certified);
  ASSERT_NE(over_budget.peek(), nullptr);
  EXPECT_FALSE(over_budget.peek()->complete);
  EXPECT_GT(lazy.zone_cubes, 0u);
  EXPECT_NEAR(lazy.lambda, plain.lambda, 4 * opt.tolerance);
  EXPECT_GE(lazy.cover_jumps, 1);
  EXPECT_LT(lazy.steps + 10, plain.steps) << "plain " << plain.steps << " lazy " << lazy.steps;
  ASSERT_TRUE(plain.contact && plain.on_target && plain.certified);
  ASSERT_TRUE(jumped.contact && jumped.on_target && jumped.certified);
  // In the block, not in the plate: the sphere's front 0.05 inside x = 1.2 (its facets within 0.01).
  EXPECT_LT(plain.lambda, -1.13);
  EXPECT_GT(plain.lambda, -1.16);
  // Both are the first crossing within the tolerance (c falls at unit rate there).
  EXPECT_NEAR(jumped.lambda, plain.lambda, 4 * opt.tolerance);
  EXPECT_GE(jumped.cover_jumps, 1);
  EXPECT_LT(jumped.steps + 10, plain.steps) << "plain " << plain.steps << " jumped " << jumped.steps;
  ASSERT_NE(cover.peek(), nullptr);
  EXPECT_TRUE(cover.peek()->complete);

  // A line beside the block: the plateau never ends; with the cover it is known at once.
  setup.fixed_ref = Vec3(0, 0.35, 0);
  const OrientationFrame beside = make_orientation_frame(setup, Eigen::Matrix3d::Identity());
  const Vec3 slanted = Vec3(-1, 0.5, 0).normalized();  // leaves the block's side at y = 0.5
  opt.deep_cover = nullptr;
  const PoseOutcome p1 = place_pose(setup, beside, &w.surface, slanted, target, opt);
  opt.deep_cover = &cover;
  const PoseOutcome p2 = place_pose(setup, beside, &w.surface, slanted, target, opt);
  const PoseOutcome p3 = place_pose(setup, beside, &w.surface, slanted, target, grown);
  EXPECT_EQ(p1.contact, p2.contact);
  EXPECT_EQ(p1.contact, p3.contact);
  if (p1.contact) {
    EXPECT_NEAR(p1.lambda, p2.lambda, 4 * opt.tolerance);
    EXPECT_NEAR(p1.lambda, p3.lambda, 4 * opt.tolerance);
  }
}

// Beyond the contact with the cover, every pose's certified clearance leaves room above the target
// (c > target there: a certificate entirely below it would refute the cover or its contact).
TEST(DeepJumps, NoPoseBeyondTheContactIsDeep) {
  for (int shape = 0; shape < 2; ++shape) {
    const Scene w = zone_scene(shape);
    const double target = zone_target(shape);
    const LazyDeepCover cover(w.fixed, target, deep_cover_options(target));
    ASSERT_NE(cover.get(), nullptr);
    std::mt19937_64 rng(11 + shape);
    int checked = 0;
    for (int i = 0; i < 12; ++i) {
      const OrientationFrame frame = make_orientation_frame(w.setup, random_rotation(rng));
      const Vec3 dir = random_direction(rng);
      const double lambda_far = w.setup.fixed_radius + w.setup.mover_radius + 1.0;
      const double lk = deep_cover_contact(*cover.get(), frame.orientation, frame.t0, dir, 1e-12, lambda_far);
      if (!(lk > -lambda_far)) continue;
      ClearanceOptions copt;
      copt.tolerance = 1e-6;
      for (int k = 1; k <= 8; ++k) {
        const double lambda = lk + 1e-6 + 0.02 * k * k;
        const Vec3 t = pose_translation(frame, dir, lambda);
        const ClearanceResult c = certify_clearance(w.fixed, w.mover, w.setup.components, frame.orientation, t, copt);
        EXPECT_GT(c.clearance.hi, target) << std::setprecision(17) << "shape " << shape << " lambda " << lambda
                                          << " lambda_K " << lk << " dir " << dir.transpose();
        ++checked;
      }
    }
    EXPECT_GT(checked, 20);
  }
}

// Random approaches on both shapes: with and without jumps, the same first crossing.
TEST(DeepJumps, SameFirstCrossingAsWithout) {
  const Scene w(plate_and_block(), make_icosphere(0.1, 1));
  ApproachSetup setup = w.attached();
  const double target = -0.05;
  const LazyDeepCover cover(w.fixed, target, deep_cover_options(target));
  DeepCoverOptions tiny = deep_cover_options(target);
  tiny.max_cells = 10;
  const LazyDeepCover over_budget(w.fixed, target, tiny);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  int jumps = 0, lazy_jumps = 0, compared = 0;
  for (int i = 0; i < 16; ++i) {
    // Lines near the plate's mid-plane, mostly along it.
    setup.fixed_ref = Vec3{0.5, u(rng), 0.005 * g(rng)};
    const OrientationFrame frame = make_orientation_frame(setup, random_rotation(rng));
    const Vec3 dir = Vec3{-1, 0.3 * g(rng), 0.02 * g(rng)}.normalized();
    PoseOptions opt;
    opt.tolerance = 1e-7;
    opt.start = PoseStart::Surface;
    opt.deep_zone_cubes = 0;
    const PoseOutcome a = place_pose(setup, frame, &w.surface, dir, target, opt);
    opt.deep_cover = &cover;
    const PoseOutcome b = place_pose(setup, frame, &w.surface, dir, target, opt);
    opt.deep_cover = &over_budget;
    opt.deep_zone_cubes = 100000;
    opt.deep_zone_cubes_per_cell = 1e9;
    const PoseOutcome z = place_pose(setup, frame, &w.surface, dir, target, opt);
    ASSERT_EQ(a.contact, b.contact) << "approach " << i;
    ASSERT_EQ(a.contact, z.contact) << "approach " << i;
    if (!a.contact) continue;
    ASSERT_TRUE(a.on_target && b.on_target && z.on_target) << "approach " << i;
    EXPECT_NEAR(a.lambda, b.lambda, 1e-5) << "approach " << i;
    EXPECT_NEAR(a.lambda, z.lambda, 1e-5) << "approach " << i;
    jumps += b.cover_jumps;
    lazy_jumps += z.cover_jumps;
    ++compared;
  }
  EXPECT_GT(compared, 8);
  EXPECT_GT(jumps, 3);
  EXPECT_GT(lazy_jumps, 3);
}

// The octree grown about the mover's path keeps the cubes near it that the built cover keeps (the
// same classification), each held to the zone's part of it by its clips: its latest contact is at
// or below the cover's, and certificates between the two leave room above the target; below a
// lambda_top, the latest one below it, likewise. A budget too small claims nothing.
TEST(DeepJumps, GrownOctreeFindsTheCoversContact) {
  for (int shape = 0; shape < 2; ++shape) {
    const Scene w = zone_scene(shape);
    const double target = zone_target(shape);
    const DeepCoverOptions co = deep_cover_options(target);
    const LazyDeepCover cover(w.fixed, target, co);
    ASSERT_NE(cover.get(), nullptr);
    DeepCubeMemo memo(target);
    std::mt19937_64 rng(23 + shape);
    int met = 0, checked = 0, tighter = 0;
    for (int i = 0; i < 12; ++i) {
      const OrientationFrame frame = make_orientation_frame(w.setup, random_rotation(rng));
      const Vec3 dir = random_direction(rng);
      const double lambda_far = w.setup.fixed_radius + w.setup.mover_radius + 1.0;
      constexpr double kInf = std::numeric_limits<double>::infinity();
      const double lk = deep_cover_contact(*cover.get(), frame.orientation, frame.t0, dir, 1e-12, lambda_far);
      const DeepZoneContact z = deep_zone_contact(w.fixed, target, co.cell_size, frame.orientation, frame.t0, dir,
                                                  1e-12, lambda_far, kInf, kInf, 1000000);
      ASSERT_TRUE(z.complete);
      EXPECT_LE(z.lambda, lk) << std::setprecision(17) << "shape " << shape << " dir " << dir.transpose();
      EXPECT_LE(z.cubes, cover.get()->cells);  // only where the mover passes
      if (z.lambda < lk && lk > -lambda_far) {
        ++tighter;
        ClearanceOptions copt;
        copt.tolerance = 1e-6;
        const double lo = std::max(z.lambda, -lambda_far);
        for (int k = 1; k <= 6; ++k) {
          const double lambda = lo + (lk - lo) * k / 6.0 + 1e-9;
          const ClearanceResult c = certify_clearance(w.fixed, w.mover, w.setup.components, frame.orientation,
                                                      pose_translation(frame, dir, lambda), copt);
          EXPECT_GT(c.clearance.hi, target) << std::setprecision(17) << "shape " << shape << " lambda " << lambda
                                            << " clipped contact " << z.lambda << " dir " << dir.transpose();
          ++checked;
        }
      }
      // Through a memo shared by queries (of other cell sizes too): the same answers and counts.
      for (const double cell : {0.1 * std::abs(target), co.cell_size, co.cell_size}) {
        const DeepZoneContact m = deep_zone_contact(w.fixed, target, cell, frame.orientation, frame.t0, dir, 1e-12,
                                                    lambda_far, kInf, kInf, 1000000, &memo);
        const DeepZoneContact n = deep_zone_contact(w.fixed, target, cell, frame.orientation, frame.t0, dir, 1e-12,
                                                    lambda_far, kInf, kInf, 1000000);
        EXPECT_EQ(m.lambda, n.lambda);
        EXPECT_EQ(m.cubes, n.cubes);
      }
      if (!(lk > -lambda_far)) continue;
      ++met;
      // Below lambda_top = that contact, a finer octree (cubes a tenth of |target|): its contact is
      // at or below it, and certificates between the two leave room above the target.
      const double top = lk;
      const DeepZoneContact y = deep_zone_contact(w.fixed, target, 0.1 * std::abs(target), frame.orientation, frame.t0,
                                                  dir, 1e-12, lambda_far, top, kInf, 1000000);
      ASSERT_TRUE(y.complete);
      EXPECT_LE(y.lambda, top);
      if (!(y.lambda > -lambda_far) || !(y.lambda < top)) continue;
      ClearanceOptions copt;
      copt.tolerance = 1e-6;
      for (int k = 1; k <= 6; ++k) {
        const double lambda = y.lambda + (top - y.lambda) * k / 6.0 + 1e-9;
        const Vec3 t = pose_translation(frame, dir, lambda);
        const ClearanceResult c = certify_clearance(w.fixed, w.mover, w.setup.components, frame.orientation, t, copt);
        EXPECT_GT(c.clearance.hi, target) << std::setprecision(17) << "shape " << shape << " lambda " << lambda
                                          << " contact " << y.lambda << " dir " << dir.transpose();
        ++checked;
      }
      const DeepZoneContact tiny = deep_zone_contact(w.fixed, target, co.cell_size, frame.orientation, frame.t0, dir,
                                                     1e-12, lambda_far, kInf, kInf, 3);
      EXPECT_FALSE(tiny.complete);
    }
    EXPECT_GT(met, 3);
    EXPECT_GT(checked, 10);
    EXPECT_GT(tighter, 2);  // the clips moved the contact
    EXPECT_GT(memo.size(), 100u);
  }
}

// The octree's contact names the mover face that met the zone there and the cube it met: at the
// contact pose that face passes within the cube's half-diagonal of its centre, and its point nearest
// the centre lies inside F (the cube holds zone points, |target| deep): the landing's hint
// (place_pose). No contact, no face.
TEST(DeepJumps, ContactNamesTheMoverFaceAtTheCubeItMet) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  int named = 0, inside = 0;
  for (int shape = 0; shape < 2; ++shape) {
    const Scene w = zone_scene(shape);
    const double target = zone_target(shape);
    const double cell = deep_cover_options(target).cell_size;
    std::mt19937_64 rng(53 + shape);
    for (int i = 0; i < 12; ++i) {
      const OrientationFrame frame = make_orientation_frame(w.setup, random_rotation(rng));
      const Vec3 dir = random_direction(rng);
      const double lambda_far = w.setup.fixed_radius + w.setup.mover_radius + 1.0;
      const DeepZoneContact z = deep_zone_contact(w.fixed, target, cell, frame.orientation, frame.t0, dir, 1e-12,
                                                  lambda_far, kInf, kInf, 1000000);
      ASSERT_TRUE(z.complete);
      if (!(z.lambda > -lambda_far)) {
        EXPECT_EQ(z.face, -1);
        continue;
      }
      ASSERT_GE(z.face, 0);
      ASSERT_LT(static_cast<std::size_t>(z.face), w.mover.faces.size());
      const std::vector<Vec3> P = frame.orientation.placed(pose_translation(frame, dir, z.lambda));
      const Face& f = w.mover.faces[static_cast<std::size_t>(z.face)];
      const Vec3 q = closest_point_on_triangle(z.cube_centre, P[f[0]], P[f[1]], P[f[2]]);
      EXPECT_LE((q - z.cube_centre).norm(), 0.87 * cell + 1e-9)
          << std::setprecision(17) << "shape " << shape << " dir " << dir.transpose() << " face " << z.face;
      ++named;
      inside += w.fixed.side(q) < 0;
    }
  }
  EXPECT_GT(named, 8);
  EXPECT_EQ(inside, named);
}

// The octree walked with the mover's sweep tree (its oriented boxes) instead of its box tree: a
// thin ring tilted at random, whose arcs' axis-aligned boxes are far fatter than they are. Its
// contact is valid (certificates above it leave room above the target, as for the box tree's),
// it classifies fewer cubes over the approaches, and a sweep mesh of another mesh is refused. The
// built cover's contact likewise.
TEST(DeepJumps, OrientedBoxesKeepTheOctreeValidWithFewerCubes) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::uint64_t box_cubes = 0, oriented_cubes = 0;
  int met = 0, checked = 0;
  for (int shape = 0; shape < 2; ++shape) {
    const Scene w(shape == 0 ? plate_and_block() : make_torus(1.0, 0.4, 24, 12), make_torus(0.2, 0.01, 32, 6));
    const double target = shape == 0 ? -0.015 : -0.12;
    const double cell = 0.25 * std::abs(target), clipped = 3.0 * std::abs(target);
    const LazyDeepCover cover(w.fixed, target, deep_cover_options(target));
    std::mt19937_64 rng(71 + shape);
    for (int i = 0; i < 10; ++i) {
      const OrientationFrame frame = make_orientation_frame(w.setup, random_rotation(rng));
      const Vec3 dir = random_direction(rng);
      const double lambda_far = w.setup.fixed_radius + w.setup.mover_radius + 1.0;
      const DeepZoneContact boxes = deep_zone_contact(w.fixed, target, cell, frame.orientation, frame.t0, dir, 1e-12,
                                                      lambda_far, kInf, kInf, 4000000, nullptr, clipped);
      const DeepZoneContact oriented = deep_zone_contact(w.fixed, target, cell, frame.orientation, frame.t0, dir,
                                                         1e-12, lambda_far, kInf, kInf, 4000000, nullptr, clipped,
                                                         nullptr, &frame.swept);
      ASSERT_TRUE(boxes.complete && oriented.complete);
      box_cubes += boxes.cubes;
      oriented_cubes += oriented.cubes;
      // The built cover's contact: the oriented boxes visit a subset of the triangle-box pairs,
      // so theirs is at or below the box tree's (the latest over all pairs: in practice the same),
      // and valid.
      if (const DeepCover* cv = cover.get()) {
        const double lb = deep_cover_contact(*cv, frame.orientation, frame.t0, dir, 1e-12, lambda_far);
        const double lo = deep_cover_contact(*cv, frame.orientation, frame.t0, dir, 1e-12, lambda_far, kInf,
                                             &frame.swept);
        EXPECT_LE(lo, lb) << std::setprecision(17) << "shape " << shape << " dir " << dir.transpose();
        if (lo > -lambda_far) {
          ClearanceOptions copt;
          copt.tolerance = 1e-6;
          for (int k = 0; k < 3; ++k) {
            const double lambda = lo + 1e-9 + 0.01 * k;
            const ClearanceResult c = certify_clearance(w.fixed, w.mover, w.setup.components, frame.orientation,
                                                        pose_translation(frame, dir, lambda), copt);
            EXPECT_GT(c.clearance.hi, target) << std::setprecision(17) << "shape " << shape << " lambda " << lambda
                                              << " cover contact " << lo << " dir " << dir.transpose();
          }
        }
      }
      if (!(oriented.lambda > -lambda_far)) continue;
      ++met;
      ClearanceOptions copt;
      copt.tolerance = 1e-6;
      // Just above the contact (where a bound that cut into the mover's nodes would claim poses
      // that meet the zone) and up to the box tree's contact.
      for (int k = 0; k <= 6; ++k) {
        const double lambda = k < 6 ? oriented.lambda + 1e-9 + 0.004 * k
                                    : oriented.lambda + 0.5 * (std::max(boxes.lambda, oriented.lambda) - oriented.lambda);
        const ClearanceResult c = certify_clearance(w.fixed, w.mover, w.setup.components, frame.orientation,
                                                    pose_translation(frame, dir, lambda), copt);
        EXPECT_GT(c.clearance.hi, target) << std::setprecision(17) << "shape " << shape << " lambda " << lambda
                                          << " contact " << oriented.lambda << " dir " << dir.transpose();
        ++checked;
      }
    }
    const SweepMesh other = make_sweep_mesh(w.fixed.mesh().vertices, w.fixed.mesh().faces);
    const OrientationFrame frame = make_orientation_frame(w.setup, Eigen::Matrix3d::Identity());
    EXPECT_THROW(deep_zone_contact(w.fixed, target, cell, frame.orientation, frame.t0, Vec3(1, 0, 0), 1e-12, 10.0, kInf,
                                   kInf, 1000, nullptr, clipped, nullptr, &other),
                 std::invalid_argument);
  }
  EXPECT_GT(met, 4);
  EXPECT_GT(checked, 30);
  EXPECT_LT(oriented_cubes, box_cubes);
}

// A query that runs out and is held, then continued (with a larger budget, under the same or a
// lower lambda_top): a complete search's answer is the latest contact over the same octree, so it
// equals a fresh query's; its cubes, before and after, are the fresh query's. A different question
// is not continued, and a completed query is no longer held.
TEST(DeepJumps, HeldQueryContinuesToTheFreshAnswer) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  int continued = 0, lowered = 0;
  for (int shape = 0; shape < 2; ++shape) {
    const Scene w = zone_scene(shape);
    const double target = zone_target(shape);
    const double cell = 0.1 * std::abs(target), clipped = 0.3 * std::abs(target);
    std::mt19937_64 rng(41 + shape);
    for (int i = 0; i < 10; ++i) {
      const OrientationFrame frame = make_orientation_frame(w.setup, random_rotation(rng));
      const Vec3 dir = random_direction(rng);
      const double lambda_far = w.setup.fixed_radius + w.setup.mover_radius + 1.0;
      const auto ask = [&](double top, std::uint64_t budget, HeldZoneQuery* held) {
        return deep_zone_contact(w.fixed, target, cell, frame.orientation, frame.t0, dir, 1e-12, lambda_far, top, kInf,
                                 budget, nullptr, clipped, held);
      };
      const DeepZoneContact fresh = ask(kInf, 1000000, nullptr);
      ASSERT_TRUE(fresh.complete);
      if (fresh.cubes < 20) continue;
      HeldZoneQuery held;
      const DeepZoneContact first = ask(kInf, fresh.cubes / 3, &held);
      ASSERT_FALSE(first.complete);
      ASSERT_TRUE(held.held());
      EXPECT_EQ(held.cell_size(), cell);
      const DeepZoneContact rest = ask(kInf, 1000000, &held);
      ASSERT_TRUE(rest.complete);
      EXPECT_FALSE(held.held());
      EXPECT_EQ(rest.lambda, fresh.lambda) << std::setprecision(17) << "shape " << shape << " dir " << dir.transpose();
      EXPECT_EQ(rest.face, fresh.face);
      EXPECT_EQ(rest.cube_centre, fresh.cube_centre);
      EXPECT_EQ(first.cubes + rest.cubes, fresh.cubes);
      ++continued;
      // Under a lower lambda_top (what a pose that advanced asks): the fresh answer there.
      if (!(fresh.lambda > -lambda_far)) continue;
      const double top = fresh.lambda + 0.25 * (lambda_far - fresh.lambda);
      const DeepZoneContact fresh_low = ask(top, 1000000, nullptr);
      const DeepZoneContact part = ask(kInf, fresh.cubes / 4, &held);
      ASSERT_FALSE(part.complete);
      const DeepZoneContact low = ask(top, 1000000, &held);
      ASSERT_TRUE(low.complete);
      EXPECT_EQ(low.lambda, fresh_low.lambda) << std::setprecision(17) << "shape " << shape << " top " << top;
      ++lowered;
      // Another question (another cell size) starts afresh and drops the held one.
      ASSERT_FALSE(ask(kInf, fresh.cubes / 4, &held).complete);
      const DeepZoneContact other = deep_zone_contact(w.fixed, target, 2.0 * cell, frame.orientation, frame.t0, dir,
                                                      1e-12, lambda_far, kInf, kInf, 1000000, nullptr, clipped, &held);
      const DeepZoneContact other_fresh = deep_zone_contact(w.fixed, target, 2.0 * cell, frame.orientation, frame.t0,
                                                            dir, 1e-12, lambda_far, kInf, kInf, 1000000, nullptr, clipped);
      EXPECT_EQ(other.lambda, other_fresh.lambda);
      EXPECT_EQ(other.cubes, other_fresh.cubes);
      EXPECT_FALSE(held.held());
    }
  }
  EXPECT_GT(continued, 6);
  EXPECT_GT(lowered, 3);
}

// The sphere (w's mover, at the setup's fixed_ref for lambda 0, moving along -dir) polished at a
// level of the plate-and-block (M = 0.4) without jumps (first) and with the level's cover, if it
// has one, and octree (second); both certified, on target and at the same first crossing.
constexpr double kPlateTolerance = 1e-7;
std::pair<PoseOutcome, PoseOutcome> with_and_without_jumps(const Scene& w, const ApproachSetup& setup, const Vec3& dir,
                                                           double target, bool segment_steps = true) {
  constexpr double max_penetration = 0.4;  // the block's
  const OrientationFrame frame = make_orientation_frame(setup, Eigen::Matrix3d::Identity());
  const LevelDeepZone zone = make_level_deep_zone(w.fixed, target, max_penetration, true, 40);
  EXPECT_EQ(zone.cover != nullptr, deep_cover_wanted(target, max_penetration));
  EXPECT_NE(zone.memo, nullptr);
  PoseOptions base;
  base.tolerance = kPlateTolerance;
  base.start = PoseStart::Surface;
  base.segment_steps = segment_steps;
  PoseOptions none = base;
  none.deep_zone_cubes = 0;
  std::pair<PoseOutcome, PoseOutcome> r{place_pose(setup, frame, &w.surface, dir, target, none),
                                        place_pose(setup, frame, &w.surface, dir, target, zone.options(base))};
  const PoseOutcome &plain = r.first, &jumped = r.second;
  EXPECT_TRUE(plain.contact && plain.on_target && plain.certified);
  EXPECT_TRUE(jumped.contact && jumped.on_target && jumped.certified);
  EXPECT_NEAR(jumped.lambda, plain.lambda, 4 * kPlateTolerance);
  return r;
}

// The sphere through the plate's mid-plane (c = -0.02 on the plate) towards the block: it jumps.
// Another plate or bar, or the sphere's lowest point at z = lowest.
std::pair<PoseOutcome, PoseOutcome> across_the_plate(double target, const TriangleMesh& fixed = plate_and_block(),
                                                     double lowest = -1.0, bool segment_steps = true) {
  const Scene w(fixed, make_icosphere(0.1, 1));
  ApproachSetup setup = w.attached();
  setup.fixed_ref = Vec3(0, 0, 0);
  if (lowest > -1.0) {  // the mover's lowest point at z = lowest, not its centre at 0
    double low = 0.0;
    for (const Vec3& v : w.mover.vertices) low = std::min(low, v[2] - setup.mover_ref[2]);
    setup.fixed_ref[2] = lowest - low;
  }
  const auto r = with_and_without_jumps(w, setup, Vec3(-1, 0, 0), target, segment_steps);
  EXPECT_LT(r.first.lambda, -1.1);  // in the block
  EXPECT_GE(r.second.cover_jumps, 1);
  EXPECT_GT(r.second.zone_cubes, 0u);
  return r;
}

// A level shallower than a fifth of M gets no cover but the octree about the mover's path, asked
// on a long plateau only: at -0.024 the gap is 0.004 for a length of 1.2 (about 250 two-sided
// steps), and the jump crosses it.
TEST(DeepJumps, ShallowLevelJumpsWithTheOctreeAlone) {
  ASSERT_FALSE(deep_cover_wanted(-0.024, 0.4));
  const Scene w(plate_and_block(), make_icosphere(0.1, 1));
  EXPECT_EQ(make_level_deep_zone(w.fixed, -0.024, 0.4, false, 40).memo, nullptr);  // not polished
  EXPECT_EQ(make_level_deep_zone(w.fixed, 0.01, 0.4, true, 40).memo, nullptr);     // separated
  const auto [plain, jumped] = across_the_plate(-0.024);
  EXPECT_GT(plain.steps, 100) << "the plateau this test is about";
  EXPECT_LT(jumped.steps + 60, plain.steps) << "plain " << plain.steps << " jumped " << jumped.steps;
}

// Levels at least a fifth of M deep step with looser certificates (kDeepStepRelativeTolerance),
// with or without polishing and covers; shallower and separated levels keep kStepRelativeTolerance.
// The width changes only the work: the sphere sinking into the plate (no jumps) reaches the same
// first crossing, certified and on target, with either.
TEST(DeepJumps, DeepLevelsStepAtALooserWidth) {
  const Scene w(plate_and_block(), make_icosphere(0.1, 1));
  ASSERT_GT(kDeepStepRelativeTolerance, kStepRelativeTolerance);
  EXPECT_EQ(make_level_deep_zone(w.fixed, -0.095, 0.4, true, 40).step_relative_tolerance, kDeepStepRelativeTolerance);
  EXPECT_EQ(make_level_deep_zone(w.fixed, -0.095, 0.4, false, 40).step_relative_tolerance, kDeepStepRelativeTolerance);
  EXPECT_EQ(make_level_deep_zone(w.fixed, -0.024, 0.4, true, 40).step_relative_tolerance, kStepRelativeTolerance);
  EXPECT_EQ(make_level_deep_zone(w.fixed, 0.01, 0.4, true, 40).step_relative_tolerance, kStepRelativeTolerance);
  const LevelDeepZone deep = make_level_deep_zone(w.fixed, -0.095, 0.4, true, 40);
  PoseOptions base;
  base.tolerance = kPlateTolerance;
  base.start = PoseStart::Surface;
  EXPECT_EQ(deep.options(base).step_relative_tolerance, kDeepStepRelativeTolerance);
  ApproachSetup setup = w.attached();
  setup.fixed_ref = Vec3(0, 0, 0.05);
  const OrientationFrame frame = make_orientation_frame(setup, Eigen::Matrix3d::Identity());
  const Vec3 dir = Vec3(-1, 0, 1).normalized();  // into the plate's top face at 45 degrees
  PoseOutcome at[2];
  for (int k = 0; k < 2; ++k) {
    PoseOptions o = base;
    o.deep_zone_cubes = 0;
    o.step_relative_tolerance = k == 0 ? kStepRelativeTolerance : kDeepStepRelativeTolerance;
    at[k] = place_pose(setup, frame, &w.surface, dir, -0.015, o);
    EXPECT_TRUE(at[k].contact && at[k].certified && at[k].on_target) << k << " " << at[k].reason;
  }
  EXPECT_NEAR(at[1].lambda, at[0].lambda, 4 * kPlateTolerance);
  EXPECT_NE(at[1].clearance_cells, at[0].clearance_cells) << "the width must change the work";
}

// A plateau just above the target: at -0.0205, c = -0.02 is 2.4 % of |target| above it (no jump is
// asked within a tenth of |target| on a short flat stretch), for about 1,500 two-sided steps;
// after 64 flat steps the octree is asked and the pose jumps to the block. Without steps over a
// segment: since session 89 a slope fitted over eight poses finds this flat plateau and segments
// cross it on their own (203 steps without jumps, 22 with); the jump is for plateaus where their
// proofs fail.
TEST(DeepJumps, LongPlateauNearTheTargetJumps) {
  const auto [plain, jumped] = across_the_plate(-0.0205, plate_and_block(), -1.0, false);
  EXPECT_GT(plain.steps, 500) << "the plateau this test is about";
  EXPECT_LT(jumped.steps + 300, plain.steps) << "plain " << plain.steps << " jumped " << jumped.steps;
}

// A plateau beside a thin deep zone, at a level with a cover: in a bar 0.2 thick and wide the zone
// at -0.095 is the rod |y|, |z| <= 0.005, and the sphere's lowest point slides 0.0005 above it (c =
// -0.0945) until the block. The cover's cubes (up to about half |target| across) that hold the rod
// hold the sphere's lowest point too, so its contact lies behind the pose; the octree about the
// path, with leaves sized by the gap, still crosses the plateau (anchor with spool as the mover at
// -35 %: 3,507 steps on one approach before the octree was asked there too). Without steps over a
// segment: since session 70 their slope over a span (back to the fall before the plateau) finds
// this flat plateau and they cross it on their own in 72 steps; the jump is for plateaus where
// their proofs fail (segments across thin blades, rotor).
TEST(DeepJumps, PlateauBesideAThinZoneJumpsWithTheOctree) {
  ASSERT_TRUE(deep_cover_wanted(-0.095, 0.4));
  const auto [plain, jumped] = across_the_plate(-0.095, plate_and_block(0.1, 0.1), 0.0055, false);
  EXPECT_GT(plain.steps, 500) << "the plateau this test is about";
  EXPECT_LT(jumped.steps + 300, plain.steps) << "plain " << plain.steps << " jumped " << jumped.steps;
}

// A slide is not a plateau: the sphere sinks into the plate's top face at a glancing angle (c
// falls at `slope` of the advance, more than 1/16), so c is flat by the plateau's test (a secant
// below 1/2, far above the target) for several steps, and the pose's own work (a hundred cells)
// is far below the octree's least query: nothing is asked, the steps reach the first crossing.
// (Asked, this small scene's query would cost about what its steps do; on an L-shaped sheet
// bracket such queries took 20,000 cubes a pose to jump two gaps: doc/performance.md, "Slides
// are not plateaus".)
TEST(DeepJumps, SlideAsksNoQueryBeforeItsWorkPays) {
  const double target = -0.005;  // shallow: no cover, the octree with a memo
  const Scene w(plate_and_block(), make_icosphere(0.1, 1));
  for (const double slope : {0.2, 0.3}) {
    ApproachSetup setup = w.attached();
    setup.fixed_ref = Vec3(0.5, 0, 0.12);  // the sphere's lowest point on the plate's top at lambda 0
    const Vec3 dir(-std::sqrt(1 - slope * slope), 0, slope);  // moving along -dir: right, down
    const auto [plain, p] = with_and_without_jumps(w, setup, dir, target);
    EXPECT_GT(p.steps, 8) << "slope " << slope << ": the slide this test is about";
    EXPECT_EQ(p.zone_cubes, 0u) << "slope " << slope << ": steps " << p.steps;
  }
}

// A pose certified where it may lie outside F although the target is below 0 (a jump's landing,
// a restart far away) gets the pair-distance path: there the branch and bound resolves the smooth
// minimum of a distance slowly (dino at -12 %: a landing of 284,142 cells, then warm starts from
// that frontier out of cells, the pose uncertified). Here an offset start whose contact lies past
// the crossing (a ball deep inside F stands for a wrong offset) restarts far away: the same pose
// as the surface start, and the far certificate costs no cells.
TEST(DeepJumps, PosesThatMayLieApartAreCertifiedByTheDistancePath) {
  const Scene w(make_icosphere(1.0, 3), make_icosphere(0.3, 2));
  const SweepMesh deep_ball = [] {
    const TriangleMesh b = make_icosphere(0.2, 1);
    return make_sweep_mesh(b.vertices, b.faces);
  }();
  const ApproachSetup setup = w.attached();
  std::mt19937_64 rng(5);
  const double target = -0.1;
  for (int k = 0; k < 6; ++k) {
    const OrientationFrame frame = make_orientation_frame(setup, random_rotation(rng));
    const Vec3 dir = random_direction(rng);
    PoseOptions opt;
    opt.tolerance = 1e-7;
    opt.start = PoseStart::Surface;
    const PoseOutcome surface = place_pose(setup, frame, &w.surface, dir, target, opt);
    opt.start = PoseStart::Offset;
    const PoseOutcome restarted = place_pose(setup, frame, &deep_ball, dir, target, opt);
    ASSERT_TRUE(surface.certified && surface.on_target) << k;
    ASSERT_TRUE(restarted.certified && restarted.on_target) << k << " " << restarted.reason;
    EXPECT_LT(restarted.raw_clearance.hi, target) << k << ": the start this test is about";
    EXPECT_NEAR(restarted.lambda, surface.lambda, 4 * opt.tolerance) << k;
    // The far pose by the distance path (no cells), then the steps into F as the surface start's.
    EXPECT_LT(restarted.clearance_cells, 2 * surface.clearance_cells + 200)
        << k << ": surface " << surface.clearance_cells << " restarted " << restarted.clearance_cells;
  }
}

// After a jump to the cover's contact the octree about the path is still asked on a long plateau:
// the cover's cubes (up to |target|/2 across) stop the mover where it only passes beside the zone.
// A sphere slides along the side of a long block, 0.04 into it, never 0.05 deep (the zone ends
// 0.01 short of its lowest point, within the cover's cubes): the cover's contact is at the block's
// end (a jump across the gap after the plate), then c stays about 0.01 above the target along the
// block until the sphere leaves it and the line ends `no-contact`. The octree proves that after 16
// flat steps (19 steps in all); the cover alone took the whole block in two-gap steps (68).
TEST(DeepJumps, AfterACoverJumpTheOctreeEndsAPlateauBesideTheZone) {
  const double target = -0.05;
  const Scene w(merge_meshes(make_box(Vec3(0, -0.5, -0.02), Vec3(1, 0.5, 0.02)),
                             make_box(Vec3(1.2, -0.5, -0.12), Vec3(3.5, 0.5, 0.12))),
                make_icosphere(0.1, 1));
  ApproachSetup setup = w.attached();
  setup.fixed_ref = Vec3(0, 0.56, 0);  // the sphere's centre at (-lambda, 0.56, 0)
  const OrientationFrame frame = make_orientation_frame(setup, Eigen::Matrix3d::Identity());
  const LazyDeepCover cover(w.fixed, target, deep_cover_options(target));
  PoseOptions opt;
  opt.tolerance = 1e-7;
  opt.start = PoseStart::Surface;
  opt.deep_cover = &cover;
  PoseOptions cover_only = opt;
  cover_only.deep_zone_cubes = 0;
  const Vec3 dir(-1, 0, 0);
  const PoseOutcome a = place_pose(setup, frame, &w.surface, dir, target, cover_only);
  const PoseOutcome b = place_pose(setup, frame, &w.surface, dir, target, opt);
  ASSERT_NE(cover.peek(), nullptr);
  ASSERT_TRUE(cover.peek()->complete);
  EXPECT_FALSE(a.contact) << a.reason;
  EXPECT_FALSE(b.contact) << b.reason;
  EXPECT_EQ(a.reason, "no-contact");
  EXPECT_EQ(b.reason, "no-contact");
  EXPECT_GE(a.cover_jumps, 1) << "the jump this test is about";
  EXPECT_GT(b.zone_cubes, 0u);
  EXPECT_LT(b.steps + 20, a.steps) << "cover only " << a.steps << " with the octree " << b.steps;
}

}  // namespace
}  // namespace cdbench
