#pragma once
// Larger meshes of the same shape, for measuring how costs grow with the triangle count: Loop
// subdivision (CGAL's Subdivision_method_3). Each step splits every triangle into four and
// smooths the vertices, so a closed 2-manifold stays closed and 2-manifold with the same genus;
// the surface moves slightly (Loop is approximating), so the result is a new mesh to validate,
// not a refinement of the input's geometry.
#include "core/triangle_mesh.h"

namespace cdbench {

// `steps` Loop subdivision steps (faces x 4^steps). The input must be a closed 2-manifold
// triangle mesh (as validate_mesh certifies); throws InputError otherwise.
TriangleMesh loop_subdivide(const TriangleMesh& mesh, int steps);

}  // namespace cdbench
