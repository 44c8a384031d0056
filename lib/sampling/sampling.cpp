#include "sampling/sampling.h"

#include <cmath>
#include <random>

#include "util/error.h"

namespace cdbench {
namespace {

const double kPi = std::acos(-1.0);

// Uniform in [0, 1) from 53 random bits: portable, unlike std::uniform_real_distribution.
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

}  // namespace

std::vector<Eigen::Vector3d> sphere_fibonacci(std::size_t n) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(n);
  const double golden_angle = kPi * (3.0 - std::sqrt(5.0));
  for (std::size_t k = 0; k < n; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / static_cast<double>(n);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = std::fmod(golden_angle * static_cast<double>(k), 2.0 * kPi);
    out.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  return out;
}

std::vector<Eigen::Vector3d> sphere_grid(std::size_t n) {
  std::vector<Eigen::Vector3d> out;
  if (n == 0) return out;
  const std::size_t rows = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(std::sqrt(n * kPi / 4.0))));
  std::vector<double> weight(rows);
  double total = 0.0;
  for (std::size_t i = 0; i < rows; ++i) total += weight[i] = std::sin((i + 0.5) * kPi / rows);
  // Largest-remainder apportionment: exactly n points, each row close to its share.
  std::vector<std::size_t> count(rows);
  std::vector<std::pair<double, std::size_t>> remainder;
  std::size_t used = 0;
  for (std::size_t i = 0; i < rows; ++i) {
    const double share = n * weight[i] / total;
    count[i] = static_cast<std::size_t>(std::floor(share));
    used += count[i];
    remainder.push_back({share - count[i], i});
  }
  std::stable_sort(remainder.begin(), remainder.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t k = 0; used < n; ++k, ++used) ++count[remainder[k % rows].second];
  out.reserve(n);
  for (std::size_t i = 0; i < rows; ++i) {
    const double theta = (i + 0.5) * kPi / rows;
    for (std::size_t j = 0; j < count[i]; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5 * (i % 2)) / count[i];  // alternate rows offset by half a step
      out.emplace_back(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    }
  }
  return out;
}

std::vector<Eigen::Quaterniond> rotations_super_fibonacci(std::size_t n) {
  std::vector<Eigen::Quaterniond> out;
  out.reserve(n);
  const double phi = std::sqrt(2.0);
  const double psi = 1.533751168755204288118041;  // the real root of psi^4 = psi + 4
  for (std::size_t i = 0; i < n; ++i) {
    const double s = i + 0.5;
    const double r = std::sqrt(s / n), R = std::sqrt(1.0 - s / n);
    const double alpha = 2.0 * kPi * s / phi, beta = 2.0 * kPi * s / psi;
    // Eigen's constructor takes (w, x, y, z).
    out.emplace_back(R * std::cos(beta), r * std::sin(alpha), r * std::cos(alpha), R * std::sin(beta));
  }
  return out;
}

std::vector<Eigen::Quaterniond> rotations_random(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Eigen::Quaterniond> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double u1 = unit(rng), u2 = unit(rng), u3 = unit(rng);
    const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
    out.emplace_back(b * std::cos(2 * kPi * u3), a * std::sin(2 * kPi * u2), a * std::cos(2 * kPi * u2),
                     b * std::sin(2 * kPi * u3));
  }
  return out;
}

void check_sampling_names(const std::string& directions, const std::string& orientations) {
  if (directions != "fibonacci" && directions != "grid")
    throw InputError("--direction-sampling: expected 'fibonacci' or 'grid', found '" + directions + "'");
  if (orientations != "super-fibonacci" && orientations != "random")
    throw InputError("--orientation-sampling: expected 'super-fibonacci' or 'random', found '" + orientations + "'");
}

std::vector<Eigen::Vector3d> sample_directions(const std::string& kind, std::size_t n) {
  check_sampling_names(kind, "random");
  return kind == "grid" ? sphere_grid(n) : sphere_fibonacci(n);
}

std::vector<Eigen::Quaterniond> sample_orientations(const std::string& kind, std::size_t n, std::uint64_t seed) {
  check_sampling_names("grid", kind);
  return kind == "random" ? rotations_random(n, seed) : rotations_super_fibonacci(n);
}

}  // namespace cdbench
