#include "distance/deep_cover.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/collaborative_call_once.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "distance/depth_bound.h"

namespace cdbench {
namespace {

struct Cube {
  Aabb box;
  Vec3 ref = Vec3::Zero();  // a point of known side (its parent's centre), or ref_side = 0
  int ref_side = 0;
  std::int64_t hint = -1;  // its parent's nearest triangle (a start for the nearest query)
};

}  // namespace

DeepCover build_deep_cover(const SignedDistance& fixed, double target, const DeepCoverOptions& options) {
  DeepCover cover;
  cover.target = target;
  if (!(target < 0.0) || fixed.mesh().faces.empty()) return cover;
  const Aabb b = fixed.bbox();
  // The root: a cube about F's box (only the cells' shape depends on it), grown to contain it.
  const double half = 0.5 * (b.hi - b.lo).maxCoeff() * (1.0 + 1e-9);
  Cube root;
  for (int k = 0; k < 3; ++k) {
    const double c = 0.5 * (b.lo[k] + b.hi[k]);
    root.box.lo[k] = std::min(b.lo[k], round_down(c - half));
    root.box.hi[k] = std::max(b.hi[k], round_up(c + half));
  }
  // Breadth first, one octree level at a time, so that a budget too small is found before the
  // finest (and largest) level is evaluated: its cubes are eight per undecided cube of the last.
  std::vector<Cube> level{root}, next;
  // A cube's classification, and what its children take over: its centre's side (0: unknown) and
  // nearest triangle.
  struct Verdict {
    enum : signed char { drop, keep, split } what = drop;
    signed char side = 0;
    std::uint32_t nearest = 0;
  };
  std::vector<Verdict> verdicts;
  const double depth = -target;  // |target|
  const auto classify = [&](const Cube& cube, std::vector<std::uint32_t>& ids, Verdict& v) {
    const Aabb& Q = cube.box;
    const Vec3 q = Q.center();
    // Every point of Q within r of q (q lies in Q: the farthest corner, rounded up).
    const Vec3 far = (Q.hi - q).cwiseMax(q - Q.lo);
    const double r = round_up(far.norm() * (1.0 + 1e-12));
    const Interval ud = fixed.unsigned_distance(q, &v.nearest, cube.hint);
    // s >= -dist(x, F) everywhere: shallow whatever q's side.
    if (round_up(ud.hi + r) < depth) return;
    const int side = cube.ref_side != 0 ? fixed.side(q, ud, cube.ref, cube.ref_side) : fixed.side(q, ud);
    if (ud.lo > 0.0) v.side = static_cast<signed char>(side);
    if (side > 0 && round_down(ud.lo - r) > target) return;  // outside: s >= dist(q, F) - r
    if (side < 0 && round_down(ud.lo - r) >= depth) {        // inside Z: s <= s(q) + r <= target
      v.what = Verdict::keep;
      return;
    }
    const std::array<Vec3, 8> corners = Q.corners();
    // Sparse weights: a cube undecided by them is split, and is cheaper to split than to bound
    // with converged weights (rotor, retinal, boeing, pinion: 20-50 % less time, as many cubes).
    const double bound = depth_upper_bound(fixed, q, round_up(ud.hi + 2 * r), corners.data(), 8, ids, nullptr, nullptr,
                                           nullptr, nullptr, 0.0, DepthWeights::sparse);
    if (bound < depth) return;  // s >= -dist >= -bound > target on the cube
    v.what = r <= options.cell_size ? Verdict::keep : Verdict::split;
  };
  while (!level.empty()) {
    // The cubes still to come must fit the budget: this level's, and near the last level the
    // next ones, which are then well predicted: about four times as many as this level's when
    // the next is the last (four children of eight kept along a surface). A budget that cannot
    // hold them is given up now rather than after those levels. (Earlier, the growth is far
    // from that.)
    const double rho = 0.5 * level.front().box.diagonal();
    const double to_come = rho > options.cell_size && 0.5 * rho <= options.cell_size ? 5.0 : 1.0;
    if (static_cast<double>(cover.cells) + to_come * static_cast<double>(level.size()) >
        static_cast<double>(options.max_cells)) {
      cover.boxes.clear();
      return cover;
    }
    // The cubes of a level are independent: classified on every thread (isolated, so that a
    // waiting thread takes no unrelated task), then assembled in order, so the cover does not
    // depend on the threads.
    verdicts.assign(level.size(), Verdict{});
    tbb::this_task_arena::isolate([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, level.size(), 64),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          std::vector<std::uint32_t> ids;
                          for (std::size_t i = range.begin(); i != range.end(); ++i) classify(level[i], ids, verdicts[i]);
                        });
    });
    cover.cells += level.size();
    next.clear();
    for (std::size_t i = 0; i < level.size(); ++i) {
      const Aabb& Q = level[i].box;
      if (verdicts[i].what == Verdict::keep) cover.boxes.push_back(Q);
      if (verdicts[i].what != Verdict::split) continue;
      // Eight children sharing the computed midpoints (q lies in Q, so they tile it).
      const Vec3 q = Q.center();
      for (int k = 0; k < 8; ++k) {
        Cube c;
        for (int a = 0; a < 3; ++a) {
          const bool upper = (k >> a) & 1;
          c.box.lo[a] = upper ? q[a] : Q.lo[a];
          c.box.hi[a] = upper ? Q.hi[a] : q[a];
        }
        c.ref = q;
        c.ref_side = verdicts[i].side;
        c.hint = verdicts[i].nearest;
        next.push_back(c);
      }
    }
    std::swap(level, next);
  }
  cover.complete = true;
  if (!cover.boxes.empty()) {
    std::vector<Eigen::Vector3d> centroids(cover.boxes.size());
    for (std::size_t i = 0; i < cover.boxes.size(); ++i) centroids[i] = cover.boxes[i].center();
    cover.tree = build_bvh<Aabb>(centroids, [&](const std::uint32_t* idx, std::uint32_t n) {
      Aabb u;
      for (std::uint32_t i = 0; i < n; ++i) u.extend(cover.boxes[idx[i]]);
      return u;
    });
  }
  return cover;
}

struct LazyDeepCover::State {
  tbb::collaborative_once_flag once;  // a thread waiting for the build helps with it
  std::atomic<bool> built{false};
  DeepCover cover;
  double seconds = 0.0;
};

LazyDeepCover::LazyDeepCover(const SignedDistance& fixed, double target, const DeepCoverOptions& options)
    : fixed_(&fixed), target_(target), options_(options), state_(std::make_unique<State>()) {}

LazyDeepCover::~LazyDeepCover() = default;

const DeepCover* LazyDeepCover::get() const {
  tbb::collaborative_call_once(state_->once, [this] {
    const auto start = std::chrono::steady_clock::now();
    state_->cover = build_deep_cover(*fixed_, target_, options_);
    state_->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state_->built.store(true, std::memory_order_release);
  });
  return state_->cover.complete ? &state_->cover : nullptr;
}

bool LazyDeepCover::built() const { return state_->built.load(std::memory_order_acquire); }

double LazyDeepCover::seconds() const { return built() ? state_->seconds : 0.0; }

const DeepCover* LazyDeepCover::peek() const { return built() ? &state_->cover : nullptr; }

}  // namespace cdbench
