#pragma once
// The pose transform, as every module evaluates it: a pose is x_world = R x + t (R, t stored
// doubles) and a placed vertex is fl(fl(R x) + t), one IEEE-double evaluation in a fixed order, so
// that poses, certificates, sweeps and collision queries place the same points. (Its rounding
// bound is MoverOrientation::transform_error, placement/mover.h.)
#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace cdbench {

// fl(R x), in the fixed order ((r0 x0 + r1 x1) + r2 x2) per coordinate.
inline Eigen::Vector3d rotate_point(const Eigen::Matrix3d& R, const Eigen::Vector3d& x) {
  Eigen::Vector3d y;
  for (int i = 0; i < 3; ++i) y[i] = R(i, 0) * x[0] + R(i, 1) * x[1] + R(i, 2) * x[2];
  return y;
}

// fl(fl(R x) + t): how every placed vertex is evaluated (poses, clearances, collision queries).
inline Eigen::Vector3d place_point(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector3d& x) {
  const Eigen::Vector3d r = rotate_point(R, x);
  return Eigen::Vector3d(r[0] + t[0], r[1] + t[1], r[2] + t[2]);
}

// The placed vertices fl(rotated[k] + t) of one pose, each computed when read, exactly as
// place_point computes it from the rotated vertices: a certificate reads only the vertices near the
// contact, so it need not place all of them (O(n) per certificate on large movers).
struct PlacedView {
  const std::vector<Eigen::Vector3d>* rotated = nullptr;
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector3d operator[](std::size_t k) const {
    const Eigen::Vector3d& r = (*rotated)[k];
    return Eigen::Vector3d(r[0] + t[0], r[1] + t[1], r[2] + t[2]);
  }
};

}  // namespace cdbench
