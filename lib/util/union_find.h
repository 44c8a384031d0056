#pragma once
// Union-find with path halving; the smallest index of a set is its root, so results do not depend
// on the order of unions (deterministic component numbering).
#include <algorithm>
#include <cstddef>
#include <numeric>
#include <vector>

namespace cdbench {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), std::size_t{0}); }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace cdbench
