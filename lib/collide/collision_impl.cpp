#include "collide/collision_impl.h"

#include "collide/own_trees.h"

namespace cdbench {

std::unique_ptr<CollisionImpl> make_cgal_impl();

#ifdef CDBENCH_WITH_FCL
std::unique_ptr<CollisionImpl> make_fcl_impl(const std::string& name);
#endif
#ifdef CDBENCH_WITH_BULLET
std::unique_ptr<CollisionImpl> make_bullet_impl();
#endif

std::vector<std::string> collision_impl_names(bool include_slow) {
  std::vector<std::string> names{"obb", "aabb", "sphere"};
#ifdef CDBENCH_WITH_FCL
  for (const char* n : {"fcl-obb", "fcl-rss", "fcl-obbrss", "fcl-kios", "fcl-aabb", "fcl-kdop16", "fcl-kdop18",
                        "fcl-kdop24", "fcl-rss-distance", "fcl-obbrss-distance", "fcl-kios-distance"})
    names.emplace_back(n);
#endif
#ifdef CDBENCH_WITH_BULLET
  names.emplace_back("bullet-gimpact");
#endif
  if (include_slow) names.emplace_back("cgal-exact");
  return names;
}

std::unique_ptr<CollisionImpl> make_plugin_impl(const std::string& path);

std::unique_ptr<CollisionImpl> make_collision_impl(const std::string& name) {
  if (name.rfind("plugin:", 0) == 0) return make_plugin_impl(name.substr(7));
  if (name == "obb") return make_own_tree(OwnBv::Obb);
  if (name == "aabb") return make_own_tree(OwnBv::Aabb);
  if (name == "sphere") return make_own_tree(OwnBv::Sphere);
  if (name == "cgal-exact") return make_cgal_impl();
#ifdef CDBENCH_WITH_FCL
  if (auto impl = make_fcl_impl(name)) return impl;
#endif
#ifdef CDBENCH_WITH_BULLET
  if (name == "bullet-gimpact") return make_bullet_impl();
#endif
  return nullptr;
}

}  // namespace cdbench
