#pragma once
// A binary bounding-volume hierarchy over primitives (triangles), generic in the bounding volume,
// and the single traversal every query uses.
//
// Build: top-down, splitting each node's primitives at the median of their centroids along the
// longest axis of the centroids' box (deterministic: ties broken by primitive index), or where the
// binned surface-area heuristic puts the cut (BvhSplit::surface_area, F's distance tree).
//
// Traversal (traverse_nearest_first): depth-first, the child with the smaller policy bound first,
// pruning every node whose bound exceeds the policy's current prune bound. A policy provides
//   double bound(const BV&)        lower bound of the node's value for this query (+inf: skip);
//   double prune_bound() const     nodes with bound > prune_bound() are skipped (may shrink);
//   void   leaf(std::uint32_t id)  visits one primitive;
//   bool   done() const            stops the traversal early.
// Nearest-point, ray-parity and box-overlap queries are policies of this one traversal.
//
// Pairs of hierarchies (traverse_pairs_nearest_first) use the same scheme on node pairs: the node
// the policy calls larger is split, the two child pairs are visited in order of their bound. The
// policy has bound(const BVA&, const BVB&), prune_bound(), leaf(id_a, id_b), done() and
// split_first(const BVA&, const BVB&) (true: split the node of the first hierarchy).
// First contact along a line (sphere trees), minimum distance and overlap (boxes) are policies.
#include <Eigen/Core>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "core/aabb.h"
#include "util/large_pages.h"

namespace cdbench {

// How a node's primitives are split in two.
enum class BvhSplit {
  median,        // at the median of the centroids along their box's longest axis
  // Where the binned surface-area heuristic puts it (the least sum over the two halves of box area
  // times count, 16 bins per axis), in subtrees of at most kBvhDeferredPrimitives primitives; the
  // top of a larger tree stays median, for its parallel build. Leaves of one primitive only (the
  // parallel build's numbering needs 2n - 1 nodes for n primitives whatever the shape). Tighter
  // boxes for meshes of mixed triangle sizes (a CAD part's long slivers beside small faces): the
  // distance queries visit fewer nodes (doc/performance.md, "Distance trees split by surface area").
  surface_area,
};

struct BvhBuildOptions {
  std::uint32_t leaf_size = 1;  // primitives per leaf at most
  BvhSplit split = BvhSplit::median;
};

// Larger trees are built in parallel: their top split at the median, subtrees of at most this
// many primitives built whole on one thread each (build_bvh).
inline constexpr std::uint32_t kBvhDeferredPrimitives = 8192;

template <class BV>
struct Bvh {
  struct Node {
    BV bv;
    std::uint32_t first = 0;  // internal node: index of the left child (right = first + 1); leaf: offset into order
    std::uint32_t count = 0;  // 0 for an internal node, else number of primitives in the leaf
  };
  using NodeArray = std::vector<Node, LargePageAllocator<Node>>;  // hundreds of MB at 10^6 triangles
  NodeArray nodes;                    // nodes[0] is the root when not empty
  std::vector<std::uint32_t> order;   // primitive ids, leaf ranges index into it

  bool empty() const { return nodes.empty(); }
};

namespace detail {

struct BuildTask {
  std::uint32_t node, begin, end;
};

// A top node whose volume is fitted later: its primitives in the order the fit would have met
// them.
struct DeferredFit {
  std::uint32_t node;
  std::vector<std::uint32_t> ids;
};

// Reorders order[begin, end) so that its first half (count / 2) holds the primitives whose
// centroids come first along the longest axis of their box (ties by index); returns the middle.
inline std::uint32_t median_split(std::vector<std::uint32_t>& order, const std::vector<Eigen::Vector3d>& centroids,
                                  std::uint32_t begin, std::uint32_t end) {
  Eigen::Vector3d lo = centroids[order[begin]], hi = lo;
  for (std::uint32_t i = begin; i < end; ++i) {
    lo = lo.cwiseMin(centroids[order[i]]);
    hi = hi.cwiseMax(centroids[order[i]]);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const std::uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [&](std::uint32_t a, std::uint32_t b) {
                     const double ca = centroids[a][axis], cb = centroids[b][axis];
                     return ca < cb || (ca == cb && a < b);
                   });
  return mid;
}

// The split of order[begin, end) by the binned surface-area heuristic (BvhSplit::surface_area):
// each axis's centroid span cut into kBins equal bins, the cut between bins with the least
// area(left box) * left count + area(right box) * right count; ties to the first axis and cut.
// Deterministic: the same order in gives the same order and middle out. The median split where
// no cut parts the centroids (all in one bin along every axis).
inline std::uint32_t surface_area_split(std::vector<std::uint32_t>& order, const std::vector<Eigen::Vector3d>& centroids,
                                        const std::vector<Aabb>& boxes, std::uint32_t begin, std::uint32_t end) {
  constexpr int kBins = 16;
  Eigen::Vector3d lo = centroids[order[begin]], hi = lo;
  for (std::uint32_t i = begin; i < end; ++i) {
    lo = lo.cwiseMin(centroids[order[i]]);
    hi = hi.cwiseMax(centroids[order[i]]);
  }
  const auto area = [](const Aabb& b) {
    const Eigen::Vector3d e = b.hi - b.lo;
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
  };
  const auto bin_of = [&](std::uint32_t id, int axis, double scale) {
    return std::min(kBins - 1, static_cast<int>((centroids[id][axis] - lo[axis]) * scale));
  };
  double best_cost = std::numeric_limits<double>::infinity();
  int best_axis = -1, best_cut = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double extent = hi[axis] - lo[axis];
    const double scale = kBins / extent;
    if (!(extent > 0.0) || !std::isfinite(scale)) continue;  // (a subnormal extent: no bins)
    std::array<Aabb, kBins> bin_box;
    std::array<std::uint32_t, kBins> bin_count{};
    for (std::uint32_t i = begin; i < end; ++i) {
      const int b = bin_of(order[i], axis, scale);
      ++bin_count[b];
      bin_box[b].extend(boxes[order[i]]);
    }
    // right_cost[c]: the cost of bins c.. (cut before bin c), 0 where empty.
    std::array<double, kBins> right_cost{};
    Aabb right;
    std::uint32_t right_count = 0;
    for (int b = kBins - 1; b > 0; --b) {
      if (bin_count[b] > 0) right.extend(bin_box[b]);
      right_count += bin_count[b];
      right_cost[b] = right_count > 0 ? area(right) * right_count : 0.0;
    }
    Aabb left;
    std::uint32_t left_count = 0;
    for (int c = 1; c < kBins; ++c) {
      if (bin_count[c - 1] > 0) left.extend(bin_box[c - 1]);
      left_count += bin_count[c - 1];
      if (left_count == 0 || left_count == end - begin) continue;
      const double cost = area(left) * left_count + right_cost[c];
      if (cost < best_cost) best_cost = cost, best_axis = axis, best_cut = c;
    }
  }
  if (best_axis < 0) return median_split(order, centroids, begin, end);
  const double scale = kBins / (hi[best_axis] - lo[best_axis]);
  const auto mid = std::partition(order.begin() + begin, order.begin() + end,
                                  [&](std::uint32_t id) { return bin_of(id, best_axis, scale) < best_cut; });
  return static_cast<std::uint32_t>(mid - order.begin());
}

// Builds the subtree of `task` (its node already allocated in `nodes`): median split of the
// centroids (given the primitives' `boxes`, the surface-area split), each node fitted before its
// split, children allocated in pairs as they are split (alloc_pair() returns the index of a new
// pair (left, left + 1) in `nodes`), left subtree first.
template <class BV, class Fit, class AllocPair>
void build_subtree(typename Bvh<BV>::NodeArray& nodes, std::vector<std::uint32_t>& order,
                   const std::vector<Eigen::Vector3d>& centroids, const Fit& fit, std::uint32_t leaf_size,
                   BuildTask root, AllocPair&& alloc_pair, const std::vector<Aabb>* boxes = nullptr) {
  std::vector<BuildTask> stack{root};
  while (!stack.empty()) {
    const BuildTask task = stack.back();
    stack.pop_back();
    const std::uint32_t count = task.end - task.begin;
    nodes[task.node].bv = fit(order.data() + task.begin, count);
    if (count <= leaf_size) {
      nodes[task.node].first = task.begin;
      nodes[task.node].count = count;
      continue;
    }
    const std::uint32_t mid = boxes ? surface_area_split(order, centroids, *boxes, task.begin, task.end)
                                    : median_split(order, centroids, task.begin, task.end);
    const std::uint32_t left = alloc_pair();
    nodes[task.node].first = left;
    nodes[task.node].count = 0;
    stack.push_back({left + 1, mid, task.end});
    stack.push_back({left, task.begin, mid});
  }
}

// The number of nodes build_subtree makes for `count` primitives (the split depends on the count
// only: halves count / 2 and count - count / 2, leaves of at most leaf_size); with `defer`, the
// nodes of the top of a deferred build (split_top), whose nodes of at most `defer` primitives
// stand for their unbuilt subtrees.
inline std::uint32_t subtree_nodes(std::uint32_t count, std::uint32_t leaf_size, std::uint32_t defer = 0) {
  if (count <= leaf_size || count <= defer) return 1;
  return 1 + subtree_nodes(count / 2, leaf_size, defer) + subtree_nodes(count - count / 2, leaf_size, defer);
}

struct TopWork {
  std::vector<BuildTask> deferred;
  std::vector<DeferredFit> fits;
  void append(TopWork&& o) {
    deferred.insert(deferred.end(), o.deferred.begin(), o.deferred.end());
    for (DeferredFit& f : o.fits) fits.push_back(std::move(f));
  }
};

// The top of a large build: nodes of more than `defer` (and leaf_size) primitives are split
// (their volumes fitted later from the listed copies), the others listed as deferred subtrees; two
// halves are split in parallel while large. Every node gets the number the serial pre-order walk
// would give it, which depends on the counts only: a node's children are the pair at
// `first_free`, then come the left child's subtree_nodes - 1 descendants, then the right child's.
// Deferred subtrees are listed left to right.
template <class BV, class Fit>
void split_top(typename Bvh<BV>::NodeArray& nodes, std::vector<std::uint32_t>& order,
               const std::vector<Eigen::Vector3d>& centroids, const Fit& fit, std::uint32_t leaf_size,
               std::uint32_t defer, BuildTask task, std::uint32_t first_free, TopWork& out) {
  constexpr std::uint32_t kParallelSplit = 65536;
  const std::uint32_t count = task.end - task.begin;
  if (count <= leaf_size || count <= defer) {  // a leaf is a deferred subtree of one node
    out.deferred.push_back(task);
    return;
  }
  out.fits.push_back({task.node, std::vector<std::uint32_t>(order.begin() + task.begin, order.begin() + task.end)});
  const std::uint32_t mid = median_split(order, centroids, task.begin, task.end);
  nodes[task.node].first = first_free;
  nodes[task.node].count = 0;
  const BuildTask left{first_free, task.begin, mid}, right{first_free + 1, mid, task.end};
  const std::uint32_t left_free = first_free + 2;
  const std::uint32_t right_free = left_free + subtree_nodes(mid - task.begin, leaf_size, defer) - 1;
  if (count <= kParallelSplit) {
    split_top<BV>(nodes, order, centroids, fit, leaf_size, defer, left, left_free, out);
    split_top<BV>(nodes, order, centroids, fit, leaf_size, defer, right, right_free, out);
    return;
  }
  TopWork right_work;
  tbb::parallel_invoke(
      [&] { split_top<BV>(nodes, order, centroids, fit, leaf_size, defer, left, left_free, out); },
      [&] { split_top<BV>(nodes, order, centroids, fit, leaf_size, defer, right, right_free, right_work); });
  out.append(std::move(right_work));
}

}  // namespace detail

// fit(ids, n) returns the bounding volume of the n primitives ids[0..n).
// Large hierarchies are built in parallel (TBB): the top is split first (its large halves in
// parallel, split_top), then the top's volumes and the subtrees of at most 8,192 primitives are
// built on all threads, the subtrees in place and numbered in a fixed order, so the tree (its
// shape, its node numbering and every volume) depends only on the input, never on the thread
// count. A top node's volume is fitted from a copy of its primitives in the order they had before
// its split, the order a serial build fits them in. (Fitted serially, the top's volumes over
// 832,000 triangles took most of a 3 s build of spheres, boxes and oriented boxes.)
// `boxes`: the primitives' boxes, for BvhSplit::surface_area (ignored by the median split).
template <class BV, class Fit>
Bvh<BV> build_bvh(const std::vector<Eigen::Vector3d>& centroids, const Fit& fit, const BvhBuildOptions& options = {},
                  const std::vector<Aabb>* boxes = nullptr) {
  Bvh<BV> bvh;
  const std::uint32_t n = static_cast<std::uint32_t>(centroids.size());
  if (n == 0) return bvh;
  const std::uint32_t leaf_size = std::max<std::uint32_t>(1, options.leaf_size);
  if (options.split == BvhSplit::surface_area && (leaf_size != 1 || !boxes || boxes->size() != n))
    throw std::invalid_argument("build_bvh: the surface-area split needs leaves of one primitive and their boxes");
  if (options.split != BvhSplit::surface_area) boxes = nullptr;
  bvh.order.resize(n);
  std::iota(bvh.order.begin(), bvh.order.end(), 0u);
  bvh.nodes.reserve(2 * n);
  bvh.nodes.emplace_back();
  const auto append_pair = [&bvh] {
    const auto left = static_cast<std::uint32_t>(bvh.nodes.size());
    bvh.nodes.emplace_back();
    bvh.nodes.emplace_back();
    return left;
  };
  constexpr std::uint32_t kDefer = kBvhDeferredPrimitives;
  if (n <= kDefer) {
    detail::build_subtree<BV>(bvh.nodes, bvh.order, centroids, fit, leaf_size, {0, 0, n}, append_pair, boxes);
    return bvh;
  }
  bvh.nodes.resize(detail::subtree_nodes(n, leaf_size, kDefer));
  detail::TopWork top;
  detail::split_top<BV>(bvh.nodes, bvh.order, centroids, fit, leaf_size, kDefer, {0, 0, n}, 1, top);
  const std::vector<detail::BuildTask>& deferred = top.deferred;
  const std::vector<detail::DeferredFit>& fits = top.fits;
  // The deferred subtrees are built in place, in parallel, numbered as if appended one after the
  // other: subtree i's root is its reserved node, its other nodes base_i .. base_i + size_i - 2.
  std::vector<std::uint32_t> base(deferred.size());
  std::uint32_t total = static_cast<std::uint32_t>(bvh.nodes.size());
  for (std::size_t i = 0; i < deferred.size(); ++i) {
    base[i] = total;
    total += detail::subtree_nodes(deferred[i].end - deferred[i].begin, leaf_size) - 1;
  }
  bvh.nodes.resize(total);
  tbb::parallel_for(std::size_t(0), fits.size() + deferred.size(), [&](std::size_t i) {
    if (i < fits.size()) {
      const detail::DeferredFit& f = fits[i];
      bvh.nodes[f.node].bv = fit(f.ids.data(), static_cast<std::uint32_t>(f.ids.size()));
      return;
    }
    const std::size_t k = i - fits.size();
    std::uint32_t next = base[k];
    detail::build_subtree<BV>(
        bvh.nodes, bvh.order, centroids, fit, leaf_size, deferred[k],
        [&next] {
          const std::uint32_t left = next;
          next += 2;
          return left;
        },
        boxes);
  });
  return bvh;
}

// A hierarchy over triangles given as vertex-index triples: split by the triangles' centroids;
// a node's volume is fit_points(n, point_at), point_at(k) being corner k % 3 of its triangle k / 3
// (bounding_box, bounding_sphere and fit_obb have that form).
inline constexpr std::uint32_t kGatherTriangles = 64;  // nodes this large fit from a gathered copy
template <class BV, class Triangles, class FitPoints>
Bvh<BV> build_triangle_bvh(const std::vector<Eigen::Vector3d>& vertices, const Triangles& triangles,
                           const FitPoints& fit_points, const BvhBuildOptions& options = {}) {
  std::vector<Eigen::Vector3d> centroids(triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f)
    centroids[f] = (vertices[triangles[f][0]] + vertices[triangles[f][1]] + vertices[triangles[f][2]]) / 3.0;
  std::vector<Aabb> boxes;
  if (options.split == BvhSplit::surface_area) {
    boxes.resize(triangles.size());
    for (std::size_t f = 0; f < triangles.size(); ++f)
      for (int c = 0; c < 3; ++c) boxes[f].extend(vertices[triangles[f][c]]);
  }
  // Each thread gathers into one buffer for the whole build: a fresh one per node allocated about
  // 70 bytes per triangle per level of the tree, mostly above malloc's mmap threshold, and the
  // kernel cleared every page of it (at 832,000 triangles, a third of the sweep tree's build).
  tbb::enumerable_thread_specific<std::vector<Eigen::Vector3d>> gathered;
  return build_bvh<BV>(
      centroids,
      [&](const std::uint32_t* ids, std::uint32_t n) {
        // A large node's corners are gathered first, so that the fit's passes over them (a sweep
        // volume makes four) read contiguous memory instead of the mesh's scattered vertices. The
        // same points in the same order: the same volume.
        if (n < kGatherTriangles)
          return fit_points(static_cast<int>(3 * n),
                            [&](int k) -> const Eigen::Vector3d& { return vertices[triangles[ids[k / 3]][k % 3]]; });
        std::vector<Eigen::Vector3d>& corners = gathered.local();
        corners.resize(3 * std::size_t(n));
        for (std::uint32_t i = 0; i < n; ++i)
          for (int c = 0; c < 3; ++c) corners[3 * std::size_t(i) + c] = vertices[triangles[ids[i]][c]];
        const Eigen::Vector3d* q = corners.data();
        return fit_points(static_cast<int>(3 * n), [q](int k) -> const Eigen::Vector3d& { return q[k]; });
      },
      options, &boxes);
}

// The box of a leaf's triangles' corners (exact: min and max do not round).
template <class Node, class Triangles>
Aabb leaf_triangles_box(const Node& leaf, const std::vector<std::uint32_t>& order, const Triangles& triangles,
                        const std::vector<Eigen::Vector3d>& vertices) {
  Aabb box;
  for (std::uint32_t i = 0; i < leaf.count; ++i)
    for (int c = 0; c < 3; ++c) box.extend(vertices[triangles[order[leaf.first + i]][c]]);
  return box;
}

namespace detail {

// Each internal node's box below node k: the union of its children's (leaves' boxes set before).
// min and max do not round, so the boxes do not depend on the order they are formed in: nodes
// above `parallel_depth` have their two subtrees done on two tasks.
template <class NodeArray, class BoxOf>
void unite_child_boxes(NodeArray& nodes, std::uint32_t k, int depth, int parallel_depth, const BoxOf& box_of) {
  auto& node = nodes[k];
  if (node.count > 0) return;
  const std::uint32_t left = node.first;
  if (depth < parallel_depth) {
    tbb::parallel_invoke([&] { unite_child_boxes(nodes, left, depth + 1, parallel_depth, box_of); },
                         [&] { unite_child_boxes(nodes, left + 1, depth + 1, parallel_depth, box_of); });
  } else {
    unite_child_boxes(nodes, left, depth + 1, parallel_depth, box_of);
    unite_child_boxes(nodes, left + 1, depth + 1, parallel_depth, box_of);
  }
  Aabb b = box_of(nodes[left]);
  b.extend(box_of(nodes[left + 1]));
  box_of(node) = b;
}

}  // namespace detail

// Sets every internal node's box to the union of its children's, the leaves' boxes being set. In
// a balanced median tree a node at depth d heads about nodes / 2^d nodes: tasks are split while
// that is at least 2^14 (at most 4,096 tasks), so small trees (every frame of a small mover) are
// united on one thread without task overhead.
template <class NodeArray, class BoxOf>
void unite_internal_boxes(NodeArray& nodes, const BoxOf& box_of) {
  if (nodes.empty()) return;
  int parallel_depth = 0;
  while (parallel_depth < 12 && (nodes.size() >> (parallel_depth + 14)) > 0) ++parallel_depth;
  detail::unite_child_boxes(nodes, 0, 0, parallel_depth, box_of);
}

// A box tree of `topology`'s shape (its nodes' children, its leaves, its order) over triangles of
// other vertices: each leaf's box from its triangles' corners, each internal node's the union of
// its children's; exact (min and max), and O(nodes) on all threads instead of a build's sorts.
// The mover's box tree in a new orientation is its own tree's shape over the rotated vertices.
template <class BV, class Triangles>
Bvh<Aabb> refit_triangle_boxes(const Bvh<BV>& topology, const std::vector<Eigen::Vector3d>& vertices,
                               const Triangles& triangles) {
  Bvh<Aabb> r;
  r.order = topology.order;
  r.nodes.resize(topology.nodes.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, topology.nodes.size(), 4096), [&](const auto& range) {
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      const auto& a = topology.nodes[k];
      auto& b = r.nodes[k];
      b.first = a.first;
      b.count = a.count;
      if (a.count > 0) b.bv = leaf_triangles_box(a, r.order, triangles, vertices);
    }
  });
  unite_internal_boxes(r.nodes, [](auto& node) -> Aabb& { return node.bv; });
  return r;
}

template <class BV, class Policy>
void traverse_nearest_first(const Bvh<BV>& bvh, Policy& policy) {
  if (bvh.empty()) return;
  struct Entry {
    std::uint32_t node;
    double bound;
  };
  // Depth is ~log2(n) for a median split; 128 levels cover any mesh we can hold in memory.
  std::array<Entry, 256> stack;
  std::size_t top = 0;
  const double root_bound = policy.bound(bvh.nodes[0].bv);
  if (!(root_bound <= policy.prune_bound())) return;
  stack[top++] = {0, root_bound};
  while (top > 0 && !policy.done()) {
    const Entry e = stack[--top];
    if (e.bound > policy.prune_bound()) continue;
    const auto& node = bvh.nodes[e.node];
    if (node.count > 0) {
      for (std::uint32_t i = 0; i < node.count; ++i) {
        policy.leaf(bvh.order[node.first + i]);
        if (policy.done()) return;
      }
      continue;
    }
    const std::uint32_t a = node.first, b = node.first + 1;
    double ba = policy.bound(bvh.nodes[a].bv), bb = policy.bound(bvh.nodes[b].bv);
    const double prune = policy.prune_bound();
    // Push the farther child first so the nearer one is visited next.
    if (ba <= bb) {
      if (bb <= prune) stack[top++] = {b, bb};
      if (ba <= prune) stack[top++] = {a, ba};
    } else {
      if (ba <= prune) stack[top++] = {a, ba};
      if (bb <= prune) stack[top++] = {b, bb};
    }
  }
}

namespace detail {

struct NodePair {
  std::uint32_t a, b;
  double bound;
};

// Runs the policy on every primitive pair of two leaves; false once the policy is done.
template <class NodeA, class NodeB, class BVA, class BVB, class Policy>
bool visit_leaf_pairs(const Bvh<BVA>& ta, const NodeA& na, const Bvh<BVB>& tb, const NodeB& nb, Policy& policy) {
  for (std::uint32_t i = 0; i < na.count; ++i)
    for (std::uint32_t j = 0; j < nb.count; ++j) {
      policy.leaf(ta.order[na.first + i], tb.order[nb.first + j]);
      if (policy.done()) return false;
    }
  return true;
}

// The two child pairs of a pair that is not two leaves (the node the policy calls larger is
// split; a leaf never is), nearer first.
template <class BVA, class BVB, class Policy>
std::array<NodePair, 2> child_pairs(const Bvh<BVA>& ta, const Bvh<BVB>& tb, const NodePair& e, Policy& policy) {
  const auto& na = ta.nodes[e.a];
  const auto& nb = tb.nodes[e.b];
  const bool split_a = nb.count > 0 || (na.count == 0 && policy.split_first(na.bv, nb.bv));
  std::array<NodePair, 2> c;
  for (std::uint32_t k = 0; k < 2; ++k)
    c[k] = split_a ? NodePair{na.first + k, e.b, policy.bound(ta.nodes[na.first + k].bv, nb.bv)}
                   : NodePair{e.a, nb.first + k, policy.bound(na.bv, tb.nodes[nb.first + k].bv)};
  if (c[1].bound < c[0].bound) std::swap(c[0], c[1]);
  return c;
}

}  // namespace detail

template <class BVA, class BVB, class Policy>
void traverse_pairs_nearest_first(const Bvh<BVA>& ta, const Bvh<BVB>& tb, Policy& policy) {
  if (ta.empty() || tb.empty()) return;
  std::vector<detail::NodePair> stack;
  stack.reserve(128);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double root_bound = policy.bound(ta.nodes[0].bv, tb.nodes[0].bv);  // +inf: never
  if (!(root_bound <= policy.prune_bound() && root_bound < kInf)) return;
  stack.push_back({0, 0, root_bound});
  while (!stack.empty() && !policy.done()) {
    const detail::NodePair e = stack.back();
    stack.pop_back();
    if (e.bound > policy.prune_bound()) continue;
    const auto& na = ta.nodes[e.a];
    const auto& nb = tb.nodes[e.b];
    if (na.count > 0 && nb.count > 0) {
      if (!detail::visit_leaf_pairs(ta, na, tb, nb, policy)) return;
      continue;
    }
    const auto c = detail::child_pairs(ta, tb, e, policy);
    const double prune = policy.prune_bound();
    if (c[1].bound <= prune && c[1].bound < kInf) stack.push_back(c[1]);  // the farther pair waits
    if (c[0].bound <= prune && c[0].bound < kInf) stack.push_back(c[0]);
  }
}

// Best-first twin of traverse_pairs_nearest_first: one heap of node pairs ordered by bound, so
// that a pair is expanded only if its bound is below the best leaf found when it comes up. For
// first-hit queries (the least entry time along a line) this expands exactly the pairs whose
// bound lies below the answer; depth-first descends into pairs that a later, better leaf would
// have pruned. The nearer child is followed at once while no waiting pair has a smaller bound
// (the order stays best-first; the heap only holds the pairs set aside). Same policy interface;
// the policy's answer must not depend on the visiting order.
template <class BVA, class BVB, class Policy>
void traverse_pairs_best_first(const Bvh<BVA>& ta, const Bvh<BVB>& tb, Policy& policy) {
  if (ta.empty() || tb.empty()) return;
  using detail::NodePair;
  const auto later = [](const NodePair& x, const NodePair& y) { return x.bound > y.bound; };  // min-heap
  std::vector<NodePair> heap;
  heap.reserve(256);
  const auto push = [&](const NodePair& p) {
    heap.push_back(p);
    std::push_heap(heap.begin(), heap.end(), later);
  };
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double root_bound = policy.bound(ta.nodes[0].bv, tb.nodes[0].bv);
  if (!(root_bound <= policy.prune_bound() && root_bound < kInf)) return;
  NodePair e{0, 0, root_bound};
  for (;;) {
    if (policy.done()) return;
    if (e.bound <= policy.prune_bound()) {
      const auto& na = ta.nodes[e.a];
      const auto& nb = tb.nodes[e.b];
      if (na.count > 0 && nb.count > 0) {
        if (!detail::visit_leaf_pairs(ta, na, tb, nb, policy)) return;
      } else {
        const auto c = detail::child_pairs(ta, tb, e, policy);
        const double prune = policy.prune_bound();
        const bool keep0 = c[0].bound <= prune && c[0].bound < kInf;
        if (c[1].bound <= prune && c[1].bound < kInf) push(c[1]);
        if (keep0 && (heap.empty() || c[0].bound <= heap.front().bound)) {
          e = c[0];
          continue;
        }
        if (keep0) push(c[0]);
      }
    }
    if (heap.empty()) return;
    std::pop_heap(heap.begin(), heap.end(), later);
    e = heap.back();
    heap.pop_back();
    if (e.bound > policy.prune_bound()) return;  // every waiting pair is bounded below by e.bound
  }
}

}  // namespace cdbench
