#include "collide/collision_impl.h"

#include <algorithm>

#include "collide/own_trees.h"
#include "collide/peer_module.h"

namespace cdbench {

std::unique_ptr<CollisionImpl> make_cgal_impl();
std::unique_ptr<CollisionImpl> make_plugin_impl(const std::string& path);

namespace {

// The peers this build has (in the module, peer_module.h), known without loading it.
std::vector<std::string> peer_names() {
  std::vector<std::string> names;
#ifdef CDBENCH_WITH_FCL
  for (const char* n : {"fcl-obb", "fcl-rss", "fcl-obbrss", "fcl-kios", "fcl-aabb", "fcl-kdop16", "fcl-kdop18",
                        "fcl-kdop24", "fcl-rss-distance", "fcl-obbrss-distance", "fcl-kios-distance"})
    names.emplace_back(n);
#endif
#ifdef CDBENCH_WITH_BULLET
  names.emplace_back("bullet-gimpact");
#endif
  return names;
}

#if defined(CDBENCH_WITH_FCL) || defined(CDBENCH_WITH_BULLET)
const PeerModule& peer_module() {
  // Once, thread-safe; a failure throws (SetupError, exit 3) and is tried again at the next call.
  static const PeerModule* const module = load_module_as<PeerModule>(
      {kPeerModuleFile, "CDBENCH_PEER_MODULE", "cdbench_peer_module", kPeerModuleAbi, CDBENCH_PEER_MODULE_BUILD,
       "the FCL and Bullet implementations need their module"});
  return *module;
}
#endif

}  // namespace

std::vector<std::string> collision_impl_names(bool include_slow) {
  std::vector<std::string> names{"obb", "aabb", "sphere"};
  for (std::string& n : peer_names()) names.push_back(std::move(n));
  if (include_slow) names.emplace_back("cgal-exact");
  return names;
}

std::unique_ptr<CollisionImpl> make_collision_impl(const std::string& name) {
  if (name.rfind("plugin:", 0) == 0) return make_plugin_impl(name.substr(7));
  if (name == "obb") return make_own_tree(OwnBv::Obb);
  if (name == "aabb") return make_own_tree(OwnBv::Aabb);
  if (name == "sphere") return make_own_tree(OwnBv::Sphere);
  if (name == "cgal-exact") return make_cgal_impl();
#if defined(CDBENCH_WITH_FCL) || defined(CDBENCH_WITH_BULLET)
  const std::vector<std::string> peers = peer_names();
  if (std::find(peers.begin(), peers.end(), name) != peers.end())
    return std::unique_ptr<CollisionImpl>(peer_module().make(name.c_str()));
#endif
  return nullptr;
}

}  // namespace cdbench
