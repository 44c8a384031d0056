#pragma once
// Rigorous enclosure of the distance between a point and a triangle, in interval arithmetic with
// outward rounding (CGAL::Interval_nt). See doc/distance.md for the case analysis.
#include "mesh/triangle_mesh.h"
#include "util/interval.h"

namespace cdbench {

// [lo, hi] containing the exact squared Euclidean distance from p to the closed triangle abc
// (a degenerate triangle is treated as the union of its edges).
Interval point_triangle_squared_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// [sqrt(lo), sqrt(hi)] rounded outward.
Interval sqrt_interval(const Interval& squared);

}  // namespace cdbench

namespace cdbench {

// Closest point of triangle abc to p in plain doubles (Ericson's region test). NOT certified:
// used only to choose heuristic weights, never as a bound.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace cdbench
