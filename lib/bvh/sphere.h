#pragma once
// Bounding sphere in doubles, built so that it contains its points despite rounding (radius
// rounded up with a relative margin far above the error of the distance computation).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "core/aabb.h"

namespace cdbench {

struct Sphere {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = -1.0;  // negative: empty
};

// A sphere containing the points p[0..n) centred at the centre of `box`, their bounding box (which
// is at most sqrt(3)/2 of the box diagonal from any point, so the radius is within a factor ~1.7 of
// optimal). Callers that also need the box pass it here instead of computing it twice.
template <class PointAt>
Sphere bounding_sphere_in_box(const Aabb& box, int n, const PointAt& point_at) {
  Sphere s;
  if (box.empty()) return s;
  s.center = box.center();
  double r2 = 0.0;
  for (int i = 0; i < n; ++i) r2 = std::max(r2, (point_at(i) - s.center).squaredNorm());
  // Each squared norm is within a few ulps; sqrt is correctly rounded; the factor and the absolute
  // term cover both (and subnormal underflow).
  s.radius = std::sqrt(r2) * (1.0 + kRoundingSlack) + 1e-300;
  return s;
}

template <class PointAt>
Sphere bounding_sphere(int n, const PointAt& point_at) {
  return bounding_sphere_in_box(bounding_box(n, point_at), n, point_at);
}

}  // namespace cdbench
