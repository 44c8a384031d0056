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
