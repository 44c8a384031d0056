#pragma once
// Upper bound of the unsigned distance to F over a convex cell given by its corners, from the
// convexity of the triangle distances d_j (certification-math note 2): for weights lambda_j >= 0,
// dist(x, F) <= sum_j lambda_j d_j(x) / sum_j lambda_j, and the right side is convex, so its maximum
// over the cell is attained at a corner. Any weights give a valid bound; weights making the
// gradients of the nearest triangles cancel (the min-norm point of their convex hull) make it
// tight at a medial point and exact on a plateau between parallel faces. For interior cells this
// bounds the depth (penetration), so -bound is a lower bound of the signed distance.
#include <cstdint>
#include <vector>

#include "distance/signed_distance.h"

namespace cdbench {

// c: a point of the cell (its centre); radius: the triangles considered are those within radius
// of c (any subset gives a valid bound; it must reach the nearest ones to be tight). Returns +inf
// when no triangle qualifies. `candidate` (optional) receives the lambda-weighted mean of the
// nearest points: a good guess for a deep point, to be certified by the caller.
// For a flat cell (a triangle), pass its unit normal: the weights then cancel the gradients'
// components within the cell's plane, which makes the bound tight where the depth restricted to
// the plane peaks on a ridge between nearest triangles (only tightness depends on the weights).
double depth_upper_bound(const SignedDistance& sdf, const Vec3& c, double radius, const Vec3* corners, int n_corners,
                         std::vector<std::uint32_t>& scratch, Vec3* candidate = nullptr,
                         const Vec3* plane_normal = nullptr, int* worst_corner = nullptr);
// worst_corner (optional) receives the corner attaining the bound: where the true depth is likely
// largest, worth certifying as a candidate (a lower bound on the maximum depth).

}  // namespace cdbench
