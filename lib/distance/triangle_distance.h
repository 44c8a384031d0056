#pragma once
// Rigorous enclosure of the distance between two triangles (and two segments), in interval
// arithmetic with outward rounding plus CGAL's exact intersection predicate.
#include "core/interval.h"
#include "core/triangle_mesh.h"

namespace cdbench {

// [lo, hi] containing the squared distance between segments p0p1 and q0q1.
Interval segment_segment_squared_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

// [lo, hi] containing the squared distance between the closed triangles abc and def:
// [0, 0] when they intersect (exact test), else the minimum over the 6 vertex-triangle and 9
// edge-edge distances, where the distance of disjoint triangles is always attained.
Interval triangle_triangle_squared_distance(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                            const Vec3& e, const Vec3& f);

// Closest points of two triangles in plain doubles (not certified): an estimate of their distance
// and of the direction of the segment joining them, from the 6 vertex-triangle and 9 edge-edge
// pairs. Returns the squared distance estimate; *p on abc, *q on def.
double triangle_triangle_closest_points(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e,
                                        const Vec3& f, Vec3* p, Vec3* q);

// A rigorous lower bound of the distance between triangles abc and def from any direction u:
// the gap between their projections on u (interval arithmetic, rounded down), divided by |u|
// rounded up; 0 when the projections overlap. Exact (up to rounding) when u joins the closest points
// of disjoint triangles, since the slab orthogonal to it separates them.
double triangle_distance_lower_bound(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e,
                                     const Vec3& f, const Vec3& u);

// A rigorous lower bound of the first s >= 0 at which triangles abc and def + s v come within
// distance r of each other (r >= 0), from any direction u (for instance the estimated closest-point
// direction): with g the gap between their projections on u, the distance at s is at least
// (g - s |u.v|) / |u| when def approaches abc along u (projection on a line is 1-Lipschitz and
// moves by s u.v), so it stays above r for s < (g - r |u|) / |u.v|, and for every s when def
// recedes. Returns 0 when the projections are not more than r |u| apart, +inf when def certainly
// recedes along u (interval arithmetic, rounded towards the smaller time). Exact for a vertex
// approaching the interior of a face along u = its normal.
double triangle_reach_time_lower_bound(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e,
                                       const Vec3& f, const Vec3& u, const Vec3& v, double r);

}  // namespace cdbench
