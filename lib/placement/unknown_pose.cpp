#include "placement/unknown_pose.h"

#include <algorithm>
#include <cmath>

namespace cdbench {

namespace {

// e is at most sqrt(3) times the radius: an eighth of the tolerance keeps it under match_settles'
// quarter. At most 2^-16 of F's largest coordinate, 256 times a single-precision rounding: a
// radius near F's edges (a tolerance of a per cent of the diagonal) would match corners with
// vertices other than their own.
double retry_radius(const SignedDistance& fixed, double tolerance) {
  return std::min(tolerance / 8.0, std::ldexp(fixed.bbox().max_abs(), -16));
}

}  // namespace

UnknownPoseOptions::UnknownPoseOptions(const SignedDistance& fixed, const TriangleMesh& mover, double tolerance,
                                       std::uint64_t max_cells)
    : coincident_(fixed.mesh()),
      coincident_wide_(fixed.mesh(), retry_radius(fixed, tolerance)),
      hull_(hull_planes_for(fixed.mesh())),
      support_(support_planes_for(hull_, mover)) {
  options_.tolerance = tolerance;
  options_.max_cells = max_cells;
  options_.pair_budget = unknown_pose_pair_budget(fixed.mesh(), mover);
  options_.coincident = &coincident_;
  options_.coincident_retry = &coincident_wide_;
  options_.support = support_.get();
  options_.hull = hull_.get();
}

}  // namespace cdbench
