#include "collide/own_trees.h"

#include <cmath>

#include "bvh/bvh.h"
#include "bvh/obb.h"
#include "bvh/sphere.h"
#include "core/aabb.h"
#include "core/pose_transform.h"
#include "distance/exact_predicates.h"
#include "distance/signed_distance.h"
#include "mesh/components.h"

namespace cdbench {
namespace {

// Overlap of a fixed-frame volume with a mover volume moved by (R, t); conservative.
inline bool overlap(const Obb& a, const Obb& b, const Eigen::Matrix3d& R, const Vec3& t) { return obb_overlap(a, b, R, t); }
inline bool overlap(const Aabb& a, const Aabb& b, const Eigen::Matrix3d& R, const Vec3& t) {
  const Vec3 c = R * b.center() + t;
  const Vec3 h = R.cwiseAbs() * (0.5 * b.extent());
  const double slack = 1e-12 * (c.cwiseAbs().maxCoeff() + t.cwiseAbs().maxCoeff() + h.maxCoeff() +
                                a.lo.cwiseAbs().maxCoeff() + a.hi.cwiseAbs().maxCoeff());
  for (int k = 0; k < 3; ++k)
    if (c[k] - h[k] > a.hi[k] + slack || c[k] + h[k] < a.lo[k] - slack) return false;
  return true;
}
inline bool overlap(const Sphere& a, const Sphere& b, const Eigen::Matrix3d& R, const Vec3& t) {
  const Vec3 c = R * b.center + t;
  const double slack = 1e-12 * (c.cwiseAbs().maxCoeff() + t.cwiseAbs().maxCoeff() + a.center.cwiseAbs().maxCoeff() +
                                a.radius + b.radius);
  return (c - a.center).norm() <= a.radius + b.radius + slack;
}
inline double size_of(const Obb& b) { return b.half.squaredNorm(); }
inline double size_of(const Aabb& b) { return b.extent().squaredNorm(); }
inline double size_of(const Sphere& b) { return b.radius; }

// The tree of a mesh with one kind of volume per BV.
template <class BV>
Bvh<BV> build_tree(const TriangleMesh& m);
template <>
Bvh<Obb> build_tree<Obb>(const TriangleMesh& m) {
  return build_triangle_bvh<Obb>(m.vertices, m.faces, [](int n, const auto& p) { return fit_obb(n, p); });
}
template <>
Bvh<Aabb> build_tree<Aabb>(const TriangleMesh& m) {
  return build_triangle_bvh<Aabb>(m.vertices, m.faces, [](int n, const auto& p) { return bounding_box(n, p); });
}
template <>
Bvh<Sphere> build_tree<Sphere>(const TriangleMesh& m) {
  return build_triangle_bvh<Sphere>(m.vertices, m.faces, [](int n, const auto& p) { return bounding_sphere(n, p); });
}

template <class BV>
struct OverlapPolicy {
  const TriangleMesh& fixed;
  const TriangleMesh& mover;
  const Eigen::Matrix3d& R;
  const Vec3& t;
  QueryAnswer& answer;

  double bound(const BV& a, const BV& b) {
    ++answer.bv_tests;
    return overlap(a, b, R, t) ? 0.0 : std::numeric_limits<double>::infinity();
  }
  double prune_bound() const { return 0.0; }
  bool split_first(const BV& a, const BV& b) const { return size_of(a) >= size_of(b); }
  void leaf(std::uint32_t fi, std::uint32_t mi) {
    ++answer.triangle_tests;
    const Face& f = fixed.faces[fi];
    const Face& m = mover.faces[mi];
    const auto place = [&](const Vec3& x) { return place_point(R, t, x); };
    if (triangles_intersect(fixed.vertices[f[0]], fixed.vertices[f[1]], fixed.vertices[f[2]], place(mover.vertices[m[0]]),
                            place(mover.vertices[m[1]]), place(mover.vertices[m[2]])))
      answer.collides = true;
  }
  bool done() const { return answer.collides; }
};

template <class BV>
class OwnTree final : public CollisionImpl {
 public:
  explicit OwnTree(std::string name) : name_(std::move(name)) {}
  std::string name() const override { return name_; }
  bool detects_containment() const override { return true; }
  void build(const TriangleMesh& fixed, const TriangleMesh& mover) override {
    fixed_ = fixed;
    mover_ = mover;
    tf_ = build_tree<BV>(fixed_);
    tm_ = build_tree<BV>(mover_);
    sdf_ = std::make_unique<SignedDistance>(fixed_);
    components_ = component_representatives(mover_);
  }
  QueryAnswer query(const Eigen::Matrix3d& R, const Vec3& t) override {
    QueryAnswer a;
    OverlapPolicy<BV> policy{fixed_, mover_, R, t, a};
    traverse_pairs_nearest_first(tf_, tm_, policy);
    if (!a.collides)
      for (std::uint32_t v : components_) {
        if (sdf_->side(place_point(R, t, mover_.vertices[v])) <= 0) {
          a.collides = true;
          break;
        }
      }
    return a;
  }

 private:
  std::string name_;
  TriangleMesh fixed_, mover_;
  Bvh<BV> tf_, tm_;
  std::unique_ptr<SignedDistance> sdf_;
  std::vector<std::uint32_t> components_;
};

}  // namespace

std::unique_ptr<CollisionImpl> make_own_tree(OwnBv bv) {
  switch (bv) {
    case OwnBv::Obb: return std::make_unique<OwnTree<Obb>>("obb");
    case OwnBv::Aabb: return std::make_unique<OwnTree<Aabb>>("aabb");
    case OwnBv::Sphere: return std::make_unique<OwnTree<Sphere>>("sphere");
  }
  return nullptr;
}

}  // namespace cdbench
