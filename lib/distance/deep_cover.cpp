#include "distance/deep_cover.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/collaborative_call_once.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "distance/depth_bound.h"
#include "distance/depth_plane.h"
#include "distance/point_triangle_distance.h"

namespace cdbench {
double deep_cube_radius(const Aabb& Q) {
  const Vec3 q = Q.center();
  // q lies in Q: the farthest corner, rounded up.
  const Vec3 far = (Q.hi - q).cwiseMax(q - Q.lo);
  return round_up(far.norm() * (1.0 + 1e-12));
}

DeepCube deep_cover_root(const SignedDistance& fixed) {
  const Aabb b = fixed.bbox();
  const double half = 0.5 * (b.hi - b.lo).maxCoeff() * (1.0 + 1e-9);
  DeepCube root;
  for (int k = 0; k < 3; ++k) {
    const double c = 0.5 * (b.lo[k] + b.hi[k]);
    root.box.lo[k] = std::min(b.lo[k], round_down(c - half));
    root.box.hi[k] = std::max(b.hi[k], round_up(c + half));
  }
  return root;
}

namespace {

// The cube's clips (DeepClip) from its nearest triangles `ids` (nearest first): the distance d_j
// to a triangle is convex, so an affine function at least d_j at the cube's eight corners is at
// least d_j on the whole cube; the zone's points there have d_j >= dist(x, F) >= depth, hence lie
// where that function is at least depth. False when one of them proves the cube shallower than
// depth everywhere. The function: d_j's least-squares fit over the corners, raised by its largest
// shortfall there (exact where d_j is affine over the cube: the triangle's plane).
bool clip_deep_cube(const SignedDistance& fixed, double depth, const Aabb& Q, const std::array<Vec3, 8>& corners,
                    const std::vector<std::uint32_t>& ids, const CornerDistances& known, DeepCubeVerdict& v) {
  const TriangleMesh& m = fixed.mesh();
  const Vec3 ext = Q.hi - Q.lo;
  if (!(ext.minCoeff() > 0.0)) return true;
  // The four nearest: more clips cost more per contact test than they save (rotor: 4, 8, 16 alike).
  const std::size_t n = std::min<std::size_t>(ids.size(), v.clips.size());
  for (std::size_t j = 0; j < n && v.n_clips < static_cast<signed char>(v.clips.size()); ++j) {
    std::array<double, 8> f;
    for (int k = 0; k < 8; ++k) f[k] = known.at(m, corners.data(), k, j, ids[j]);  // the depth bound's, when it has it
    // The least-squares gradient over the corners (only tightness depends on it); corner k is on
    // the upper side of axis a when bit a of k is set (Aabb::corners).
    Vec3 a = Vec3::Zero();
    for (int k = 0; k < 8; ++k)
      for (int ax = 0; ax < 3; ++ax) a[ax] += ((k >> ax) & 1 ? f[k] : -f[k]);
    for (int ax = 0; ax < 3; ++ax) a[ax] /= 4.0 * ext[ax];
    // a.v at each corner, bracketed by its error bound; b with the exact a.x + b >= f there.
    std::array<double, 8> av_lo, av_hi;
    double b = -std::numeric_limits<double>::infinity();
    for (int k = 0; k < 8; ++k) {
      const PlaneOffset o = plane_offset(a, 0.0, corners[k]);
      av_lo[k] = round_down(o.value - o.error);
      av_hi[k] = round_up(o.value + o.error);
      b = std::max(b, round_up(f[k] - av_lo[k]));
    }
    // The function's largest and least values over the cube (it is affine: at corners).
    double top = -std::numeric_limits<double>::infinity(), lowest = -top;
    for (int k = 0; k < 8; ++k) {
      top = std::max(top, round_up(av_hi[k] + b));
      lowest = std::min(lowest, round_down(av_lo[k] + b));
    }
    if (top < depth) return false;  // d_j < depth on the whole cube
    // Zone points: a.x + b >= depth, i.e. -a.x <= b - depth; worth keeping only when it cuts the
    // cube (some corner beyond it).
    DeepClip& c = v.clips[v.n_clips];
    c.n = -a;
    c.off = round_up(b - depth);
    if (lowest < depth) ++v.n_clips;
  }
  return true;
}

}  // namespace

bool DeepCubeList::covers(const Vec3& x, double radius) const {
  return round_up(round_up(radius + round_up((x - centre).norm() * (1.0 + 1e-12))) * (1.0 + 1e-15)) <= reach;
}

bool deep_cube_list(const SignedDistance& fixed, const Aabb& cube, const DeepCubeHead& verdict,
                    std::size_t max_count, DeepCubeList& list) {
  list.centre = cube.center();
  list.reach = round_up((verdict.near + 2.0 * deep_cube_radius(cube)) * (1.0 + 1e-12));
  return verdict.near > 0.0 && fixed.triangles_within(list.centre, list.reach, max_count, list.ids);
}

DeepCubeVerdict classify_deep_cube(const SignedDistance& fixed, double target, double cell_size, const DeepCube& cube,
                                   std::vector<std::uint32_t>& ids, const DeepCubeList* parent) {
  DeepCubeVerdict v;
  const double depth = -target;  // |target|
  const Aabb& Q = cube.box;
  const Vec3 q = Q.center();
  const double r = deep_cube_radius(Q);  // every point of Q within r of q
  // What the parent left decides most cubes near the mover's path before any tree query: the
  // distance to its centre's nearest triangle bounds dist(q, F) from above, and q inside the
  // parent centre's free ball has that centre's side (the segment between them misses F). The
  // verdicts are those of the queries below (a cube they drop has no children).
  double hint_distance = std::numeric_limits<double>::infinity();  // an upper bound of dist(q, F)
  if (cube.hint >= 0) {
    const auto hint = static_cast<std::uint32_t>(cube.hint);
    hint_distance = point_triangle_distance_upper_near(q, fixed.mesh(), hint);
    if (round_up(hint_distance + r) < depth) {
      v.nearest = hint;
      return v;  // s >= -dist(x, F) > target on Q
    }
  }
  const bool in_free_ball =
      cube.ref_side != 0 && round_up((q - cube.ref).norm() * (1.0 + 1e-12)) < cube.ref_free;
  if (in_free_ball && cube.ref_side > 0 && round_down(-r) > target) {
    v.side = 1;
    return v;  // outside: s >= dist(q, F) - r >= -r > target
  }
  // The parent's list holds q's nearest triangles when it holds every triangle within an upper
  // bound of dist(q, F) of q, and the segment from the parent's centre when it reaches q.
  bool unique = false;  // v.nearest is q's only nearest triangle
  const Interval ud = parent && parent->covers(q, hint_distance)
                          ? fixed.unsigned_distance_among(q, parent->ids, &v.nearest, DistanceEnds::enclosed, &unique)
                          : fixed.unsigned_distance(q, &v.nearest, cube.hint, DistanceEnds::enclosed, &unique);
  v.free = ud.lo;
  v.near = ud.hi;
  // s >= -dist(x, F) everywhere: shallow whatever q's side.
  if (round_up(ud.hi + r) < depth) return v;
  const bool segment_listed = parent && cube.ref_side != 0 && parent->covers(q, 0.0);
  const int side = in_free_ball ? cube.ref_side
                                : fixed.side_by_nearest(q, ud, v.nearest, unique, cube.ref, cube.ref_side,
                                                        segment_listed ? &parent->ids : nullptr);
  if (ud.lo > 0.0) v.side = static_cast<signed char>(side);
  if (side > 0 && round_down(ud.lo - r) > target) return v;  // outside: s >= dist(q, F) - r
  if (side < 0 && round_down(ud.lo - r) >= depth) {        // inside Z: s <= s(q) + r <= target
    v.what = DeepCubeVerdict::keep;
    return v;
  }
  const std::array<Vec3, 8> corners = Q.corners();
  // Sparse weights: a cube undecided by them is split, and is cheaper to split than to bound with
  // converged weights (rotor, retinal, boeing, pinion: 20-50 % less time, as many cubes).
  const double reach = round_up(ud.hi + 2 * r);
  double bound;
  CornerDistances known;  // the clips' distances that the bound computes
  if (parent && parent->covers(q, reach)) {
    fixed.triangles_within_among(q, reach, parent->ids, ids);
    bound = depth_upper_bound_among(fixed, q, ids, corners.data(), 8, nullptr, nullptr, nullptr, nullptr, 0.0,
                                    DepthWeights::sparse, nullptr, &known);
  } else {
    bound = depth_upper_bound(fixed, q, reach, corners.data(), 8, ids, nullptr, nullptr, nullptr, nullptr, 0.0,
                              DepthWeights::sparse, nullptr, &known);
  }
  if (bound < depth) return v;  // s >= -dist >= -bound > target on the cube
  if (!clip_deep_cube(fixed, depth, Q, corners, ids, known, v)) return v;  // a clip proves it shallow
  v.what = r <= cell_size ? DeepCubeVerdict::keep : DeepCubeVerdict::split;
  return v;
}

bool deep_cube_regions(const SignedDistance& fixed, double target, const DeepCube& cube, const DeepCubeHead& verdict,
                       std::vector<std::uint32_t>& ids, const DeepCubeList* parent) {
  const double depth = -target;
  const Aabb& Q = cube.box;
  const double r = deep_cube_radius(Q);
  if (verdict.what != DeepCubeVerdict::split || !(verdict.near > 0.0) || !(r <= kRegionCellRadius * depth)) return false;
  // A centre at least |target| deep is in the zone itself; one nearly that deep seldom lets the
  // cube go.
  if (verdict.side < 0 && !(verdict.free < kRegionCentreDepth * depth)) return false;
  const Vec3 q = Q.center();
  // Every triangle nearest to a point of the cube (a region's seeds: the nearest faces first, then
  // those facing the other way) lies within near + 2r of q. More than kMaxListed: not a wall's few
  // faces (64 lost a third of the repaired shark's drops, 512 dropped no more than 128).
  constexpr std::size_t kMaxListed = 128;
  const double reach = round_up((verdict.near + 2.0 * r) * (1.0 + 1e-12));
  const bool listed = parent && parent->covers(q, reach);
  if (!region_seeds(fixed, q, reach, kMaxListed, listed ? &parent->ids : nullptr, ids) || ids.empty()) return false;
  const std::array<Vec3, 8> corners = Q.corners();
  // Only the interior points of the solid matter (the zone's): the bound is of their depth. The
  // two sides' regions first (staged); no slices (as tight on the shark, 10 % cheaper).
  return region_depth_bound(fixed, q, verdict.side, corners.data(), 8, ids, {depth, false, true, false}) < depth;
}

DeepCube deep_cube_child(const Aabb& box, const Aabb& parent, const DeepCubeHead& parent_verdict) {
  DeepCube c;
  c.box = box;
  c.ref = parent.center();
  c.ref_side = parent_verdict.side;
  c.ref_free = parent_verdict.free;
  c.hint = parent_verdict.nearest;
  return c;
}

std::array<Aabb, 8> deep_cube_child_boxes(const Aabb& Q) {
  const Vec3 q = Q.center();
  std::array<Aabb, 8> boxes;
  for (int k = 0; k < 8; ++k)
    for (int a = 0; a < 3; ++a) {
      const bool upper = (k >> a) & 1;
      boxes[k].lo[a] = upper ? q[a] : Q.lo[a];
      boxes[k].hi[a] = upper ? Q.hi[a] : q[a];
    }
  return boxes;
}

std::array<DeepCube, 8> deep_cube_children(const DeepCube& cube, const DeepCubeVerdict& verdict) {
  const std::array<Aabb, 8> boxes = deep_cube_child_boxes(cube.box);
  std::array<DeepCube, 8> children;
  for (int k = 0; k < 8; ++k) children[k] = deep_cube_child(boxes[k], cube.box, verdict);
  return children;
}

DeepCover build_deep_cover(const SignedDistance& fixed, double target, const DeepCoverOptions& options) {
  DeepCover cover;
  cover.target = target;
  if (!(target < 0.0) || fixed.mesh().faces.empty()) return cover;
  // Breadth first, one octree level at a time, so that a budget too small is found before the
  // finest (and largest) level is evaluated: its cubes are eight per undecided cube of the last.
  std::vector<DeepCube> level{deep_cover_root(fixed)}, next;
  std::vector<DeepCubeVerdict> verdicts;
  while (!level.empty()) {
    // The cubes still to come must fit the budget: this level's and those of the levels down to
    // the cell size, predicted at kGrowth times as many per level (four children of eight kept
    // along a surface; measured 2.4-5 on CGAL's solids below the root's first levels). A budget
    // that cannot hold them is given up now rather than after those levels: a cover that will not
    // fit costs a few levels instead of its whole budget (pinion, boeing: 58,801 and 82,809 cubes
    // before). Only the spending depends on the prediction; a cover built is complete.
    constexpr double kGrowth = 3.5;
    double rho = 0.5 * level.front().box.diagonal(), to_come = 1.0, per_cube = 1.0;
    for (; rho > options.cell_size && to_come < 1e12; rho *= 0.5) {
      per_cube *= kGrowth;
      to_come += per_cube;
    }
    if (static_cast<double>(cover.cells) + to_come * static_cast<double>(level.size()) >
        static_cast<double>(options.max_cells)) {
      cover.boxes.clear();
      return cover;
    }
    // The cubes of a level are independent: classified on every thread (isolated, so that a
    // waiting thread takes no unrelated task), then assembled in order, so the cover does not
    // depend on the threads.
    verdicts.assign(level.size(), DeepCubeVerdict{});
    tbb::this_task_arena::isolate([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, level.size(), 64),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          std::vector<std::uint32_t> ids;
                          for (std::size_t i = range.begin(); i != range.end(); ++i)
                            verdicts[i] = classify_deep_cube(fixed, target, options.cell_size, level[i], ids);
                        });
    });
    cover.cells += level.size();
    next.clear();
    for (std::size_t i = 0; i < level.size(); ++i) {
      if (verdicts[i].what == DeepCubeVerdict::keep) cover.boxes.push_back(level[i].box);
      if (verdicts[i].what != DeepCubeVerdict::split) continue;
      for (const DeepCube& c : deep_cube_children(level[i], verdicts[i])) next.push_back(c);
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

namespace {
constexpr std::size_t kMemoShards = 64;  // chosen by a hash's top 6 bits
// A cube of the octree is its lower corner and its side (lo, and hi.x), compared bit for bit.
struct CubeKey {
  std::array<std::uint64_t, 4> bits;
  bool operator==(const CubeKey& o) const { return bits == o.bits; }
};
CubeKey cube_key(const Aabb& c) {
  CubeKey k;
  const double x[4] = {c.lo[0], c.lo[1], c.lo[2], c.hi[0]};
  std::memcpy(k.bits.data(), x, sizeof x);
  return k;
}
// The octree's doubles differ in few high bits: every word is mixed in full (splitmix64's
// finaliser), so both the shard (the top bits) and the slot (the low bits) spread.
std::uint64_t mix(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ull;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
std::uint64_t cube_hash(const CubeKey& k) {
  std::uint64_t h = 0x9e3779b97f4a7c15ull;
  for (const std::uint64_t b : k.bits) h = mix(h ^ b);
  return h;
}
}  // namespace

// Open addressing, linear probing, at most half full: a look-up is one probe of a flat array in
// most cases (an unordered_map's division and node chase were a tenth of rotor's octree queries).
struct DeepCubeMemo::Shard {
  struct Slot {
    CubeKey key;
    std::uint32_t verdict = 0;  // index + 1 into verdicts; 0: empty
  };
  struct Entry {
    DeepCubeHead head;
    std::uint32_t clips = 0;  // its clips: clips[this, this + head.n_clips)
  };
  mutable std::mutex mutex;
  std::vector<Slot> slots;  // a power of two in size, or empty
  std::vector<Entry> verdicts;
  std::vector<DeepClip> clips;  // most cubes have none: 32 bytes a verdict instead of 152

  // The slot holding k, or the empty one where it would go (slots must not be empty or full).
  std::size_t probe(const CubeKey& k, std::uint64_t h) const {
    const std::size_t mask = slots.size() - 1;
    std::size_t i = h & mask;
    while (slots[i].verdict != 0 && !(slots[i].key == k)) i = (i + 1) & mask;
    return i;
  }
  void grow() {
    std::vector<Slot> old(std::max<std::size_t>(64, 2 * slots.size()));
    old.swap(slots);
    for (const Slot& s : old)
      if (s.verdict != 0) slots[probe(s.key, cube_hash(s.key))] = s;  // keys are distinct: an empty slot
  }
};

DeepCubeMemo::DeepCubeMemo(double target, std::size_t max_entries)
    : target_(target), max_per_shard_(max_entries / kMemoShards + 1), shards_(new Shard[kMemoShards]) {}

DeepCubeMemo::~DeepCubeMemo() = default;

bool DeepCubeMemo::find(const Aabb& cube, DeepCubeVerdict* verdict) const {
  const CubeKey k = cube_key(cube);
  const std::uint64_t h = cube_hash(k);
  const Shard& s = shards_[h >> 58];
  std::lock_guard<std::mutex> lock(s.mutex);
  if (s.slots.empty()) return false;
  const std::uint32_t at = s.slots[s.probe(k, h)].verdict;
  if (at == 0) return false;
  const Shard::Entry& e = s.verdicts[at - 1];
  static_cast<DeepCubeHead&>(*verdict) = e.head;
  std::copy_n(s.clips.begin() + e.clips, e.head.n_clips, verdict->clips.begin());
  return true;
}

void DeepCubeMemo::insert(const Aabb& cube, const DeepCubeVerdict& verdict) {
  const CubeKey k = cube_key(cube);
  const std::uint64_t h = cube_hash(k);
  Shard& s = shards_[h >> 58];
  std::lock_guard<std::mutex> lock(s.mutex);
  if (s.verdicts.size() >= max_per_shard_) return;
  if (2 * (s.verdicts.size() + 1) > s.slots.size()) s.grow();
  Shard::Slot& slot = s.slots[s.probe(k, h)];
  if (slot.verdict != 0) return;  // another thread's verdict for the same cube: the same verdict
  s.verdicts.push_back({verdict, static_cast<std::uint32_t>(s.clips.size())});
  s.clips.insert(s.clips.end(), verdict.clips.begin(), verdict.clips.begin() + verdict.n_clips);
  slot.key = k;
  slot.verdict = static_cast<std::uint32_t>(s.verdicts.size());
}

void DeepCubeMemo::refine(const Aabb& cube, const DeepCubeHead& head) {
  const CubeKey k = cube_key(cube);
  const std::uint64_t h = cube_hash(k);
  Shard& s = shards_[h >> 58];
  std::lock_guard<std::mutex> lock(s.mutex);
  if (s.slots.empty()) return;
  const std::uint32_t at = s.slots[s.probe(k, h)].verdict;
  if (at == 0) return;  // never inserted (the memo was full)
  Shard::Entry& e = s.verdicts[at - 1];
  const signed char n_clips = e.head.n_clips;  // its clips stay where they are
  e.head = head;
  e.head.n_clips = std::min(n_clips, head.n_clips);
}

std::size_t DeepCubeMemo::size() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < kMemoShards; ++i) {
    std::lock_guard<std::mutex> lock(shards_[i].mutex);
    n += shards_[i].verdicts.size();
  }
  return n;
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
