// The header-only core (lib/core).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/aabb.h"
#include "core/interval.h"

namespace cdbench {
namespace {

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}
double from_bits(std::uint64_t b) {
  double x;
  std::memcpy(&x, &b, sizeof b);
  return x;
}

// The inline outward rounding is std::nextafter towards the infinities, to the bit (NaN: any NaN).
void expect_as_nextafter(double x) {
  const double inf = std::numeric_limits<double>::infinity();
  const double u = std::nextafter(x, inf), d = std::nextafter(x, -inf);
  if (std::isnan(x)) {
    EXPECT_TRUE(std::isnan(round_up(x)));
    EXPECT_TRUE(std::isnan(round_down(x)));
    return;
  }
  EXPECT_EQ(bits(round_up(x)), bits(u)) << std::hexfloat << x;
  EXPECT_EQ(bits(round_down(x)), bits(d)) << std::hexfloat << x;
}

// The largest coordinate magnitude of a box: from either corner, whichever side of 0 it lies on.
TEST(Core, BoxLargestCoordinateMagnitude) {
  Aabb b;
  b.extend(Eigen::Vector3d(-3.0, 1.0, 2.0));
  b.extend(Eigen::Vector3d(-1.0, 5.0, 2.5));
  EXPECT_EQ(b.max_abs(), 5.0);
  b.extend(Eigen::Vector3d(-7.0, 0.0, 0.0));
  EXPECT_EQ(b.max_abs(), 7.0);
  Aabb far;
  far.extend(Eigen::Vector3d(1e6, 1e6 + 1.0, 1e6));
  EXPECT_EQ(far.max_abs(), 1e6 + 1.0);
}

TEST(Core, OutwardRoundingIsNextafterOnEveryClassOfDouble) {
  using L = std::numeric_limits<double>;
  const std::vector<double> special{0.0, -0.0, L::denorm_min(), -L::denorm_min(), L::min(), -L::min(),
                                    from_bits(bits(L::min()) - 1), -from_bits(bits(L::min()) - 1), L::max(),
                                    -L::max(), L::infinity(), -L::infinity(), L::quiet_NaN(), -L::quiet_NaN(),
                                    1.0, -1.0, 0.5, -0.5, 2.0, L::epsilon(), 1e-300, -1e300};
  for (double x : special) expect_as_nextafter(x);
  // Random bit patterns cover every exponent and sign, subnormals and NaN payloads included.
  std::mt19937_64 rng(20261126);
  for (int i = 0; i < 1000000; ++i) expect_as_nextafter(from_bits(rng()));
  // Random ordinary doubles near the sizes our distances take.
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (int i = 0; i < 100000; ++i) {
    const double mantissa = u(rng);
    expect_as_nextafter(mantissa * std::pow(10.0, u(rng)));
  }
  // The signs of zero: one step up from -0 and from +0 is the smallest subnormal, and back.
  EXPECT_EQ(bits(round_down(L::denorm_min())), bits(0.0));
  EXPECT_EQ(bits(round_up(-L::denorm_min())), bits(-0.0));
}

}  // namespace
}  // namespace cdbench
