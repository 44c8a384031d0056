#pragma once
// Union-find with path halving; the smallest index of a set is its root, so results do not depend
// on the order of unions (deterministic component numbering), which also makes unions from several
// threads at once safe to offer: roots are only ever linked under smaller roots (by compare-and-
// swap), so the sets and their roots are the same whatever the interleaving.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>

namespace cdbench {

class UnionFind {
 public:
  // Large sets are initialised on every thread (the pages' first touch; 2.5 million corners of an
  // 832K-face mesh: 20 MB).
  explicit UnionFind(std::size_t n) : n_(n), parent_(new std::atomic<std::size_t>[n]) {
    const auto init = [this](std::size_t lo, std::size_t hi) {
      for (std::size_t i = lo; i < hi; ++i) parent_[i].store(i, std::memory_order_relaxed);
    };
    if (n < (std::size_t(1) << 18)) {
      init(0, n);
      return;
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::size_t(1) << 16),
                      [&](const tbb::blocked_range<std::size_t>& r) { init(r.begin(), r.end()); });
  }
  std::size_t size() const { return n_; }

  // One thread at a time (the plain load/stores of a serial union-find).
  std::size_t find(std::size_t x) {
    for (std::size_t p; (p = load(x)) != x;) {
      const std::size_t g = load(p);
      parent_[x].store(g, std::memory_order_relaxed);
      x = g;
    }
    return x;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)].store(std::min(a, b), std::memory_order_relaxed);
  }

  // Safe from several threads at once (with each other, not with find or unite above). A parent
  // only ever moves to a smaller ancestor in the same set, so a failed halving is harmless and a
  // failed link (the larger root was linked meanwhile) retries from the new roots.
  std::size_t find_concurrent(std::size_t x) {
    for (;;) {
      std::size_t p = parent_[x].load(std::memory_order_acquire);
      if (p == x) return x;
      const std::size_t g = parent_[p].load(std::memory_order_acquire);
      if (g != p) parent_[x].compare_exchange_weak(p, g, std::memory_order_acq_rel, std::memory_order_relaxed);
      x = g;
    }
  }
  void unite_concurrent(std::size_t a, std::size_t b) {
    for (;;) {
      a = find_concurrent(a);
      b = find_concurrent(b);
      if (a == b) return;
      if (a < b) std::swap(a, b);  // link the larger root under the smaller
      std::size_t expected = a;
      if (parent_[a].compare_exchange_strong(expected, b, std::memory_order_acq_rel, std::memory_order_acquire)) return;
    }
  }

 private:
  std::size_t load(std::size_t x) const { return parent_[x].load(std::memory_order_relaxed); }
  std::size_t n_;
  std::unique_ptr<std::atomic<std::size_t>[]> parent_;
};

}  // namespace cdbench
