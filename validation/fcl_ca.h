#pragma once
// FCL's translational conservative advancement on one approach of a pose set, as bench_poses and
// fcl_poses run it: fcl::detail::conservativeAdvancementMeshOriented (OBBRSS, TranslationMotion)
// of the mover from the far start (lambda = far) to the mirrored far end (lambda = -far).
#include <fcl/fcl.h>
#include <fcl/narrowphase/detail/conservative_advancement_func_matrix.h>

#include "placement/place_pose.h"
#include "util/timer.h"

namespace cdbench {

// True when FCL reports a contact; then *lambda is its pose along dir (t = t0 + lambda dir).
// *seconds receives the time of the conservative-advancement call alone.
inline bool fcl_ca_contact(const fcl::BVHModel<fcl::OBBRSS<double>>& fixed, const fcl::BVHModel<fcl::OBBRSS<double>>& mover,
                           const OrientationFrame& frame, const Vec3& dir, double far, double* lambda, double* seconds) {
  fcl::Transform3<double> start = fcl::Transform3<double>::Identity(), end = start, id = start;
  start.linear() = frame.orientation.R;
  end.linear() = frame.orientation.R;
  start.translation() = pose_translation(frame, dir, far);
  end.translation() = pose_translation(frame, dir, -far);
  fcl::TranslationMotion<double> m1(id, id), m2(start, end);
  fcl::CollisionRequest<double> request;
  fcl::CollisionResult<double> result;
  double toc = 1.0;
  const Timer timer;
  const bool hit = fcl::detail::conservativeAdvancementMeshOriented<
      fcl::OBBRSS<double>, fcl::detail::MeshConservativeAdvancementTraversalNodeOBBRSS<double>>(fixed, &m1, mover, &m2,
                                                                                                 request, result, toc);
  *seconds = timer.seconds();
  *lambda = far - toc * 2 * far;
  return hit;
}

}  // namespace cdbench
