#pragma once
// Faces' planes that bound the depth over a convex cell where F curves away from them only nearby
// (a thin wall's facets, curved or not): convex members of the convexity bound (depth_bound.h)
// that, unlike the faces' distances, do not grow past the faces' edges. See doc/distance.md,
// "Regions beyond faces".
//
// For up to twelve faces with planes n_i.y = d_i (n_i outward, unnormalised), levels H_i and the
// convex region W = {y : n_i.y >= H_i for each i} (a half-space beyond one face; beyond several
// where the solid is concave across their edges, as inside a tube, a wedge or a corner), and a
// convex cell P (the hull of `points`) lying in {n_i.y <= H_i} for some i (so no point of P is inside
// W): the point of W nearest to a point x of P is x's projection on one of the planes
// {n_i.y = H_i}, on the line common to two, or the point common to three (three planes whose
// normals are exactly dependent share no single point), so all of them lie in the box Pi of those
// projections of P's corners. Let B be an open box holding Pi. If every triangle of F meeting B has,
// over its part in B, n_i.y <= H_i for some i, the convex region R = B n int W holds no point of F
// and lies on one side of it; if one point of R is proven outside, all of R is. Then for every point
// x of P inside the solid, the segment from x to its nearest point of W ends where R's outside
// points accumulate, so it meets F:
//   dist(x, F) <= dist(x, W),
// a convex function of x (for one face, (H - n.x) / |n|). The region grows from one face: a
// triangle of B above every level adds its face (a neighbour bending back, as inside a tube) while
// fewer than twelve are in and its plane is well placed; otherwise the level it exceeds least rises
// to it. Where a face's neighbours bend away from the solid (a convex edge), one face at its own
// level suffices.
//
// A cell across the face's plane (some point of P above the face's own level): B must also hold P.
// Then no interior point x of the solid in P lies in B n int W = R (outside), so dist(x, F) <=
// dist(x, W) = sd(x), W's signed distance (negative in W: minus the distance to its boundary), which
// is convex as W is; for one face the affine (H - n.x) / |n|. Negative where the cell reaches into
// W, the member cuts the cell there as a clip would (doc/distance.md, "Regions beyond faces").
#include <array>
#include <cstdint>
#include <vector>

#include "distance/signed_distance.h"

namespace cdbench {

// W's planes as proven (prove_depth_region fills them; the other functions read them instead of
// rebuilding them): normals, unit normals, squared norms and levels; the pairs whose common line
// meets W (its edges, where the nearest point of W may lie besides the planes), and the triples of
// planes with one common point.
struct DepthRegionPlanes {
  static constexpr int kMaxFaces = 12;
  std::array<Vec3, kMaxFaces> n, u;
  std::array<double, kMaxFaces> nn{}, level{};
  int nf = 0;
  std::array<unsigned, 4> triples{};  // bit masks of three planes
  int nt = 0;
  double gram = 1.0;  // the least Gram determinant of its pairs and triples
  std::array<std::array<std::uint8_t, 2>, kMaxFaces * (kMaxFaces - 1) / 2> edges{};
  int ne = 0;
};

struct DepthRegion {
  static constexpr int kMaxFaces = DepthRegionPlanes::kMaxFaces;
  static constexpr int kMaxEdges = 12;  // edge points a cell is cut at
  std::array<std::uint32_t, kMaxFaces> face{};  // its faces; planes.level[i] is face i's level H_i
  int n = 0;
  bool crossing = false;  // the cell reaches into W: its member is W's signed distance
  bool capped = false;    // a level rose where a face would have joined but for max_faces
  DepthRegionPlanes planes;
};

// Tries to prove the bound above from `face` (grown as said) for the hull of points[0..n)
// (n <= 16). ref: a point whose side ref_side (+-1) is known, from which the outside point of R is
// reached by a segment (0: by the ray test). The region takes at most max_faces faces (a triangle
// that would join past them makes a level rise instead: out->capped, set on failure too). False
// when the proof fails (too many triangles near, a neighbour rising far above the faces, R not
// outside: then the region bounds nothing here).
bool prove_depth_region(const SignedDistance& sdf, std::uint32_t face, const Vec3* points, int n, const Vec3& ref,
                        int ref_side, DepthRegion* out, std::vector<std::uint32_t>& scratch,
                        int max_faces = DepthRegion::kMaxFaces);

// A certified upper end of dist(x, W) (at least 1e-300), for x outside W's interior: the distance to
// a point proven in W. For a crossing region, of W's signed distance (any sign).
double depth_region_value(const SignedDistance& sdf, const DepthRegion& region, const Vec3& x);

// Points of the region's edges (lines common to two faces, where its distance is not affine) near
// x: plain doubles, where to cut a cell, not a bound. Returns how many (at most kMaxEdges).
int depth_region_edge_points(const SignedDistance& sdf, const DepthRegion& region, const Vec3& x,
                             std::array<Vec3, DepthRegion::kMaxEdges>& out);

// The point nearest to x of the line common to two crossing one-face regions' planes (a convex edge
// of F across the cell, where each member is tight on its side of the faces' bisector): plain
// doubles, where to cut a cell. False for other regions or (nearly) parallel planes.
bool crossing_regions_edge_point(const SignedDistance& sdf, const DepthRegion& a, const DepthRegion& b, const Vec3& x,
                                 Vec3* out);

// The minimax bound (depth_bound.h) over a box's eight corners `points` (numbered as kBoxEdges,
// distance/slab_cut.h) with the regions beyond the nearest faces of `ids` (nearest first) that can
// be proven there, besides the first triangles' distances: an upper bound of dist(x, F) at every
// point x of the box inside the solid. On a curved thin wall the facets' distances grow past their
// edges quadratically in the box's size over the wall's half thickness; the regions' distances are
// exact across edges where the solid is convex, and convex across those where it is concave,
// where the box is cut into slices. A region whose face the box crosses bounds by its signed
// distance, negative where the box reaches into it (outside the solid): the box's corners outside
// the wall do not raise the bound. +inf when no region is proven (or n != 8). ref: a point of the
// box whose side is ref_side (+-1; 0: not known), from which the regions' outside points are
// reached. Regions are tried from the two nearest distinct faces and up to four facing the other
// way (a wall's other side).
struct RegionBoundOptions {
  double enough = 0.0;  // a bound at most this is returned as soon as found (no slices, no more regions)
  // Regions whose growth stopped at four faces are grown again up to twelve when the bound is still
  // above `enough`.
  bool regrow = false;
  // The bound from the nearest face's region and the nearest facing the other way first, the other
  // regions only when it is above `enough` (a thin wall's two sides often suffice; each region's
  // proof is most of the cost).
  bool staged = false;
  // Where the bound over the box is above `enough`, the box cut into slices at the regions' edges
  // and each bounded apart (tighter where a concave edge of F crosses the box, at the cost of a
  // cut and a bound per slice).
  bool slices = true;
};
// stats (optional): whether regions were grown again, and whether that set the box aside.
struct RegionBoundStats {
  bool regrown = false;
  bool regrown_won = false;
};
// Where callers try region_depth_bound for the depth asked (a heuristic: only the work depends on
// it): cells whose radius is at most kRegionCellRadius times that depth (larger ones are seldom
// proven shallow: 7 % of the repaired shark's cubes of 8-16 times, 77-88 % of those of 1-4 times),
// and not where the cell's centre is certainly inside F at least kRegionCentreDepth times that
// depth (none of 3,000 such cubes on P, a few percent on rotor and elephant).
constexpr double kRegionCellRadius = 8.0;
constexpr double kRegionCentreDepth = 0.9;
// The seeds for region_depth_bound about a cell's centre c: the triangles of F within `reach` of
// c (every triangle nearest to a point of a cell of radius r lies within dist(c, F) + 2 r), from
// `candidates` when given (they must hold every such triangle) or F's tree, nearest first by
// their certified distance's upper end (ties by id: the same order from either source). False
// when more than max_count qualify (not a wall's few faces: regions seldom pay there).
bool region_seeds(const SignedDistance& sdf, const Vec3& c, double reach, std::size_t max_count,
                  const std::vector<std::uint32_t>* candidates, std::vector<std::uint32_t>& out);
// Reorders ids nearest to c first, as region_seeds leaves its seeds (by the certified distance's
// upper end, ties by id).
void sort_nearest_first(const SignedDistance& sdf, const Vec3& c, std::vector<std::uint32_t>& ids);
double region_depth_bound(const SignedDistance& sdf, const Vec3& ref, int ref_side, const Vec3* points, int n,
                          const std::vector<std::uint32_t>& ids, const RegionBoundOptions& options,
                          RegionBoundStats* stats = nullptr);

}  // namespace cdbench
