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

// sqrt(3) rounded up (the nearest double is below it): a cube's covering radius over its half side.
constexpr double kSqrt3Up = 1.7320508075688774;

// Bounds of |v| for a 3-vector v from its computed squared norm q = fl(v.v): q carries three
// roundings (at most 3 u relative) and the root one more.
inline double norm3_lower(double q) { return std::sqrt(q) * (1.0 - 4e-15); }
inline double norm3_upper(double q) { return std::sqrt(q) * (1.0 + 4e-15); }

}  // namespace cdbench
