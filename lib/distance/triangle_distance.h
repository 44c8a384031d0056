#pragma once
// Rigorous enclosure of the distance between two triangles (and two segments), in interval
// arithmetic with outward rounding plus CGAL's exact intersection predicate.
#include "mesh/triangle_mesh.h"
#include "util/interval.h"

namespace cdbench {

// [lo, hi] containing the squared distance between segments p0p1 and q0q1.
Interval segment_segment_squared_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

// [lo, hi] containing the squared distance between the closed triangles abc and def:
// [0, 0] when they intersect (exact test), else the minimum over the 6 vertex-triangle and 9
// edge-edge distances, where the distance of disjoint triangles is always attained.
Interval triangle_triangle_squared_distance(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                            const Vec3& e, const Vec3& f);

}  // namespace cdbench
