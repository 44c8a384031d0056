#pragma once
// The mover in one orientation: rotated vertices, an AABB tree and a sphere tree over them, and
// the bound on the rounding of R x + t. A pose is x_world = R x + t (R, t stored doubles); our
// placed vertices are fl(fl(R x) + t), one IEEE-double evaluation of it. Any IEEE-double
// evaluation of a 4-term sum of products differs from the exact value by at most
// gamma_4 * sum |terms| per coordinate (gamma_n = n u / (1 - n u), u = 2^-53; with or without
// FMA, in any order), which transform_error() bounds.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "bvh/bvh.h"
#include "bvh/sphere.h"
#include "core/aabb.h"
#include "core/pose_transform.h"
#include "core/triangle_mesh.h"

namespace cdbench {

struct MoverOrientation {
  Eigen::Matrix3d R;             // the stored rotation (row-major in files)
  std::vector<Vec3> rotated;     // fl(R x) per vertex
  const std::vector<Face>* faces = nullptr;
  Bvh<Aabb> boxes;               // over `rotated` (a pose adds t: box [fl(lo + t), fl(hi + t)] covers it)
  Vec3 abs_max = Vec3::Zero();   // max over vertices of |R| |x| per coordinate

  // fl(rotated + t): the placed vertices of the pose (R, t).
  std::vector<Vec3> placed(const Vec3& t) const;
  PlacedView placed_view(const Vec3& t) const { return PlacedView{&rotated, t}; }
  // Euclidean bound on |fl-evaluated R x + t - exact R x + t| for any vertex and any evaluation.
  double transform_error(const Vec3& t) const;

  // The shift from another pose `from` of this orientation (SweepTrees::mover_t, whose volumes hold
  // the vertices placed there) to t: D = t - from as computed, and a pad with every placed vertex
  // fl(r + t) within it of fl(r + from) + D. Each placed vertex is within the transform's bound of
  // r + t (r + from), and the computed D within 2u |t - from| per coordinate of the exact
  // difference (any rounding mode); the factor covers the pad's own rounding.
  struct Shift {
    Vec3 D;
    double pad;
  };
  Shift shift_from(const Vec3& from, const Vec3& t) const;
};

MoverOrientation make_mover_orientation(const TriangleMesh& mover, const Eigen::Matrix3d& R);
// The same in two steps (rotated vertices first, then the box tree), for callers that build other
// trees from the rotated vertices at the same time (or refit a tree of their own shape instead:
// make_orientation_frame).
MoverOrientation rotate_mover(const TriangleMesh& mover, const Eigen::Matrix3d& R);
void build_mover_boxes(MoverOrientation& o);

}  // namespace cdbench
