// FCL 0.7 mesh-mesh collision through its traversal nodes in relative frames (OBB, RSS, kIOS,
// OBBRSS): the models are built once; a query only initialises a node with the two transforms.
// (fcl::collide on BVHModel pairs would copy and rebuild RSS/AABB/KDOP trees per call.)
#include <fcl/fcl.h>

#include "collide/collision_impl.h"
#include "collide/fcl_model.h"

namespace cdbench {
namespace {

// The two models built once, the fixed one at the identity and the mover at (R, t) per query.
template <class BV>
class FclModels : public CollisionImpl {
 public:
  explicit FclModels(std::string name) : name_(std::move(name)) {}
  std::string name() const override { return name_; }
  void build(const TriangleMesh& fixed, const TriangleMesh& mover) override {
    fixed_ = fcl_model<BV>(fixed);
    mover_ = fcl_model<BV>(mover);
  }

 protected:
  static fcl::Transform3<double> pose(const Eigen::Matrix3d& R, const Vec3& t) {
    fcl::Transform3<double> tf = fcl::Transform3<double>::Identity();
    tf.linear() = R;
    tf.translation() = t;
    return tf;
  }
  template <class Node>
  static void count(const Node& node, QueryAnswer& a) {
    a.bv_tests = static_cast<std::uint64_t>(node.num_bv_tests);
    a.triangle_tests = static_cast<std::uint64_t>(node.num_leaf_tests);
  }
  std::string name_;
  std::shared_ptr<fcl::BVHModel<BV>> fixed_, mover_;
};

// Collision through a relative-frame traversal node. Const models select the relative-frame
// overloads of initialize (the generic one transforms and refits copies).
template <class BV, class Node>
class FclImpl final : public FclModels<BV> {
 public:
  using FclModels<BV>::FclModels;
  QueryAnswer query(const Eigen::Matrix3d& R, const Vec3& t) override {
    const fcl::Transform3<double> tf1 = fcl::Transform3<double>::Identity(), tf2 = this->pose(R, t);
    fcl::CollisionRequest<double> request;  // one contact: stop at the first
    fcl::CollisionResult<double> result;
    Node node;
    node.enable_statistics = true;
    const fcl::BVHModel<BV>& m1 = *this->fixed_;
    const fcl::BVHModel<BV>& m2 = *this->mover_;
    fcl::detail::initialize(node, m1, tf1, m2, tf2, request, result);
    fcl::detail::collide<double>(&node, nullptr);
    QueryAnswer a;
    a.collides = result.isCollision();
    this->count(node, a);
    return a;
  }
};

// The same models through FCL's distance traversal: collides when the distance is <= 0. FCL's
// meshes are surfaces: penetrating meshes get distance 0, a mover inside the solid a positive one.
template <class BV, class Node>
class FclDistanceImpl final : public FclModels<BV> {
 public:
  using FclModels<BV>::FclModels;
  QueryAnswer query(const Eigen::Matrix3d& R, const Vec3& t) override {
    const fcl::Transform3<double> tf1 = fcl::Transform3<double>::Identity(), tf2 = this->pose(R, t);
    fcl::DistanceRequest<double> request;
    fcl::DistanceResult<double> result;
    Node node;
    node.enable_statistics = true;
    const fcl::BVHModel<BV>& m1 = *this->fixed_;
    const fcl::BVHModel<BV>& m2 = *this->mover_;
    fcl::detail::initialize(node, m1, tf1, m2, tf2, request, result);
    fcl::detail::distance<double>(&node, nullptr, 2);
    QueryAnswer a;
    a.distance = result.min_distance;
    a.collides = result.min_distance <= 0.0;
    this->count(node, a);
    return a;
  }
};

// BVs without a relative-frame traversal in FCL (AABB, k-DOPs): FCL's way is to transform the
// mover's vertices into the fixed frame and refit its tree for every pose (what fcl::collide does,
// after copying the models). We replace the vertices of one kept model and refit bottom-up; the
// timed query includes that refit, since it is these BVs' cost of a static query in FCL.
template <class BV>
class FclRefitImpl final : public FclModels<BV> {
 public:
  using FclModels<BV>::FclModels;
  void build(const TriangleMesh& fixed, const TriangleMesh& mover) override {
    FclModels<BV>::build(fixed, mover);
    local_.assign(mover.vertices.begin(), mover.vertices.end());
    placed_.resize(local_.size());
  }
  QueryAnswer query(const Eigen::Matrix3d& R, const Vec3& t) override {
    for (std::size_t i = 0; i < local_.size(); ++i) placed_[i] = R * local_[i] + t;
    this->mover_->beginReplaceModel();
    this->mover_->replaceSubModel(placed_);
    this->mover_->endReplaceModel(true, true);
    fcl::Transform3<double> tf1 = fcl::Transform3<double>::Identity(), tf2 = tf1;
    fcl::CollisionRequest<double> request;
    fcl::CollisionResult<double> result;
    fcl::detail::MeshCollisionTraversalNode<BV> node;
    node.enable_statistics = true;
    fcl::detail::initialize(node, *this->fixed_, tf1, *this->mover_, tf2, request, result);  // identity: no copy
    fcl::detail::collide<double>(&node, nullptr);
    QueryAnswer a;
    a.collides = result.isCollision();
    this->count(node, a);
    return a;
  }

 private:
  std::vector<fcl::Vector3<double>> local_, placed_;
};

}  // namespace

std::unique_ptr<CollisionImpl> make_fcl_impl(const std::string& name) {
  using S = double;
  if (name == "fcl-obb") return std::make_unique<FclImpl<fcl::OBB<S>, fcl::detail::MeshCollisionTraversalNodeOBB<S>>>(name);
  if (name == "fcl-rss") return std::make_unique<FclImpl<fcl::RSS<S>, fcl::detail::MeshCollisionTraversalNodeRSS<S>>>(name);
  if (name == "fcl-kios") return std::make_unique<FclImpl<fcl::kIOS<S>, fcl::detail::MeshCollisionTraversalNodekIOS<S>>>(name);
  if (name == "fcl-obbrss")
    return std::make_unique<FclImpl<fcl::OBBRSS<S>, fcl::detail::MeshCollisionTraversalNodeOBBRSS<S>>>(name);
  if (name == "fcl-aabb") return std::make_unique<FclRefitImpl<fcl::AABB<S>>>(name);
  if (name == "fcl-kdop16") return std::make_unique<FclRefitImpl<fcl::KDOP<S, 16>>>(name);
  if (name == "fcl-kdop18") return std::make_unique<FclRefitImpl<fcl::KDOP<S, 18>>>(name);
  if (name == "fcl-kdop24") return std::make_unique<FclRefitImpl<fcl::KDOP<S, 24>>>(name);
  if (name == "fcl-rss-distance")
    return std::make_unique<FclDistanceImpl<fcl::RSS<S>, fcl::detail::MeshDistanceTraversalNodeRSS<S>>>(name);
  if (name == "fcl-obbrss-distance")
    return std::make_unique<FclDistanceImpl<fcl::OBBRSS<S>, fcl::detail::MeshDistanceTraversalNodeOBBRSS<S>>>(name);
  if (name == "fcl-kios-distance")
    return std::make_unique<FclDistanceImpl<fcl::kIOS<S>, fcl::detail::MeshDistanceTraversalNodekIOS<S>>>(name);
  return nullptr;
}

}  // namespace cdbench
