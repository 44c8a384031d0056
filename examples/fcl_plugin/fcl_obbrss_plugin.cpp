// A cdbench plugin wrapping FCL's mesh-mesh collision with OBBRSS trees, through the C ABI of
// cdbench/plugin.h only: build it outside cdbench, then
//   cdbench bench POSESET --impl plugin:/path/to/libcdbench_fcl_obbrss.so -o DIR
// Its verdicts equal cdbench's built-in fcl-obbrss (the same BV and traversal).
#include <cdbench/plugin.h>
#include <fcl/fcl.h>

#include <cstdio>
#include <exception>
#include <memory>
#include <vector>

namespace {

using Model = fcl::BVHModel<fcl::OBBRSS<double>>;

struct State {
  std::shared_ptr<Model> fixed, mover;
};

std::shared_ptr<Model> model(const cdbench_mesh* m) {
  std::vector<fcl::Vector3<double>> v(m->vertex_count);
  for (size_t i = 0; i < m->vertex_count; ++i) v[i] = {m->vertices[3 * i], m->vertices[3 * i + 1], m->vertices[3 * i + 2]};
  std::vector<fcl::Triangle> t(m->triangle_count);
  for (size_t i = 0; i < m->triangle_count; ++i) t[i] = {m->triangles[3 * i], m->triangles[3 * i + 1], m->triangles[3 * i + 2]};
  auto out = std::make_shared<Model>();
  out->beginModel();
  out->addSubModel(v, t);
  out->endModel();
  return out;
}

void* create(const cdbench_mesh* fixed, const cdbench_mesh* mover, char* error, size_t error_size) {
  try {
    return new State{model(fixed), model(mover)};
  } catch (const std::exception& e) {
    std::snprintf(error, error_size, "FCL model: %s", e.what());
    return nullptr;
  }
}

int query(void* state, const double R[9], const double t[3], cdbench_answer* answer) {
  const State& s = *static_cast<const State*>(state);
  fcl::Transform3<double> tf2 = fcl::Transform3<double>::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) tf2.linear()(i, j) = R[3 * i + j];
    tf2.translation()[i] = t[i];
  }
  const fcl::Transform3<double> tf1 = fcl::Transform3<double>::Identity();
  fcl::CollisionRequest<double> request;  // stop at the first contact
  fcl::CollisionResult<double> result;
  fcl::detail::MeshCollisionTraversalNodeOBBRSS<double> node;
  node.enable_statistics = true;
  const Model& m1 = *s.fixed;
  const Model& m2 = *s.mover;
  if (!fcl::detail::initialize(node, m1, tf1, m2, tf2, request, result)) return 1;
  fcl::detail::collide<double>(&node, nullptr);
  answer->collides = result.isCollision();
  answer->bv_tests = static_cast<uint64_t>(node.num_bv_tests);
  answer->triangle_tests = static_cast<uint64_t>(node.num_leaf_tests);
  return 0;
}

void destroy(void* state) { delete static_cast<State*>(state); }

const cdbench_plugin kPlugin = {CDBENCH_PLUGIN_ABI_VERSION, "fcl-obbrss-plugin", CDBENCH_PLUGIN_COUNTS_TESTS, create,
                                query, destroy};

}  // namespace

extern "C" const cdbench_plugin* cdbench_plugin_entry(void) { return &kPlugin; }
