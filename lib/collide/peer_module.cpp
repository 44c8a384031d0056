// The module libcdbench_peers.so (peer_module.h): FCL's and Bullet's implementations by name.
#include "collide/peer_module.h"

namespace cdbench {

#ifdef CDBENCH_WITH_FCL
std::unique_ptr<CollisionImpl> make_fcl_impl(const std::string& name);
#endif
#ifdef CDBENCH_WITH_BULLET
std::unique_ptr<CollisionImpl> make_bullet_impl();
#endif

namespace {

CollisionImpl* make_peer(const char* name) {
  const std::string n = name;
#ifdef CDBENCH_WITH_FCL
  if (auto impl = make_fcl_impl(n)) return impl.release();
#endif
#ifdef CDBENCH_WITH_BULLET
  if (n == "bullet-gimpact") return make_bullet_impl().release();
#endif
  return nullptr;
}

}  // namespace
}  // namespace cdbench

extern "C" __attribute__((visibility("default"))) const cdbench::PeerModule* cdbench_peer_module() {
  static const cdbench::PeerModule module{{cdbench::kPeerModuleAbi, CDBENCH_VERSION}, &cdbench::make_peer};
  return &module;
}
