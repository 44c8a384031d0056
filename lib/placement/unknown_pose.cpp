#include "placement/unknown_pose.h"

namespace cdbench {

UnknownPoseOptions::UnknownPoseOptions(const SignedDistance& fixed, const TriangleMesh& mover, double tolerance,
                                       std::uint64_t max_cells)
    : coincident_(fixed.mesh()),
      // e is at most sqrt(3) times the radius: an eighth keeps it under match_settles' quarter.
      coincident_wide_(fixed.mesh(), tolerance / 8.0),
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
