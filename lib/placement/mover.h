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

#include "bvh/aabb.h"
#include "bvh/bvh.h"
#include "bvh/sphere.h"
#include "mesh/triangle_mesh.h"

namespace cdbench {

// fl(R x), in the fixed order ((r0 x0 + r1 x1) + r2 x2) per coordinate.
inline Vec3 rotate_point(const Eigen::Matrix3d& R, const Vec3& x) {
  Vec3 y;
  for (int i = 0; i < 3; ++i) y[i] = R(i, 0) * x[0] + R(i, 1) * x[1] + R(i, 2) * x[2];
  return y;
}

// fl(fl(R x) + t): how every placed vertex is evaluated (poses, clearances, collision queries).
inline Vec3 place_point(const Eigen::Matrix3d& R, const Vec3& t, const Vec3& x) {
  const Vec3 r = rotate_point(R, x);
  return Vec3(r[0] + t[0], r[1] + t[1], r[2] + t[2]);
}

// The placed vertices fl(rotated[k] + t) of one pose, each computed when read, exactly as
// MoverOrientation::placed computes it: a certificate reads only the vertices near the contact,
// so it need not place all of them (O(n) per certificate on large movers).
struct PlacedView {
  const std::vector<Vec3>* rotated = nullptr;
  Vec3 t = Vec3::Zero();
  Vec3 operator[](std::size_t k) const {
    const Vec3& r = (*rotated)[k];
    return Vec3(r[0] + t[0], r[1] + t[1], r[2] + t[2]);
  }
};

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
};

MoverOrientation make_mover_orientation(const TriangleMesh& mover, const Eigen::Matrix3d& R);
// The same in two steps (rotated vertices first, then the box tree), for callers that build other
// trees from the rotated vertices at the same time.
MoverOrientation rotate_mover(const TriangleMesh& mover, const Eigen::Matrix3d& R);
void build_mover_boxes(MoverOrientation& o);

// One vertex index per connected component (faces sharing vertices) of a mesh, ascending.
std::vector<std::uint32_t> component_representatives(const TriangleMesh& mesh);

}  // namespace cdbench
