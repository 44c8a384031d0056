#pragma once
// FCL's and Bullet's implementations (fcl_impls.cpp, bullet_impl.cpp) as a module,
// libcdbench_peers.so, that make_collision_impl loads when it is first asked for one of them
// (util/module_loader.h). Why apart: linked into the program, FCL (with liboctomap and libccd) and
// Bullet cost every command about 12 ms of dynamic linking before main (doc/build.md), serial time
// on every thread count, though only `cdbench bench` uses them; and a consumer of cdbench::collide
// then needs neither library to link.
#include "collide/collision_impl.h"
#include "util/module_loader.h"

namespace cdbench {

// Bumped whenever PeerModule or CollisionImpl change.
constexpr int kPeerModuleAbi = 1;

struct PeerModule {
  ModuleHeader header;  // kPeerModuleAbi, the cdbench version it was built with
  // A new implementation by name ("fcl-obbrss", "bullet-gimpact", ...), owned by the caller;
  // nullptr for a name the module does not know. May throw.
  CollisionImpl* (*make)(const char* name);
};

constexpr const char* kPeerModuleFile = "libcdbench_peers.so";

}  // namespace cdbench

// The module's one exported symbol.
extern "C" const cdbench::PeerModule* cdbench_peer_module();
