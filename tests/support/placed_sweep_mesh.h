#pragma once
// A mesh's sweep structure at a pose (R x + t for every vertex), shared by the sweep tests.
#include <Eigen/Core>
#include <vector>

#include "sweep/mesh_sweep.h"

namespace cdbench::test {

inline SweepMesh placed(const TriangleMesh& m, const Eigen::Matrix3d& R, const Vec3& t) {
  std::vector<Vec3> v;
  for (const Vec3& p : m.vertices) v.push_back(R * p + t);
  return make_sweep_mesh(v, m.faces);
}

}  // namespace cdbench::test
