#pragma once
// Signed distance in plain doubles, NOT certified: the fast twin of SignedDistance, for the surface
// mesher's millions of evaluations. Nearest triangle over the same AABB tree (warm-started from the
// previous query of the thread), sign from the angle-weighted pseudo-normal of the nearest feature
// (Baerentzen & Aanaes), which is correct for closed manifold meshes up to rounding near the
// surface; outside the bounding box the sign is +, since far away the nearest feature is a
// tie within rounding. Tests compare it with SignedDistance; certification never uses it.
#include <vector>

#include "distance/signed_distance.h"

namespace cdbench {

class FastSignedDistance {
 public:
  explicit FastSignedDistance(const SignedDistance& exact);
  double operator()(const Vec3& p) const;
  // Value and unit gradient (direction away from the nearest surface point, times the sign).
  double value_and_gradient(const Vec3& p, Vec3& gradient) const;
  const SignedDistance& exact() const { return exact_; }

 private:
  const SignedDistance& exact_;
  std::vector<Vec3> face_normal_;      // unit, outward
  std::vector<Vec3> vertex_normal_;    // angle-weighted sums
  std::vector<std::array<Vec3, 3>> edge_normal_;  // per face, edge k = (v_k, v_{k+1}): sum of both faces' normals
};

// A point of {fast = d} near a point x where fast - d has a known sign: Newton overshoot along the
// fast gradient, then bisection to the last double (uncertified; seeds and new vertices of offset
// candidates). False when the three overshoots do not change the sign.
bool point_on_level_near(const FastSignedDistance& fast, double d, const Vec3& x, Vec3& on);

// point_on_level_near, or where its overshoots along the gradient all miss the level set (beside a
// sharp crease of an inward level, where the gradient points past the crease), the nearest to x of
// points_on_level_around's points within 2^max_doublings |fast(x) - d| (uncertified; new vertices of
// repaired candidates). False when neither finds a point.
bool point_on_level_close(const FastSignedDistance& fast, double d, const Vec3& x, Vec3& on, int max_doublings = 4);

// Where the edge (a, b) of a candidate (both ends about on {fast = d}) crosses a crease of the level
// set, the point of the crease above the edge: the gradients at a and b differ by more than
// acos(crease_cos); the point m of the edge where the gradient turns from a's to b's is found by
// bisection (where both sheets are equally near), and from m the level is followed along the
// bisector of the two gradients, which keeps both sheets' distances equal, so it ends on the
// crease (exactly for two planes). False when there is no crease between a and b or the level is
// not reached within |b - a| (uncertified; new vertices of repaired candidates).
bool point_on_crease_across(const FastSignedDistance& fast, double d, const Vec3& a, const Vec3& b, Vec3& on,
                            double crease_cos = 0.7);

// The first point of {fast = d} along the ray from x in the unit direction u, within `max_length`:
// steps of 1.5 |fast - d| (fast is 1-Lipschitz: a step of |fast - d| cannot cross the level set,
// so only a sheet thinner than half a step can be passed over), then bisection to the last double
// (uncertified; new vertices of offset candidates). False when the ray leaves `max_length` first.
bool point_on_level_along(const FastSignedDistance& fast, double d, const Vec3& x, const Vec3& u, double max_length,
                          Vec3& on);

// Points of {fast = d} all around x (fast - d != 0 at x): along each of 14 directions (the axes and
// the cube's diagonals), the first sign change found at distances 2, 4, ..., 2^max_doublings times
// |fast(x) - d|, located by bisection; appended to `out`. Seeds for a small component of a level
// set that the mesher missed: one seed on it gives Surface_mesher no facet to refine, a ring of
// them does (uncertified; only the candidate depends on them). A small `max_doublings` keeps the
// ring on x's own component (far sign changes are often other components).
void points_on_level_around(const FastSignedDistance& fast, double d, const Vec3& x, std::vector<Vec3>& out,
                            int max_doublings = 12);

}  // namespace cdbench
