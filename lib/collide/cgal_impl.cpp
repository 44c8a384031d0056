// The slow exact reference: CGAL's AABB tree over the fixed triangles (Epick: filtered exact
// predicates), each placed mover triangle tested against it; surface intersection only.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "collide/collision_impl.h"
#include "core/pose_transform.h"

namespace cdbench {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

class CgalImpl final : public CollisionImpl {
 public:
  std::string name() const override { return "cgal-exact"; }
  bool counts_tests() const override { return false; }
  void build(const TriangleMesh& fixed, const TriangleMesh& mover) override {
    triangles_.clear();
    for (const Face& f : fixed.faces) {
      const K::Triangle_3 t(point(fixed.vertices[f[0]]), point(fixed.vertices[f[1]]), point(fixed.vertices[f[2]]));
      if (!t.is_degenerate()) triangles_.push_back(t);  // valid meshes have none
    }
    tree_ = std::make_unique<Tree>(triangles_.begin(), triangles_.end());
    tree_->accelerate_distance_queries();
    mover_ = mover;
  }
  QueryAnswer query(const Eigen::Matrix3d& R, const Vec3& t) override {
    QueryAnswer a;
    std::vector<K::Point_3> p(mover_.vertices.size());
    for (std::size_t i = 0; i < p.size(); ++i) p[i] = point(place_point(R, t, mover_.vertices[i]));
    for (const Face& f : mover_.faces) {
      ++a.triangle_tests;
      const K::Triangle_3 tri(p[f[0]], p[f[1]], p[f[2]]);
      if (!tri.is_degenerate() && tree_->do_intersect(tri)) {
        a.collides = true;
        break;
      }
    }
    return a;
  }

 private:
  static K::Point_3 point(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
  Triangles triangles_;
  std::unique_ptr<Tree> tree_;
  TriangleMesh mover_;
};

}  // namespace

std::unique_ptr<CollisionImpl> make_cgal_impl() { return std::make_unique<CgalImpl>(); }

}  // namespace cdbench
