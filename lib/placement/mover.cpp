#include "placement/mover.h"

#include <cmath>

#include "core/interval.h"

namespace cdbench {

MoverOrientation make_mover_orientation(const TriangleMesh& mover, const Eigen::Matrix3d& R) {
  MoverOrientation o = rotate_mover(mover, R);
  build_mover_boxes(o);
  return o;
}

MoverOrientation rotate_mover(const TriangleMesh& mover, const Eigen::Matrix3d& R) {
  MoverOrientation o;
  o.R = R;
  o.faces = &mover.faces;
  o.rotated.resize(mover.vertices.size());
  const Eigen::Matrix3d absR = R.cwiseAbs();
  for (std::size_t k = 0; k < mover.vertices.size(); ++k) {
    const Vec3& x = mover.vertices[k];
    o.rotated[k] = rotate_point(R, x);
    o.abs_max = o.abs_max.cwiseMax(absR * x.cwiseAbs());
  }
  return o;
}

void build_mover_boxes(MoverOrientation& o) {
  o.boxes = build_triangle_bvh<Aabb>(o.rotated, *o.faces, [](int n, const auto& p) { return bounding_box(n, p); });
}

std::vector<Vec3> MoverOrientation::placed(const Vec3& t) const {
  std::vector<Vec3> p(rotated.size());
  for (std::size_t k = 0; k < rotated.size(); ++k) p[k] = Vec3(rotated[k][0] + t[0], rotated[k][1] + t[1], rotated[k][2] + t[2]);
  return p;
}

double MoverOrientation::transform_error(const Vec3& t) const {
  constexpr double u = 0x1p-53;
  constexpr double gamma4 = 4 * u / (1 - 4 * u);
  // abs_max is itself a double evaluation (relative error << 1e-12); the factor covers it.
  const Vec3 e = gamma4 * (abs_max + t.cwiseAbs()) * (1.0 + 1e-10);
  return round_up(e.norm() * (1.0 + 1e-12));
}

MoverOrientation::Shift MoverOrientation::shift_from(const Vec3& from, const Vec3& t) const {
  const Vec3 D(t[0] - from[0], t[1] - from[1], t[2] - from[2]);
  return {D, round_up((transform_error(t) + transform_error(from)) * (1.0 + 1e-12) + 1e-15 * D.cwiseAbs().sum())};
}

}  // namespace cdbench
