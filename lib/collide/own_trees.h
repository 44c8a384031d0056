#pragma once
// Our reference trees, as in the paper: OBB tree (separating axes), AABB tree (the mover's boxes
// carried into the fixed frame as |R|-enlarged boxes) and sphere tree, all through the one pair
// traversal of bvh/bvh.h with an overlap policy; leaves run CGAL's exact triangle-triangle test on
// the placed triangles. Bounding-volume tests are conservative (margins above rounding), so the
// answer is exact for the placed (double) vertices. A mover not touching the surface is then tested
// for containment (one exact inside test per mover component), so "collides" means: some point of
// the mover's surface lies in the closed fixed solid (clearance <= 0).
#include <memory>
#include <string>

#include "collide/collision_impl.h"

namespace cdbench {

enum class OwnBv { Obb, Aabb, Sphere };
std::unique_ptr<CollisionImpl> make_own_tree(OwnBv bv);

}  // namespace cdbench
