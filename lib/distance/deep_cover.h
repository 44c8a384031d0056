#pragma once
// A cover of F's deep zone Z = {x : s(x) <= target} (target < 0) by boxes: every point at least
// |target| inside F lies in one of them. A mover whose surface misses every box has c > target
// (doc/poses.md, "Deep-zone jumps"), so the first contact of the moving mover with the boxes bounds
// a penetrating level's first crossing from above, whatever plateau lies before it.
//
// Built by an octree over F's bounding cube: a cube is dropped when proven shallower than |target|
// (s >= -dist(q, F) - r from its centre q and half-diagonal r, s >= dist(q, F) - r outside, or the
// convexity bound over its corners, depth_bound.h), kept whole when proven inside Z (s(q) + r <=
// target), kept when its half-diagonal is at most `cell_size`, and split into eight otherwise.
// The cubes' corners are the doubles computed by halving (a child's faces are its parent's or the
// computed midpoints, shared by its siblings), so the kept and dropped cubes tile the root exactly.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "bvh/bvh.h"
#include "core/aabb.h"
#include "distance/signed_distance.h"

namespace cdbench {

struct DeepCoverOptions {
  double cell_size = 0.0;              // the kept cubes' half-diagonal at most (unless inside Z)
  // Cubes evaluated at most; a cover that would need more is given up (complete = false) as soon as
  // an octree level's cubes would pass it, before they are evaluated.
  std::uint64_t max_cells = 20000;
};

// One cube of the octree and what its classification leaves its children: a point of known side
// (its parent's centre; ref_side 0 when unknown) and a start for the nearest query.
struct DeepCube {
  Aabb box;
  Vec3 ref = Vec3::Zero();
  int ref_side = 0;
  double ref_free = 0.0;  // the open ball of this radius about ref misses F
  std::int64_t hint = -1;
};

// A half-space {x : n.x <= off} (exact arithmetic on the stored doubles) holding the zone's part
// of a cube. From one of F's triangles near the cube: the distance d_j to it is convex, so an affine
// function at least d_j at the cube's corners is at least d_j on the cube, and a point of the zone
// there (d_j >= dist(x, F) >= |target|) lies where that function is at least |target|. Exact where
// the cube projects into the triangle: a thin wall's two faces then hold the zone's sheet between
// them whatever the cube's size (doc/distance.md, "Clips"; doc/poses.md, "Clipped cubes").
struct DeepClip {
  Vec3 n = Vec3::Zero();
  double off = 0.0;
};

// A cube's verdict less its clips: what octrees and the memo keep for every cube (24 bytes), the
// clips, which few cubes have, stored apart.
struct DeepCubeHead {
  enum Kind : signed char { drop, keep, split };
  Kind what = drop;  // keep: inside Z, or at most cell_size
  signed char side = 0;        // the centre's side when certain (0: not known)
  signed char n_clips = 0;     // clips[0, n_clips): Z's part of the cube lies in each (keep, split)
  bool regions_tried = false;  // split: deep_cube_regions has run on it (then the verdict is final)
  std::uint32_t nearest = 0;   // the centre's nearest triangle
  double free = 0.0;           // a lower bound of the centre's distance to F (0: not known)
  double near = 0.0;           // an upper bound of it (0: not known)
};

struct DeepCubeVerdict : DeepCubeHead {
  std::array<DeepClip, 4> clips;
};

// A bound on |x - centre| over the cube: the half-diagonal the rules compare with cell_size.
double deep_cube_radius(const Aabb& box);
// The root cube: about F's bounding box (its shape only), grown to contain it.
DeepCube deep_cover_root(const SignedDistance& fixed);
// Triangles of F listed about a split cube's centre for its children: every triangle within
// `reach` of `centre` is among `ids` (deep_cube_list).
struct DeepCubeList {
  Vec3 centre = Vec3::Zero();
  double reach = 0.0;
  std::vector<std::uint32_t> ids;
  bool covers(const Vec3& x, double radius) const;  // every triangle within radius of x is listed
};
// The list of a split cube (its verdict's `near` known): the triangles within near + 2 r of its
// centre, which hold every child centre's nearest triangles and the segments from the centre to
// them; false when more than `max_count` qualify (then `list` is not to be used).
bool deep_cube_list(const SignedDistance& fixed, const Aabb& cube, const DeepCubeHead& verdict,
                    std::size_t max_count, DeepCubeList& list);

// A cube's verdict for the zone {s <= target} (target < 0). `ids`: scratch. `parent` (optional):
// its parent's list (deep_cube_list), from which its distance, side and depth candidates are
// answered without tree queries where the list provably holds them.
DeepCubeVerdict classify_deep_cube(const SignedDistance& fixed, double target, double cell_size, const DeepCube& cube,
                                   std::vector<std::uint32_t>& ids, const DeepCubeList* parent = nullptr);
// The second stage of an undecided cube's verdict (classify_deep_cube's split), worth its cost
// only on cubes a query is about to split or test (deep_zone_contact): the regions beyond the faces
// of F near the cube (distance/depth_plane.h, region_depth_bound) bound the depth of its interior
// points. A cube across a thin wall has corners beyond the wall's faces, where every triangle's
// distance is large (the convexity bound over the corners is the half thickness plus how far they
// stick out), while a region's signed distance is negative there: the cube is proven shallow at
// the wall's scale instead of the gap's. True when it is (s > target on the cube: to be dropped).
// Not tried (depth_plane.h, kRegionCellRadius, kRegionCentreDepth): cubes whose half-diagonal
// exceeds 8 |target|, and cubes whose centre is certainly inside F at least 0.9 |target| deep (the
// cube then holds or nearly holds the zone). `verdict`: the cube's classify_deep_cube verdict;
// `parent` (optional) as there.
bool deep_cube_regions(const SignedDistance& fixed, double target, const DeepCube& cube, const DeepCubeHead& verdict,
                       std::vector<std::uint32_t>& ids, const DeepCubeList* parent = nullptr);

// The eight children of a split cube, cut at its computed centre (they tile it exactly), child k
// on the upper side of axis a when bit a of k is set.
std::array<DeepCube, 8> deep_cube_children(const DeepCube& cube, const DeepCubeVerdict& verdict);
// Their boxes alone, and one of them from its box and its parent's box and verdict (what
// deep_cube_children gives it): an octree need not keep each cube's reference point, hint and
// free ball.
std::array<Aabb, 8> deep_cube_child_boxes(const Aabb& cube);
DeepCube deep_cube_child(const Aabb& box, const Aabb& parent, const DeepCubeHead& parent_verdict);

// Verdicts of one zone's cubes (classified with cell_size 0: split stands for "not decided"),
// shared by every pose and thread of a level. A verdict depends only on the cube, F and the
// target, so what is found here is what classifying would give: sharing changes the work, not
// the answers. Thread-safe; past max_entries nothing more is remembered.
class DeepCubeMemo {
 public:
  explicit DeepCubeMemo(double target, std::size_t max_entries = 1000000);
  ~DeepCubeMemo();
  DeepCubeMemo(const DeepCubeMemo&) = delete;
  DeepCubeMemo& operator=(const DeepCubeMemo&) = delete;
  double target() const { return target_; }
  bool find(const Aabb& cube, DeepCubeVerdict* verdict) const;
  void insert(const Aabb& cube, const DeepCubeVerdict& verdict);
  // A cube's verdict after deep_cube_regions (its head replaces the one inserted; its clips stay).
  void refine(const Aabb& cube, const DeepCubeHead& head);
  std::size_t size() const;

 private:
  struct Shard;
  double target_;
  std::size_t max_per_shard_;
  std::unique_ptr<Shard[]> shards_;
};

struct DeepCover {
  double target = 0.0;
  bool complete = false;      // false: the budget ran out, and the boxes cover nothing
  std::uint64_t cells = 0;    // cubes evaluated
  std::vector<Aabb> boxes;    // kept cubes: Z lies in their union
  Bvh<Aabb> tree;             // over `boxes`
};

DeepCover build_deep_cover(const SignedDistance& fixed, double target, const DeepCoverOptions& options);

// A level's cover, built by the first caller of get() (others wait for it): only levels where some
// pose needs it pay for it. Its content depends only on F, the target and the options, never on
// which thread or pose asked first, so the poses that use it are the same for any thread count.
class LazyDeepCover {
 public:
  LazyDeepCover(const SignedDistance& fixed, double target, const DeepCoverOptions& options);
  ~LazyDeepCover();
  LazyDeepCover(const LazyDeepCover&) = delete;
  LazyDeepCover& operator=(const LazyDeepCover&) = delete;
  double target() const { return target_; }
  const DeepCoverOptions& options() const { return options_; }  // as built (its budget: max_cells)
  // The cover, or null when it is incomplete (the budget ran out). Threads that call it while it
  // is being built help build it (its cubes are classified in parallel).
  const DeepCover* get() const;
  // Whether get() has built it, the seconds that took (0 before), and the cover if built (null
  // otherwise; never builds).
  bool built() const;
  double seconds() const;
  const DeepCover* peek() const;

 private:
  struct State;
  const SignedDistance* fixed_;
  double target_;
  DeepCoverOptions options_;
  std::unique_ptr<State> state_;
};

}  // namespace cdbench
