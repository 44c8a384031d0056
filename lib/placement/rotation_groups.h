#pragma once
// Work on many poses whose rotations repeat (a pose set: every level and direction of an
// orientation share its R): poses sharing R bit for bit share one per-rotation state (the mover's
// rotated trees), built by the first thread that needs it and freed after its last pose. Poses are
// handed out one at a time (parallel_for_dynamic), grouped by rotation in first-seen order so that
// few states are alive at once.
#include <Eigen/Core>
#include <algorithm>
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "util/dynamic_parallel.h"

namespace cdbench {

// The rotation group of each listed pose: poses whose R are equal bit for bit share a number,
// numbered 0, 1, ... in the order of first appearance in `indices` (entries of unlisted poses: 0).
inline std::vector<std::size_t> rotation_group_ids(const std::vector<Eigen::Matrix3d>& rotations,
                                                   const std::vector<std::size_t>& indices) {
  std::map<std::vector<double>, std::size_t> group_of_R;
  std::vector<std::size_t> group(rotations.size(), 0);
  for (std::size_t i : indices) {
    const Eigen::Matrix3d& R = rotations[i];
    group[i] = group_of_R.emplace(std::vector<double>(R.data(), R.data() + 9), group_of_R.size()).first->second;
  }
  return group;
}

// rotations[i]: the R of pose i; only the poses listed in `todo` are visited.
// make_state(R) -> State; body(i, const State&).
template <class State, class MakeState, class Body>
void for_each_pose_by_rotation(const std::vector<Eigen::Matrix3d>& rotations, const std::vector<std::size_t>& todo,
                               const MakeState& make_state, const Body& body) {
  struct Lazy {
    std::once_flag once;
    std::unique_ptr<State> state;
    std::atomic<std::size_t> left{0};
  };
  const std::vector<std::size_t> group = rotation_group_ids(rotations, todo);
  std::size_t groups = 0;
  for (std::size_t i : todo) groups = std::max(groups, group[i] + 1);
  std::vector<Lazy> states(groups);
  std::vector<std::size_t> order = todo;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return group[a] < group[b]; });
  for (std::size_t i : order) ++states[group[i]].left;
  parallel_for_dynamic(order.size(), [&](std::size_t k) {
    const std::size_t i = order[k];
    Lazy& lazy = states[group[i]];
    std::call_once(lazy.once, [&] { lazy.state = std::make_unique<State>(make_state(rotations[i])); });
    body(i, *lazy.state);
    if (--lazy.left == 0) lazy.state.reset();
  });
}

}  // namespace cdbench
