#pragma once
// One small interface for every static collision implementation under test: built once per pair
// of meshes, then queried per pose of the mover (x_world = R x + t).
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/triangle_mesh.h"

namespace cdbench {

struct QueryAnswer {
  bool collides = false;
  double distance = std::numeric_limits<double>::quiet_NaN();  // when the implementation computes one
  std::uint64_t bv_tests = 0, triangle_tests = 0;
};

class CollisionImpl {
 public:
  virtual ~CollisionImpl() = default;
  virtual std::string name() const = 0;
  // Whether "collides" also covers a mover lying entirely inside the fixed solid (surface-only
  // libraries miss that case; the benchmark reports it separately).
  virtual bool detects_containment() const { return false; }
  // Whether bv_tests / triangle_tests are the implementation's own counts (Bullet exposes none).
  virtual bool counts_tests() const { return true; }
  virtual void build(const TriangleMesh& fixed, const TriangleMesh& mover) = 0;
  virtual QueryAnswer query(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) = 0;
};

// Implementations by name: "obb", "aabb", "sphere" (ours); "fcl-..." when built with FCL;
// "bullet-gimpact" with Bullet; "cgal-exact" (slow: one tree query per mover triangle, so it is
// listed only with include_slow); "plugin:PATH" loads a shared library behind the C ABI of
// include/cdbench/plugin.h (InputError when it cannot be loaded). Returns nullptr for an unknown name.
std::unique_ptr<CollisionImpl> make_collision_impl(const std::string& name);
std::vector<std::string> collision_impl_names(bool include_slow = false);

}  // namespace cdbench
