#pragma once
// Runs body(i) for every i in [0, n) on the threads of the current TBB arena, handing the indices
// out one at a time in increasing order. There is no barrier: a thread that finishes a cheap item
// takes the next one at once, so items whose costs differ by orders of magnitude (the approaches
// of a pose set) keep every thread busy, and the items in flight stay close together in index
// order (state shared by neighbouring items, such as an orientation's frame, stays small).
// The first exception thrown by a body stops the hand-out and is rethrown to the caller.
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <functional>
#include <queue>
#include <vector>

namespace cdbench {

template <class Body>
void parallel_for_dynamic(std::size_t n, const Body& body) {
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stop{false};
  const int workers = std::max(1, tbb::this_task_arena::max_concurrency());
  tbb::parallel_for(
      0, workers,
      [&](int) {
        for (;;) {
          if (stop.load(std::memory_order_relaxed)) return;
          const std::size_t i = next.fetch_add(1, std::memory_order_relaxed);
          if (i >= n) return;
          try {
            body(i);
          } catch (...) {
            stop = true;
            throw;
          }
        }
      },
      tbb::simple_partitioner());
}

// The wall time parallel_for_dynamic would take on `workers` threads for items of the given costs
// (seconds, in index order), were each item's cost the same on any thread: each item goes to the
// thread that frees up first. A model of the hand-out alone (no memory contention, no shared
// setup), for estimating thread scaling from a run on fewer cores (doc/performance.md).
inline double dynamic_makespan(const std::vector<double>& costs, int workers) {
  std::priority_queue<double, std::vector<double>, std::greater<double>> free_at;
  for (int w = 0; w < std::max(1, workers); ++w) free_at.push(0.0);
  double end = 0.0;
  for (double c : costs) {
    const double t = free_at.top() + c;
    free_at.pop();
    free_at.push(t);
    end = std::max(end, t);
  }
  return end;
}

}  // namespace cdbench
