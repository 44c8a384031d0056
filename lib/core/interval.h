#pragma once
// A closed interval of reals [lo, hi] with double endpoints, used for certified quantities.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace cdbench {

struct Interval {
  double lo = 0.0, hi = 0.0;
  double width() const { return hi - lo; }
  double mid() const { return 0.5 * (lo + hi); }
  bool contains(double x) const { return lo <= x && x <= hi; }
};

// Next double towards +inf / -inf (one ulp of outward rounding): std::nextafter(x, +-inf) to the
// bit (NaN and the infinity itself stay, +-0 go to the smallest subnormal), but inline. The library
// call was 4 % of a penetrating level's profile; the two agree on every class of double (test_core).
inline double round_up(double x) {
  if (!(x < std::numeric_limits<double>::infinity())) return x;  // NaN, +inf
  if (x == 0.0) return std::numeric_limits<double>::denorm_min();
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  b = x > 0.0 ? b + 1 : b - 1;  // the magnitude's bits are ordered like the magnitudes
  std::memcpy(&x, &b, sizeof b);
  return x;
}
inline double round_down(double x) { return -round_up(-x); }

}  // namespace cdbench
