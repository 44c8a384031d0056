#pragma once
// A closed interval of reals [lo, hi] with double endpoints, used for certified quantities.
#include <algorithm>
#include <cmath>

namespace cdbench {

struct Interval {
  double lo = 0.0, hi = 0.0;
  double width() const { return hi - lo; }
  double mid() const { return 0.5 * (lo + hi); }
  bool contains(double x) const { return lo <= x && x <= hi; }
};

// Next double towards +inf / -inf (one ulp of outward rounding).
inline double round_up(double x) { return std::nextafter(x, HUGE_VAL); }
inline double round_down(double x) { return std::nextafter(x, -HUGE_VAL); }

}  // namespace cdbench
