#pragma once
// How `cdbench certify` and `cdbench validate` certify poses of unknown status (a user's poses,
// any tool's): one setup for both, so that the two commands' certificates agree.
#include <cstdint>
#include <memory>

#include "core/triangle_mesh.h"
#include "distance/signed_distance.h"
#include "distance/support_planes.h"
#include "placement/clearance.h"
#include "placement/coincident_faces.h"

namespace cdbench {

// ClearanceOptions for such poses, with what they point into: the pair-distance path within
// unknown_pose_pair_budget (doc/validate-your-library.md, "Widths"); F's faces indexed for mover
// faces placed onto them, exactly or up to rounding, and, for a pose whose search ends short,
// within an eighth of the tolerance or 2^-16 of F's largest coordinate, whichever is less (built
// only then); F's supporting planes, and a convex F's planes tried first for penetrating poses.
// All speed only. Not copyable: `options` points into it.
class UnknownPoseOptions {
 public:
  UnknownPoseOptions(const SignedDistance& fixed, const TriangleMesh& mover, double tolerance, std::uint64_t max_cells);
  UnknownPoseOptions(const UnknownPoseOptions&) = delete;
  UnknownPoseOptions& operator=(const UnknownPoseOptions&) = delete;
  // Copied per pose, where hints and sweep trees are added.
  const ClearanceOptions& options() const { return options_; }

 private:
  CoincidentFaces coincident_;
  LazyCoincidentFaces coincident_wide_;
  std::shared_ptr<const SupportPlanes> hull_, support_;
  ClearanceOptions options_;
};

}  // namespace cdbench
