#pragma once
// Connected components of a triangle mesh (faces sharing vertices).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/triangle_mesh.h"

namespace cdbench {

// One vertex index per connected component, the least of each, ascending; vertices no face uses
// belong to none. (The side tests of a clearance or a collision query need one point per
// component of the mover.)
std::vector<std::uint32_t> component_representatives(const TriangleMesh& mesh);

// Each face's component (0, 1, ... in the order of component_representatives); `count` (if
// given) receives the number of components.
std::vector<std::uint32_t> face_components(const TriangleMesh& mesh, std::size_t* count = nullptr);

}  // namespace cdbench
