#pragma once
// Certified one-sided Hausdorff distance h(A, B) = max over points p of the triangles of A of
// dist(p, B), as an interval [lo, hi] that contains it. Used to say how far a repair moved a
// surface (cdbench wrap / repair). Argument and measurements: doc/mesh-intake.md.
//
// Branch and bound over A's triangles, subdivided 1-to-4. A cell's corners get certified distance
// enclosures (lo is a valid lower bound of the max, since the corner is a point of A). Its upper
// bound is the smaller of
//   - convexity: for any single triangle t of B, dist(., B) <= dist(., t), and dist(., t) is convex,
//     so over the cell it is at most its largest value at the corners (t = a corner's nearest
//     triangle of B); exact when the cell's nearest points lie on one triangle;
//   - pieces: when the corners' nearest triangles differ (the cell straddles an edge or a vertex
//     of B, where the single-triangle bound is off by about the cell's size), the cell is cut at
//     the crossings of the distances into two or three polygons, each bounded by convexity with
//     its corner's triangle at its own vertices (cut points are exact points of the cell for the
//     double parameters used, up to a few ulps of slack); tried only when the others are too wide;
//   - Lipschitz: dist(., B) is 1-Lipschitz, so it is at most a corner's value plus the longest edge;
// plus the cell's slack: midpoints are rounded to doubles, so a computed corner lies within its
// accumulated rounding ("drift") of a true point of A; the cell covers its exact region up to the
// largest drift of its corners, which is added to its upper bound and subtracted from lower bounds.
// A triangle is refined until its largest cell bound is within the tolerance of the best lower
// bound known to it; triangles are independent, so the result does not depend on thread count.
#include <cstddef>

#include "core/interval.h"
#include "core/triangle_mesh.h"
#include "distance/signed_distance.h"

namespace cdbench {

struct HausdorffOptions {
  double relative_tolerance = 1e-2;  // stop when hi - lo <= max(relative * lo, absolute)
  double absolute_tolerance = 0.0;   // <= 0: 1e-9 x the bounding-box diagonal of A
  std::size_t max_cells_per_triangle = 1000000;  // work limit; beyond it the interval stays valid, only wider
};

struct HausdorffResult {
  Interval distance;                // contains max_{p in A} dist(p, B)
  Vec3 witness = Vec3::Zero();      // a point (within rounding of A) where distance.lo was found
  std::size_t cells = 0;            // cells evaluated
  bool converged = true;            // false when a triangle hit max_cells_per_triangle
  double seconds = 0.0;
};

// `a`: any triangles (degenerate ones included); `b`: the target surface (only its unsigned
// distance is used, so B need not be closed). Parallel over A's triangles (TBB).
HausdorffResult one_sided_hausdorff(const TriangleMesh& a, const SignedDistance& b, const HausdorffOptions& options = {});

// Both directions between two surfaces.
struct SurfaceDeviation {
  HausdorffResult first_to_second, second_to_first;
};
SurfaceDeviation two_sided_hausdorff(const TriangleMesh& first, const TriangleMesh& second,
                                     const HausdorffOptions& options = {});

}  // namespace cdbench
