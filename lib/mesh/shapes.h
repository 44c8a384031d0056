#pragma once
// Small closed test meshes generated exactly from parameters (used by tests and data/).
#include "core/triangle_mesh.h"

namespace cdbench {

// Icosahedron subdivided `subdivisions` times, vertices projected onto the sphere (outward).
TriangleMesh make_icosphere(double radius, int subdivisions, const Vec3& center = Vec3::Zero());

// Torus around the z axis: major radius R, tube radius r, nu segments around z, nv around the tube.
TriangleMesh make_torus(double major_radius, double minor_radius, int nu, int nv);

// Axis-aligned box, 12 triangles, outward.
TriangleMesh make_box(const Vec3& lo, const Vec3& hi);

// Concatenation of meshes (several components).
TriangleMesh merge_meshes(const TriangleMesh& a, const TriangleMesh& b);

}  // namespace cdbench
