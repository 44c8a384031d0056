#pragma once
// Exact geometric predicates on double input (CGAL's filtered predicates: doubles when the sign is
// certain, exact arithmetic otherwise). Non-template functions so that callers need no CGAL headers.
#include "core/triangle_mesh.h"

namespace cdbench {

// Whether p lies on the closed triangle abc (exact).
bool point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Whether a, b and c lie on one line (exact): a zero-area triangle.
bool corners_collinear(const Vec3& a, const Vec3& b, const Vec3& c);

// Whether the vectors a, b and c are linearly dependent (exact): their determinant is 0.
bool vectors_coplanar(const Vec3& a, const Vec3& b, const Vec3& c);

// The sign of the orientation of d against the triangle abc (exact): +1 when d lies on the side its
// normal (b - a) x (c - a) points to, -1 on the other, 0 in its plane (or abc degenerate).
int orientation_sign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// Whether the closed triangles abc and def share a point (exact). A degenerate triangle (collinear
// corners) is the union of its edges, a segment or a point. The one exact triangle-triangle
// intersection test: certified distances and our collision trees both use it.
bool triangles_intersect(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e, const Vec3& f);

enum class SegmentCrossing { None, Proper, Degenerate };

// How the segment pq meets triangle abc, for ray parity: Proper = crosses the open triangle
// transversally at one point; Degenerate = touches an edge or vertex, lies in the plane, or q is in
// the plane (try another segment); None = no contact. Assumes p is not on the triangle.
// A zero-area triangle never counts (it bounds no volume).
SegmentCrossing segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace cdbench
