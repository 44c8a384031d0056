// Bullet 3.24 (double precision) GImpact mesh-mesh: both meshes as btGImpactMeshShape (margin 0),
// queried with contactPairTest. GImpact computes all contacts (no early exit); surface-only.
#include <btBulletCollisionCommon.h>
#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>

#include "collide/collision_impl.h"

namespace cdbench {
namespace {

struct BulletMesh {
  std::vector<btScalar> xyz;
  std::vector<int> idx;
  std::unique_ptr<btTriangleIndexVertexArray> array;
  std::unique_ptr<btGImpactMeshShape> shape;
  btCollisionObject object;

  explicit BulletMesh(const TriangleMesh& m) {
    for (const Vec3& p : m.vertices)
      for (int k = 0; k < 3; ++k) xyz.push_back(p[k]);
    for (const Face& f : m.faces)
      for (int k = 0; k < 3; ++k) idx.push_back(static_cast<int>(f[k]));
    array = std::make_unique<btTriangleIndexVertexArray>(static_cast<int>(m.faces.size()), idx.data(), 3 * sizeof(int),
                                                         static_cast<int>(m.vertices.size()), xyz.data(),
                                                         3 * sizeof(btScalar));
    shape = std::make_unique<btGImpactMeshShape>(array.get());
    shape->setMargin(0);
    shape->updateBound();
    object.setCollisionShape(shape.get());
  }
};

struct AnyContact : btCollisionWorld::ContactResultCallback {
  bool hit = false;
  std::uint64_t contacts = 0;
  btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper*, int, int, const btCollisionObjectWrapper*,
                           int, int) override {
    ++contacts;
    if (cp.getDistance() <= 0) hit = true;
    return 0;
  }
};

class BulletImpl final : public CollisionImpl {
 public:
  std::string name() const override { return "bullet-gimpact"; }
  bool counts_tests() const override { return false; }
  void build(const TriangleMesh& fixed, const TriangleMesh& mover) override {
    config_ = std::make_unique<btDefaultCollisionConfiguration>();
    dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
    btGImpactCollisionAlgorithm::registerAlgorithm(dispatcher_.get());
    // contactPairTest looks in the closest-points table: without this it silently reports nothing.
    static btGImpactCollisionAlgorithm::CreateFunc create;
    dispatcher_->registerClosestPointsCreateFunc(GIMPACT_SHAPE_PROXYTYPE, GIMPACT_SHAPE_PROXYTYPE, &create);
    broadphase_ = std::make_unique<btDbvtBroadphase>();
    world_ = std::make_unique<btCollisionWorld>(dispatcher_.get(), broadphase_.get(), config_.get());
    fixed_ = std::make_unique<BulletMesh>(fixed);
    mover_ = std::make_unique<BulletMesh>(mover);
  }
  QueryAnswer query(const Eigen::Matrix3d& R, const Vec3& t) override {
    btMatrix3x3 basis(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2));
    mover_->object.setWorldTransform(btTransform(basis, btVector3(t.x(), t.y(), t.z())));
    AnyContact cb;
    world_->contactPairTest(&fixed_->object, &mover_->object, cb);
    QueryAnswer a;
    a.collides = cb.hit;
    (void)cb.contacts;
    return a;
  }

 private:
  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<btCollisionWorld> world_;
  std::unique_ptr<BulletMesh> fixed_, mover_;
};

}  // namespace

std::unique_ptr<CollisionImpl> make_bullet_impl() { return std::make_unique<BulletImpl>(); }

}  // namespace cdbench
