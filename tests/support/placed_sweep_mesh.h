#pragma once
// A mesh's sweep structure at a pose, its vertices placed as every module places them
// (place_point: fl(fl(R x) + t)), shared by the sweep tests.
#include <Eigen/Core>
#include <vector>

#include "core/pose_transform.h"
#include "sweep/mesh_sweep.h"

namespace cdbench::test {

inline SweepMesh placed(const TriangleMesh& m, const Eigen::Matrix3d& R, const Vec3& t) {
  std::vector<Vec3> v;
  v.reserve(m.vertices.size());
  for (const Vec3& p : m.vertices) v.push_back(place_point(R, t, p));
  return make_sweep_mesh(v, m.faces);
}

}  // namespace cdbench::test
