#include "distance/max_penetration.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

#include "core/interval.h"
#include "distance/depth_bound.h"
#include "distance/depth_plane.h"
#include "distance/point_triangle_distance.h"
#include "distance/slab_cut.h"
#include "util/progress.h"
#include "util/timer.h"

namespace cdbench {
namespace {

struct Cell {
  Vec3 center;
  signed char sign;    // -1 inside, +1 outside, 0 unknown (a certified fact about the centre)
  double parent_upper;  // certified depth bound over the parent cell (covers this one)
  std::int64_t near = -1;  // a triangle near the parent's centre: the first guess of the queries
};

struct Outcome {
  bool keep = false;
  bool full = false;
  bool side_query = false;
  signed char sign = 0;
  double lower = -1.0;     // certified depth of `point` (inside only), else -1
  Vec3 point = Vec3::Zero();
  double upper = 0.0;      // certified upper bound of the depth over the cell's interior points
  double child_margin = 0.0;  // dist lower bound at the centre: children closer than it share the sign
  std::uint32_t near = 0;      // the triangle found nearest to the centre (or one proving the bound)
  bool regions_tried = false;  // region_depth_bound ran on the cell
  bool regions_won = false;    // and set it aside
  RegionBoundStats regrowth;   // regions grown again past four faces, and whether that set it aside
};

// The computed corners of the cube c +- h, numbered as kBoxEdges (distance/slab_cut.h) expects:
// corner k is on the high side of x, y, z where bit 0, 1, 2 of k is set. Both bounds below work on
// the box these corners span.
std::array<Vec3, 8> cube_corners(const Vec3& c, double h) {
  std::array<Vec3, 8> v;
  for (int k = 0; k < 8; ++k) v[k] = c + Vec3((k & 1) ? h : -h, (k & 2) ? h : -h, (k & 4) ? h : -h);
  return v;
}

// Whether a costly bound is worth trying on a level's other cells: it set at least one in `per` of
// the `tried` cells it was tried on aside, or any of them when fewer than `enough` were tried.
bool pays(std::uint64_t tried, std::uint64_t won, std::uint64_t enough, std::uint64_t per) {
  return tried >= enough ? per * won >= tried : won > 0;
}

// The convexity bound over a cube: its 8 corners (see distance/depth_bound.h).
// Near-coplanar triangles within coplanar_slack of a plane count as one planar patch where they
// cover the cube's projection (distance/planar_patch.h): machined parts' plateaus between parallel
// faces tiled by many triangles.
// When that bound still exceeds `enough`, the weights minimising it over the corners are tried too
// (minimax_depth_bound: the seams of faceted walls).
double convexity_bound(const SignedDistance& sdf, const Vec3& c, double h, double radius, std::uint32_t near,
                       std::vector<std::uint32_t>& ids, Vec3& candidate, double coplanar_slack, double enough) {
  const std::array<Vec3, 8> corners = cube_corners(c, h);
  if (!sdf.triangles_within(c, radius, kMaxDepthTriangles - 1, ids)) {
    // More triangles within reach than the bound takes: the nearest ones, which about a thick
    // part's axis (a finely faceted cylinder) all lie on one side of it, so that no weights balance
    // them. The nearest triangle found for c and the one across, nearest to the point as far beyond
    // c as c's nearest point of F is before it, take the place of two (a heuristic: any subset
    // gives a valid bound).
    const Face& f = sdf.mesh().faces[near];
    const Vec3 q = 2.0 * c - closest_point_on_triangle(c, sdf.mesh().vertices[f[0]], sdf.mesh().vertices[f[1]],
                                                       sdf.mesh().vertices[f[2]]);
    std::uint32_t across = near;
    sdf.unsigned_distance(q, &across);
    ids.resize(kMaxDepthTriangles - 3);
    for (const std::uint32_t t : {near, across})
      if (std::find(ids.begin(), ids.end(), t) == ids.end()) ids.push_back(t);
  }
  double bound = depth_upper_bound_among(sdf, c, ids, corners.data(), 8, &candidate, nullptr, nullptr, nullptr,
                                         coplanar_slack);
  if (bound > enough) bound = std::min(bound, minimax_depth_bound(sdf, ids, corners.data(), 8));
  return bound;
}

// Triangles near a cube for slab_depth_bound: beyond this many its slab is seldom thin.
constexpr std::size_t kMaxSlabTriangles = 32;

// A cube across F (a thin wall, or a face it dips through) bounded by its part between the planes of
// the faces it crosses (doc/distance.md, "Cubes across a thin wall"):
// - T: every triangle within reach of c, reach >= |x - c| for every x of the cube K spanned by the
//   computed corners (a certified superset of the triangles meeting K); an axis n (of the normals
//   of T's first four, the one across which T spans the thinnest slab) and h >= n.y >= l over T's
//   points y in K (rigorous; `span` below).
// - R+ = {y in K : n.y > h} is convex and meets no triangle of F (one meeting it meets K, so lies
//   in T, whose points all have n.y <= h): it lies on one side of F. It is outside when it holds
//   the centre, off F and outside, or a corner whose side the segment from the centre finds outside
//   (that segment lies in K, so its crossings are among T), or the ray test when the centre is on F.
//   Likewise R- below l.
// - An interior point x of K lies in neither region that is outside, so n.x <= h where R+ is (and
//   >= l where R- is): x lies in K cut by those planes, the hull of cut_by_slab's points within its
//   err. The convexity bound over T at those points (planar patches decided on K's corners,
//   min-norm then minimax weights) plus err bounds dist(x, F).
// A region not proven outside is not cut. For a wall whose two faces are planes the bound is half
// its thickness whatever the cube's size. Returns +inf when it cannot help (heuristics: only the
// bound decides whether a cube is set aside): more than kMaxSlabTriangles near, a slab more than
// twice `enough` thick (halved when K crosses both planes), a kept part deeper than 2 `enough`.
// centre_side: the centre's certified side (+-1) when it is off F, else 0. deep / deep_lower: a point
// midway through a wall proven outside on both sides, on an edge of K crossing both planes, and its
// certified depth (-1 if none; tried only where it could exceed `enough`).
double slab_depth_bound(const SignedDistance& sdf, const Vec3& c, double half, double reach, int centre_side,
                        double coplanar_slack, double enough, std::vector<std::uint32_t>& ids, Vec3* deep,
                        double* deep_lower) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  *deep_lower = -1.0;
  if (!sdf.triangles_within(c, reach, kMaxSlabTriangles, ids) || ids.empty()) return kInf;
  // K's box about c, its corners' rounding included.
  const double hk = round_up(half + 4e-16 * (c.cwiseAbs().maxCoeff() + half));
  const auto span = [&](const Vec3& n, double* h, double* l) {
    const Interval s = triangles_span_in_box(sdf.mesh(), sdf.planes(), ids, n, c, hk);
    *h = s.hi, *l = s.lo;
  };
  Vec3 n = Vec3::Zero();
  double h = kInf, l = -kInf, thick = kInf;
  for (std::size_t i = 0; i < std::min<std::size_t>(ids.size(), 4); ++i) {
    const Vec3 ni = sdf.planes()[ids[i]].n;
    const double len = ni.norm();
    if (!(len > 0.0)) continue;
    double hi, li;
    span(ni, &hi, &li);
    if ((hi - li) / len < thick) n = ni, h = hi, l = li, thick = (hi - li) / len;
  }
  if (!(thick < kInf)) return kInf;
  const double n_up = round_up(n.norm() * (1.0 + 1e-12));  // >= |n|
  const std::array<Vec3, 8> v = cube_corners(c, half);
  std::array<PlaneOffset, 8> ov;
  int top = 0, bottom = 0;
  double reach_hi = -kInf, reach_lo = kInf;  // n.x over K lies within
  for (int k = 0; k < 8; ++k) {
    ov[k] = plane_offset(n, 0.0, v[k]);
    if (ov[k].value > ov[top].value) top = k;
    if (ov[k].value < ov[bottom].value) bottom = k;
    reach_hi = std::max(reach_hi, round_up(ov[k].value + ov[k].error));
    reach_lo = std::min(reach_lo, round_down(ov[k].value - ov[k].error));
  }
  const bool across = reach_hi > h && reach_lo < l;  // K may cross both planes: a wall
  const bool want_bound = (across ? 0.5 : 1.0) * (h - l) < 2.0 * n_up * enough;
  // A point midway through a wall (below) could raise the depth found: the wall is thinner than
  // the cube, so the cube's other candidates are far from its mid-plane. K may also end on one of
  // the planes, within rounding: a flat face on the bounding box's side lies on the sides of a whole
  // layer of cubes at every level (a plate, a washer), which then never cross it.
  const double touch = 1e-9 * (h - l);
  const bool want_deep = reach_hi > h - touch && reach_lo < l + touch && (h - l) > 2.0 * n_up * enough &&
                         (h - l) < 2.0 * n_up * half;
  if (!want_bound && !want_deep) return kInf;
  const PlaneOffset oc = plane_offset(n, 0.0, c);
  const auto outside = [&](int k, bool above) {
    if (centre_side != 0 && (above ? round_down(oc.value - oc.error) > h : round_up(oc.value + oc.error) < l))
      return centre_side > 0;  // the centre is in it
    if (!(above ? round_down(ov[k].value - ov[k].error) > h : round_up(ov[k].value + ov[k].error) < l)) return false;
    // v_k lies in the region, hence off F.
    return (centre_side != 0 ? sdf.side_among(v[k], Interval{std::numeric_limits<double>::min(), kInf}, c,
                                              centre_side, ids)
                             : sdf.side(v[k])) > 0;
  };
  const bool cut_hi = reach_hi > h && outside(top, true), cut_lo = reach_lo < l && outside(bottom, false);
  // Outside on both sides, or on one side with K ending on the other plane.
  if (want_deep && (cut_hi || cut_lo) && (cut_hi || !(reach_hi > h + touch)) && (cut_lo || !(reach_lo < l - touch))) {
    // A wall: a point midway through it on an edge crossing its mid-plane (on a flat wall's
    // mid-plane), certified: a deep point found long before cubes fit inside a thin wall (the
    // crossing in plain doubles; the point is certified as it is).
    const double mid = 0.5 * (h + l);
    for (const auto& e : kBoxEdges) {
      const double a = ov[e[0]].value, b = ov[e[1]].value;
      if (!(a != b)) continue;
      const double t = (mid - a) / (b - a);
      if (!(t >= 0.0 && t <= 1.0)) continue;
      *deep = v[e[0]] + t * (v[e[1]] - v[e[0]]);
      *deep_lower = -sdf.signed_distance(*deep).hi;
      break;
    }
  }
  if (!want_bound || (!cut_hi && !cut_lo)) return kInf;
  if ((!cut_hi && reach_hi > h && !(reach_hi - h < 2.0 * n_up * enough)) ||
      (!cut_lo && reach_lo < l && !(l - reach_lo < 2.0 * n_up * enough)))
    return kInf;
  SlabCut cut;
  if (!cut_by_slab(v.data(), ov.data(), 8, kBoxEdges.data(), 12, cut_hi ? h : kInf, cut_lo ? l : -kInf, cut))
    return kInf;
  if (cut.n == 0) return 0.0;  // no point of K inside F
  Vec3 centroid = Vec3::Zero();
  for (int k = 0; k < cut.n; ++k) centroid += cut.q[k];
  centroid /= cut.n;
  CornerDistances known;
  double depth = depth_upper_bound_among(sdf, centroid, ids, cut.q.data(), cut.n, nullptr, nullptr, nullptr, nullptr,
                                         coplanar_slack, DepthWeights::converged, nullptr, &known, v.data());
  if (depth > enough) depth = std::min(depth, minimax_depth_bound(sdf, ids, cut.q.data(), cut.n, 12, nullptr, &known));
  if (!(depth < kInf)) return kInf;
  return round_up(depth + cut.err);
}

// Candidates of a deep point refined from the previous candidate, per kept cell (see the loop).
constexpr int kCandidateRounds = 6;


}  // namespace

MaxPenetrationResult certified_max_penetration(const SignedDistance& sdf, const MaxPenetrationOptions& options) {
  Timer timer;
  MaxPenetrationResult result;
  const Aabb box = sdf.bbox();
  const double diag = box.diagonal();
  // A hair below the requested width, so that the outward rounding of the bounds stays within it.
  const double eps = options.relative_tolerance * diag * (1.0 - 1e-9);
  const Vec3 extent = box.extent();
  double half = 0.5 * extent.maxCoeff() / std::max(1, options.initial_resolution);

  std::vector<Cell> frontier;
  {
    const int nx = std::max(1, static_cast<int>(std::ceil(extent.x() / (2 * half))));
    const int ny = std::max(1, static_cast<int>(std::ceil(extent.y() / (2 * half))));
    const int nz = std::max(1, static_cast<int>(std::ceil(extent.z() / (2 * half))));
    // Grow the cells a little so that they cover the box despite rounding of the centres.
    half *= 1.0 + 1e-9;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          frontier.push_back({box.lo + Vec3((2 * i + 1) * half, (2 * j + 1) * half, (2 * k + 1) * half), 0,
                              std::numeric_limits<double>::infinity()});
  }

  double best = 0.0;             // certified: some interior point has depth >= best
  Vec3 best_point = box.center();
  double upper_left = 0.0;  // max certified upper bound over the discarded cells and those a stop left
  bool stopped = false;     // a safety stop after a level: its next level was not built
  std::uint64_t regions_tried_before = 0, regions_won_before = 0;  // the previous level's
  std::uint64_t regrown_before = 0, regrown_won_before = 0;
  Progress progress("max penetration", 0);

  while (!frontier.empty()) {  // (a stop leaves it empty: the next level is not built)
    if (result.cells + frontier.size() > options.max_cells || frontier.size() > options.max_frontier) break;
    const double r = round_up(half * kSqrt3Up);  // covering radius of a cell around its centre
    const double snapshot = best;
    // The regions beyond faces cost more than the other bounds and help only on thin curved walls:
    // every 16th cell of a level is evaluated first, with them; the others try them when those
    // set at least 1 % of the cells they were tried on aside (any, below 16 tries), or when the
    // previous level's cells did (counts over fixed cells: the same for any thread count).
    const bool regions_before = pays(regions_tried_before, regions_won_before, 64, 100);
    bool regions_everywhere = true;  // during the first pass, which holds only sampled cells
    // Regions grown again past four faces (a curved wall's cubes spanning many facets) cost about
    // as much as the first growth: the others grow them again when that set at least a quarter of
    // the sampled cells it was tried on aside, or the previous level's cells (any, below 16 tries).
    const bool regrow_before = pays(regrown_before, regrown_won_before, 64, 4);
    bool regrow_everywhere = true;
    std::vector<Outcome> out(frontier.size());
    // Grain 1: after the first level the frontier holds 8-600 cells of 10 us to 1 ms each (armadillo),
    // which chunks of 64 gave to at most 9 threads (one below 65 cells).
    // Pass 0: the sampled cells (i % 16 == 0); pass 1: the others.
    const auto evaluate = [&](int pass) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, frontier.size(), 1), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        if ((i % 16 == 0) != (pass == 0)) continue;
        const Cell& cell = frontier[i];
        Outcome& o = out[i];
        // Discard without a full query when some triangle is close enough to the centre:
        // depth over the cell <= dist(c) + r <= snapshot + eps.
        const double theta = snapshot + eps - r;
        Interval d;
        bool unique = false;  // o.near is the centre's only nearest triangle
        if (sdf.distance_at_most(cell.center, theta, &d, &o.near, cell.near, &unique)) {
          o.upper = round_up(theta + r);
          if (options.progress) progress.advance();
          continue;
        }
        o.full = true;
        o.sign = cell.sign;
        if (o.sign == 0) {
          o.side_query = true;
          const int s = sdf.side_by_nearest(cell.center, d, o.near, unique, cell.center, 0);
          o.sign = static_cast<signed char>(s == 0 ? 1 : s);  // on the surface: depth 0, treat as outside
        }
        o.child_margin = d.lo;
        // The candidate (the weighted mean of the nearest points) is a medial point only along the
        // directions its weights balance: on a bar, weights on two opposite faces give a point on
        // the mid-plane between them, not on the axis. Candidates from the candidate (up to
        // kCandidateRounds, while the cell is still kept) balance the others; each is a heuristic
        // only, certified like the first.
        const auto refine = [&](Vec3 candidate, std::vector<std::uint32_t>& ids, int rounds) {
          for (int round = 0; round <= rounds; ++round) {
            if (!((candidate - cell.center).cwiseAbs().array() <= half).all()) break;
            // Within the ball of radius d.lo about the centre, which holds no point of F: the
            // candidate is on the centre's side, and needs no ray test.
            const bool in_ball = (candidate - cell.center).norm() * (1.0 + 1e-12) < d.lo;
            const Interval sc = in_ball ? with_side(sdf.unsigned_distance(candidate, nullptr, o.near), o.sign)
                                        : sdf.signed_distance(candidate);
            if (-sc.hi > o.lower) {
              o.lower = -sc.hi;
              o.point = candidate;
            }
            if (round == rounds || !(o.upper > std::max(snapshot, o.lower) + eps)) break;
            const Vec3 from = candidate;
            depth_upper_bound_among(sdf, from, ids, &from, 1, &candidate);
          }
        };
        // A cell the triangles' bounds keep: its candidates first (while they keep it, as without
        // the regions: cells set aside early would not refine the deepest point, on which every
        // level's pruning depends), then the regions beyond its nearest faces.
        const auto regions = [&](const Vec3& candidate, std::vector<std::uint32_t>& ids, int rounds) {
          if (!(o.upper > snapshot + eps)) return;
          thread_local std::vector<std::uint32_t> nearest;
          nearest = ids;  // nearest first to the centre; refine reorders ids about its candidates
          refine(candidate, ids, rounds);
          if (!(o.upper > std::max(snapshot, o.lower) + eps) || !regions_everywhere) return;
          const std::array<Vec3, 8> corners = cube_corners(cell.center, half);
          o.upper = std::min(o.upper, region_depth_bound(sdf, cell.center, d.lo > 0.0 ? o.sign : 0, corners.data(), 8,
                                                         nearest, {snapshot + eps, regrow_everywhere, false}, &o.regrowth));
          o.regions_tried = true;
          o.regions_won = !(o.upper > snapshot + eps);
        };
        if (o.sign < 0) {
          o.lower = d.lo;
          o.point = cell.center;
          o.upper = round_up(d.hi + r);
          // The Lipschitz bound cannot discard a cell on a plateau or near a medial point; the
          // convexity bound can. Worth its cost only for cells well inside.
          if (o.upper > snapshot + eps && r <= d.lo) {
            thread_local std::vector<std::uint32_t> ids;
            Vec3 candidate;
            o.upper = std::min(o.upper,
                               convexity_bound(sdf, cell.center, half, round_up(d.hi + 2 * r), o.near, ids, candidate, 0.25 * eps,
                                               snapshot + eps));
            regions(candidate, ids, kCandidateRounds);
          }
        } else {
          o.upper = round_up(r - d.lo);  // a point inside at distance <= r crosses the surface first
        }
        // A cube that may cross F (a thin wall): its part between the planes of the faces it crosses.
        // Not where the centre is deeper than the bound would need to be (no bound can set it aside).
        if (o.upper > snapshot + eps && !(r <= d.lo) && !(o.sign < 0 && d.lo > snapshot + eps)) {
          thread_local std::vector<std::uint32_t> ids;
          const double reach = round_up(r + 1e-15 * (cell.center.cwiseAbs().maxCoeff() + half));
          Vec3 deep;
          double deep_lower;
          o.upper = std::min(o.upper, slab_depth_bound(sdf, cell.center, half, reach, d.lo > 0.0 ? o.sign : 0,
                                                       0.25 * eps, snapshot + eps, ids, &deep, &deep_lower));
          if (deep_lower > o.lower) {
            o.lower = deep_lower;
            o.point = deep;
          }
          // A cube whose centre is inside but which may reach F: the faces' regions bound the
          // depth of its interior points whatever its other points are (distance/depth_plane.h),
          // those whose face it crosses cutting it there. Its candidate deep point too: cubes
          // across a curved wall reach its mid-surface before cubes inside it do, and the deepest
          // point found decides which cells are kept.
          if (o.upper > snapshot + eps && o.sign < 0) {
            Vec3 candidate;
            o.upper = std::min(o.upper, convexity_bound(sdf, cell.center, half, round_up(d.hi + 2 * r), o.near, ids, candidate,
                                                        0.25 * eps, snapshot + eps));
            regions(candidate, ids, 0);
          } else if (o.upper > snapshot + eps && snapshot > 0.0 && o.sign > 0 && d.lo > 0.0 && regions_everywhere &&
                     !ids.empty() && ids.size() < kMaxSlabTriangles) {
            // A cube whose centre is outside, reaching into a thin wall from its hollow or from
            // outside (most of the cubes across a curved wall): the lemma needs only the cube's
            // interior points, never its centre's side, so the regions bound them likewise, those
            // whose face the cube crosses clipping it there; the outside centre, off F, is the
            // segment test's known end. Nearest faces first, as the seeds are picked in that order:
            // the slab bound's triangles (within r), or when none faces the other way those within
            // r + best + eps, where an interior point deeper than best + eps has every face that
            // bounds it (the wall's far side, beyond r from the hollow). (Heuristics: not on the
            // first level, whose cubes the next level sets aside anyway, nor where the slab bound
            // found more triangles near than it takes.)
            thread_local std::vector<std::uint32_t> sorted, wide;
            sorted = ids;
            sort_nearest_first(sdf, cell.center, sorted);
            const Vec3 first = sdf.planes()[sorted[0]].n;
            const bool other_side = std::any_of(sorted.begin(), sorted.end(), [&](std::uint32_t t) {
              return sdf.planes()[t].n.dot(first) < 0.0;
            });
            if (!other_side && region_seeds(sdf, cell.center, round_up(r + snapshot + eps), kMaxSlabTriangles, nullptr, wide))
              std::swap(sorted, wide);
            const std::array<Vec3, 8> corners = cube_corners(cell.center, half);
            o.upper = std::min(
                o.upper, region_depth_bound(sdf, cell.center, o.sign, corners.data(), 8, sorted, {snapshot + eps, regrow_everywhere, false},
                                          &o.regrowth));
            o.regions_tried = true;
            o.regions_won = !(o.upper > snapshot + eps);
          }
        }
        o.keep = o.upper > snapshot + eps;
        if (options.progress) progress.advance();
      }
    });
    };
    evaluate(0);
    {
      std::uint64_t tried = 0, won = 0, regrown = 0, regrown_won = 0;
      for (std::size_t i = 0; i < out.size(); i += 16) {
        tried += out[i].regions_tried, won += out[i].regions_won;
        regrown += out[i].regrowth.regrown, regrown_won += out[i].regrowth.regrown_won;
      }
      regions_everywhere = regions_before || pays(tried, won, 16, 100);
      regrow_everywhere = regrow_before || pays(regrown, regrown_won, 16, 4);
    }
    evaluate(1);

    // The next level (eight cells for each kept one) is counted before it is built: one past the
    // safety stops is never built (its cells would only carry their parents' bounds, which the stop
    // reports from the kept cells themselves: the same interval), so that the memory stays within
    // them; a level that is built takes one allocation.
    std::uint64_t kept = 0;
    regions_tried_before = regions_won_before = regrown_before = regrown_won_before = 0;
    for (const Outcome& o : out) {
      kept += o.keep;
      regions_tried_before += o.regions_tried;
      regions_won_before += o.regions_won;
      regrown_before += o.regrowth.regrown;
      regrown_won_before += o.regrowth.regrown_won;
    }
    const std::uint64_t next_cells = 8 * kept;
    const bool stop = next_cells > 0 && (next_cells > options.max_frontier ||
                                         result.cells + frontier.size() + next_cells > options.max_cells);
    std::vector<Cell> next;
    if (!stop) next.reserve(next_cells);
    const double child_half = 0.5 * half;
    const double child_offset = round_up(child_half * kSqrt3Up);  // distance from a centre to a child's centre
    for (std::size_t i = 0; i < frontier.size(); ++i) {
      const Outcome& o = out[i];
      ++result.cells;
      result.full_queries += o.full;
      result.side_queries += o.side_query;
      if (o.lower > best) {
        best = o.lower;
        best_point = o.point;
      }
      if (!o.keep || stop) {  // discarded, or left unexplored by the stop: its bound covers it
        upper_left = std::max(upper_left, o.upper);
        continue;
      }
      const signed char child_sign = o.child_margin > child_offset ? o.sign : 0;
      for (int k = 0; k < 8; ++k) {
        const Vec3 offset((k & 1) ? child_half : -child_half, (k & 2) ? child_half : -child_half,
                          (k & 4) ? child_half : -child_half);
        next.push_back({frontier[i].center + offset, child_sign, o.upper, o.near});
      }
    }
    // Kept cells whose children were computed are replaced by them; the children cover the parent
    // (same centre spacing), so every point of space stays covered by a live or discarded cell.
    frontier = std::move(next);
    half = child_half;
    ++result.levels;
    stopped = stop;
    if (options.progress) {
      std::ostringstream os;
      os.precision(9);
      os << "level " << result.levels << ", " << (stop ? next_cells : frontier.size()) << " cells"
         << (stop ? " (past the safety stop)" : "") << ", depth >= " << best;
      progress.set_detail(os.str());
    }
  }
  progress.finish();

  result.tolerance_reached = frontier.empty() && !stopped;
  double upper = std::max(best, upper_left);
  // Cells of the first level left unexplored by a safety stop are bounded by their parents' bounds.
  for (const Cell& c : frontier) upper = std::max(upper, c.parent_upper);
  result.depth = {best, upper};
  result.point = best_point;
  result.seconds = timer.seconds();
  return result;
}

}  // namespace cdbench
