#pragma once
// Shared by the placement tests: random rotations and directions, and a scene (a fixed solid, a
// mover, F's sweep mesh) set up for place_pose.
#include <Eigen/Geometry>
#include <random>

#include "placement/place_pose.h"

namespace cdbench::testing {

// A random rotation (normalised random quaternion) and a random unit direction.
// The draws are sequenced (last coordinate first, the order g++ chose for the unsequenced
// arguments these helpers had until session 93): as arguments of one call their order was
// unspecified, and an unrelated edit of a test file changed it, and so every scenario drawn.
inline Eigen::Matrix3d random_rotation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double w = u(rng), z = u(rng), y = u(rng), x = u(rng);
  return Eigen::Quaterniond(Eigen::Vector4d(x, y, z, w).normalized()).toRotationMatrix();
}
inline Vec3 random_direction(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double z = u(rng), y = u(rng), x = u(rng);
  return Vec3(x, y, z).normalized();
}

// A fixed solid, a mover and the fixed surface's sweep mesh (the surface start's contact).
struct Scene {
  SignedDistance fixed;
  TriangleMesh mover;
  ApproachSetup setup;  // points into fixed and mover: a Scene is neither copied nor moved
  SweepMesh surface;
  Scene(const TriangleMesh& f, TriangleMesh m)
      : fixed(f), mover(std::move(m)), setup(make_approach_setup(fixed, mover)),
        surface(make_sweep_mesh(f.vertices, f.faces)) {}
  Scene(const Scene&) = delete;
  // The setup with F's sweep mesh attached (touching poses certified by the sweep).
  ApproachSetup attached() const {
    ApproachSetup s = setup;
    attach_surface_sweep(s, surface);
    return s;
  }
};

}  // namespace cdbench::testing
