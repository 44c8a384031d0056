#pragma once
// Axis-aligned bounding box in doubles. Boxes built from double vertices are exact (min/max do not
// round); query-side bounds below are rounded so that they never exceed the true value.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <limits>

namespace cdbench {

struct Aabb {
  Eigen::Vector3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::infinity()};
  Eigen::Vector3d hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()};

  bool empty() const { return !(lo.x() <= hi.x()); }
  void extend(const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void extend(const Aabb& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  Eigen::Vector3d center() const { return 0.5 * (lo + hi); }
  Eigen::Vector3d extent() const { return hi - lo; }
  double diagonal() const { return (hi - lo).norm(); }
  // The largest coordinate magnitude of its points (exact): the scale of their doubles' rounding.
  double max_abs() const { return std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()); }
  // Corner k (0..7): bit 0 selects hi.x, bit 1 hi.y, bit 2 hi.z.
  Eigen::Vector3d corner(int k) const {
    return {(k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z()};
  }
  std::array<Eigen::Vector3d, 8> corners() const {
    std::array<Eigen::Vector3d, 8> c;
    for (int k = 0; k < 8; ++k) c[k] = corner(k);
    return c;
  }
  bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
  }
  // Strictly apart along some axis (exact: comparisons do not round), so no point is in both.
  bool apart(const Aabb& b) const { return (hi.array() < b.lo.array()).any() || (lo.array() > b.hi.array()).any(); }
};

// The box of the points p[0..n) (exact: min and max do not round).
template <class PointAt>
Aabb bounding_box(int n, const PointAt& point_at) {
  Aabb b;
  for (int i = 0; i < n; ++i) b.extend(point_at(i));
  return b;
}

// Relative slack that covers the rounding of a handful of double operations (each <= 2^-52
// relative under any rounding mode) with a wide margin: a lower bound computed in doubles and then
// multiplied by (1 - kRoundingSlack) is a true lower bound.
constexpr double kRoundingSlack = 1e-13;

// A lower bound on the squared distance from p to the box, never larger than the true value.
inline double squared_distance_lower_bound(const Aabb& box, const Eigen::Vector3d& p) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    double d = 0.0;
    if (p[k] < box.lo[k]) d = box.lo[k] - p[k];
    else if (p[k] > box.hi[k]) d = p[k] - box.hi[k];
    d2 += d * d;
  }
  return d2 * (1.0 - kRoundingSlack);
}

// A lower bound on the squared distance between two boxes, never larger than the true value.
inline double squared_distance_lower_bound(const Aabb& a, const Aabb& b) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    double g = 0.0;
    if (a.hi[k] < b.lo[k]) g = b.lo[k] - a.hi[k];
    else if (b.hi[k] < a.lo[k]) g = a.lo[k] - b.hi[k];
    d2 += g * g;
  }
  return d2 * (1.0 - kRoundingSlack);
}

// Whether the segment p + t (q - p), t in [0, 1], may meet the box. Conservative: the box is
// grown by a margin far above the rounding error of the slab computation, so a true hit is never
// missed (false hits only cost an exact test).
inline bool segment_may_hit(const Aabb& box, const Eigen::Vector3d& p, const Eigen::Vector3d& q, double margin) {
  double t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 3; ++k) {
    const double lo = box.lo[k] - margin, hi = box.hi[k] + margin;
    const double d = q[k] - p[k];
    if (d == 0.0) {
      if (p[k] < lo || p[k] > hi) return false;
      continue;
    }
    double ta = (lo - p[k]) / d, tb = (hi - p[k]) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace cdbench
