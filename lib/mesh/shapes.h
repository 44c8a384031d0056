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

// Thick-walled tube around the z axis, z in [0, length]: inner and outer n-gons of circumradii
// r_in < r_out with vertices at the same angles (a faceted pipe), annular ends; outward.
TriangleMesh make_tube(double r_in, double r_out, double length, int n);

// Solid faceted cylinder around the z axis, z in [0, length]: an n-gon of circumradius r, each end
// a fan from its first vertex (slivers, as CAD exports triangulate planar faces); outward.
TriangleMesh make_cylinder(double r, double length, int n);

// Concatenation of meshes (several components).
TriangleMesh merge_meshes(const TriangleMesh& a, const TriangleMesh& b);

}  // namespace cdbench
