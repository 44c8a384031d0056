#pragma once
// The least of (key, index) pairs offered one at a time: ties of the key go to the least index, so
// the choice depends only on the set offered, never on the order of the offers. The nearest-
// triangle queries use it (distance/signed_distance.cpp), which makes their answers the same
// whether or not a hint reorders the visits.
#include <cstdint>
#include <limits>

namespace cdbench {

struct LeastKey {
  double key = std::numeric_limits<double>::infinity();
  std::uint32_t index = 0;
  // True when (k, i) becomes the least. A NaN key is never taken.
  bool offer(double k, std::uint32_t i) {
    if (k < key || (k == key && i < index)) {
      key = k;
      index = i;
      return true;
    }
    return false;
  }
};

}  // namespace cdbench
