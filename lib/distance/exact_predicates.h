#pragma once
// Exact geometric predicates on double input (CGAL's filtered predicates: doubles when the sign is
// certain, exact arithmetic otherwise). Non-template functions so that callers need no CGAL headers.
#include "core/triangle_mesh.h"

namespace cdbench {

// Whether p lies on the closed triangle abc (exact).
bool point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

enum class SegmentCrossing { None, Proper, Degenerate };

// How the segment pq meets triangle abc, for ray parity: Proper = crosses the open triangle
// transversally at one point; Degenerate = touches an edge or vertex, lies in the plane, or q is in
// the plane (try another segment); None = no contact. Assumes p is not on the triangle.
// A zero-area triangle never counts (it bounds no volume).
SegmentCrossing segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace cdbench
