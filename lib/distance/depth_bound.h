#pragma once
// Upper bound of the unsigned distance to F over a convex cell given by its corners, from the
// convexity of the triangle distances d_j (certification-math note 2): for weights lambda_j >= 0,
// dist(x, F) <= sum_j lambda_j d_j(x) / sum_j lambda_j, and the right side is convex, so its maximum
// over the cell is attained at a corner. Any weights give a valid bound; weights making the
// gradients of the nearest triangles cancel (the min-norm point of their convex hull) make it
// tight at a medial point and exact on a plateau between parallel faces. For interior cells this
// bounds the depth (penetration), so -bound is a lower bound of the signed distance.
#include <array>
#include <cstdint>
#include <vector>

#include "distance/signed_distance.h"

namespace cdbench {

// The same bound for the cell translated by any vector D (doc/poses.md, "Warm starts keep the
// depth bounds"). With q_jk a point of triangle j near corner k (point_of_triangle_near) and the
// weights normalised, d_j(v_k + D) <= |w_jk + D| (w_jk = v_k - q_jk) and, by Jensen,
//   sum_j l_j |w_jk + D| <= sqrt(sum_j l_j |w_jk + D|^2) = sqrt(A_k + 2 W_k.D + |D|^2),
// A_k = sum_j l_j |w_jk|^2, W_k = sum_j l_j w_jk: two moments per corner bound the depth of the
// translated cell for every D, and the bound grows only as fast as the cell deepens along D (a
// shifted Lipschitz bound grows by |D|).
struct CornerMoments {
  double a = 0.0;
  Vec3 w = Vec3::Zero();
};
struct TranslatedDepthBound {
  std::array<CornerMoments, 8> corners;
  int n = 0;          // corners used; 0: no bound
  double err = 0.0;   // the points q_jk's distance to their triangles, w's rounding (absolute)
};
// A certified upper bound of dist(x, F) for every point x of the cell (the convex hull of the
// corners given to depth_upper_bound) translated by D, for the computed D itself (a caller whose
// real translation differs adds the difference: the bound is 1-Lipschitz in D). +inf when n = 0.
double translated_depth(const TranslatedDepthBound& b, const Vec3& D);

// The weights of a convexity bound, kept to evaluate it again on the same cell moved a little
// (a warm start's stale cells: placement/clearance.cpp): up to four triangles of F with positive
// weights. Any weights give a valid bound (above), so the four largest of a bound's weights are as
// valid as all of them; the bound from them is exact where F is flat across the cell as before.
struct DepthWitness {
  std::array<std::uint32_t, 4> face{};
  std::array<float, 4> weight{};
  int n = 0;
};
// sum_j w_j d_j(v) / sum_j w_j at the worst of the corners v (certified upper ends of the
// distances, the mean rounded up): a certified upper bound of dist(x, F) on their convex hull.
// +inf when w is empty.
double witness_depth_bound(const SignedDistance& sdf, const DepthWitness& w, const Vec3* corners, int n_corners);

// The certified distances (point_triangle_distance_upper_near) of the first four triangles of `ids`, as
// the bound leaves them, at up to eight corners, where the bound computed them (NaN elsewhere): a
// caller that needs the same distances (deep_cover.cpp's clips, minimax_depth_bound) takes them from here.
struct CornerDistances {
  std::array<std::array<double, 4>, 8> d;
  // d_face at corners[k], face being the j-th triangle of those `ids`: the bound's value when it
  // computed it, else computed now (point_triangle_distance_upper_near).
  double at(const TriangleMesh& m, const Vec3* corners, int k, std::size_t j, std::uint32_t face) const;
};

// How far the weights are optimised (only the bound's tightness and cost depend on it).
// `converged`: Frank-Wolfe to the min-norm point (up to 100 steps): the tightest on plateaus and
// seams, for the maximum penetration's cubes. `sparse`: stopped once the duality gap is at most
// 1/2, after one or two steps that cancel opposing gradients: a few weighted triangles, so the
// corners' certified distances are few; the pose certificates' cells, which the branch and bound
// splits anyway (doc/poses.md, "The depth bound's weights").
// The most triangles a bound combines: a partial set is still valid, and the nearest ones make it
// tight (the first found by the tree's nearest-first order, or the nearest of a candidate list).
constexpr std::size_t kMaxDepthTriangles = 49;

enum class DepthWeights { converged, sparse };

// Since session 93 a centre c lying exactly on one of the triangles (where that triangle's distance
// has no gradient) weights it by its normal instead of giving no bound (1), and so does a centre
// off it by the nearest point's rounding only, whose gradient is rounding noise, while the branch
// and bound no longer splits a cell proved outside F by a hair without its depth bound (2): a cell
// lying on F keeps the bound of the triangle and planar patch it lies on. Run keys carry this
// value (certificates, and so poses, may differ within the tolerance from earlier binaries').
constexpr int kOnSurfaceDepthBounds = 2;

// c: a point of the cell (its centre); radius: the triangles considered are those within radius
// of c (any subset gives a valid bound; it must reach the nearest ones to be tight). Returns +inf
// when no triangle qualifies. `candidate` (optional) receives the lambda-weighted mean of the
// nearest points: a good guess for a deep point, to be certified by the caller.
// For a flat cell (a triangle), pass its unit normal: the weights then cancel the gradients'
// components within the cell's plane, which makes the bound tight where the depth restricted to
// the plane peaks on a ridge between nearest triangles (only tightness depends on the weights).
double depth_upper_bound(const SignedDistance& sdf, const Vec3& c, double radius, const Vec3* corners, int n_corners,
                         std::vector<std::uint32_t>& scratch, Vec3* candidate = nullptr,
                         const Vec3* plane_normal = nullptr, int* worst_corner = nullptr,
                         TranslatedDepthBound* moments = nullptr, double coplanar_slack = 0.0,
                         DepthWeights weights = DepthWeights::converged, DepthWitness* witness = nullptr,
                         CornerDistances* computed = nullptr);
// The same bound from the triangles `ids` (any set; it should hold the nearest ones of the cell's
// points to be tight), of which the nearest 49 to c are kept (16 with sparse weights): `ids` is
// reordered nearest first and cut to those used. depth_upper_bound is triangles_within then this.
double depth_upper_bound_among(const SignedDistance& sdf, const Vec3& c, std::vector<std::uint32_t>& ids,
                               const Vec3* corners, int n_corners, Vec3* candidate = nullptr,
                               const Vec3* plane_normal = nullptr, int* worst_corner = nullptr,
                               TranslatedDepthBound* moments = nullptr, double coplanar_slack = 0.0,
                               DepthWeights weights = DepthWeights::converged, DepthWitness* witness = nullptr,
                               CornerDistances* computed = nullptr, const Vec3* cover_box = nullptr);
// The same bound with the weights that minimise its largest corner value (a linear program over
// the first max_members triangles of `ids`, e.g. the nearest ones as depth_upper_bound_among leaves
// them): tighter than the min-norm weights where the nearest feature changes across the cell, as
// at the seams of a faceted wall whose deepest points lie where several facets are equally near.
// The program only picks the weights (any weights are valid); the bound is evaluated rigorously at
// the corners. +inf when `ids` is empty.
// known (optional): distances a bound over the same ids and corners computed (NaN: not), reused.
double minimax_depth_bound(const SignedDistance& sdf, const std::vector<std::uint32_t>& ids, const Vec3* corners,
                           int n_corners, std::size_t max_members = 12, DepthWitness* witness = nullptr,
                           const CornerDistances* known = nullptr);
// coplanar_slack > 0 (flat cells of at most 3 corners, the 8 corners of an axis-aligned box, or any
// corners with cover_box, the 8 corners of an axis-aligned box holding them): triangles within that
// distance of a
// common plane that provably cover the cell's projection form one member, a planar patch
// (distance/planar_patch.h), whose bound is exact on its plane across the triangles' shared edges.
// The result is the smaller of the bounds with and without patches; moments and candidate come
// from the triangle-wise bound.
// witness (optional) receives the triangle-wise bound's four largest weights (DepthWitness).
// worst_corner (optional) receives the corner attaining the bound: where the true depth is likely
// largest, worth certifying as a candidate (a lower bound on the maximum depth). moments (optional,
// at most 8 corners) receives the translated form of the same bound, with the same weights.

// The bound of minimax_depth_bound from any members: D[k * M + j] (K corners, M members, both at
// most 16, D > 0) certified upper values at the cell's corners of M convex functions, each at least
// dist(x, F) at the cell's points x that matter (e.g. its interior points of the solid: a triangle's
// distance, or a plane's from distance/depth_plane.h). The weights of the program below, then the
// largest corner's weighted mean rounded up: an upper bound of dist(x, F) at those points, as
// every weighted mean of the members is convex. +inf when the program does not finish. weights
// (optional) receives the members' weights (empty when the program did not finish).
double minimax_bound(const double* D, int K, int M, std::vector<double>* weights = nullptr);

// The small linear program behind minimax_depth_bound: weights lambda on the simplex minimising
// max_k sum_j lambda_j D[k][j] (K rows, M members, D > 0 row-major, K, M <= 16). It only picks
// weights (callers evaluate their bounds rigorously); false when it does not finish.
bool minimax_weights(const double* D, int K, int M, std::vector<double>& lambda);

}  // namespace cdbench
