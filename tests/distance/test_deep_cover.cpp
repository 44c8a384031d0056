// The deep zone's cover (distance/deep_cover.h): every point at least |target| inside F, decided
// independently (CGAL's inside test and exact rational distances), lies in a kept box; the cover is
// deterministic; a budget too small gives no cover rather than a partial one.
#include <gtest/gtest.h>

#include <deque>
#include <iomanip>
#include <random>

#include "distance/deep_cover.h"
#include "distance/depth_plane.h"
#include "distance/signed_distance.h"
#include "exact_reference.h"
#include "mesh/shapes.h"
#include "test_scale.h"

namespace cdbench {
namespace {

using testing::Epeck;
using testing::CgalSide;

// A thin plate (0.04 thick, deepest point 0.02) beside a thick block: at -0.05 only the block has a
// deep zone, the plate none.
TriangleMesh plate_and_block() {
  return merge_meshes(make_box(Vec3(0, -0.5, -0.02), Vec3(1, 0.5, 0.02)), make_box(Vec3(1.2, -0.5, -0.5), Vec3(2, 0.5, 0.5)));
}

bool covered(const DeepCover& c, const Vec3& p) {
  for (const Aabb& b : c.boxes)
    if (b.contains(p)) return true;
  return false;
}

// Points with exact depth >= |target| (inside, exact squared distance >= target^2) must be covered.
// Samples concentrate near the zone's boundary, where a cover too tight would miss them.
void expect_covers_deep_points(const TriangleMesh& m, double target, double cell, std::uint64_t seed) {
  const SignedDistance sdf(m);
  DeepCoverOptions o;
  o.cell_size = cell;
  o.max_cells = 2000000;
  const DeepCover c = build_deep_cover(sdf, target, o);
  ASSERT_TRUE(c.complete);
  ASSERT_FALSE(c.boxes.empty());
  const CgalSide side(m);
  std::mt19937_64 rng(seed);
  const Aabb b = m.bbox();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int deep = 0, shallow_out = 0;
  for (int i = 0; i < 4000; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = b.lo[k] + u(rng) * (b.hi[k] - b.lo[k]);
    if (side(p) >= 0) continue;
    const Epeck::FT d2 = testing::exact_squared_distance(p, m);
    const bool is_deep = d2 >= Epeck::FT(target) * target;
    if (is_deep) {
      ++deep;
      ASSERT_TRUE(covered(c, p)) << std::setprecision(17) << "deep point (" << p.x() << ", " << p.y() << ", " << p.z()
                                 << ") outside every box; target " << target;
    } else if (!covered(c, p)) {
      ++shallow_out;
    }
  }
  EXPECT_GT(deep, 50);        // the zone was sampled
  EXPECT_GT(shallow_out, 50);  // and the cover is not all of F
}

TEST(DeepCover, HoldsEveryDeepPoint) {
  expect_covers_deep_points(plate_and_block(), -0.05, 0.025, 1);
  expect_covers_deep_points(make_torus(1.0, 0.4, 24, 12), -0.1, 0.05, 2);
  expect_covers_deep_points(make_icosphere(1.0, 2), -0.3, 0.15, 3);
}

// The octree's first `levels` levels, breadth first: f(cube, verdict, level) for each cube
// classified (cell size 0) and the list it was classified with (null: none), the split ones'
// children on the next level; with `lists`, each child
// classified from its parent's list of nearby triangles (deep_cube_list, at most 64), as the
// octree about the mover's path does.
template <class F>
void walk_octree(const SignedDistance& sdf, double target, int levels, F f, bool lists = false) {
  std::vector<std::pair<DeepCube, int>> level{{deep_cover_root(sdf), -1}}, next;  // (cube, its parent's list)
  std::deque<DeepCubeList> made;  // stable: a child's pointer outlives later lists
  std::vector<std::uint32_t> ids;
  for (int l = 0; l < levels; ++l) {
    next.clear();
    for (const auto& [cube, list] : level) {
      const DeepCubeList* parent = list >= 0 ? &made[static_cast<std::size_t>(list)] : nullptr;
      const DeepCubeVerdict v = classify_deep_cube(sdf, target, 0.0, cube, ids, parent);
      if (v.what == DeepCubeVerdict::split) {
        int own = -1;
        DeepCubeList m;
        if (lists && deep_cube_list(sdf, cube.box, v, 64, m)) {
          made.push_back(std::move(m));
          own = static_cast<int>(made.size()) - 1;
        }
        for (const DeepCube& c : deep_cube_children(cube, v)) next.emplace_back(c, own);
      }
      f(cube, v, l, parent);
    }
    std::swap(level, next);
  }
}

// A cube's clips (DeepClip) hold every deep point of the cube, in exact arithmetic, and a cube
// dropped holds none: octree cubes near the zone's boundary of a flat-faced plate and block and of
// a curved torus, each sampled at random points whose depth is decided exactly.
void expect_clips_hold_deep_points(const TriangleMesh& m, double target, int levels, std::uint64_t seed) {
  const SignedDistance sdf(m);
  const CgalSide side(m);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int clipped = 0, deep = 0, cut = 0;
  walk_octree(sdf, target, levels, [&](const DeepCube& cube, const DeepCubeVerdict& v, int l, const DeepCubeList*) {
    if (l + 3 < levels) return;  // sampled on the last levels only
    if (v.n_clips > 0) ++clipped;
    for (int i = 0; i < test_scale::pick(6, 1); ++i) {  // one point a cube under the sanitizers
      Vec3 p;
      for (int k = 0; k < 3; ++k) p[k] = cube.box.lo[k] + u(rng) * (cube.box.hi[k] - cube.box.lo[k]);
      if (side(p) >= 0 || testing::exact_squared_distance(p, m) < Epeck::FT(target) * target) {
        // Shallow: count the clips that exclude it (they do cut the cube).
        for (int c = 0; c < v.n_clips; ++c) {
          const DeepClip& k = v.clips[c];
          const Epeck::FT np = Epeck::FT(k.n.x()) * p.x() + Epeck::FT(k.n.y()) * p.y() + Epeck::FT(k.n.z()) * p.z();
          if (np > Epeck::FT(k.off)) ++cut;
        }
        continue;
      }
      ++deep;
      ASSERT_NE(v.what, DeepCubeVerdict::drop) << std::setprecision(17) << "deep point (" << p.transpose()
                                               << ") in a dropped cube " << cube.box.lo.transpose() << " / "
                                               << cube.box.hi.transpose();
      for (int c = 0; c < v.n_clips; ++c) {
        const DeepClip& k = v.clips[c];
        const Epeck::FT np = Epeck::FT(k.n.x()) * p.x() + Epeck::FT(k.n.y()) * p.y() + Epeck::FT(k.n.z()) * p.z();
        ASSERT_TRUE(np <= Epeck::FT(k.off)) << std::setprecision(17) << "deep point (" << p.transpose()
                                            << ") beyond clip " << c << " n " << k.n.transpose() << " off " << k.off;
      }
    }
  });
  EXPECT_GT(clipped, 20);  // clips were made
  EXPECT_GT(deep, 50);     // deep points were tested against them
  EXPECT_GT(cut, 50);      // and they exclude shallow points of kept cubes
}

TEST(DeepCover, ClipsHoldEveryDeepPoint) {
  expect_clips_hold_deep_points(plate_and_block(), -0.05, 7, 4);
  expect_clips_hold_deep_points(make_torus(1.0, 0.4, 24, 12), -0.1, 7, 5);
}

// What a parent leaves its children (its centre's nearest triangle, side and free ball, and its
// list of nearby triangles) decides many cubes before any tree query; it changes the work, not
// the verdicts: each cube of the first levels classified with it and without it (no hint, no
// reference point, no list) gets the same verdict, and the same centre side wherever both know it
// (the free ball's and the list's sides are the ray test's).
void expect_parent_shortcuts_agree(const TriangleMesh& m, double target, int levels) {
  const SignedDistance sdf(m);
  std::vector<std::uint32_t> ids;
  int with_parent = 0, free_ball = 0, sides = 0, listed = 0;
  walk_octree(sdf, target, levels, [&](const DeepCube& cube, const DeepCubeVerdict& v, int, const DeepCubeList* list) {
    DeepCube bare = cube;
    bare.hint = -1;
    bare.ref_side = 0;
    bare.ref_free = 0.0;
    const DeepCubeVerdict w = classify_deep_cube(sdf, target, 0.0, bare, ids);
    ASSERT_EQ(v.what, w.what) << std::setprecision(17) << "cube " << cube.box.lo.transpose() << " / "
                              << cube.box.hi.transpose() << " target " << target;
    if (v.side != 0 && w.side != 0) {
      ASSERT_EQ(v.side, w.side) << std::setprecision(17) << "cube " << cube.box.lo.transpose();
      ++sides;
    }
    if (cube.hint >= 0) ++with_parent;
    if (list && list->covers(cube.box.center(), 0.0)) ++listed;
    if (cube.ref_side != 0 && (cube.box.center() - cube.ref).norm() < 0.99 * cube.ref_free) ++free_ball;
  }, /*lists=*/true);
  EXPECT_GT(with_parent, 100);  // the shortcuts had cubes to decide
  EXPECT_GT(free_ball, 20);
  EXPECT_GT(sides, 50);
  EXPECT_GT(listed, 100);
}

TEST(DeepCover, ParentShortcutsChangeTheWorkNotTheVerdicts) {
  expect_parent_shortcuts_agree(plate_and_block(), -0.05, 6);
  expect_parent_shortcuts_agree(make_torus(1.0, 0.4, 24, 12), -0.1, 6);
  expect_parent_shortcuts_agree(make_icosphere(1.0, 2), -0.3, 5);
}

// The second stage of an undecided cube (deep_cube_regions) drops only cubes without a deep
// point: every cube of the octree's first levels that the regions drop, sampled at random points
// whose depth is decided exactly, has none. On a thin tube whose wall is shallower than |target|
// everywhere they drop cubes across the wall that the first stage could not (its corners beyond
// the wall's faces count their distance as depth); on the torus and the plate beside a block they
// must keep every cube that holds a deep point.
int expect_regions_drop_only_shallow_cubes(const TriangleMesh& m, double target, int levels, std::uint64_t seed) {
  const SignedDistance sdf(m);
  const CgalSide side(m);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::uint32_t> ids;
  int dropped = 0, tried = 0;
  walk_octree(sdf, target, levels, [&](const DeepCube& cube, const DeepCubeVerdict& v, int, const DeepCubeList* list) {
    if (v.what != DeepCubeVerdict::split) return;
    if (deep_cube_radius(cube.box) <= kRegionCellRadius * -target) ++tried;
    if (!deep_cube_regions(sdf, target, cube, v, ids, list)) return;
    ++dropped;
    for (int i = 0; i < test_scale::pick(8, 2); ++i) {
      Vec3 p;
      for (int k = 0; k < 3; ++k) p[k] = cube.box.lo[k] + u(rng) * (cube.box.hi[k] - cube.box.lo[k]);
      if (side(p) >= 0) continue;
      ASSERT_TRUE(testing::exact_squared_distance(p, m) < Epeck::FT(target) * target)
          << std::setprecision(17) << "deep point (" << p.transpose() << ") in a cube the regions dropped "
          << cube.box.lo.transpose() << " / " << cube.box.hi.transpose() << " target " << target;
    }
  }, /*lists=*/true);
  EXPECT_GT(tried, 0);
  return dropped;
}

TEST(DeepCover, RegionsDropOnlyShallowCubes) {
  // Wall 0.1 thick (0.05 deep at most), target -0.07: no deep zone, cubes across the wall.
  EXPECT_GT(expect_regions_drop_only_shallow_cubes(make_tube(0.9, 1.0, 2.0, 48), -0.07, 7, 6), 50);
  // Beside a deep zone (each drops a few hundred, sampled).
  EXPECT_GT(expect_regions_drop_only_shallow_cubes(make_torus(1.0, 0.4, 24, 12), -0.1, 6, 7), 20);
  EXPECT_GT(expect_regions_drop_only_shallow_cubes(plate_and_block(), -0.05, 7, 8), 20);
}

TEST(DeepCover, ThePlateHasNoDeepZone) {
  // Only the block's interior is kept: no box reaches into the plate's slab beyond its boundary
  // layer (the plate's deepest points are 0.02 deep, the target 0.05).
  const SignedDistance sdf(plate_and_block());
  DeepCoverOptions o;
  o.cell_size = 0.025;
  o.max_cells = 2000000;
  const DeepCover c = build_deep_cover(sdf, -0.05, o);
  ASSERT_TRUE(c.complete);
  for (const Aabb& b : c.boxes) EXPECT_GT(b.hi.x(), 1.2 + 0.05 - 2 * 0.025 - 1e-9) << b.lo.transpose();
}

TEST(DeepCover, DeterministicAndBudgeted) {
  const SignedDistance sdf(make_torus(1.0, 0.4, 24, 12));
  DeepCoverOptions o;
  o.cell_size = 0.05;
  o.max_cells = 2000000;
  const DeepCover a = build_deep_cover(sdf, -0.1, o), b = build_deep_cover(sdf, -0.1, o);
  ASSERT_TRUE(a.complete);
  ASSERT_EQ(a.boxes.size(), b.boxes.size());
  for (std::size_t i = 0; i < a.boxes.size(); ++i) {
    EXPECT_EQ(a.boxes[i].lo, b.boxes[i].lo);
    EXPECT_EQ(a.boxes[i].hi, b.boxes[i].hi);
  }
  // A budget below what the cover needs: no boxes at all (a partial cover would claim too much),
  // and given up from the predicted growth before most of the budget is spent.
  o.max_cells = a.cells / 2;
  const DeepCover c = build_deep_cover(sdf, -0.1, o);
  EXPECT_FALSE(c.complete);
  EXPECT_TRUE(c.boxes.empty());
  EXPECT_LE(c.cells, o.max_cells / 4) << "cover " << a.cells << " cubes, budget " << o.max_cells;
  // The lazy form builds the same cover once.
  o.max_cells = 2000000;
  const LazyDeepCover lazy(sdf, -0.1, o);
  EXPECT_FALSE(lazy.built());
  EXPECT_EQ(lazy.peek(), nullptr);
  const DeepCover* l = lazy.get();
  ASSERT_NE(l, nullptr);
  EXPECT_TRUE(lazy.built());
  EXPECT_EQ(l->boxes.size(), a.boxes.size());
  EXPECT_EQ(lazy.get(), l);
  // Deeper than the solid: nothing to cover, and complete.
  const DeepCover none = build_deep_cover(sdf, -0.5, o);
  EXPECT_TRUE(none.complete);
  EXPECT_TRUE(none.boxes.empty());
}

}  // namespace
}  // namespace cdbench
