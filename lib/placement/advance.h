#pragma once
// Conservative advancement of a separated mover towards a target clearance > 0 without a
// clearance certificate per step (doc/poses.md, "Separated advance"): a pair traversal bounds, for
// every triangle pair, the first advance at which the pair can come within the target (plus the
// rounding margins) of each other; the least of these bounds is a step that keeps c above the
// target. As FCL's conservative advancement, with rigorous bounds.
#include <cstdint>
#include <limits>
#include <memory>

#include "distance/deep_cover.h"
#include "distance/signed_distance.h"
#include "distance/support_planes.h"
#include "placement/mover.h"
#include "sweep/mesh_sweep.h"

namespace cdbench {

struct SeparatedAdvance {
  double h = 0.0;  // the proven step (0: none); h_max when no pair can come within reach before it
  // The pair that set h (fixed face, mover face), -1 if none: a hint for the next certificate.
  std::int64_t fixed_face = -1, mover_face = -1;
  // With sweep trees: whether their oriented boxes still pruned at the end (ObbTrial); when they
  // did not, the caller's next traversals are cheaper on the box trees.
  bool oriented_paid = false;
};

// Precondition: at the pose t the placed mover's surface (vertices fl(fl(R x) + t)) is outside F and
// disjoint from it, e.g. a certificate at t has a positive lower end. `slack` bounds, over the poses
// t' the caller will take, |t' - (t - mu d)| for the mu that t' stands for (the rounding of the
// pose translation); d has length 1 up to rounding.
// Returns h in [0, h_max] such that, for 0 <= mu <= h, every triangle pair of the placed mover moved
// by -mu d is at least target + slack + the transform's rounding at t and at t' (transform_error)
// apart, strictly for mu < h. Every pose t' within `slack` of t - mu d then has c >= target for the
// exact transform and any double evaluation (c > target for mu < h): the mover's surface stays
// outside F along the way, where c is the least pair distance, and c is 1-Lipschitz in the vertices.
// `hint_fixed`, `hint_mover` (optional): a pair likely to set h (the last certificate's nearest
// pair, the previous step's limiting pair), bounded first so that its bound prunes from the start.
// `trees` (optional): the pairs are visited on these trees instead, their oriented boxes pruning
// too (sweep/mesh_sweep.h, ObbTrial).
SeparatedAdvance separated_advance(const SignedDistance& fixed, const MoverOrientation& orientation, const Vec3& t,
                                   const Vec3& d, double target, double slack, double h_max,
                                   std::int64_t hint_fixed = -1, std::int64_t hint_mover = -1,
                                   const SweepTrees* trees = nullptr);

// Conservative advancement towards a penetrating target by F's supporting planes
// (distance/support_planes.h; doc/poses.md, "Supporting planes"): each mover triangle's weighted
// plane bound falls linearly along the line, so the least of the triangles' crossings of the target
// is a step, much longer than the Lipschitz step where c falls slower than the advance (a convex F,
// whose bound is exact inside it: Newton's method on a piecewise-linear c).
struct HalfspaceAdvance {
  double h = 0.0;          // the proven step (0: none), at most h_max
  std::int64_t face = -1;  // the mover face that set h, and a guess of its deepest point (a hint)
  double beta = 1.0 / 3, gamma = 1.0 / 3;
};
// `slack` as for separated_advance. Returns h in [0, h_max] such that every pose t' within `slack`
// of t - mu d, 0 <= mu <= h, has c >= target for the exact transform and any double evaluation. No
// precondition: the bound holds at every pose. The mover's box tree is walked best first, nodes
// bounded by the planes at their boxes' corners, so that only triangles that may set h are bounded.
// `seeds` (optional): each triangle's members from earlier bounds of the advance, updated (speed
// only). `trees` (optional; only its mover part is used): the mover's sweep tree placed at
// mover_t, walked instead of the box tree, its nodes bounded at their oriented boxes' corners
// (moved to t and grown by the rounding): a long, tilted part's world-aligned boxes are far
// looser. Any tree gives a valid h; h may differ between them.
HalfspaceAdvance halfspace_advance(const SupportPlanes& support, const MoverOrientation& orientation, const Vec3& t,
                                   const Vec3& d, double target, double slack, double h_max,
                                   HalfspaceSeeds* seeds = nullptr, const SweepTrees* trees = nullptr,
                                   std::int64_t hint = -1);

// The least plane bound over the placed mover's triangles at the pose t (no margins: the placed
// doubles' triangles), the same walk: a lower bound of c at t up to the transform's rounding, and
// the face and point where it is least (for the certificate's upper end).
struct HalfspaceMinimum {
  double lower = 0.0;
  std::int64_t face = -1;
  double beta = 1.0 / 3, gamma = 1.0 / 3;
};
HalfspaceMinimum least_halfspace_bound(const SupportPlanes& support, const MoverOrientation& orientation,
                                       const Vec3& t, HalfspaceSeeds* seeds = nullptr,
                                       const SweepTrees* trees = nullptr, std::int64_t hint = -1);

// The latest advance at which the mover can meet a box of F's deep-zone cover
// (distance/deep_cover.h; doc/poses.md, "Deep-zone jumps"): lambda_K such that every pose t' within
// `slack` of t0 + lambda d, lambda_K < lambda <= lambda_max, has its mover's surface (exact
// transform, or any double evaluation of it) outside every box, so c(t') > the cover's target.
// The boxes are grown by twice the transform's rounding at the farthest such pose plus slack, and
// the mover's triangles (the rotated doubles moved by t0 + lambda d, exactly) tested against them.
// -inf when no box is met on the whole line (or the cover is incomplete: then nothing is claimed,
// and the caller must not use it). The search stops at the first contact found at or beyond
// `stop_at` and returns it (a lambda_K that large is of no use to the caller; +inf: the exact
// latest contact). mover_sweep (optional): the orientation's sweep mesh placed at t0
// (OrientationFrame::swept, the same faces), walked instead of the box tree: its oriented boxes
// part thin, tilted nodes from boxes (the answer stays valid; it may differ from the box tree's).
double deep_cover_contact(const DeepCover& cover, const MoverOrientation& orientation, const Vec3& t0, const Vec3& d,
                          double slack, double lambda_max,
                          double stop_at = std::numeric_limits<double>::infinity(),
                          const SweepMesh* mover_sweep = nullptr);

// The same bound without a prebuilt cover: the octree of distance/deep_cover.h grown on demand,
// only where the moving mover comes near it between -lambda_max and lambda_top, its cubes kept at
// a half-diagonal of `cell_size`, or of `clipped_cell_size` when larger and the cube has clips
// (DeepClip: they hold the zone's part of it; doc/poses.md, "Deep-zone jumps"). lambda: the latest lambda <=
// lambda_top at which the mover can meet a kept cube (-inf: none), with the guarantee of
// deep_cover_contact for lambda < lambda' <= lambda_top. Costs cubes where the mover passes near
// the zone, not over all of it: a thin shell's zone, which no budget covers whole, is refined only
// about the contact. complete = false: `max_cubes` cubes were classified before the answer was
// known, and nothing is claimed. `memo` (optional): verdicts shared with other queries of the
// same zone (distance/deep_cover.h), the same answers with less work.
struct DeepZoneContact {
  double lambda = 0.0;
  bool complete = false;
  std::uint64_t cubes = 0;  // cubes classified by this call
  // The mover face of the latest contact and the centre of the zone's cube it met there (F's
  // coordinates): a point of the mover likely inside F at that pose, for the landing's certificate
  // (ClearanceOptions::hint_face). -1: no contact. A hint only.
  std::int64_t face = -1;
  Vec3 cube_centre = Vec3::Zero();
};
// A query that ran out of its budget, kept to be continued by a later call (deep_zone_contact's
// `held`) instead of classified again from the root: a plateau's queries are retried with twice
// the budget, and each retry used to redo its predecessors' cubes.
class HeldZoneQuery {
 public:
  HeldZoneQuery();
  ~HeldZoneQuery();
  HeldZoneQuery(HeldZoneQuery&&) noexcept;
  HeldZoneQuery& operator=(HeldZoneQuery&&) noexcept;
  bool held() const;
  double cell_size() const;          // the held query's (0 when none is held)
  double clipped_cell_size() const;  // the held query's
  void clear();
  struct State;

 private:
  friend DeepZoneContact deep_zone_contact(const SignedDistance&, double, double, const MoverOrientation&,
                                           const Vec3&, const Vec3&, double, double, double, double, std::uint64_t,
                                           DeepCubeMemo*, double, HeldZoneQuery*, const SweepMesh*);
  std::unique_ptr<State> state_;
};
// held (optional): a query that runs out is kept there; one held there for the same fixed mesh,
// target, cell sizes, orientation, t0, d, slack, lambda_max and memo, whose latest contact so far is
// at most lambda_top, is continued with the new lambda_top, stop_at and budget (max_cubes counts
// its cubes from its start). The answer is then the one above for that query's octree: valid, and a
// deterministic function of the calls made. Emptied when a query completes.
// mover_sweep (optional): as for deep_cover_contact.
DeepZoneContact deep_zone_contact(const SignedDistance& fixed, double target, double cell_size,
                                  const MoverOrientation& orientation, const Vec3& t0, const Vec3& d, double slack,
                                  double lambda_max, double lambda_top, double stop_at, std::uint64_t max_cubes,
                                  DeepCubeMemo* memo = nullptr, double clipped_cell_size = 0.0,
                                  HeldZoneQuery* held = nullptr, const SweepMesh* mover_sweep = nullptr);

}  // namespace cdbench
