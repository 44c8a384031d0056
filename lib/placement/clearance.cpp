#include "placement/clearance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>
#include <utility>

#include "core/interval.h"
#include "distance/depth_bound.h"
#include "distance/point_triangle_distance.h"
#include "distance/slab_cut.h"
#include "distance/triangle_distance.h"
#include "mesh/components.h"
#include "placement/advance.h"
#include "util/thread_scratch.h"

namespace cdbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The searches' distance queries: near-point upper ends and slab lower ends, no interval enclosure
// (signed_distance.h; about 1e-13 max|coordinate| wider, far inside any tolerance).
constexpr DistanceEnds kEnds = DistanceEnds::near_points;

inline double down(double x) { return round_down(x); }
inline double up(double x) { return round_up(x); }
// A triangle's edges for cut_by_slab: edge k runs from corner k to corner k + 1.
constexpr std::array<std::array<int, 2>, 3> kTriangleEdges{{{0, 1}, {1, 2}, {2, 0}}};

// The box of a tree node after translation by t: rounding to nearest is monotone, so it contains
// fl(p + t) for every p in the box.
inline Aabb moved(const Aabb& b, const Vec3& t) {
  Aabb m;
  for (int k = 0; k < 3; ++k) {
    m.lo[k] = b.lo[k] + t[k];
    m.hi[k] = b.hi[k] + t[k];
  }
  return m;
}

// The relative tolerance's stopping point (ClearanceOptions::relative_tolerance): values at or
// above it need no refinement. Non-increasing as `upper` falls, so a part set aside under an
// earlier threshold stays above every later one.
inline double relaxed_threshold(double upper, double tol, double rel, double target) {
  return upper - std::max(tol, rel * (upper - target));
}

// How far p0 + b e1 + g e2 (e1 = p1 - p0, e2 = p2 - p0 computed, weights in [0, 1]), computed in
// doubles, lies from the exact point of the placed triangle: per coordinate within 20.002 u M of it
// (M the corners' largest coordinate, at most S = |p0| + |e1| + |e2| in max norm; the count of
// closest_point_error, distance/point_triangle_distance.cpp, each rounding at most 2u in any mode,
// u = 2^-53), i.e. 2.3e-15 S; 4e-15 S per coordinate covers it 1.8 times (1e-14 S until session 69:
// the certificates' width at 10^7 from the origin).
inline double combination_rounding(const Vec3& p0, const Vec3& e1, const Vec3& e2) {
  return 4e-15 * (p0.cwiseAbs().maxCoeff() + e1.cwiseAbs().maxCoeff() + e2.cwiseAbs().maxCoeff()) * kSqrt3Up;
}

// The interval of c computed for the placed doubles, widened to hold for the exact transform and
// any double evaluation of it (twice the transform's rounding bound).
void widen_for_transform(ClearanceResult& r, const MoverOrientation& o, const Vec3& t) {
  r.transform_error = o.transform_error(t);
  r.clearance.lo = down(r.clearance.lo - 2 * r.transform_error);
  r.clearance.hi = up(r.clearance.hi + 2 * r.transform_error);
}

// Minimum triangle-pair distance between the placed mover and F (squared, certified), stopping at
// the first proven intersection. In the fast mode a leaf costs a double closest-point estimate plus
// a rigorous lower bound from the projections on the estimated direction (exact up to rounding for
// the closest pair); pruning uses the estimated best distance with a margin, and the caller
// verifies afterwards, rigorously, that the margin held (else it reruns in the rigorous mode).
struct DistancePolicy {
  const TriangleMesh& F;
  const std::vector<TrianglePlane>& planes;
  const PlacedView P;
  const std::vector<Face>& faces;
  const Vec3& t;
  bool fast = true;
  double min_lo_sq = kInf, best_hi_sq = kInf;  // rigorous mode: enclosure of the minimum
  double best_est_sq = kInf, threshold_sq = kInf;  // fast mode: estimate and pruning threshold
  double tiny_sq = 0.0, margin_sq = 0.0;
  // Relative tolerance (fast mode): prune at (e - rel (e - target))^2 below the best estimate e,
  // so that the lower end min(leaves, final threshold) is within rel of the gap to the target.
  double rel = 0.0, target = 0.0;
  std::uint32_t best_f = 0, best_m = 0;
  bool intersect = false;
  std::uint64_t tests = 0;
  // Fast mode, ClearanceOptions::pair_budget: past this many pairs the path stops, undecided, and
  // the branch and bound, which decides every case, takes over.
  std::uint64_t give_up_after = std::numeric_limits<std::uint64_t>::max();
  bool gave_up = false;

  double bound(const Aabb& f, const Aabb& m) const { return squared_distance_lower_bound(f, moved(m, t)); }
  // Sweep trees (ClearanceOptions::sweep_trees): the mover's volumes hold its points at mover_t;
  // at t they lie within shift_pad of them moved by D. The boxes' bound, then (while ObbTrial
  // keeps it) the oriented boxes'.
  Vec3 D = Vec3::Zero();
  double shift_pad = 0.0;
  ObbTrial trial = ObbTrial();
  double bound(const SweepVolume& f, const SweepVolume& m) {
    Aabb n;
    for (int k = 0; k < 3; ++k) {
      // Rounded outward by more than the three roundings of each (at most 2u each, any mode).
      const double lo = m.box.lo[k] + D[k], hi = m.box.hi[k] + D[k];
      n.lo[k] = lo - (shift_pad * (1.0 + 1e-14) + 1e-15 * std::abs(lo));
      n.hi[k] = hi + (shift_pad * (1.0 + 1e-14) + 1e-15 * std::abs(hi));
    }
    const double box = squared_distance_lower_bound(f.box, n);
    if (!(box <= prune_bound()) || f.obb.half[0] < 0.0 || m.obb.half[0] < 0.0) return box;
    if (!trial.try_pair()) return box;
    // Round to nearest here: the factor covers the pad's own rounding (the advance rounds upward).
    const Obb o = shifted_obb(m.obb, D, shift_pad * (1.0 + 1e-14));
    const double oriented = obb_squared_distance_lower_bound(f.obb, o);
    trial.record(oriented > prune_bound());
    return std::max(box, oriented);
  }
  bool split_first(const SweepVolume& f, const SweepVolume& m) const { return split_first(f.box, m.box); }
  void use_sweep_trees(const SweepTrees& trees, const MoverOrientation& o) {
    const MoverOrientation::Shift shift = o.shift_from(trees.mover_t, t);
    D = shift.D;
    shift_pad = shift.pad;
  }
  double prune_bound() const { return fast ? threshold_sq : best_hi_sq; }
  bool split_first(const Aabb& f, const Aabb& m) const { return f.extent().squaredNorm() >= m.extent().squaredNorm(); }
  void leaf(std::uint32_t fi, std::uint32_t mi) {
    if (++tests > give_up_after && fast) {
      gave_up = true;
      return;
    }
    const Face& a = F.faces[fi];
    const Face& b = faces[mi];
    const Vec3 &A0 = F.vertices[a[0]], &A1 = F.vertices[a[1]], &A2 = F.vertices[a[2]];
    const Vec3 &B0 = P[b[0]], &B1 = P[b[1]], &B2 = P[b[2]];
    if (fast) {
      // Beyond the threshold by the fixed triangle's plane alone: as a pruned pair (below).
      const double pl = plane_pair_lower_bound(planes[fi], B0, B1, B2);
      if (pl > 0.0 && pl * pl * (1.0 - 1e-15) >= threshold_sq) return;
      Vec3 p, q;
      const double e2 = triangle_triangle_closest_points(A0, A1, A2, B0, B1, B2, &p, &q);
      const double lb = e2 > tiny_sq ? triangle_distance_lower_bound(A0, A1, A2, B0, B1, B2, q - p) : 0.0;
      if (lb > 0.0) min_lo_sq = std::min(min_lo_sq, down(lb * lb));
      else rigorous(A0, A1, A2, B0, B1, B2);
      if (e2 < best_est_sq) {
        best_est_sq = e2;
        threshold_sq = e2 * (1.0 + 1e-6) + margin_sq;
        if (rel > 0.0) {
          const double e = std::sqrt(e2), p = relaxed_threshold(e, 0.0, rel, target);
          if (p > 0.0 && p < e) threshold_sq = std::min(threshold_sq, p * p);  // p < e: e above the target
        }
        best_f = fi;
        best_m = mi;
      }
      return;
    }
    best_hi_sq = std::min(best_hi_sq, rigorous(A0, A1, A2, B0, B1, B2).hi);
  }
  bool done() const { return intersect || gave_up; }
  // The certified enclosure of one pair (exact intersection test included), taken into the lower end.
  Interval rigorous(const Vec3& A0, const Vec3& A1, const Vec3& A2, const Vec3& B0, const Vec3& B1, const Vec3& B2) {
    const Interval d2 = triangle_triangle_squared_distance(A0, A1, A2, B0, B1, B2);
    min_lo_sq = std::min(min_lo_sq, d2.lo);
    if (d2.hi == 0.0) intersect = true;
    return d2;
  }
};

// A cell of the branch and bound: a node of the mover's tree, or a (sub)triangle of a face given by
// the dyadic barycentric coordinates of its corners.
struct Cell {
  double lower;
  std::uint64_t seq;  // deterministic order among equal bounds
  bool is_node;
  std::uint32_t id;   // node index or face index
  int level;
  std::array<std::array<double, 2>, 3> bary;  // (beta, gamma) of the corners; exact dyadics
  bool stale = false;  // a warm-start cell: its bound is shifted, not evaluated at this pose
  SideBall ball = {};  // from its evaluation (or, for a stale cell, from the previous pose's)
  std::int32_t depth = -1;  // its translated depth bound (index into BranchAndBound::depth_), if any
  double ud_hi = std::numeric_limits<double>::infinity();  // upper end of dist(centre, F) when evaluated
  std::int64_t near_face = -1;  // a triangle of F at that upper end
  DepthWitness witness = {};  // the weights of its depth bound, when it had one (restale)
  // Its separating plane's gather found more than kMaxSeparatingCandidates triangles within its
  // reach: its children's candidate list, over a larger ball about the same centre, would too.
  bool crowded = false;
  // Smaller than its own rounding (evaluate_face): splitting it cannot narrow the interval, so the
  // search stops when it leads (ClearanceResult::rounding_floor).
  bool floored = false;
};

// Dyadic barycentric coordinates (beta, gamma) of a face cell's three corners.
using CellBary = std::array<std::array<double, 2>, 3>;
// The midpoint of two corners (exact: dyadic).
inline std::array<double, 2> bary_mid(const std::array<double, 2>& x, const std::array<double, 2>& y) {
  return {0.5 * (x[0] + y[0]), 0.5 * (x[1] + y[1])};
}
// The corners of a face cell of `f` relative to its first vertex, from `vertices` (the mover's own
// or its rotated ones).
std::array<Vec3, 3> face_cell_corners(const std::vector<Vec3>& vertices, const Face& f, const CellBary& b) {
  const Vec3 &p0 = vertices[f[0]], e1 = vertices[f[1]] - p0, e2 = vertices[f[2]] - p0;
  std::array<Vec3, 3> v;
  for (int k = 0; k < 3; ++k) v[k] = b[k][0] * e1 + b[k][1] * e2;
  return v;
}
// A face cell's children by its edges' midpoints (dyadic, so exact in the barycentrics), given its
// corners u in a frame that keeps lengths: a needle (one edge under half of each other) is cut
// across its length into three, each about half as long, so that thin cells shrink where they are
// long; any other cell into four. Only the shape of the subdivision depends on u (a heuristic).
// Every child's corners are the parent's corners or its edges' midpoints.
struct CellChildren {
  std::array<CellBary, 4> cells;
  int count;
};
CellChildren split_face_cell(const CellBary& b, const std::array<Vec3, 3>& u) {
  std::array<double, 3> len2;
  for (int k = 0; k < 3; ++k) len2[k] = (u[(k + 1) % 3] - u[k]).squaredNorm();
  const int s = static_cast<int>(std::min_element(len2.begin(), len2.end()) - len2.begin());
  if (4.0 * len2[s] < std::min(len2[(s + 1) % 3], len2[(s + 2) % 3])) {  // a needle on edge s
    const auto &B = b[s], &C = b[(s + 1) % 3], &A = b[(s + 2) % 3];
    const std::array<double, 2> M = bary_mid(A, B), N = bary_mid(A, C);
    return {{{{{A, M, N}}, {{M, B, C}}, {{M, C, N}}, {}}}, 3};
  }
  const std::array<double, 2> m01 = bary_mid(b[0], b[1]), m12 = bary_mid(b[1], b[2]), m20 = bary_mid(b[2], b[0]);
  return {{{{{b[0], m01, m20}}, {{m01, b[1], m12}}, {{m20, m12, b[2]}}, {{m01, m12, m20}}}}, 4};
}

// Triangles of F listed once for the four children of a split cell: every triangle within `radius`
// of the parent's centre m (certified superset). A child query that provably cannot reach a
// triangle outside that ball is answered from the list, without a tree traversal.
struct ParentCandidates {
  // Longer lists cost more than the queries they replace: a child's query scans its parent's whole
  // list, while a tree query visits about 85 leaves. 64 since 2026-11-28 (1,024 before): CAD parts
  // whose faces are many times |target| long listed much of the mesh for each split (pinion,
  // spool: 10-14 % faster); armadillo, bunny00 and fandisk_large unchanged (doc/performance.md).
  // 32 since session 86 (with kMaxSeparatingCandidates): pinion moving against spool 7-16 %
  // faster, a thin tube moving 0-5 %, CGAL's solids against themselves 1 % (doc/performance.md,
  // "Shorter candidate lists"). The branch and bound's lists and the segment search's alike.
  static constexpr std::size_t kMaxCount = kCandidateListLength;
  Vec3 m;
  double ud_hi = 0.0;   // upper end of dist(m, F)
  double radius = 0.0;
  std::vector<std::uint32_t> ids;
  // Every triangle within `reach` of x (x's distance to m added, rounded up) is listed.
  bool covers(const Vec3& x, double reach) const { return up(reach + up((x - m).norm() * (1.0 + 1e-12))) <= radius; }
  // An upper bound of dist(x, F): dist(m, F) + |x - m|.
  double distance_bound(const Vec3& x) const { return up(ud_hi + up((x - m).norm() * (1.0 + 1e-12))); }
};

// dist(x, F) from a candidate list when it provably holds x's nearest triangles (they lie within
// dist(x, F) <= `ud_bound` of x), else from F's tree (`hint`: a triangle likely nearest).
Interval distance_at(const SignedDistance& fixed, const Vec3& x, const ParentCandidates* list, double ud_bound,
                     std::uint32_t* nearest = nullptr, std::int64_t hint = -1, bool* unique = nullptr) {
  if (list && list->covers(x, ud_bound)) return fixed.unsigned_distance_among(x, list->ids, nearest, kEnds, unique);
  return fixed.unsigned_distance(x, nearest, hint, kEnds, unique);
}

// A lower bound of s on a cell's points placed in doubles at the pose t (rounding `rounding_t`), from
// its translated depth bound: they lie within d.rounding + rounding_t of the evaluated cell moved by
// the real t - d.t, which is within 1e-15 |D| of the computed D, and the bound is 1-Lipschitz in D.
double translated_lower(const CellDepthBound& d, const Vec3& t, double rounding_t) {
  const Vec3 D = t - d.t;
  const double depth = translated_depth(d.bound, D) + 1e-15 * D.norm() + d.rounding + rounding_t;
  return down(-up(depth * (1.0 + 1e-15)));
}

// A kept cell's translated depth bound d (an index into `from`, or -1) as an index into `to`, where
// each bound of `from` is copied once (renumber: from's indices in `to`, -1 until copied).
std::int32_t keep_depth_bound(std::int32_t d, const std::vector<CellDepthBound>& from, std::vector<CellDepthBound>& to,
                              std::vector<std::int32_t>& renumber) {
  if (d < 0) return -1;
  if (renumber[d] < 0) {
    renumber[d] = static_cast<std::int32_t>(to.size());
    to.push_back(from[d]);
  }
  return renumber[d];
}

// The side of x, when x certainly lies in the ball (0 otherwise). The computed norm's relative
// error is a few ulps; the factor covers it.
int side_from_ball(const SideBall* b, const Vec3& x) {
  if (b == nullptr || b->side == 0 || !(b->free > 0.0)) return 0;
  return up((x - b->centre).norm() * (1.0 + 1e-12)) < b->free ? b->side : 0;
}
struct CellOrder {
  bool operator()(const Cell& a, const Cell& b) const {
    return a.lower > b.lower || (a.lower == b.lower && a.seq > b.seq);
  }
};

// The storage of one branch and bound, kept per thread between runs: on a plateau the queue and
// the set-aside cells reach 10^4 cells per certificate, and growing them afresh each time spent
// 10-15 % of the run in reallocation and page faults (rotor_small, doc/performance.md). A run
// that finds its thread's storage in use (none does today) gets its own (util/thread_scratch.h).
struct BranchAndBoundStorage {
  std::vector<Cell> heap, discarded;
  std::vector<CellDepthBound> depth;
  std::vector<std::uint32_t> ids, parent_ids, slab_ids;
  void clear() {
    heap.clear();
    discarded.clear();
    depth.clear();
    ids.clear();
    parent_ids.clear();
    slab_ids.clear();
  }
};

class BranchAndBound {
 public:
  // keep_frontier: remember discarded cells too, for export_frontier().
  // mover: the mover mesh in its own coordinates (the cells' shape is judged there, so that every
  // pose and rotation splits a cell the same way).
  BranchAndBound(const SignedDistance& fixed, const TriangleMesh& mover, const MoverOrientation& o, const PlacedView& P,
                 const Vec3& t, const ClearanceOptions& opt, bool keep_frontier,
                 PlacedMatches* matches = nullptr)
      : fixed_(fixed), mover_(mover), o_(o), P_(P), t_(t), hull_(opt.hull && !opt.hull->empty() ? opt.hull : nullptr),
        matches_(matches), retry_(opt.coincident ? opt.coincident_retry : nullptr),
        probe_cells_(opt.retry_probe_cells),
        tol_(opt.tolerance), rel_(opt.relative_tolerance),
        target_(opt.target), floor_(opt.floor > -kInf ? up(opt.floor + 2.0 * o.transform_error(t)) : -kInf),
        keep_discarded_(keep_frontier), store_(scratch_.get()), heap_(store_.heap),
        discarded_(store_.discarded), depth_(store_.depth), ids_(store_.ids),
        slab_ids_(store_.slab_ids) {
    store_.clear();
    std::swap(parent_.ids, store_.parent_ids);
  }
  ~BranchAndBound() {
    std::swap(parent_.ids, store_.parent_ids);
  }
  BranchAndBound(const BranchAndBound&) = delete;
  BranchAndBound& operator=(const BranchAndBound&) = delete;

  void run(std::uint64_t max_cells, std::int64_t hint_face, double hint_beta, double hint_gamma,
           const ClearanceFrontier* warm, ClearanceResult& r) {
    if (hint_face >= 0 && static_cast<std::size_t>(hint_face) < o_.faces->size()) {
      Cell h{0, 0, false, static_cast<std::uint32_t>(hint_face), 1,
             {{{hint_beta, hint_gamma}, {hint_beta, hint_gamma}, {hint_beta, hint_gamma}}}};
      evaluate_face(h);  // sets the upper bound only (a point cell, not pushed)
    }
    if (warm) {
      // Each placed vertex moved by the translation difference plus the roundings of both poses;
      // a cell with a translated depth bound may keep a tighter bound from it.
      const double rounding = o_.transform_error(t_);
      const double shift = up(up((t_ - warm->t).norm() * (1.0 + 1e-12)) + up(warm->transform_error + rounding));
      depth_ = warm->depth;
      // Pushed at once and heaped in linear time: the order of the pops is that of (lower, seq)
      // whatever the heap's layout, so the same as one push at a time.
      heap_.reserve(warm->cells.size());
      for (const ClearanceFrontier::Cell& w : warm->cells) {
        double lower = down(w.lower - shift);
        if (w.depth >= 0) lower = std::max(lower, translated_lower(depth_[w.depth], t_, rounding));
        Cell c{lower, 0, w.is_node, w.id, w.level, w.bary, true, w.ball, w.depth};
        c.near_face = w.near_face;
        c.witness = w.witness;
        push(c, false);
      }
      std::make_heap(heap_.begin(), heap_.end(), CellOrder());
    } else {
      push(evaluate_node(0));
    }
    while (!heap_.empty()) {
      const Cell c = heap_.front();
      if (c.lower >= threshold()) break;
      if (r.cells >= max_cells) break;
      if (retry_ && r.cells >= probe_cells_ && probe_cells_ < max_cells) {
        const bool near = retry_->get().any_vertex(P_, o_.rotated.size());
        retry_ = nullptr;  // asked once
        if (near) {
          r.probe_stopped = true;  // for the retry with wider matches (certify_clearance)
          break;
        }
      }
      if (c.floored && !c.stale) {
        r.rounding_floor = true;
        break;
      }
      pop();
      ++r.cells;
      if (c.stale) {  // evaluate it at this pose before splitting it
        // First the bounds from its last nearest triangle (no tree query), which often set the
        // cell aside for good.
        Cell q = restale(c);
        if (q.lower >= threshold()) {
          push(q);
          continue;
        }
        Cell e = c.is_node ? evaluate_node(c.id, &c.ball, c.near_face)
                           : evaluate_face(hinted(Cell{0, 0, false, c.id, c.level, c.bary}, c), &c.ball);
        if (q.lower > e.lower) e.lower = q.lower;  // both valid at this pose
        if (e.witness.n == 0) e.witness = c.witness;  // still valid weights for a later pose
        push(e);
        continue;
      }
      if (c.is_node) {
        const auto& node = o_.boxes.nodes[c.id];
        if (node.count == 0) {
          for (std::uint32_t child = node.first; child < node.first + 2; ++child) {
            const auto& kid = o_.boxes.nodes[child];
            if (kid.count == 1) {
              // A leaf of one face: its face cell at once. The box would be evaluated (a distance
              // query, a ray test, a depth bound) only to be split into that same face, whose
              // bounds are at least as tight; on CAD parts whose faces are many times |target|
              // most leaves near a penetration are split so (pinion: 280 per cold certificate).
              push(evaluate_face(hinted(whole_face(o_.boxes.order[kid.first]), c), &c.ball));
            } else if (double ud_hi; hopeless(c, child, &ud_hi)) {
              // Its centre's distance bounded from this node's: it cannot be set aside by its own
              // bound, so it is split without one (this node's bound holds on it).
              Cell k{c.lower, 0, true, child, 0, {}};
              k.ball = c.ball;
              k.near_face = c.near_face;
              k.ud_hi = ud_hi;
              push(k);
            } else {
              push(evaluate_node(child, &c.ball, c.near_face));
            }
          }
        } else {
          for (std::uint32_t i = 0; i < node.count; ++i)
            push(evaluate_face(hinted(whole_face(o_.boxes.order[node.first + i]), c), &c.ball));
        }
      } else {
        // Judged in the mover's own coordinates: the same at every pose and for every rounding of
        // the rotation.
        const ParentCandidates* parent = list_candidates(c);
        const CellChildren kids = split_face_cell(c.bary, own_corners(c));
        for (int k = 0; k < kids.count; ++k)
          push(evaluate_face(hinted(Cell{0, 0, false, c.id, c.level + 1, kids.cells[k]}, c), &c.ball, parent));
      }
    }
    double lower = min_discarded_;
    if (!heap_.empty()) lower = std::min(lower, heap_.front().lower);
    // The width asked for; a floor not reached (the budget spent on it) does not count against it.
    r.tolerance_reached =
        heap_.empty() || (upper_ < kInf && heap_.front().lower >= relaxed_threshold(upper_, tol_, rel_, target_));
    r.clearance = {lower, upper_};
    r.distance_queries = queries_;
    r.far_cells = far_cells_;
    r.argmin_face = argmin_face_;
    r.argmin_beta = argmin_bary_[0];
    r.argmin_gamma = argmin_bary_[1];
  }

  // The leaves of this search: the cells left in the queue and the discarded ones.
  void export_frontier(ClearanceFrontier& f) {
    f.cells.clear();
    f.depth.clear();
    std::vector<std::int32_t> renumber(depth_.size(), -1);  // only the bounds of kept cells
    const auto keep = [&](const Cell& c) {
      const std::int32_t d = keep_depth_bound(c.depth, depth_, f.depth, renumber);
      f.cells.push_back({c.lower, c.is_node, c.id, c.level, c.bary, c.ball, d, c.near_face, c.witness});
    };
    for (const Cell& c : discarded_) keep(c);
    f.cells.reserve(f.cells.size() + heap_.size());
    while (!heap_.empty()) {
      keep(heap_.front());
      pop();
    }
    f.t = t_;
    f.transform_error = o_.transform_error(t_);
    f.valid = true;
  }

 private:
  // How far from a common plane the triangles of a planar patch may lie (distance/planar_patch.h):
  // the patch's bound exceeds the plane's distance by at most that, a fraction of the tolerance.
  // A quarter: pinion's faces, coplanar only to its six printed digits, still form patches.
  double coplanar_slack() const { return 0.25 * tol_; }

  // Cells with a lower bound at or above this need no refinement (relaxed_threshold: a cell set
  // aside earlier never falls below a later threshold, so the result's lower end stays consistent).
  // With a floor (ClearanceOptions::floor, raised by the transform's widening) the threshold is at
  // least the floor while the upper end is at or above it, and at most upper - tol: still
  // non-decreasing in the upper end.
  double threshold() const {
    if (!(upper_ < kInf)) return kInf;
    const double relaxed = relaxed_threshold(upper_, tol_, rel_, target_);
    return upper_ >= floor_ ? std::max(relaxed, std::min(floor_, upper_ - tol_)) : relaxed;
  }

  // heaped = false: appended only (the caller heaps them all at once).
  void push(Cell c, bool heaped = true) {
    c.seq = seq_++;
    if (c.lower >= threshold()) {
      min_discarded_ = std::min(min_discarded_, c.lower);
      if (keep_discarded_) discarded_.push_back(c);
      return;
    }
    heap_.push_back(c);
    if (heaped) std::push_heap(heap_.begin(), heap_.end(), CellOrder());
  }
  void pop() {
    std::pop_heap(heap_.begin(), heap_.end(), CellOrder());
    heap_.pop_back();
  }

  // s at x from its unsigned distance; the side from `ball` when x lies in it, else from x's only
  // nearest face or a parity test (SignedDistance::side_by_nearest).
  // `own` receives the ball about x that this evaluation certifies.
  // known: x's side when already decided (set_aside_far), else 0.
  // nearest, unique: ud's nearest triangle of F and whether it is x's only one.
  Interval signed_at(const Vec3& x, const Interval& ud, const SideBall* ball, SideBall* own, int known = 0,
                     std::uint32_t nearest = 0, bool unique = false) {
    int side = known != 0 ? known : side_from_ball(ball, x);
    // Outside the ball, the side of its only nearest face, else the parity of the short segment from
    // its centre (of known side).
    if (side == 0) side = fixed_.side_by_nearest(x, ud, nearest, unique, ball ? ball->centre : x, ball ? ball->side : 0);
    if (own) *own = SideBall{x, side == 0 ? 0.0 : ud.lo, side};
    return with_side(ud, side);
  }

  // A cell to evaluate, with the triangle of F last found nearest to `from` (its parent, or itself
  // at an earlier pose) as the first guess of its distance query.
  static Cell hinted(Cell c, const Cell& from) {
    c.near_face = from.near_face;
    return c;
  }

  // The cell of a whole face of the mover (level 0, its own corners).
  static Cell whole_face(std::uint32_t face) { return Cell{0, 0, false, face, 0, {{{0, 0}, {1, 0}, {0, 1}}}}; }

  // Whether the node `child` of the node cell c could not be set aside by its own evaluation's
  // Lipschitz bound: s at its centre x is at most dist(x, F) <= c's distance bound + |x - c's
  // centre| (*ud_hi), less its half-diagonal still below the threshold. Only where c's centre is
  // outside F (inside, a child's depth bound might set it aside). A heuristic: skipping only costs
  // tightness.
  bool hopeless(const Cell& c, std::uint32_t child, double* ud_hi) {
    if (!c.is_node || c.ball.side <= 0 || !(c.ud_hi < kInf)) return false;
    const Aabb pb = moved(o_.boxes.nodes[c.id].bv, t_), kb = moved(o_.boxes.nodes[child].bv, t_);
    const double r = 0.5 * kb.diagonal();
    *ud_hi = up(c.ud_hi + up((kb.center() - pb.center()).norm() * (1.0 + 1e-12)));
    return *ud_hi - r < threshold();
  }

  // hint: a triangle of F likely near the node's centre (unsigned_distance's hint), or -1.
  Cell evaluate_node(std::uint32_t n, const SideBall* parent = nullptr, std::int64_t hint = -1) {
    Cell c{0, 0, true, n, 0, {}};
    if (matches_)
      if (const double e = matches_->node(n); settles(e)) return on_f(c, e);
    const Aabb box = moved(o_.boxes.nodes[n].bv, t_);
    const Vec3 centre = box.center();
    // Half diagonal, plus the rounding of the centre, rounded up.
    const double r = up(up(0.5 * box.diagonal()) * (1.0 + 1e-12));
    ++queries_;
    int known_side = 0;
    if (set_aside_far(centre, r, 0.0, parent, hint, c, &known_side)) return c;
    std::uint32_t nearest = 0;
    bool unique = false;
    const Interval ud = fixed_.unsigned_distance(centre, &nearest, hint, kEnds, &unique);
    c.near_face = nearest;
    c.ud_hi = ud.hi;
    const Interval s = signed_at(centre, ud, parent, &c.ball, known_side, nearest, unique);
    double lower = down(s.lo - r);
    // The depth bound only when it can set the node aside: never when its centre lies below the
    // threshold (every bound of the node is at most s there), e.g. a large box across F at a contact.
    if (lower < threshold() && s.hi < 0.0 && !(s.hi < threshold())) {
      const std::array<Vec3, 8> corners = box.corners();
      TranslatedDepthBound moments;
      const double depth = depth_upper_bound(fixed_, centre, up(ud.hi + 2 * r), corners.data(), 8, ids_, nullptr,
                                             nullptr, nullptr, &moments, 0.0, DepthWeights::sparse, &c.witness);
      lower = std::max(lower, -depth);
      c.depth = keep_depth(moments, 0.0);
    }
    c.lower = lower;
    return c;
  }

  // A cell outside F whose centre lies so far from F that its Lipschitz bound sets it aside: only
  // that is asked (distance_lower, up to a margin beyond the need), not the nearest triangle, which
  // for a centre far inside a hollow shell is found only after most of F's tree (a thin shell's
  // -20 % poses spent most of their time so; doc/performance.md, "Far cells"). Its bound is then
  // the margin's, not its own: only how soon a warm start evaluates it again depends on that.
  // r: the cell's radius about `centre` (with any rounding of it); at_least: a distance below which
  // the caller needs the full evaluation (a face cell's centre, whose s may lower the upper end).
  // *known_side: the centre's side when this decided it (0: not), for the caller's evaluation when
  // this returns false: it then needs no side test of its own.
  bool set_aside_far(const Vec3& centre, double r, double at_least, const SideBall* parent, std::int64_t hint,
                     Cell& c, int* known_side) {
    const double thr = threshold();
    if (!(thr < kInf)) return false;
    // Inside by the parent's ball: its depth bound is needed (the full evaluation).
    const int ball_side = side_from_ball(parent, centre);
    *known_side = ball_side;
    if (ball_side < 0) return false;
    const double need = up(std::max({0.0, thr, at_least}) + r);  // dist >= need: lower = dist - r >= thr
    // A triangle of F nearer than that (the parent's nearest, often) shows the cell is not far.
    if (hint >= 0 && point_triangle_distance_upper_near(centre, fixed_.mesh(), static_cast<std::uint32_t>(hint)) < need)
      return false;
    const double enough = up(need + kFarMargin * (r + std::abs(target_)));
    const double lo = fixed_.distance_lower(centre, enough, need);
    if (!(lo >= need)) return false;
    int side = ball_side;
    if (side == 0) {  // as signed_at would decide it: only lo > 0 matters there
      const Interval ud{lo, kInf};
      side = parent ? fixed_.side(centre, ud, parent->centre, parent->side) : fixed_.side(centre, ud);
      *known_side = side;
    }
    if (side <= 0) return false;  // inside: its depth bound is needed
    c.ball = SideBall{centre, lo, 1};
    c.near_face = hint;
    c.lower = down(lo - r);
    ++far_cells_;
    return true;
  }
  static constexpr double kFarMargin = 2.0;

  // A (sub)triangle cell placed at this pose: corners v, centre m, radius r (every exact cell point
  // within r of m), eta (the corners' distance from the exact sub-triangle's), eta_m (m's).
  struct FaceGeometry {
    std::array<Vec3, 3> v;
    std::array<double, 3> w;  // m = sum w_k v_k
    Vec3 m;
    double r = 0.0, eta = 0.0, eta_m = 0.0;
  };
  FaceGeometry geometry(const Cell& c) const {
    FaceGeometry g;
    const Face& f = (*o_.faces)[c.id];
    const Vec3 &p0 = P_[f[0]], &p1 = P_[f[1]], &p2 = P_[f[2]];
    auto& v = g.v;
    if (c.level == 0) {
      v = {p0, p1, p2};
    } else {
      const Vec3 e1 = p1 - p0, e2 = p2 - p0;
      for (int k = 0; k < 3; ++k) v[k] = p0 + c.bary[k][0] * e1 + c.bary[k][1] * e2;
      g.eta = combination_rounding(p0, e1, e2);
    }
    g.w = centre_weights(c);
    g.m = g.w[0] == g.w[1] && g.w[1] == g.w[2] ? Vec3((v[0] + v[1] + v[2]) / 3.0)
                                                : Vec3(g.w[0] * v[0] + g.w[1] * v[1] + g.w[2] * v[2]);
    // m lies within a few ulps (of the corners' magnitude) of the computed triangle (weights summing
    // to 1, dyadic or thirds); eta_m covers it.
    const double mag = std::max({v[0].cwiseAbs().maxCoeff(), v[1].cwiseAbs().maxCoeff(), v[2].cwiseAbs().maxCoeff()});
    g.eta_m = g.eta + 2e-15 * mag * kSqrt3Up + 1e-300;
    for (const Vec3& x : v) g.r = std::max(g.r, (x - g.m).norm());
    g.r = up(g.r * (1.0 + 1e-12));
    return g;
  }

  // The weights of a face cell's centre m = sum w_k v_k: of the centroid, the edges' midpoints and
  // the middles of the medians, the point whose farthest corner is nearest (r, in every bound,
  // is that distance: a needle's centroid lies 2/3 of its length from the apex, the middle of its
  // median 1/2; an obtuse cell's longest edge's midpoint has the other corner within). Judged in
  // the mover's own coordinates, so the same at every pose. Only tightness depends on it.
  std::array<double, 3> centre_weights(const Cell& c) const {
    const std::array<double, 3> centroid{1.0 / 3, 1.0 / 3, 1.0 / 3};
    const std::array<Vec3, 3> u = own_corners(c);
    const auto radius = [&](const std::array<double, 3>& w) {
      const Vec3 m = w[0] * u[0] + w[1] * u[1] + w[2] * u[2];
      return std::max({(u[0] - m).squaredNorm(), (u[1] - m).squaredNorm(), (u[2] - m).squaredNorm()});
    };
    std::array<double, 3> best = centroid;
    double best_r = 0.95 * 0.95 * radius(centroid);  // another centre only when clearly better
    for (int k = 0; k < 3; ++k) {
      std::array<double, 3> edge{0.5, 0.5, 0.5}, median{0.25, 0.25, 0.25};
      edge[k] = 0.0;
      median[k] = 0.5;
      for (const auto& w : {edge, median}) {
        const double r = radius(w);
        if (r < best_r) best_r = r, best = w;
      }
    }
    return best;
  }

  // The corners of a face cell in the mover's own coordinates, relative to the face's first vertex.
  std::array<Vec3, 3> own_corners(const Cell& c) const {
    return face_cell_corners(mover_.vertices, mover_.faces[c.id], c.bary);
  }

  // The candidate list for the children of a face cell about to be split: the triangles within
  // dist(m, F) + 2.5 r of its centre. A child's centre x lies within r/2 of m (either split), so its
  // nearest triangles lie within dist(x, F) + |x - m| <= dist(m, F) + 2 |x - m| of m, and its depth
  // candidates (within dist(x, F) + 2 r/2 of x) within dist(m, F) + 2 r; the margin covers rounding.
  // nullptr when the list would be long (a traversal per child is then cheaper).
  const ParentCandidates* list_candidates(const Cell& c) {
    if (!(c.ud_hi < kInf) || c.crowded) return nullptr;
    const FaceGeometry g = geometry(c);
    parent_.m = g.m;
    parent_.ud_hi = c.ud_hi;
    parent_.radius = up(c.ud_hi + up(2.5 * g.r));
    if (!fixed_.triangles_within(g.m, parent_.radius, ParentCandidates::kMaxCount, parent_.ids)) return nullptr;
    return &parent_;
  }
  // The separating plane's candidates (evaluate_face): beyond this many, no plane is tried. Such a
  // list is a cell far larger than its distance to F (a sliver across F), where a plane through
  // all of them seldom clears the cell, and gathering them took a tenth of pinion's -20 % time.
  // 32 since session 86 (64 before): a thin tube's slivers overflowed two gathers in three.
  static constexpr std::size_t kMaxSeparatingCandidates = kCandidateListLength;
  // A crowded cell's list would overflow: its ball (radius ud + 2.5 r) holds the gather's (ud + 2 r).
  static_assert(kMaxSeparatingCandidates >= ParentCandidates::kMaxCount, "Cell::crowded implies a long list");

  Cell evaluate_face(Cell c, const SideBall* parent = nullptr, const ParentCandidates* list = nullptr) {
    if (matches_)
      if (const double e = matches_->face(c.id); settles(e)) return on_f(c, e);
    const FaceGeometry geo = geometry(c);
    const auto& v = geo.v;
    const Vec3& m = geo.m;
    const double r = geo.r, eta = geo.eta, eta_m = geo.eta_m;
    // Its bounds carry eta_m and F's near-point errors (about 2e-14 of the coordinates' magnitude,
    // closest_point_error) whatever its size: a cell below them is as tight as it will get. Only
    // where the tolerance is near the doubles' resolution (a part far from the origin).
    c.floored = r <= eta_m + 2.5e-14 * m.cwiseAbs().maxCoeff();
    ++queries_;
    // (Its centre's s could lower the upper end only below upper_.)
    int known_side = 0;
    if (!list && set_aside_far(m, up(r + eta_m), upper_, parent, c.near_face, c, &known_side)) return c;
    // dist(m, F) <= dist(parent centre, F) + |m - parent centre|.
    std::uint32_t nearest = 0;
    bool unique = false;
    const Interval ud = distance_at(fixed_, m, list, list ? list->distance_bound(m) : kInf, &nearest, c.near_face, &unique);
    c.ud_hi = ud.hi;
    c.near_face = nearest;
    const Interval s = signed_at(m, ud, parent, &c.ball, known_side, nearest, unique);
    const auto& w = geo.w;
    offer_upper(up(s.hi + eta_m), c.id,
                {w[0] * c.bary[0][0] + w[1] * c.bary[1][0] + w[2] * c.bary[2][0],
                 w[0] * c.bary[0][1] + w[1] * c.bary[1][1] + w[2] * c.bary[2][1]});
    double lower = down(down(s.lo - r) - eta_m);
    if (lower < threshold() && s.hi < 0.0) {
      // Deep: first the convexity bound of the nearest triangle alone (three enclosures; see
      // restale), which often sets the cell aside before the candidate list is gathered.
      lower = std::max(lower, face_corner_lower(nearest, v.data(), 3, eta));
    }
    // The plane of the nearest face alone, where it supports F: no gather, no distance from the
    // cell to F (a tube's slivers along its wall, each near F all along: that distance was most of
    // the certificates' time).
    if (lower < threshold() && threshold() < 0.0) lower = std::max(lower, hull_lower(v, nearest, eta, false));
    if (lower < threshold()) {
      // Distance from the cell to F, needed only where the cell may reach F (otherwise the
      // Lipschitz bound already proves it disjoint): the nearest triangles of any cell point lie
      // within ud + 2r of m.
      double dlo = down(down(ud.lo - r) - eta_m);
      const double reach = up(ud.hi + 2 * r);
      const bool listed = list && list->covers(m, reach);
      if (listed) fixed_.triangles_within_among(m, reach, list->ids, ids_);
      bool gathered = listed;  // ids_ holds every triangle within reach
      // Only an outside centre can prove the cell disjoint (the first branch below); otherwise
      // the depth bound is taken whatever dlo is (from the triangles gathered here or for the
      // separating plane, else its own gather).
      if (!(dlo > 0.0) && s.lo > 0.0) dlo = cell_distance_lower(v, eta, eta_m, threshold());
      if (dlo > eta_m && s.lo > 0.0) {
        // The exact cell is disjoint from F and on m's side (outside).
        lower = std::max(lower, dlo);
      } else if (s.lo > 0.0 && lower < threshold()) {
        // A cell touching F from outside (a contact): a plane separating it from F nearby, from
        // every triangle within reach.
        // Every triangle within reach, or no plane (kMaxSeparatingCandidates).
        const bool complete = listed || fixed_.triangles_within(m, reach, kMaxSeparatingCandidates, ids_);
        c.crowded = !complete;
        gathered = complete;
        int corner = 0;
        const double sep = complete ? separating_plane_lower(v, m, r, eta_m, ud.lo, &corner) : -kInf;
        if (sep > -kInf) {
          lower = std::max(lower, down(sep - eta));
          // The corner nearest the plane is where the contact is: certify it for the upper end.
          if (lower < upper_) offer_corner(c, v[corner], corner, list, up(ud.hi + r), nearest, eta);
        }
      }
      // No plane where F is not convex at the contact, nor at a centre on F: a face hinged on F's
      // edges from outside. The sign from the centre, or where that lies on F (an edge midpoint on
      // the hinge), from the centroid (eta_m covers either's rounding): a ball about the exact
      // point, free of F and outside it, meets the open cell.
      if (lower < threshold() && matches_ && !(s.hi < 0.0) && interior_apart(c.id, v, eta) &&
          (s.lo > eta_m || (++queries_, fixed_.signed_distance(Vec3((v[0] + v[1] + v[2]) / 3.0)).lo > eta_m)))
        lower = std::max(lower, 0.0);
      // The depth bound sets a cell aside only when -bound >= threshold < 0, and the bound is at
      // least the distance of each point of the cell: where its centre lies outside F farther than
      // -threshold it cannot (eta_m: the computed centre's offset from the cell). Nor, measured,
      // where the cell's radius exceeds twice -threshold: its corners then lie far outside F (a
      // mover face across a thin wall). Such a cell is split without it; only the bound's by-products
      // (its worst corner certified, a warm start's moments) are lost (doc/performance.md,
      // "Post-jump certificates").
      // Except a cell centred on F up to rounding (proved outside by a hair): it may lie on F (a
      // resting or coinciding face), where the depth bound is 0 (doc/poses.md, "Cells lying on F").
      const auto on_f = [&] { return ud.hi <= 4.0 * eta_m + 1e-13 * m.cwiseAbs().maxCoeff(); };
      const bool depth_hopeless = s.lo > 0.0 && threshold() < 0.0 &&
                                  (down(ud.lo - eta_m) > -threshold() || (r > 2.0 * -threshold() && !on_f()));
      if (lower < threshold() && (s.hi < 0.0 || !(dlo > eta_m)) && !depth_hopeless) {
        Vec3 normal = (v[1] - v[0]).cross(v[2] - v[0]);
        const double len = normal.norm();
        int corner = 0;
        if (len > 0.0) normal /= len;
        TranslatedDepthBound moments;
        CornerDistances known;  // for the minimax weights below
        const double depth =
            gathered ? depth_upper_bound_among(fixed_, m, ids_, v.data(), 3, nullptr, len > 0.0 ? &normal : nullptr,
                                             &corner, &moments, coplanar_slack(), DepthWeights::sparse, &c.witness,
                                             &known)
                   : depth_upper_bound(fixed_, m, reach, v.data(), 3, ids_, nullptr, len > 0.0 ? &normal : nullptr,
                                       &corner, &moments, coplanar_slack(), DepthWeights::sparse, &c.witness, &known);
        c.depth = keep_depth(moments, eta);
        // The deepest point of a cell is often a corner (a mover vertex or edge): certify it, so
        // that the upper end meets the convexity bound without subdividing towards that corner.
        // (Not when the cell's own lower bound already reaches the upper end: s at the corner is
        // at least that, so it could not lower the upper end.)
        if (depth < kInf && down(-depth - eta) < upper_) {
          // dist(corner, F) <= dist(m, F) + |corner - m| <= ud.hi + r.
          offer_corner(c, v[corner], corner, list, up(ud.hi + r), nearest, eta);
        }
        lower = std::max(lower, down(-depth - eta));
        // Still not set aside: the weights that minimise the bound over the corners, among the four
        // nearest triangles (doc/poses.md; four measured cheapest, 6 and 12 no tighter where it pays).
        if (lower < threshold() && depth < kInf) {
          DepthWitness w;
          const double mm = down(-minimax_depth_bound(fixed_, ids_, v.data(), 3, 4, &w, &known) - eta);
          if (mm > lower) {
            lower = mm;
            if (w.n > 0) c.witness = w;
          }
        }
        if (lower < threshold() && depth < kInf) lower = std::max(lower, hull_lower(v, nearest, eta, true));
      }
      // A cell centred outside F and across it (a mover face through a wall, or into F through a
      // face), whose convexity bound grows with its corners beyond the faces it crosses: its part
      // that may lie inside F cut by the planes of those faces (slab_lower). (Tried for cells
      // centred inside too: more instructions on every thin part measured.) Not for a cell more
      // than kSlabMaxRadiusDepths times the threshold's depth in radius (a cold start's whole
      // 4-long sliver faces of a thin tube): there a proof cost about 25 us and set aside a
      // quarter of the cells, and splitting them is cheaper (doc/performance.md, "Coarse cells").
      if (lower < threshold() && threshold() < 0.0 && !(dlo > eta_m) && s.lo > 0.0 &&
          !(r > kSlabMaxRadiusDepths * -threshold()))
        lower = std::max(lower, slab_lower(v, m, eta, eta_m, nearest, c.id, c.bary, &c.ball));
    }
    c.lower = lower;
    return c;
  }

  // The corner x (index k) of the face cell c certified for the upper end: dist(x, F) from the
  // list when it covers `ud_bound` (an upper bound of it), the side from c's ball or x's only
  // nearest face where it has one.
  void offer_corner(const Cell& c, const Vec3& x, int k, const ParentCandidates* list, double ud_bound,
                    std::uint32_t hint, double eta) {
    ++queries_;
    std::uint32_t nearest = 0;
    bool unique = false;
    const Interval d = distance_at(fixed_, x, list, ud_bound, &nearest, hint, &unique);
    const Interval s = signed_at(x, d, &c.ball, nullptr, 0, nearest, unique);
    offer_upper(up(s.hi + eta), c.id, c.bary[k]);
  }

  // The bound of s over a cell (corners v within eta of the exact ones) from the planes of F's
  // faces that support F (ClearanceOptions::hull) among its nearest face and the triangles the
  // depth bound gathered (ids_, with `gathered`): s >= the planes' weighted mean, exact where the
  // cell's deepest points lie under faces of F's convex hull, whatever F's tessellation there. The triangle-wise
  // bounds are loose where a cell lies across the long edges of a finely faceted wall (a tube's
  // 4-long slivers: the branch and bound cut them into pieces under 10^-3 all along; doc/poses.md,
  // "Hull planes in the branch and bound"). -inf without a hull plane at the nearest face.
  double hull_lower(const std::array<Vec3, 3>& v, std::uint32_t nearest, double eta, bool gathered) const {
    if (!hull_ || hull_->plane_of(nearest) < 0) return -kInf;
    std::array<std::int32_t, 16> members;
    int n = 0;
    members[n++] = hull_->plane_of(nearest);
    for (std::size_t i = 0; gathered && i < ids_.size() && n < 16; ++i) {
      const std::int32_t p = hull_->plane_of(ids_[i]);
      if (p >= 0 && std::find(members.begin(), members.begin() + n, p) == members.begin() + n) members[n++] = p;
    }
    const HalfspaceBound b = halfspace_bound_among(*hull_, members.data(), n, v.data(), 3, Vec3::Zero());
    return down(b.lower - eta);
  }

  // A lower bound of s over a face cell K (corners v, centre m certainly outside F with
  // dist(m, F) >= ud_lo, radius r) that may touch F, from an axis n separating it from F nearby (a
  // contact seen from outside). With h = max n.w over the vertices w of ids_ (every triangle within
  // reach of m, hence every one that meets a point within r of K) and l = min n.v over K's corners:
  // the region R = {y : dist(y, K) < r, n.y > h} is convex and free of F, and it holds y0 = m +
  // lift n (in m's free ball, so outside F): R lies outside F. A point x of K inside F has n.x <= h,
  // and x + delta n/|n| lies in R for any delta > (h - n.x)/|n|, delta <= (h - l)/|n| < r/2, so
  // dist(x, F) <= (h - l)/|n|: s >= -max(0, h - l)/|n| on K. Axes tried: the nearest triangle's
  // normal (a mover vertex on a face of F), the cell's normal both ways (a vertex of F on a mover
  // face), the direction from F's nearest point to m, and the cross products of the cell's edges
  // with the nearest triangle's (edge on edge). -inf when none separates; `corner` receives the
  // corner of K lowest along the best axis (where the contact is likely).
  double separating_plane_lower(const std::array<Vec3, 3>& v, const Vec3& m, double r, double eta_m, double ud_lo,
                                int* corner) {
    if (!(ud_lo > 0.0) || !(r > 4 * eta_m) || ids_.empty()) return -kInf;
    const auto& F = fixed_.mesh();
    std::uint32_t near = 0;
    fixed_.unsigned_distance_among(m, ids_, &near, kEnds);
    const Face& nf = F.faces[near];
    const Vec3 &a = F.vertices[nf[0]], &b = F.vertices[nf[1]], &cc = F.vertices[nf[2]];
    const Vec3 g = m - closest_point_on_triangle(m, a, b, cc);  // from F towards m
    std::array<Vec3, 14> axes;
    int n_axes = 0;
    axes[n_axes++] = fixed_.planes()[near].n;
    const Vec3 cell_normal = (v[1] - v[0]).cross(v[2] - v[0]);
    axes[n_axes++] = cell_normal;
    axes[n_axes++] = -cell_normal;
    axes[n_axes++] = g;
    const std::array<Vec3, 3> fe{b - a, cc - b, a - cc}, ke{v[1] - v[0], v[2] - v[1], v[0] - v[2]};
    for (const Vec3& x : ke)
      for (const Vec3& y : fe) {
        const Vec3 n = x.cross(y);
        axes[n_axes++] = n.dot(g) < 0.0 ? Vec3(-n) : n;
      }
    double best = -kInf;
    for (int i = 0; i < n_axes; ++i) {
      const double len = axes[i].norm();
      if (!(len > 0.0) || !std::isfinite(len)) continue;
      const Vec3 n = axes[i] / len;
      // l: a lower bound of n.v over the corners; the lowest corner.
      double l = kInf, lowest_value = kInf;
      int lowest = 0;
      for (int k = 0; k < 3; ++k) {
        const PlaneOffset o = plane_offset(n, 0.0, v[k]);
        l = std::min(l, o.value - o.error);
        if (o.value < lowest_value) lowest_value = o.value, lowest = k;
      }
      const double lift = 0.25 * std::min(r, ud_lo);
      const Vec3 y0 = m + lift * n;
      // y0 within m's free ball (outside F) and within r/2 of K (m is within eta_m < r/4 of it).
      if (!(up((y0 - m).norm() * (1.0 + 1e-12)) < std::min(0.5 * r, ud_lo))) continue;
      const PlaneOffset oy = plane_offset(n, 0.0, y0);
      const double y0_at = oy.value - oy.error;  // n.y0 >= this
      double h = -kInf;
      for (std::uint32_t j : ids_) {
        for (std::uint32_t w : F.faces[j]) {
          const PlaneOffset o = plane_offset(n, 0.0, F.vertices[w]);
          h = std::max(h, o.value + o.error);
        }
        if (!(h < y0_at)) break;
      }
      if (!(h < y0_at)) continue;
      // |n| >= norm3_lower(fl(n.n)); h - l rounded up.
      const double bound = h > l ? up(up(h - l) / norm3_lower(n.squaredNorm()) * (1.0 + 1e-15)) : 0.0;
      if (-bound > best && bound < 0.5 * r) {
        best = -bound;
        *corner = lowest;
      }
    }
    return best;
  }

  // A lower bound of s over a face cell K whose centre m lies outside F and which crosses F (a
  // mover face through a thin wall, or dipping into F through a face), or -inf. Its convexity bound
  // grows with its corners beyond the faces it crosses; this one cuts them off. K's computed
  // corners v lie within eta of its exact ones, m within eta_m of a point of K. With T every
  // triangle of F within delta > max(eta, eta_m) of K (a certified superset: triangles_near_triangle
  // about the computed triangle, reach delta + eta), an axis n and h >= n.w >= l over T's vertices w:
  // - R+ = {y : dist(y, K) < delta, n.y > h} is convex and meets no triangle of F (a triangle
  //   meeting it lies within delta of K, so in T, all of whose points have n.y <= h): it lies on
  //   one side of F. It is outside when it holds m, or a corner v_k with n.v_k > h (within eta of
  //   K) whose side is found outside by the segment from m (within delta of K: its crossings are
  //   among T). Likewise R- = {dist(y, K) < delta, n.y < l}.
  // - A point x of K inside F lies in neither (K's points beyond h lie in R+), so n.x <= h where R+
  //   is outside (cut_hi), n.x >= l where R- is (cut_lo); its computed counterpart x~ (within eta)
  //   lies in the computed triangle cut by those planes moved out by eta |n|: in the convex hull of
  //   the computed corners there and of the edges' crossings of the planes, each within `err` of
  //   its computed point (the crossing's parameter enclosed).
  // - The convexity bound over T at those points (any triangles of F give a valid bound) bounds
  //   dist(x~, F) - err from above, and dist(x, F) <= dist(x~, F) + eta.
  // So s >= min(0, -(bound + err + eta)) on K: for a wall whose two faces are planes, half its
  // thickness whatever K's size; for a dip through a plane face, the deepest corner's depth. The
  // axis (the thinnest span of the normals of m's nearest triangle and of T's first four) and the
  // points certified for the upper end (the deepest corner, an edge's point midway through the
  // wall) are heuristics.
  double slab_lower(const std::array<Vec3, 3>& v, const Vec3& m, double eta, double eta_m, std::uint32_t nearest,
                    std::uint32_t face, const std::array<std::array<double, 2>, 3>& bary, SideBall* ball) {
    const double delta = up(2.0 * up(eta + eta_m));  // eta_m > 0
    if (!fixed_.triangles_near_triangle(v, up(delta + eta), kMaxSlabCandidates, slab_ids_)) return -kInf;
    if (slab_ids_.empty()) return 0.0;  // {dist(y, K) < delta} misses F and holds m: K lies outside
    const auto& F = fixed_.mesh();
    // The axis: of the normals of m's nearest triangle and of the first triangles of T, the one
    // across which T's vertices span the thinnest slab (only tightness depends on it).
    const auto span = [&](const Vec3& n, double* h, double* l) {
      *h = -kInf, *l = kInf;
      for (std::uint32_t j : slab_ids_)
        for (std::uint32_t w : F.faces[j]) {
          const PlaneOffset o = plane_offset(n, 0.0, F.vertices[w]);
          *h = std::max(*h, up(o.value + o.error));
          *l = std::min(*l, down(o.value - o.error));
        }
    };
    Vec3 n = fixed_.planes()[nearest].n;
    double h, l;
    span(n, &h, &l);
    double thick = (h - l) / n.norm();
    for (std::size_t i = 0; i < std::min<std::size_t>(slab_ids_.size(), 4); ++i) {
      if (slab_ids_[i] == nearest) continue;  // its span is the one above
      const Vec3 ni = fixed_.planes()[slab_ids_[i]].n;
      double hi, li;
      span(ni, &hi, &li);
      if ((hi - li) / ni.norm() < thick) n = ni, h = hi, l = li, thick = (hi - li) / ni.norm();
    }
    const double n_up = up(n.norm() * (1.0 + 1e-12));  // >= |n|
    const double eta_n = up(eta * n_up);
    std::array<PlaneOffset, 3> ov;
    int top = 0, bottom = 0;
    double reach_hi = -kInf, reach_lo = kInf;  // n.x over K's exact points lies within
    for (int k = 0; k < 3; ++k) {
      ov[k] = plane_offset(n, 0.0, v[k]);
      if (ov[k].value > ov[top].value) top = k;
      if (ov[k].value < ov[bottom].value) bottom = k;
      reach_hi = std::max(reach_hi, up(up(ov[k].value + ov[k].error) + eta_n));
      reach_lo = std::min(reach_lo, down(down(ov[k].value - ov[k].error) - eta_n));
    }
    // Not worth the side tests where the bound seldom sets the cell aside (a heuristic: only the
    // bound decides; 2 |threshold|, not 1, since the points certified below may lower the upper
    // end): T's slab deeper than 2 |threshold|, halved when K crosses both its planes (a wall).
    const double share = reach_hi > h && reach_lo < l ? 0.5 : 1.0;
    if (!(share * (h - l) < 2.0 * n_up * -threshold())) return -kInf;
    const PlaneOffset om = plane_offset(n, 0.0, m);
    // Whether the region beyond h (above) or l (below) lies outside F.
    const auto outside = [&](int k, bool above) {
      if (above ? down(om.value - om.error) > h : up(om.value + om.error) < l) return true;  // m is in it
      if (!(above ? down(ov[k].value - ov[k].error) > h : up(ov[k].value + ov[k].error) < l)) return false;
      // v_k lies in the region, hence off F (dist > 0); its side from m's (outside).
      return fixed_.side_among(v[k], Interval{std::numeric_limits<double>::min(), kInf}, m, 1, slab_ids_) > 0;
    };
    // The planes that cut K's part that may lie inside F: h when K reaches beyond it and that
    // region is outside, likewise l.
    const bool cut_hi = reach_hi > h && outside(top, true), cut_lo = reach_lo < l && outside(bottom, false);
    if (!cut_hi && !cut_lo) return -kInf;
    // Nor where a part of K kept beyond a plane (inside F there) reaches 2 |threshold| beyond it.
    if ((!cut_hi && reach_hi > h && !(reach_hi - h < 2.0 * n_up * -threshold())) ||
        (!cut_lo && reach_lo < l && !(l - reach_lo < 2.0 * n_up * -threshold()))) return -kInf;
    // The computed triangle cut to the widened slab [ls, hs]: its corners there and the crossings.
    const double hs = cut_hi ? up(h + eta_n) : kInf, ls = cut_lo ? down(l - eta_n) : -kInf;
    SlabCut cut;
    if (!cut_by_slab(v.data(), ov.data(), 3, kTriangleEdges.data(), 3, hs, ls, cut, 8)) return -kInf;
    const int nq = cut.n;
    const auto& q = cut.q;
    const auto& corner_of = cut.corner_of;
    const auto& cross_t = cut.cross_t;
    const double err = cut.err;
    if (nq == 0) return 0.0;  // no point of K inside F
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < nq; ++k) c += q[k];
    c /= nq;
    Vec3 normal = (v[1] - v[0]).cross(v[2] - v[0]);
    const double len = normal.norm();
    if (len > 0.0) normal /= len;
    CornerDistances known;
    int worst = 0;
    const double depth =
        depth_upper_bound_among(fixed_, c, slab_ids_, q.data(), nq, nullptr, len > 0.0 ? &normal : nullptr, &worst,
                                nullptr, coplanar_slack(), DepthWeights::sparse, nullptr, &known);
    if (!(depth < kInf)) return -kInf;
    double lower = down(-up(up(depth + err) + eta));
    // Points certified for the upper end only where the bound leaves the cell (a lower upper end
    // may then set it aside).
    if (lower < threshold()) {
      // An edge across both planes (a wall): its point midway between them is likely among the
      // deepest of K (on a flat wall's mid-plane), so certified it is a good upper end. A point of the
      // computed edge within 4e-15 (|a| + |b|) of the computed one, and within eta of K.
      for (int k = 0; k < 3; ++k) {
        if (!(cross_t[k][0] >= 0.0 && cross_t[k][1] >= 0.0)) continue;
        const Vec3 &a = v[k], &b = v[(k + 1) % 3];
        const double t = 0.5 * (cross_t[k][0] + cross_t[k][1]);
        const Vec3 p = a + t * (b - a);
        ++queries_;
        const Interval sp = signed_at(p, fixed_.unsigned_distance(p, nullptr, nearest, kEnds), ball, nullptr);
        const double rounding = up(4e-15 * (a.cwiseAbs().maxCoeff() + b.cwiseAbs().maxCoeff()));
        const auto &ba = bary[k], &bb = bary[(k + 1) % 3];
        offer_upper(up(up(sp.hi + rounding) + eta), face, {ba[0] + t * (bb[0] - ba[0]), ba[1] + t * (bb[1] - ba[1])});
        break;
      }
    }
    // The deepest point is often a corner of K inside F: certified, it may meet the bound.
    if (corner_of[worst] >= 0 && lower < threshold()) {
      const int k = corner_of[worst];
      ++queries_;
      const Interval s_corner =
          signed_at(v[k], fixed_.unsigned_distance(v[k], nullptr, nearest, kEnds), ball, nullptr);
      offer_upper(up(s_corner.hi + eta), face, bary[k]);
    }
    if (lower < threshold()) {
      const double mm = minimax_depth_bound(fixed_, slab_ids_, q.data(), nq, 4, nullptr, &known);
      lower = std::max(lower, down(-up(up(mm + err) + eta)));
    }
    return std::min(0.0, lower);
  }
  // Triangles near a cell for slab_lower: beyond this many the slab is seldom thin.
  static constexpr std::size_t kMaxSlabCandidates = 32;
  // slab_lower only for cells of radius at most this many times the threshold's depth (16 against
  // 8, 32, 64 and none: doc/performance.md, "Coarse cells").
  static constexpr double kSlabMaxRadiusDepths = 16.0;

  // A lower bound of the distance from the cell (corners v, within eta of the exact cell) to F, or
  // -inf once it is certain to be at most eta_m (the cell may touch F: its value is then not used).
  // F's tree is searched from the cell's box (a long triangle's box reaches far fewer triangles
  // than the ball about its centre): SignedDistance::triangle_squared_distance_lower.
  // With threshold <= 0 (a penetrating pose) any distance above eta_m sets the cell aside, so the
  // search only has to show the cell disjoint from F: F's triangles farther than a few eta are not
  // looked at (on pinion's first penetrating steps this was 37 % of a cold certificate). With
  // threshold > 0 (a cold certificate before a point inside F is found) a distance above
  // 1.125 threshold + need sets the cell aside as well (need > eta: the lower bound returned is then
  // above the threshold, which only falls), so nothing farther is looked at: a 4-long sliver of a
  // finely faceted tube 1.8 from F had visited 3,000 of F's triangles to measure that distance
  // (doc/performance.md, "Cold certificates of thin tubes").
  double cell_distance_lower(const std::array<Vec3, 3>& v, double eta, double eta_m, double threshold) {
    const double touch_sq = down(down(eta_m + eta) * down(eta_m + eta));
    const double need = up(4.0 * up(eta_m + eta));
    const double enough = threshold <= 0.0 ? need : up(up(threshold * 1.125) + need);
    const double enough_sq = enough < kInf ? up(enough * enough) : kInf;
    const double d2lo = fixed_.triangle_squared_distance_lower(v, touch_sq, enough_sq);
    if (d2lo <= touch_sq) return -kInf;
    return down(sqrt_interval({d2lo, d2lo}).lo - eta);
  }

  // Stores a cell's translated depth bound at this pose (eta: its corners' rounding); its index.
  std::int32_t keep_depth(TranslatedDepthBound& b, double eta) {
    if (b.n == 0) return -1;
    b.err = up(b.err + eta);
    depth_.push_back(CellDepthBound{b, t_, o_.transform_error(t_)});
    return static_cast<std::int32_t>(depth_.size() - 1);
  }

  // A stale cell's bound at this pose with no tree query (lower = -inf when there is none), from
  // the triangle f nearest to its centre at its last evaluation: s >= -dist(., F) >= -d_f
  // everywhere (inside s = -dist, outside s >= 0), and d_f is convex, so on the cell s >= -(max
  // over the corners of d_f) (the corners' rounding added): what a fresh evaluation's convexity
  // bound gives when f is still the nearest, minus the tree query. (The Lipschitz bound from the
  // centre, -(d_f(m) + r), is never above it: each corner lies within r of m.)
  Cell restale(const Cell& c) {
    Cell q{-kInf, 0, c.is_node, c.id, c.level, c.bary};
    q.ball = c.ball;
    q.near_face = c.near_face;
    if (c.near_face < 0) return q;
    const auto f = static_cast<std::uint32_t>(c.near_face);
    q.witness = c.witness;
    if (c.is_node) {
      const std::array<Vec3, 8> corners = moved(o_.boxes.nodes[c.id].bv, t_).corners();
      q.lower = face_corner_lower(f, corners.data(), 8, 0.0);
      if (q.lower < threshold() && c.witness.n > 0)
        q.lower = std::max(q.lower, down(-witness_depth_bound(fixed_, c.witness, corners.data(), 8)));
    } else {
      const FaceGeometry geo = geometry(c);
      q.lower = face_corner_lower(f, geo.v.data(), 3, geo.eta);
      // The weights of its last depth bound, at the corners where it is now: on a wall between
      // two faces of F (a plateau, a slide) as tight as a fresh evaluation, without its queries.
      if (q.lower < threshold() && c.witness.n > 0)
        q.lower = std::max(q.lower, down(-up(witness_depth_bound(fixed_, c.witness, geo.v.data(), 3) + geo.eta)));
    }
    return q;
  }

  // -(max over the corners of d_f) - eta: a lower bound of s on their convex hull (d_f is convex,
  // s >= -d_f everywhere), eta the corners' distance from the exact cell's.
  double face_corner_lower(std::uint32_t f, const Vec3* corners, int n, double eta) const {
    return down(-max_distance_upper_near(corners, n, fixed_.mesh(), f) - eta);
  }

  // Whether the relative interior of a cell of mover face f (corners v within eta of the exact
  // ones) misses F's surface: that of the face meets it at most in the triangles
  // triangles_meeting_interior lists (computed once a face), and the cell, within the face, is
  // certified apart from each. Then s keeps one sign on the open cell; a caller whose cell centre
  // lies outside F by more than its rounding has s >= 0 on the whole cell (doc/poses.md, "Faces
  // hinged on F's edges").
  bool interior_apart(std::uint32_t f, const std::array<Vec3, 3>& v, double eta) {
    auto it = interior_lists_.find(f);
    if (it == interior_lists_.end()) {
      const Face& x = (*o_.faces)[f];
      std::vector<std::uint32_t> ids;
      const bool ok = triangles_meeting_interior(fixed_, P_[x[0]], P_[x[1]], P_[x[2]], kMaxInteriorTriangles, ids);
      it = interior_lists_.emplace(f, std::make_pair(ok, std::move(ids))).first;
    }
    if (!it->second.first) return false;
    const double eta_sq = up(eta * eta);
    const auto& V = fixed_.mesh().vertices;
    for (const std::uint32_t id : it->second.second) {
      const Face& t = fixed_.mesh().faces[id];
      if (!(triangle_triangle_squared_distance(V[t[0]], V[t[1]], V[t[2]], v[0], v[1], v[2]).lo > eta_sq)) return false;
    }
    return true;
  }
  static constexpr std::size_t kMaxInteriorTriangles = 16;

  // A cell of faces placed onto F's faces (coincident_faces.h), up to e: |s| <= e at each of its
  // points, for the placed triangles the search bounds (the transform's rounding is widened for
  // after it); e = 0 for F's faces exactly.
  Cell on_f(Cell c, double e) {
    std::uint32_t face = c.id;
    if (c.is_node) {
      std::uint32_t n = c.id;
      while (o_.boxes.nodes[n].count == 0) n = o_.boxes.nodes[n].first;
      face = o_.boxes.order[o_.boxes.nodes[n].first];
    }
    offer_upper(e, face, c.is_node ? std::array<double, 2>{0.0, 0.0} : c.bary[0]);
    c.lower = -e;
    return c;
  }
  bool settles(double e) const { return match_settles(e, tol_); }

  // A certified value of s at a mover surface point (face, barycentrics): the upper end so far.
  void offer_upper(double value, std::uint32_t face, const std::array<double, 2>& bary) {
    if (value < upper_) {
      upper_ = value;
      argmin_face_ = face;
      argmin_bary_ = bary;
    }
  }

  const SignedDistance& fixed_;
  const TriangleMesh& mover_;
  const MoverOrientation& o_;
  const PlacedView P_;
  const Vec3& t_;
  const SupportPlanes* hull_;
  // With the face index and a placed vertex near one of F's (ClearanceOptions::coincident).
  PlacedMatches* matches_;
  // ClearanceOptions::coincident_retry (with `coincident` only, as certify_clearance retries only
  // then; null once asked) and retry_probe_cells: where the search reaches that many cells with a
  // placed vertex near one of F's, it stops for the retry.
  const LazyCoincidentFaces* retry_;
  std::uint64_t probe_cells_;
  // Per mover face, with matches_: whether triangles_meeting_interior succeeded, and its list.
  std::unordered_map<std::uint32_t, std::pair<bool, std::vector<std::uint32_t>>> interior_lists_;
  double tol_, rel_, target_, floor_;
  double upper_ = kInf;
  std::int64_t argmin_face_ = -1;
  std::array<double, 2> argmin_bary_{0.0, 0.0};
  bool keep_discarded_;
  ThreadScratch<BranchAndBoundStorage> scratch_;
  BranchAndBoundStorage& store_;
  std::vector<Cell>& heap_;  // a binary heap under CellOrder, kept as std::priority_queue keeps one
  std::vector<Cell>& discarded_;
  std::vector<CellDepthBound>& depth_;
  std::vector<std::uint32_t>& ids_;
  std::vector<std::uint32_t>& slab_ids_;  // slab_lower's triangles
  double min_discarded_ = kInf;
  std::uint64_t seq_ = 0, queries_ = 0, far_cells_ = 0;
  ParentCandidates parent_;
};

}  // namespace

namespace {

// The certificate from F's supporting planes (ClearanceOptions::support; doc/poses.md, "Supporting
// planes"): every triangle of the placed mover has s >= its weighted plane bound, so c is at least
// the least of them; the upper end is the certified s at the guessed deepest point of the triangle
// with the least bound (a point of the placed mover's surface within eta of the computed one).
// False when the two ends are farther apart than the requested width.
bool halfspace_certificate(const SignedDistance& fixed, const SupportPlanes& support, const MoverOrientation& o,
                           const Vec3& t, const ClearanceOptions& options, ClearanceResult& r) {
  const HalfspaceMinimum m = least_halfspace_bound(support, o, t, options.support_seeds, options.support_trees, options.hint_face);
  if (m.face < 0 || !(m.lower > -kInf)) return false;
  const PlacedView P = o.placed_view(t);
  const Face& tri = (*o.faces)[static_cast<std::size_t>(m.face)];
  const Vec3 &p0 = P[tri[0]], &p1 = P[tri[1]], &p2 = P[tri[2]];
  const Vec3 e1 = p1 - p0, e2 = p2 - p0;
  const Vec3 x = p0 + m.beta * e1 + m.gamma * e2;
  const double upper = up(fixed.signed_distance(x).hi + combination_rounding(p0, e1, e2));
  if (!(m.lower >= relaxed_threshold(upper, options.tolerance, options.relative_tolerance, options.target)))
    return false;
  r.clearance = {m.lower, upper};
  r.argmin_face = m.face;
  r.argmin_beta = m.beta;
  r.argmin_gamma = m.gamma;
  return true;
}

// Whether s stays above a floor on the mover's surface at every pose of a segment of translations
// (check_segment_above, clearance.h; doc/poses.md, "Steps proved over a segment"): the mover's
// cells swept over the segment or a part of it (prisms: the convex hulls of a cell's corners at
// the part's two ends), from a frontier's cells, bounded by the convexity of the distances to F's
// triangles over those corners, split across or along the segment where that is not enough.
class SegmentSearch {
 public:
  SegmentSearch(const SignedDistance& fixed, const MoverOrientation& o, const Vec3& ta, const Vec3& tb, double pad,
                double floor)
      : fixed_(fixed), o_(o), ta_(ta), tb_(tb), pad_(pad),
        floor_(floor) {}

  // end: when not null, receives the leaves at tb (see check_segment_above).
  SegmentCheck run(const ClearanceFrontier& f, std::uint64_t budget, ClearanceFrontier* end) {
    // Every point of a frontier cell moves by at most this from where its bound was evaluated.
    const double shift =
        up(up(std::max((ta_ - f.t).norm(), (tb_ - f.t).norm()) * (1.0 + 1e-12)) + up(f.transform_error + pad_));
    stack_.clear();
    lists_.clear();
    lowest_.clear();
    end_ = end;
    if (end_) {  // (left invalid by check_segment_above until the verdict is `above`)
      end_->cells.clear();
      end_->depth.clear();
    }
    std::vector<std::int32_t> renumber(end_ ? f.depth.size() : 0, -1);
    for (const ClearanceFrontier::Cell& w : f.cells) {
      const double shifted = down(w.lower - shift);
      // The translated depth bound is convex in D (the square root of a maximum of convex
      // quadratics plus convex rounding terms), so over the segment it is largest at an end.
      const bool deep_bound = w.depth >= 0 && !(shifted > floor_);
      const double at_b = deep_bound ? translated_lower(f.depth[w.depth], tb_, pad_) : -kInf;
      if (shifted > floor_ || (deep_bound && std::min(translated_lower(f.depth[w.depth], ta_, pad_), at_b) > floor_)) {
        // Set aside: both bounds hold at tb (within pad_ of the exact pose there). Its translated
        // depth bound is kept, and the certificate's warm start evaluates it at tb as it does for
        // any frontier cell, so it is not evaluated here where the shifted bound sets the cell aside.
        if (end_) {
          ClearanceFrontier::Cell k = w;
          k.lower = std::max(shifted, at_b);
          k.depth = keep_depth_bound(w.depth, f.depth, end_->depth, renumber);
          end_->cells.push_back(k);
        }
        continue;
      }
      stack_.push_back(
          Item{w.is_node, w.id, w.level, w.bary, w.witness, w.near_face, w.ball, -1, {0.0, 1.0}, false, w.level});
      lowest_.push_back(w.lower);
    }
    // The lowest cells first (popped last pushed): where the segment fails, they show it soonest.
    std::vector<std::uint32_t> order(stack_.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return lowest_[a] > lowest_[b] || (lowest_[a] == lowest_[b] && a < b);
    });
    std::vector<Item> sorted;
    sorted.reserve(order.size());
    for (std::uint32_t i : order) sorted.push_back(stack_[i]);
    stack_.swap(sorted);
    SegmentCheck r;
    // The frontier's cells lie at the bottom of the stack, their parts above: `low` of them are
    // still to be done. A try that has spent half its budget on fewer than kAbandon of them
    // gives up (a heuristic: such tries seldom finish; rotor's through thin blades).
    const std::size_t base = stack_.size();
    std::size_t low = base;
    while (!stack_.empty()) {
      low = std::min(low, stack_.size());
      if (r.cells >= budget ||
          (2 * r.cells > budget && static_cast<double>(base - low) < kAbandon * static_cast<double>(base)))
        return r;
      Item c = stack_.back();
      stack_.pop_back();
      ++r.cells;
      const Verdict v = c.is_node ? node_clear(c) : face_clear(c);
      if (v == Verdict::clear) {
        // Its bound holds over its part of the segment; the parts that reach tb cover the cell there.
        if (end_ && c.seg[1] == 1.0)
          end_->cells.push_back({c.bound, c.is_node, c.id, c.level, c.bary, c.ball, -1, c.near_face, c.witness});
        continue;
      }
      if (v == Verdict::below) {
        r.verdict = SegmentVerdict::below;
        return r;
      }
      if (!split(c)) return r;
    }
    r.verdict = SegmentVerdict::above;
    if (end_) {
      end_->t = tb_;
      end_->transform_error = o_.transform_error(tb_);
      end_->valid = true;
    }
    return r;
  }

 private:
  enum class Verdict { clear, split, below };
  struct Item {
    bool is_node;
    std::uint32_t id;
    int level;
    std::array<std::array<double, 2>, 3> bary;
    DepthWitness witness;  // the weights of its own or its parent's depth bound
    std::int64_t near_face;
    SideBall ball;       // a ball free of F with its side (its own or an ancestor's)
    std::int32_t list;   // its parent's candidate list (lists_), or -1
    std::array<double, 2> seg;  // its part of the segment: the poses at[x], x in [seg[0], seg[1]]
    bool along = false;  // when evaluated: to be split along the segment rather than across
    int first_level = 0;  // the level of the frontier cell it is a part of
    double bound = -kInf;  // when cleared: a lower bound of s over its prism (clear())
  };
  // A face cell split this many times below its frontier cell, or a part of the segment this short,
  // is not split further (the segment is left undecided: such a cell is almost surely at a
  // crossing). Counted from the frontier cell: a needle's splits leave pinion's frontier cells at
  // levels 25-39, which an absolute limit of 40 stopped after a few splits.
  static constexpr int kMaxSplits = 24;
  static constexpr double kShortestPart = 0x1p-20;
  // run(): the share of the frontier's cells to be done by half the budget (0.25: no gain; 0.6:
  // rotor's instructions -0.4 %, with pinion moving -1.1 %, spool's unchanged).
  static constexpr double kAbandon = 0.6;

  // Pushes c's parts; false when it cannot be split further.
  bool split(const Item& c) {
    if (!c.is_node && c.level >= c.first_level + kMaxSplits) return false;
    if (!c.is_node && c.along) {
      if (!(c.seg[1] - c.seg[0] > kShortestPart)) return false;
      const double h = 0.5 * (c.seg[0] + c.seg[1]);
      Item x = c;
      x.seg = {c.seg[0], h};
      stack_.push_back(x);
      x.seg = {h, c.seg[1]};
      stack_.push_back(x);
      return true;
    }
    if (c.is_node) {
      const auto& node = o_.boxes.nodes[c.id];
      if (node.count == 0) {
        for (std::uint32_t k = node.first; k < node.first + 2; ++k)
          stack_.push_back(Item{true, k, 0, {}, c.witness, c.near_face, c.ball, -1, c.seg, false, 0});
      } else {
        for (std::uint32_t i = 0; i < node.count; ++i)
          stack_.push_back(Item{false, o_.boxes.order[node.first + i], 0, {{{0, 0}, {1, 0}, {0, 1}}}, c.witness,
                                c.near_face, c.ball, -1, c.seg, false, 0});
      }
      return true;
    }
    // As the branch and bound splits it (needles across their length), judged in the rotated
    // frame (the mover's own coordinates are not at hand; only the cost depends on it).
    const CellChildren kids = split_face_cell(c.bary, face_cell_corners(o_.rotated, (*o_.faces)[c.id], c.bary));
    for (int k = 0; k < kids.count; ++k)
      stack_.push_back(Item{false, c.id, c.level + 1, kids.cells[k], c.witness, c.near_face, c.ball, c.list, c.seg,
                            false, c.first_level});
    return true;
  }

  // Every bound is of s over the convex hull of the computed corners v (both ends), less their
  // rounding eta and pad_ (the exact poses' distance from the computed ends): a point of an exact
  // prism lies within eta + pad_ of the same combination of the computed corners.
  Verdict clear(Item& c, const Vec3* v, int nv, double eta) {
    const auto ok = [&](double depth) {
      c.bound = down(-up(up(depth + eta) + pad_));
      return c.bound > floor_;
    };
    // s >= -d_f everywhere (inside s = -dist, outside s >= 0) and d_f is convex: its largest value
    // over the corners bounds the hull.
    const auto corner_max = [&](std::uint32_t f) { return max_distance_upper_near(v, nv, fixed_.mesh(), f); };
    if (c.witness.n > 0 && ok(witness_depth_bound(fixed_, c.witness, v, nv))) return Verdict::clear;
    if (c.near_face >= 0 && ok(corner_max(static_cast<std::uint32_t>(c.near_face)))) return Verdict::clear;
    Vec3 m = Vec3::Zero();
    for (int k = 0; k < nv; ++k) m += v[k];
    m /= nv;
    double r = 0.0;
    for (int k = 0; k < nv; ++k) r = std::max(r, (v[k] - m).norm());
    // Every hull point within r of the computed m (its rounding: a few ulps of its magnitude).
    r = up(up(r * (1.0 + 1e-12)) + 1e-15 * m.cwiseAbs().maxCoeff());
    const ParentCandidates* list = c.list >= 0 ? &lists_[static_cast<std::size_t>(c.list)] : nullptr;
    std::uint32_t nearest = 0;
    const Interval ud = distance_at(fixed_, m, list, list ? list->distance_bound(m) : kInf, &nearest, c.near_face);
    c.near_face = nearest;
    if (ok(up(ud.hi + r))) return Verdict::clear;  // s >= -dist(m) - r on the hull
    const bool may_clear_outside = down(down(ud.lo - r) - up(eta + pad_)) > floor_;
    // A face cell's m is a mover point at the segment's middle pose up to eta and pad_: deep below
    // the floor there, the segment is refused at once (refusing is always allowed; the caller only
    // steers by it).
    const bool may_be_below = !c.is_node && -ud.lo < floor_;
    if (may_clear_outside || may_be_below) {
      int side = side_from_ball(&c.ball, m);
      if (side == 0) {
        side = fixed_.side(m, ud);
        if (side != 0) c.ball = SideBall{m, ud.lo, side};
      }
      if (side > 0 && may_clear_outside) {  // s(m) >= ud.lo, 1-Lipschitz
        c.bound = down(down(ud.lo - r) - up(eta + pad_));
        return Verdict::clear;
      }
      if (side < 0 && may_be_below) return Verdict::below;
    }
    if (ok(corner_max(nearest))) return Verdict::clear;
    // The convexity bound from the triangles near the hull (any set is valid; those within
    // ud + 2r of m hold every hull point's nearest ones).
    const double reach = up(ud.hi + 2.0 * r);
    DepthWitness w;
    double depth;
    if (list && list->covers(m, reach)) {
      fixed_.triangles_within_among(m, reach, list->ids, ids_);
      depth = depth_upper_bound_among(fixed_, m, ids_, v, nv, nullptr, nullptr, nullptr, nullptr, 0.0,
                                      DepthWeights::sparse, &w);
    } else {
      depth = depth_upper_bound(fixed_, m, reach, v, nv, ids_, nullptr, nullptr, nullptr, nullptr, 0.0,
                                DepthWeights::sparse, &w);
    }
    if (w.n > 0) c.witness = w;
    if (ok(depth)) return Verdict::clear;
    if (depth < kInf && ok(minimax_depth_bound(fixed_, ids_, v, nv, 4, &w))) return Verdict::clear;
    // To be split: its children's candidates (a child's centre and corners lie within r of m, so
    // their nearest triangles within ud + 2.5 r, with margin).
    if (!c.is_node) {
      ParentCandidates l{m, ud.hi, up(ud.hi + up(2.5 * r)), {}};
      if (fixed_.triangles_within(m, l.radius, ParentCandidates::kMaxCount, l.ids)) {
        c.list = static_cast<std::int32_t>(lists_.size());
        lists_.push_back(std::move(l));
      }
    }
    return Verdict::split;
  }
  // The computed pose at x of the segment (ta, tb themselves at its ends), within pad_x() of the
  // exact ta + x (tb - ta) (x dyadic: x (tb - ta) rounds once, the sum once).
  Vec3 at(double x) const { return x == 0.0 ? ta_ : x == 1.0 ? tb_ : Vec3(ta_ + x * (tb_ - ta_)); }
  double pad_x() const { return up(1e-15 * (ta_.cwiseAbs().maxCoeff() + tb_.cwiseAbs().maxCoeff())); }
  Verdict face_clear(Item& c) {
    const Face& f = (*o_.faces)[c.id];
    std::array<Vec3, 6> v;
    double eta = 0.0;
    for (int e = 0; e < 2; ++e) {
      const PlacedView P = o_.placed_view(at(c.seg[e]));
      const Vec3 p0 = P[f[0]], e1 = P[f[1]] - p0, e2 = P[f[2]] - p0;
      for (int k = 0; k < 3; ++k) v[3 * e + k] = p0 + c.bary[k][0] * e1 + c.bary[k][1] * e2;
      eta = std::max(eta, combination_rounding(p0, e1, e2));
    }
    const Verdict verdict = clear(c, v.data(), 6, up(eta + pad_x()));
    if (verdict == Verdict::split) {
      // Split along the segment where its part is longer than the cell is wide and the cell's
      // first end lies in a ball known to be outside F (a mover face entering F: the bound over
      // the whole part is the outside corners' distance, which only a shorter part lowers), else
      // across. A heuristic: only the cost depends on it.
      const Vec3 ma = (v[0] + v[1] + v[2]) / 3.0, mb = (v[3] + v[4] + v[5]) / 3.0;
      const double extent = std::max({(v[0] - ma).norm(), (v[1] - ma).norm(), (v[2] - ma).norm()});
      c.along = (ma - mb).norm() > 2.0 * extent && side_from_ball(&c.ball, ma) > 0;
    }
    return verdict;
  }
  // A node's box at both ends of its part and between lies in the box spanning both (8 corners).
  Verdict node_clear(Item& c) {
    Aabb u = moved(o_.boxes.nodes[c.id].bv, at(c.seg[0]));
    u.extend(moved(o_.boxes.nodes[c.id].bv, at(c.seg[1])));
    const std::array<Vec3, 8> corners = u.corners();
    return clear(c, corners.data(), 8, pad_x());
  }

  const SignedDistance& fixed_;
  const MoverOrientation& o_;
  const Vec3 ta_, tb_;
  const double pad_, floor_;
  std::vector<Item> stack_;
  std::vector<double> lowest_;
  std::vector<ParentCandidates> lists_;
  std::vector<std::uint32_t> ids_;
  ClearanceFrontier* end_ = nullptr;
};

// Whether the hinted point of the mover's surface (ClearanceOptions::hint_face) lies strictly inside
// F at this pose, for penetrating targets: the surfaces are then not apart, and the pair-distance
// path would only look for a crossing pair before handing over to the branch and bound. Where a
// deep-zone jump lands (place_pose tries that path first, in case the mover landed outside F), a
// thin tube's 4-long slivers moving against a machined part had it visit 31,000-265,000 pairs, half
// of the landing's certificate (doc/performance.md, "Landings inside F"). Speed only: the branch
// and bound decides every case, so a point placed in doubles, a little off the exact one, will do.
bool hint_inside(const SignedDistance& fixed, const TriangleMesh& mover, const PlacedView& P,
                 const ClearanceOptions& options) {
  if (!(options.target < 0.0) || options.hint_face < 0 ||
      static_cast<std::size_t>(options.hint_face) >= mover.faces.size())
    return false;
  const Face& f = mover.faces[static_cast<std::size_t>(options.hint_face)];
  const Vec3 &p0 = P[f[0]], &p1 = P[f[1]], &p2 = P[f[2]];
  const Vec3 x = p0 + options.hint_beta * (p1 - p0) + options.hint_gamma * (p2 - p0);
  return fixed.side(x) < 0;
}

}  // namespace

namespace {

ClearanceResult certify_clearance_once(const SignedDistance& fixed, const TriangleMesh& mover,
                                       const std::vector<std::uint32_t>& components,
                                       const MoverOrientation& orientation, const Vec3& t,
                                       const ClearanceOptions& options) {
  ClearanceResult r;
  const PlacedView P = orientation.placed_view(t);
  // Faces placed onto F's faces are looked up only where some vertex is placed onto one of F's (or
  // within CoincidentFaces::radius() of it).
  std::optional<PlacedMatches> matches;
  if (options.coincident && options.coincident->any_vertex(P, orientation.rotated.size()))
    matches.emplace(*options.coincident, orientation.boxes, mover.faces, P);
  if (const double e = matches ? matches->node(0) : -1.0; match_settles(e, options.tolerance)) {
    // Every face lies on F, or within e of it: |s| <= e on the whole placed surface.
    r.clearance = {-e, e};
    r.argmin_face = orientation.boxes.order[0];
    if (options.frontier) options.frontier->valid = false;
    widen_for_transform(r, orientation, t);
    return r;
  }
  if (options.support && !options.support->empty() &&
      halfspace_certificate(fixed, *options.support, orientation, t, options, r)) {
    if (options.frontier) options.frontier->valid = false;
    widen_for_transform(r, orientation, t);
    return r;
  }
  const SweepTrees* trees =
      options.sweep_trees && options.sweep_trees->fixed && options.sweep_trees->mover ? options.sweep_trees : nullptr;
  const auto pair_traversal = [&](DistancePolicy& policy) {
    if (trees) {
      policy.use_sweep_trees(*trees, orientation);
      traverse_pairs_nearest_first(trees->fixed->tree, trees->mover->tree, policy);
    } else {
      traverse_pairs_nearest_first(fixed.tree(), orientation.boxes, policy);
    }
  };
  DistancePolicy dist{fixed.mesh(), fixed.planes(), P, mover.faces, t};
  double scale = fixed.bbox().lo.cwiseAbs().maxCoeff() + fixed.bbox().hi.cwiseAbs().maxCoeff();
  // The mover's root box, moved, bounds every placed vertex (and its extremes are vertices).
  const Aabb mover_box = moved(orientation.boxes.nodes[0].bv, t);
  scale = std::max(scale, mover_box.max_abs());
  dist.tiny_sq = (1e-9 * scale) * (1e-9 * scale);
  dist.margin_sq = (1e-10 * scale) * (1e-10 * scale);
  dist.rel = options.relative_tolerance;
  dist.target = options.target;
  if (options.pair_budget > 0) dist.give_up_after = options.pair_budget;
  const bool try_pairs = options.try_distance_path && !hint_inside(fixed, mover, P, options);
  if (try_pairs) {
    if (options.hint_pair_fixed >= 0 && options.hint_pair_mover >= 0 &&
        static_cast<std::size_t>(options.hint_pair_fixed) < fixed.mesh().faces.size() &&
        static_cast<std::size_t>(options.hint_pair_mover) < mover.faces.size())
      dist.leaf(static_cast<std::uint32_t>(options.hint_pair_fixed), static_cast<std::uint32_t>(options.hint_pair_mover));
    if (!dist.done()) pair_traversal(dist);
  }
  r.pair_tests = dist.tests;
  if (!dist.intersect && !dist.gave_up && dist.best_est_sq < kInf) {
    r.nearest_pair_fixed = dist.best_f;
    r.nearest_pair_mover = dist.best_m;
    // Rigorous upper end from the best pair. Pruned pairs lie beyond the final threshold (it only
    // falls), so min(leaves, threshold) is a lower end; without a relative tolerance it is the
    // leaves' own (tight) when the best pair lies at or below the threshold, else redo rigorously.
    const Face& a = fixed.mesh().faces[dist.best_f];
    const Face& b = mover.faces[dist.best_m];
    const auto& fv = fixed.mesh().vertices;
    const Interval best =
        triangle_triangle_squared_distance(fv[a[0]], fv[a[1]], fv[a[2]], P[b[0]], P[b[1]], P[b[2]]);
    dist.min_lo_sq = std::min({dist.min_lo_sq, best.lo, dist.threshold_sq});
    dist.best_hi_sq = best.hi;
    if (!(best.hi <= dist.threshold_sq) && !(dist.rel > 0.0)) {
      DistancePolicy rigorous{fixed.mesh(), fixed.planes(), P, mover.faces, t};
      rigorous.fast = false;
      pair_traversal(rigorous);
      r.pair_tests += rigorous.tests;
      dist.min_lo_sq = rigorous.min_lo_sq;
      dist.best_hi_sq = rigorous.best_hi_sq;
      dist.intersect = rigorous.intersect;
    }
  }
  bool all_outside = try_pairs && !dist.intersect && !dist.gave_up && dist.min_lo_sq > 0.0;
  if (all_outside)
    for (std::uint32_t v : components)
      if (fixed.side(P[v]) < 0) all_outside = false;
  if (all_outside) {
    r.separated = true;
    r.clearance = sqrt_interval({dist.min_lo_sq, dist.best_hi_sq});
    if (options.frontier) options.frontier->valid = false;
  } else {
    BranchAndBound bb(fixed, mover, orientation, P, t, options, options.frontier != nullptr,
                      matches ? &*matches : nullptr);
    const ClearanceFrontier* warm = options.frontier && options.frontier->valid ? options.frontier : nullptr;
    bb.run(options.max_cells, options.hint_face, options.hint_beta, options.hint_gamma, warm, r);
    if (options.frontier) bb.export_frontier(*options.frontier);
  }
  widen_for_transform(r, orientation, t);
  return r;
}

}  // namespace

namespace {

// Both enclose c for the same exact pose: so does their intersection, never empty. Work is summed;
// the flags are the later run's, the tolerance reached when the intersection is narrow enough.
ClearanceResult intersect_runs(const ClearanceResult& a, ClearanceResult b, double tolerance) {
  b.clearance = {std::max(a.clearance.lo, b.clearance.lo), std::min(a.clearance.hi, b.clearance.hi)};
  b.cells += a.cells;
  b.pair_tests += a.pair_tests;
  b.distance_queries += a.distance_queries;
  b.far_cells += a.far_cells;
  b.transform_error = std::max(a.transform_error, b.transform_error);
  b.tolerance_reached = true;  // so that reaches_tolerance judges the intersection's width alone
  b.tolerance_reached = reaches_tolerance(b, tolerance);
  return b;
}

}  // namespace

ClearanceResult certify_clearance(const SignedDistance& fixed, const TriangleMesh& mover,
                                  const std::vector<std::uint32_t>& components, const MoverOrientation& orientation,
                                  const Vec3& t, const ClearanceOptions& options) {
  ClearanceResult r = certify_clearance_once(fixed, mover, components, orientation, t, options);
  if (!options.coincident || !options.coincident_retry || reaches_tolerance(r, options.tolerance)) return r;
  // Only where some placed vertex lies that near one of F's (the search stops at
  // retry_probe_cells cells when one does: BranchAndBound::run): a hard pose of another kind is
  // not searched twice.
  if (!r.probe_stopped &&
      !options.coincident_retry->get().any_vertex(orientation.placed_view(t), orientation.rotated.size()))
    return r;
  ClearanceOptions wide = options;
  wide.coincident = &options.coincident_retry->get();
  wide.coincident_retry = nullptr;
  wide.frontier = nullptr;  // from the root: the first run's frontier holds cells the index would settle
  if (options.frontier) options.frontier->valid = false;
  const ClearanceResult w =
      intersect_runs(r, certify_clearance_once(fixed, mover, components, orientation, t, wide), options.tolerance);
  if (w.tolerance_reached || !r.probe_stopped) return w;
  // The wide run fell short too: the first search with the whole budget, as without a probe.
  ClearanceOptions whole = options;
  whole.coincident_retry = nullptr;
  return intersect_runs(w, certify_clearance_once(fixed, mover, components, orientation, t, whole),
                        options.tolerance);
}

const char* to_string(SegmentVerdict v) {
  switch (v) {
    case SegmentVerdict::above: return "above";
    case SegmentVerdict::below: return "below";
    case SegmentVerdict::undecided: return "undecided";
  }
  return "?";
}

bool reaches_tolerance(const ClearanceResult& c, double tolerance) {
  const double lo = c.clearance.lo, hi = c.clearance.hi;
  return c.tolerance_reached && std::isfinite(lo) && std::isfinite(hi) &&
         hi - lo <= (tolerance + 4.0 * c.transform_error) * (1.0 + 1e-12);
}

std::uint64_t unknown_pose_pair_budget(const TriangleMesh& fixed, const TriangleMesh& mover) {
  return 16 * static_cast<std::uint64_t>(fixed.faces.size() + mover.faces.size());
}

std::shared_ptr<const SupportPlanes> hull_planes_for(const TriangleMesh& fixed) {
  // The default budget (2e7 vertex tests and node bounds) or 64 a face, whichever is larger: the
  // search by the vertices' tree costs about 18 a face on armadillo x16 (832,000 faces).
  auto S = std::make_shared<SupportPlanes>(
      SupportPlanes::build(fixed, std::max(2e7, 64.0 * static_cast<double>(fixed.faces.size()))));
  if (S->empty()) return nullptr;
  return S;
}

std::shared_ptr<const SupportPlanes> support_planes_for(std::shared_ptr<const SupportPlanes> hull,
                                                        const TriangleMesh& mover) {
  constexpr std::size_t kMaxPlanes = 1024;
  if (mover.faces.empty() || !hull || !hull->convex() || hull->planes().size() > kMaxPlanes) return nullptr;
  return hull;
}

ClearanceResult certify_clearance(const SignedDistance& fixed, const TriangleMesh& mover, const Eigen::Matrix3d& R,
                                  const Vec3& t, double tolerance) {
  ClearanceOptions options;
  options.tolerance = tolerance;
  return certify_clearance(fixed, mover, component_representatives(mover), make_mover_orientation(mover, R), t, options);
}

SegmentCheck check_segment_above(const SignedDistance& fixed, const MoverOrientation& o, const ClearanceFrontier& f,
                                 const Vec3& ta, const Vec3& tb, double pad, double floor, std::uint64_t budget,
                                 ClearanceFrontier* end) {
  if (end) end->valid = false;
  if (!f.valid) return {};
  SegmentSearch s(fixed, o, ta, tb, pad, floor);
  return s.run(f, budget, end);
}
}  // namespace cdbench
