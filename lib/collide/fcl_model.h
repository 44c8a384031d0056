#pragma once
// A mesh as an FCL 0.7 BVHModel of any bounding volume (only for translation units built with FCL).
#include <fcl/fcl.h>

#include <memory>
#include <vector>

#include "core/triangle_mesh.h"

namespace cdbench {

template <class BV>
std::shared_ptr<fcl::BVHModel<BV>> fcl_model(const TriangleMesh& m) {
  auto model = std::make_shared<fcl::BVHModel<BV>>();
  std::vector<fcl::Vector3<double>> v(m.vertices.begin(), m.vertices.end());
  std::vector<fcl::Triangle> t;
  t.reserve(m.faces.size());
  for (const Face& f : m.faces) t.emplace_back(f[0], f[1], f[2]);
  model->beginModel();
  model->addSubModel(v, t);
  model->endModel();
  return model;
}

}  // namespace cdbench
