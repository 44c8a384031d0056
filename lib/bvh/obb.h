#pragma once
// Oriented bounding box (Gottschalk, Lin, Manocha 1996): centre, orthonormal axes (columns), half
// extents; fitted by the principal axes of the points; separating-axis overlap test. Rounded
// outward: the extents carry a relative margin far above the rounding of the fit and of the test.
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "core/aabb.h"

namespace cdbench {

struct Obb {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns: unit axes
  Eigen::Vector3d half = Eigen::Vector3d::Constant(-1.0);
  // Every point lies within `pad` of the box {center + axes a : |a_k| <= half_k} (0 for a fitted
  // box; a box carried by a rotation, sweep/mesh_sweep.h, covers the rounding so).
  double pad = 0.0;
};

// An OBB containing the points p[0..n): axes from the covariance of the points, extents from the
// projections (so containment holds for any axes; the margin covers rounding).
template <class PointAt>
Obb fit_obb(int n, const PointAt& point_at) {
  Obb b;
  if (n <= 0) return b;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) mean += point_at(i);
  mean /= n;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d d = point_at(i) - mean;
    cov += d * d.transpose();
  }
  // The closed-form 3x3 solver: about 10x faster than the iterative one and accurate enough for
  // a heuristic choice of axes (containment never depends on them, see below).
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(cov);
  Eigen::Matrix3d axes = eig.eigenvectors();
  // Re-orthonormalise (Gram-Schmidt) so the test's assumption |axes| orthonormal holds closely.
  axes.col(0).normalize();
  axes.col(1) = (axes.col(1) - axes.col(0).dot(axes.col(1)) * axes.col(0)).normalized();
  axes.col(2) = axes.col(0).cross(axes.col(1));
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL), hi = -lo;
  double scale = 0.0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d q = axes.transpose() * point_at(i);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
    scale = std::max(scale, point_at(i).cwiseAbs().maxCoeff());
  }
  b.axes = axes;
  b.center = axes * (0.5 * (lo + hi));
  // Containment: a point's projection is exact up to ~1e-15 * scale; the centre's reconstruction
  // and the axes' departure from orthonormality (~1e-15) likewise. The margin covers them amply.
  b.half = 0.5 * (hi - lo) + Eigen::Vector3d::Constant(1e-12 * (scale + 1.0));
  return b;
}

// The half-width of a box along L, the one projection kernel of the oriented boxes (the exact
// sweep's and the separated advance's pair bounds, sweep/mesh_sweep.h; the deep zone's queries,
// placement/advance.cpp): for every x within b.pad + pad of the box (the exact L and x; the box's
// axes need not be exactly orthonormal, the half extents hold along the computed ones),
// |L.x - L.c| <= r, and the computed L.c, or L.(c - c') for another box c' with its own r', is
// within the slack of r (+ r') of the exact one. Any rounding mode: L.c and each |L.U_k| are within
// 3u |L|_1 |c|_inf and 3u |L|_1 (|U_k|_inf <= 1 + 1e-15) of their exact values, c - c' within
// u (|c|_inf + |c'|_inf) per coordinate, and the sums within a few ulps; r grows by 1e-12 |L|_1
// (|c|_inf + sum of halves), far above that, and the pads by a relative 1e-12 (their product's and
// the sums' rounding). l1 = |L|_1; mag = obb_magnitude(b).
inline double obb_magnitude(const Obb& b) { return b.center.cwiseAbs().maxCoeff() + b.half.sum(); }
inline double obb_radius(const Obb& b, const Eigen::Vector3d& L, double l1, double mag, double pad = 0.0) {
  double spread = 0.0;
  for (int k = 0; k < 3; ++k) spread += b.half[k] * std::abs(L.dot(b.axes.col(k)));
  return (1.0 + 1e-12) * (spread + (b.pad + pad) * l1) + 1e-12 * l1 * mag + 1e-300;
}
// The projection of the box on the line of L: [lo, hi] holds L.x for every such x (lo and hi are
// within the slack of L.c -+ r).
struct ObbProjection {
  double lo, hi;
};
inline ObbProjection obb_projection(const Obb& b, const Eigen::Vector3d& L, double pad = 0.0) {
  const double r = obb_radius(b, L, L.cwiseAbs().sum(), obb_magnitude(b), pad);
  const double c = L.dot(b.center);
  return {c - r, c + r};
}

// Whether box a and box b, the latter moved by (R, t) (x -> R x + t), may overlap. Conservative:
// false only when a separating axis is proven with a margin above rounding.
inline bool obb_overlap(const Obb& a, const Obb& b, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  // b's axes and centre in a's frame.
  const Eigen::Matrix3d B = a.axes.transpose() * (R * b.axes);
  const Eigen::Vector3d T = a.axes.transpose() * (R * b.center + t - a.center);
  const Eigen::Matrix3d absB = B.cwiseAbs().array() + 1e-12;  // also covers nearly parallel edges
  const Eigen::Vector3d& ea = a.half;
  const Eigen::Vector3d& eb = b.half;
  // Rounding of B and T is ~1e-15 of the magnitudes involved; the slack is a thousand times that.
  // The pads: every axis tested has length at most about 1 (unit axes and their cross products).
  const double slack = 1e-12 * (a.center.cwiseAbs().maxCoeff() + b.center.cwiseAbs().maxCoeff() +
                                t.cwiseAbs().maxCoeff() + ea.maxCoeff() + eb.maxCoeff()) +
                       1.01 * (a.pad + b.pad);
  for (int i = 0; i < 3; ++i)
    if (std::abs(T[i]) > ea[i] + absB.row(i).dot(eb) + slack) return false;
  for (int j = 0; j < 3; ++j)
    if (std::abs(T.dot(B.col(j))) > absB.col(j).dot(ea) + eb[j] + slack) return false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double ra = ea[i1] * absB(i2, j) + ea[i2] * absB(i1, j);
      const double rb = eb[j1] * absB(i, j2) + eb[j2] * absB(i, j1);
      if (std::abs(T[i2] * B(i1, j) - T[i1] * B(i2, j)) > ra + rb + slack) return false;
    }
  return true;
}

}  // namespace cdbench
