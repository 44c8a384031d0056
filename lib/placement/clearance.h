#pragma once
// Certified clearance of a placed mover against the fixed surface F:
//   c = min over the points x of the mover's surface of s(x)
// (s the signed distance to F, negative inside; for a penetrating pose -c is its maximal depth).
// The result [lo, hi] contains c for the exact real transform R x + t of the stored doubles and for
// any IEEE-double evaluation of it. See doc/poses.md for the argument:
//  * surfaces provably disjoint and every mover component outside F: c is the minimum triangle
//    pair distance (certified intervals, exact intersection tests), a few ulps wide;
//  * otherwise branch and bound over the mover's AABB tree, its triangles and their dyadic
//    subdivisions, with the Lipschitz bound, the convexity (depth) bound and a certified
//    cell-to-F distance for cells proved disjoint, down to the requested tolerance;
//  * then widened by twice the transform's rounding bound (ours vs exact, exact vs any other).
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "core/interval.h"
#include "distance/depth_bound.h"
#include "distance/signed_distance.h"
#include "distance/support_planes.h"
#include "placement/coincident_faces.h"
#include "placement/mover.h"
#include "sweep/mesh_sweep.h"

namespace cdbench {

// A ball that certainly does not meet F (radius: a certified lower bound of the distance from its
// centre to F), with the side of F it lies on (-1 inside, +1 outside; 0 = unknown). Every point
// within it is on that side: a cell's centre or corner inside its parent's ball needs no ray test.
struct SideBall {
  Vec3 centre = Vec3::Zero();
  double free = 0.0;
  int side = 0;
};

// A cell's translated depth bound (distance/depth_bound.h) as evaluated at the pose t: at any pose
// t', every point of the cell, placed in doubles, has s >= -(translated_depth(bound, t' - t) + the
// rounding of t' - t + rounding + the rounding of the pose t'); s >= -dist(x, F) holds inside and
// outside. The cell's own corner rounding is in bound.err.
struct CellDepthBound {
  TranslatedDepthBound bound;
  Vec3 t = Vec3::Zero();
  double rounding = 0.0;  // transform_error(t)
};

// The leaves of a branch and bound's search (cells of the mover's surface in its own coordinates,
// with their lower bounds) at the pose t: a warm start for a nearby pose. Every point of a cell
// moves by at most |t' - t| plus the two poses' rounding bounds, and s is 1-Lipschitz, so the old
// lower bounds shifted by that are valid at t'; so is a cell's translated depth bound, which
// falls only as fast as the cell really deepens. Cells are re-evaluated only when they matter.
struct ClearanceFrontier {
  struct Cell {
    double lower;
    bool is_node;
    std::uint32_t id;
    int level;
    std::array<std::array<double, 2>, 3> bary;
    SideBall ball;  // at the frontier's pose: a ball free of F around the cell's centre, and its side
    std::int32_t depth = -1;  // index into `depth`, or -1 (no translated depth bound)
    std::int64_t near_face = -1;  // a triangle of F nearest to its centre when evaluated, or -1
    DepthWitness witness = {};  // the weights of its last depth bound, if any (re-evaluated when stale)
  };
  bool valid = false;
  Vec3 t = Vec3::Zero();
  double transform_error = 0.0;
  std::vector<Cell> cells;
  std::vector<CellDepthBound> depth;
};

struct ClearanceOptions {
  double tolerance = 0.0;             // absolute; target width for the branch-and-bound case
  // A looser width while the upper end is far above `target`: max(tolerance, relative_tolerance *
  // (upper - target)), in the branch and bound and in the pair-distance path (separated poses).
  // For advance steps towards a target, where only the lower end's distance to the target
  // matters; 0 = the absolute tolerance alone. Only the work changes, never the rigour.
  double relative_tolerance = 0.0;
  double target = 0.0;
  // A lower end wanted (-inf: none): while the upper end stays at or above it, the branch and bound
  // goes on past the relative width until the lower end reaches it (a two-sided step's far end,
  // which is refused below it). Only the work changes, never the rigour.
  double floor = -std::numeric_limits<double>::infinity();
  // false: go straight to the branch and bound (which decides every case), skipping the pair
  // distance path that only pays off for separated poses.
  bool try_distance_path = true;
  // The pair-distance path's work limit (triangle pairs; 0 = none): past it the branch and bound
  // decides, with an interval at most `tolerance` wide instead of a few ulps. For poses of unknown
  // status (`cdbench certify`): at a pose where the mover crosses F the path looks for a crossing
  // pair, and where the boxes of long slivers overlap everywhere (two finely faceted tubes) it
  // visited 4-9 million pairs before it found one, 70 % of the command's time.
  std::uint64_t pair_budget = 0;
  std::uint64_t max_cells = 400000;   // safety stop (the result then reports a wider interval)
  // A mover surface point (face, barycentrics) likely to be near the minimum, e.g. the previous
  // pose's: it only speeds up the branch and bound (an early upper bound prunes more). With a
  // target < 0, a hinted point strictly inside F also skips the pair-distance path (the surfaces
  // are not apart; the branch and bound decides). Speed only.
  std::int64_t hint_face = -1;
  double hint_beta = 1.0 / 3, hint_gamma = 1.0 / 3;
  // A triangle pair (fixed face, mover face) likely to be nearest, e.g. the previous pose's: the
  // pair-distance path visits it first, so that its threshold prunes from the start. Speed only.
  std::int64_t hint_pair_fixed = -1, hint_pair_mover = -1;
  // When set (fixed: F's own sweep mesh; mover: this orientation's), the pair-distance path visits
  // node pairs of these trees, their oriented boxes pruning as well (ObbTrial). Speed only.
  const SweepTrees* sweep_trees = nullptr;
  // F's supporting planes (distance/support_planes.h), when F is convex: the certificate is first
  // tried from them (a rigorous lower end from each mover triangle's weighted plane bound, the upper
  // end at its guessed deepest point), which is tight wherever c < 0; the usual paths run when it
  // is not tight enough. For penetrating poses; speed only.
  const SupportPlanes* support = nullptr;
  // In/out, with `support`: its triangles' members from the advance's earlier bounds (speed only).
  HalfspaceSeeds* support_seeds = nullptr;
  // With `support`: the mover's sweep tree (its mover part) for the planes' walk
  // (least_halfspace_bound). Speed only.
  const SweepTrees* support_trees = nullptr;
  // The planes of F's faces that support F (any F; hull_planes_for): a bound of each deep cell of
  // the branch and bound from those at its nearest faces, tight under F's convex hull (a tube's
  // outer wall). Speed only.
  const SupportPlanes* hull = nullptr;
  // In/out: when valid, the branch and bound starts from it; replaced by this run's frontier
  // (invalidated when the distance path decides).
  ClearanceFrontier* frontier = nullptr;
  // F's faces by their corners (coincident_faces.h): a mover face placed exactly onto one of them
  // is settled at s = 0, a node of such faces at once, and a mover lying wholly on F gets [0, 0]
  // before any other path; with it, a cell of a face hinged on F's edges from outside is set aside
  // at s >= 0 (triangles_meeting_interior). For poses of unknown status (`cdbench certify`,
  // `validate`: a part against itself at the identity); approaches never place faces so. Speed only.
  const CoincidentFaces* coincident = nullptr;
  // With `coincident`: where the search ends short of the tolerance, it runs once more with this
  // wider index (faces within its radius of F's settled at [-e, e]: a copy of F written in single
  // precision), and the result's interval is the intersection of the two runs' (each rigorous).
  // Its radius must leave the match room to settle (match_settles: e <= tolerance / 4, and e is up
  // to sqrt(3) times the radius): at most tolerance / 8 (UnknownPoseOptions: also at most 2^-16 of
  // F's largest coordinate). Only after a failure, so that a pose resting a hair apart keeps its
  // interval a few ulps wide where the first run settles it. A first run that reaches
  // retry_probe_cells cells with such a vertex stops there for the wide run (a single-precision copy
  // of armadillo x16 spent its whole 400,000 cells first); if that falls short too, the first
  // search runs again with the whole budget, as without the retry.
  const LazyCoincidentFaces* coincident_retry = nullptr;
  std::uint64_t retry_probe_cells = std::uint64_t(1) << 15;
};

struct ClearanceResult {
  Interval clearance;
  bool tolerance_reached = true;
  bool separated = false;  // decided by the distance path (surfaces disjoint, mover outside)
  // The search stopped short of the tolerance at a cell smaller than its own rounding: the width
  // the doubles allow at these coordinates (a part far from the origin; doc/poses.md).
  bool rounding_floor = false;
  double transform_error = 0.0;
  // Stopped at ClearanceOptions::retry_probe_cells with a placed vertex near one of F's.
  bool probe_stopped = false;
  std::uint64_t pair_tests = 0, cells = 0, distance_queries = 0;
  std::uint64_t far_cells = 0;  // cells set aside by a lower bound of their centre's distance alone
  // Where the branch and bound found its upper end (a hint for the next, nearby pose); -1 if unused.
  std::int64_t argmin_face = -1;
  double argmin_beta = 0.0, argmin_gamma = 0.0;
  // The pair-distance path's nearest pair (fixed face, mover face), when it ran; -1 otherwise.
  std::int64_t nearest_pair_fixed = -1, nearest_pair_mover = -1;
};

// How many of F's triangles a certificate lists for a cell: for a split cell's children (a list
// their queries scan instead of F's tree) and for a separating plane; a cell with more gets none.
// 32 since session 86 (64 before; doc/performance.md, "Shorter candidate lists"). Certificates,
// and so poses, depend on it: `cdbench poses` records it in its run key.
constexpr std::size_t kCandidateListLength = 32;

// ClearanceOptions::pair_budget for poses of unknown status (`cdbench certify`, `cdbench
// validate`): 16 triangle pairs a triangle of the two meshes. Apart poses of CGAL's solids need far
// fewer (bunny00 at +4 %: at most 35,000 of 2.4 million); two finely faceted tubes 5-43 million.
std::uint64_t unknown_pose_pair_budget(const TriangleMesh& fixed, const TriangleMesh& mover);

// Whether a certificate of a given pose settles its clearance to `tolerance`: the search reached
// it and the interval is finite and at most that wide, up to the transform's widening. The branch
// and bound stops there; the distance path of separated poses is tight up to rounding, which far
// out exceeds the tolerance (a translation of 1e20 against the unit sphere: 3e6 wide).
bool reaches_tolerance(const ClearanceResult& c, double tolerance);

// `mover` is the mover mesh in its own coordinates, `components` its component_representatives.
ClearanceResult certify_clearance(const SignedDistance& fixed, const TriangleMesh& mover,
                                  const std::vector<std::uint32_t>& components, const MoverOrientation& orientation,
                                  const Vec3& t, const ClearanceOptions& options);

// Whether the mover's clearance stays above `floor` at every pose of a segment of translations:
// every point of the mover's surface (orientation `o`) placed at any pose within `pad` of the
// computed ends' segment [ta, tb] has s > floor (`pad`: the caller's bound on the exact poses'
// distance from that segment plus the transforms' rounding). From the frontier `f` of a
// certificate at a pose nearby, whose cells move by at most their distance from its pose (their
// lower bounds shifted by that), and where that is not enough from the convexity of the distances
// to F's triangles over each cell's corners at both ends (the cell swept over the segment is
// their convex hull), split where needed (doc/poses.md, "Steps proved over a segment").
enum class SegmentVerdict {
  above,      // proved: c > floor on the whole segment
  below,      // a point of a mover face found below the floor at about the segment's middle pose (a
              // heuristic verdict, for steering: the crossing is likely in the first half)
  undecided,  // the budget of cell evaluations ran out, or a cell could not be split further
};
const char* to_string(SegmentVerdict v);  // "above", "below", "undecided"
struct SegmentCheck {
  SegmentVerdict verdict = SegmentVerdict::undecided;
  std::uint64_t cells = 0;  // cells evaluated
};
// end: when not null, and the verdict is `above`, the search's leaves at tb as a frontier there (a
// warm start for a certificate at tb: each leaf's bound over its part of the segment that reaches
// tb, each frontier cell set aside at once by the bound that set it aside, at tb, with its
// translated depth bound); invalid otherwise.
SegmentCheck check_segment_above(const SignedDistance& fixed, const MoverOrientation& o, const ClearanceFrontier& f,
                                 const Vec3& ta, const Vec3& tb, double pad, double floor, std::uint64_t budget,
                                 ClearanceFrontier* end = nullptr);

// F's supporting planes where they pay as a certificate's first try and for steps
// (ClearanceOptions::support, halfspace_advance): F convex with at most 1,024 distinct face planes.
// Each node and triangle the walk bounds picks its planes from all of them, so many planes cost
// more than the branch and bound saves on a sphere (measured: doc/poses.md, "Supporting planes");
// a finely faceted cylinder, whose triangles are long slivers, gains 5-60x. Null otherwise. `hull`:
// F's supporting planes (hull_planes_for), the same set when F is convex.
std::shared_ptr<const SupportPlanes> support_planes_for(std::shared_ptr<const SupportPlanes> hull,
                                                        const TriangleMesh& mover);
// F's supporting planes for ClearanceOptions::hull: null when no face of F supports it (or the
// search ran over its budget: SupportPlanes::build).
std::shared_ptr<const SupportPlanes> hull_planes_for(const TriangleMesh& fixed);

// The one-call form (builds the mover's orientation tree each time: for many poses of one rotation,
// make_mover_orientation once and call the function above).
ClearanceResult certify_clearance(const SignedDistance& fixed, const TriangleMesh& mover, const Eigen::Matrix3d& R,
                                  const Vec3& t, double tolerance);

}  // namespace cdbench
