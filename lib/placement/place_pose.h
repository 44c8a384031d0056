#pragma once
// Placement as in the paper: the mover rotated by R about its reference point (bbox centre), the
// two reference points together, then translated along the approach direction d: it comes from
// far away on the side of +d and moves along -d until its first contact with an offset surface.
// The exact first-contact time (sphere-tree query, exact sweeps) gives the raw pose; polishing then
// advances it conservatively (certification-math note 6) until its certified clearance is within
// the tolerance of the target. See doc/poses.md.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "distance/deep_cover.h"
#include "distance/signed_distance.h"
#include "placement/clearance.h"
#include "placement/mover.h"
#include "sweep/mesh_sweep.h"

namespace cdbench {

struct ApproachSetup {
  const SignedDistance* fixed = nullptr;  // the original fixed surface (certificates)
  const TriangleMesh* mover = nullptr;    // in its own coordinates
  std::vector<std::uint32_t> components;  // component_representatives(*mover)
  Vec3 fixed_ref = Vec3::Zero(), mover_ref = Vec3::Zero();  // bbox centres
  double fixed_radius = 0.0, mover_radius = 0.0;  // max distance of a vertex from the reference point
  // Targets > 0 up to this use the separated advance (PoseOptions::separated_advance): the smaller
  // of 12 e and 1650 e^2 / D, e the smaller of the two meshes' median edge lengths and D of their
  // bounding-box diagonals. A heuristic that only picks the kind of step: the advance's traversal
  // visits every pair that may come within the target, and where that band holds many triangles
  // certified steps are cheaper (measured, doc/poses.md).
  double advance_target_limit = 0.0;
  // The fixed surface's own sweep mesh, when attached: a first contact with it is certified by the
  // exact sweep (a touching pose, c in a few-ulp interval about 0), without a branch and bound.
  const SweepMesh* surface = nullptr;
  // The mover's sweep mesh in its own coordinates, built once: each orientation carries it
  // (placed_sweep_mesh) instead of building a tree.
  std::shared_ptr<const SweepMesh> mover_sweep;
  // F's supporting planes where they pay (support_planes_for: F convex, at most 1,024 planes),
  // else null: penetrating targets then step and certify by them (doc/poses.md,
  // "Supporting planes").
  std::shared_ptr<const SupportPlanes> support;
  // The planes of F's faces that support F, for any F (hull_planes_for; null when none): bounds of
  // the penetrating certificates' cells near F's convex hull (ClearanceOptions::hull).
  std::shared_ptr<const SupportPlanes> hull;
  // A pose of a separated target keeps the sweep trees even where their oriented boxes prune
  // little (ObbTrial): a quarter or more of F's or the mover's faces are long (long_face_share), so
  // the world-aligned boxes of the box trees overlap across the whole crossing (a faceted rod's
  // slivers: a million triangle pairs in one advance). Speed only.
  bool keep_sweep_trees = false;
  // With `support`: its steps at separated targets too, where a quarter or more of F's faces are
  // long (a finely faceted rod or pin: outside F the planes' bound is the distance to a face's
  // plane, within a hair of the distance to F across its sides). Speed only.
  bool separated_planes = false;
};
// The share of m's faces whose longest edge exceeds a quarter of m's bounding-box diagonal (0 for
// an empty mesh).
double long_face_share(const TriangleMesh& m);
// Whether pair traversals between F and the mover keep the sweep trees whatever their oriented
// boxes prune (ApproachSetup::keep_sweep_trees; `cdbench certify` too): a quarter or more of F's
// or the mover's faces are long.
bool long_faces_keep_sweep_trees(const TriangleMesh& fixed, const TriangleMesh& mover);
// mover_sweep: the mover's sweep mesh in its own coordinates when the caller has it (the fixed
// surface's, when the mover is the fixed mesh); built here otherwise.
ApproachSetup make_approach_setup(const SignedDistance& fixed, const TriangleMesh& mover,
                                  std::shared_ptr<const SweepMesh> mover_sweep = nullptr);
// Attaches `surface` (which must outlive the setup) after checking that it has F's vertices and
// faces exactly (std::invalid_argument otherwise).
void attach_surface_sweep(ApproachSetup& setup, const SweepMesh& surface);

// Everything that depends on the orientation only.
struct OrientationFrame {
  MoverOrientation orientation;
  Vec3 t0 = Vec3::Zero();  // fl(fixed_ref - fl(R mover_ref)): reference points together
  SweepMesh swept;         // the mover at fl(fl(R x) + t0), with its sphere tree
};
OrientationFrame make_orientation_frame(const ApproachSetup& setup, const Eigen::Matrix3d& R);
// Whether a frame's box tree is the mover's own tree's shape refitted to the rotated vertices
// (movers of at least 2^18 faces) rather than built from them (make_orientation_frame).
bool refits_mover_boxes(const TriangleMesh& mover);

// The translation of the pose lambda along d: fl(t0 + fl(lambda d)) per coordinate.
Vec3 pose_translation(const OrientationFrame& frame, const Vec3& dir, double lambda);

// Where the raw pose comes from, before polishing by conservative advancement. Each is a pose
// before the first crossing of the target (coming from far along +d), so the advance cannot pass
// it (doc/poses.md):
//  * Offset: the exact first contact with a certified offset at target + 2 band (its band and
//    completeness keep every earlier pose above the target); `cdbench poses --start offset`.
//  * Surface: the exact first contact with the fixed surface itself. Before it the mover is
//    outside F, so c > 0 >= target: valid for every target <= 0 and exact for target 0. Needs no
//    offset mesh; the default for targets <= 0.
//  * Far: no sweep; the mover's bounding sphere apart from F's by more than |target|. Valid for
//    any target; the default for targets > 0.
enum class PoseStart { Offset, Surface, Far };
const char* to_string(PoseStart s);

// Which starts a pose set uses. NoOffsets: the surface for targets <= 0, far away for targets > 0
// (no offset mesh at all; measured cheaper overall, doc/poses.md). Offsets: a certified offset at
// target + 2 band for every target != 0.
enum class StartPolicy { NoOffsets, Offsets };
// The words of `cdbench poses --start` and of the run key: "auto" (NoOffsets), "offset".
const char* to_string(StartPolicy p);
// The start of a level's poses. Target 0 always starts at the surface (its exact first contact is
// the pose); without polishing the raw first contact with the level's own offset is the pose.
// band: the swept offsets' band (absolute). With Offsets and polishing, a target in
// (-kNearSurfaceBands * band, 0) starts at the surface too: its swept offset would lie within two
// bands of F, where an offset costs a mesh as fine as F's details (armadillo +-1.1 band: 35-62 s,
// doc/offsets.md) and would save the polishing of at most two bands.
constexpr double kNearSurfaceBands = 4.0;
PoseStart planned_start(double target, bool polish, StartPolicy policy, double band = 0.0);
// When a level's offset could not be certified: the NoOffsets start (polishing only; returns false
// when there is no valid start without an offset).
bool fallback_start(double target, bool polish, PoseStart* start);

// Polishing steps per pose before it is reported as stalled; the pose-set request's default too.
// Plateaus of saturated depth take hundreds of steps (doc/poses.md).
constexpr int kDefaultMaxSteps = 10000;

// While far from the target an advance step needs only a loose lower bound: the steps' certificates
// stop at a width of this part of the remaining gap (upper end - target, tightening as the search
// lowers the upper end), which costs at most that part of the step; the reported pose gets the full
// tolerance. 3/8: more, cheaper steps; the fewest thread-seconds of 1/16 ... 4/5 on armadillo,
// bunny00 and fandisk_large (1/8: 1.15-1.25x slower), neutral on CAD parts (doc/performance.md).
constexpr double kStepRelativeTolerance = 0.375;
// The same on levels at least a fifth of the maximum penetration deep (deep_cover_wanted): their
// poses slide and cross plateaus, where looser steps cost fewer cells for about as many steps
// (rotor, spool -21 %: 11-13 % faster a pose; 0.5-0.8 alike, 0.9 slower; shallower levels slower
// with it; doc/performance.md, "Looser steps on deep levels").
constexpr double kDeepStepRelativeTolerance = 0.6;
// The same for separated targets that step by certificates (separated_steps_by_certificates):
// there c falls about as fast as the mover advances, so a tighter lower end makes each step
// longer (armadillo x4 and bunny00 +25 %: 14-22 % faster a pose; 0.1-0.2 alike, 0.375 and 0.6
// slower; doc/performance.md, "Tighter steps on separated levels").
constexpr double kSeparatedStepRelativeTolerance = 0.15;

// What a certificate of a pose's polishing is for (PolishEvent): the raw pose's against F (an
// offset's contact, or a contact not certified by the sweep), a far start's, a deep-zone jump's
// landing, after supporting planes' or the separated advance's steps, a proved segment's end, a
// two-sided step's far end, a plain Lipschitz step's, a loose one tightened before the advance
// gives up, and the reported pose's full-width one.
enum class PolishPurpose { contact, far_start, landing, planes, advance, segment_end, two_sided, step, tighten, report };
const char* to_string(PolishPurpose p);

// One event of a pose's polishing, reported as it happens to PoseOptions::trace (diagnostics:
// where a slow pose's steps and cells go; `bench_poses --trace`). Nothing depends on it.
struct PolishEvent {
  // certificate: a certify_clearance run; segment: a check_segment_above try; zone_query: a
  // deep-zone contact asked for a jump (its landing, when taken, is the next certificate).
  enum class Kind { certificate, segment, zone_query };
  Kind kind = Kind::certificate;
  PolishPurpose purpose = PolishPurpose::step;  // certificate
  double target = 0.0;
  // certificate: its pose; segment: the segment's start; zone_query: the pose it was asked from.
  double lambda = 0.0;
  // segment: its end; zone_query: the contact found (NaN: none; beyond -lambda_far: the line
  // misses the zone).
  double to = 0.0;
  Interval clearance;  // certificate
  bool loose = false;  // certificate: a step's loose width (PoseOptions::step_relative_tolerance)
  bool warm = false;   // certificate: started from the previous certificate's frontier
  SegmentVerdict verdict = SegmentVerdict::undecided;  // segment
  // certificate: branch-and-bound cells; segment: cells evaluated; zone_query: octree cubes.
  std::uint64_t work = 0;
  std::uint64_t budget = 0;  // segment: its budget of cells
  // Its wall time (seconds; measured only while tracing; a zone query leaves out the level's
  // cover if it built it: setup): where a level's time goes, by kind, which the cells alone do
  // not tell (a landing's cells each cost a fresh distance query).
  double seconds = 0.0;
};
using PolishTrace = std::function<void(const PolishEvent&)>;

struct PoseOptions {
  double tolerance = 0.0;  // absolute: certificate width and polishing target band
  // The steps' loose certificates' relative width (kStepRelativeTolerance; the level's,
  // LevelDeepZone::options; at most kSeparatedStepRelativeTolerance where a separated target steps
  // by certificates). Only the work depends on it.
  double step_relative_tolerance = kStepRelativeTolerance;
  bool polish = true;
  int max_steps = kDefaultMaxSteps;  // conservative-advancement steps before giving up (reported)
  std::uint64_t max_cells = 400000;
  PoseStart start = PoseStart::Offset;
  // Where c is flat (slope below 1/2), try steps of up to twice the gap proved from both ends
  // (doc/poses.md); off: one-sided Lipschitz steps only (for A/B measurements).
  bool two_sided_steps = true;
  // Targets < 0, on a steady slide (c falling at most 1/8 of the advance): steps of up to 512 gaps
  // proved over the whole segment from the last certificate's frontier (doc/poses.md, "Steps
  // proved over a segment"); off: for A/B measurements.
  bool segment_steps = true;
  // After a segment's search runs out of its budget, segments are tried again once the gap has
  // halved: at most this many times a pose (-1: after every failure; 1: once, as before session
  // 85; for A/B measurements).
  int segment_retries = -1;
  // Where no span of poses resolves c's slope (a slide that holds its gap), segments are gated and
  // aimed by a slope fitted over the last eight poses (since session 89); off: by the secants over
  // the last two steps alone, as before (for A/B measurements).
  bool fitted_segments = true;
  // Targets < 0: where c rests on a floor after a steep fall (flat over the last eight poses, near
  // the target), the deep zone is asked after eight flat steps rather than 20 (since session 89;
  // doc/poses.md, "Deep-zone jumps"); off: for A/B measurements.
  bool floor_queries = true;
  // Targets > 0: once the mover is certified above the target, advance by the pair traversal's
  // reach bounds (advance.h) without a certificate per step; off: a certificate per step (A/B).
  bool separated_advance = true;
  // Targets < 0 with a convex F: steps and certificates from F's supporting planes
  // (ApproachSetup::support); off: certificates and Lipschitz steps only (for A/B measurements).
  bool support_planes = true;
  // Targets < 0: the level's cover of F's deep zone (distance/deep_cover.h), built when a pose
  // first finds c flat: its first contact along the line is a start before the first crossing
  // (doc/poses.md, "Deep-zone jumps"), to which the advance jumps when it lies beyond its own
  // pose. Null: no jumps.
  const LazyDeepCover* deep_cover = nullptr;
  // Where deep_cover runs out of its budget (a zone too large to cover whole: thin shells): the
  // jump's contact from the zone's octree grown about the mover's path (advance.h,
  // deep_zone_contact), at most min(this, deep_zone_cubes_per_cell x the pose's certificate cells
  // so far) cubes per query (and at least deep_zone_min_cubes), tried again once that has doubled,
  // and once more when it reaches this cap. 0: none. A query holds about 330 bytes per cube it
  // classifies (about 1.3 GB at the cap, per thread; 200 before a verdict carried its clips),
  // reached only by poses that have spent a million certificate cells (thin shells' plateaus:
  // doc/performance.md, "Thin shells").
  std::uint64_t deep_zone_cubes = 4000000;
  // A cube costs about what a certificate's cell does: at 4, a query that runs out costs at most
  // about four times the advance it could have spared, and a long plateau soon pays for one
  // (doc/performance.md, "Thin shells").
  double deep_zone_cubes_per_cell = 4.0;
  // On a long plateau (c flat for DeepZoneJumps' 8 steps, falling by at most 1/16 of the advance),
  // this many instead: there the pose's steps while a held query waits for its budget are mostly
  // spared by the jump it finds (the repaired thin shells' -20 % poses: lion 11 %, lion-head 5 %,
  // the shark 6 % faster, their certificate cells 1.3-2x fewer), while thin CAD parts' queries,
  // asked sooner on shorter stretches, seldom wait so long (rotor, spool, pinion moving against
  // spool, a thin tube as the mover: the same work; doc/performance.md, "Long plateaus' budget").
  double deep_zone_long_plateau_cubes_per_cell = 16.0;
  // A query gets at least this many cubes or none: on thin machined parts' plateaus smaller
  // budgets ran out and were paid again, while every query completed within 11,000 (rotor -20 %;
  // doc/performance.md, "Clipped cubes"). A pose reaches it by its own work
  // (deep_zone_cubes_per_cell) or by a plateau: c flat for 4 steps, over which (or over the last
  // two of which) it fell by at most 1/16 of the advance (a steeper fall is a slide that reaches
  // the zone a few steps on).
  std::uint64_t deep_zone_min_cubes = 20000;
  // The level's cube verdicts shared by its poses' octree queries (optional; the same poses either
  // way, less work).
  DeepCubeMemo* deep_zone_memo = nullptr;
  // Called with each event of the polishing (PolishEvent), when set (diagnostics only).
  const PolishTrace* trace = nullptr;
};

// Whether a separated target (> 0) steps by certificates rather than by the separated advance: it is
// beyond ApproachSetup::advance_target_limit, or PoseOptions::separated_advance is off. Their steps'
// certificates stop at kSeparatedStepRelativeTolerance (or the options' width, if tighter).
bool separated_steps_by_certificates(const ApproachSetup& setup, double target, const PoseOptions& options);

// The deep-zone cover a penetrating level uses (PoseOptions::deep_cover): cubes of half-diagonal
// at most |target| / 2 along the zone's boundary, at most 150,000 cubes evaluated (about a second;
// beyond, the level goes without), and at most 1,000 per approach of the level (`approaches`: the
// whole request's, not a shard's, so that shards make the same poses): a cover is built once per
// level and serves its poses, and for a small request one that needs more costs more than the
// octree about each pose's path (doc/performance.md, "Covers sized by the request").
DeepCoverOptions deep_cover_options(double target,
                                    std::uint64_t approaches = std::numeric_limits<std::uint64_t>::max());
// Whether a penetrating level gets a cover at all: its target at least a fifth of the maximum
// penetration deep. Shallower zones lie just under most of F's surface, so a jump to them is short
// while their covers are large (about F's area over target^2; armadillo -10 %: 91,000 cubes for
// no gain; rotor and spool -10 %: over the budget). Such levels still get the octree about the
// mover's path (a memo, no cover), asked only once c has been flat for 4 steps.
bool deep_cover_wanted(double target, double max_penetration);

// How long c has been flat where a pose asks the zone's octree (place_pose): not a plateau; a
// plateau (4 flat steps over which, or over the last two of which, c fell by at most 1/16 of the
// advance); a long one (8 such steps).
enum class ZonePlateau { none, plateau, long_plateau };
// The cube budget of a pose's next octree query (PoseOptions::deep_zone_cubes): cells is the
// pose's certificate cells so far, tried the budget of its last query that ran out (0: none). On a
// plateau at least PoseOptions::deep_zone_min_cubes; on a long one
// deep_zone_long_plateau_cubes_per_cell a cell instead of deep_zone_cubes_per_cell.
// 0: no query is due (below deep_zone_min_cubes, or not yet double the last one, unless it is the
// first at the cap).
std::uint64_t deep_zone_query_budget(const PoseOptions& options, std::uint64_t cells, std::uint64_t tried,
                                     ZonePlateau plateau = ZonePlateau::none);

// A level's deep-zone state, shared by its poses: the cover (built by the first pose that asks)
// and the memo of its octree's cube verdicts. The cover null where deep_cover_wanted says no,
// both null for levels >= 0 or with polishing off. Deterministic: the poses do not depend on which pose
// builds the cover nor on the order the memo fills in.
struct LevelDeepZone {
  std::unique_ptr<LazyDeepCover> cover;
  std::unique_ptr<DeepCubeMemo> memo;
  // kDeepStepRelativeTolerance where deep_cover_wanted, else kStepRelativeTolerance (set with or
  // without polishing and covers).
  double step_relative_tolerance = kStepRelativeTolerance;
  // The options for this level's poses: `base` with its cover, memo and step tolerance. They point
  // into this zone, so not from a temporary (deleted below: such options would dangle).
  PoseOptions options(const PoseOptions& base) const&;
  PoseOptions options(const PoseOptions& base) const&& = delete;
};
LevelDeepZone make_level_deep_zone(const SignedDistance& fixed, double target, double max_penetration, bool polish,
                                   std::uint64_t approaches);

struct PoseOutcome {
  bool contact = false;  // the approach line met the offset surface
  double lambda_raw = 0.0, lambda = 0.0;  // translation along d from the reference placement
  Vec3 t = Vec3::Zero();                  // the pose's translation (x_world = R x + t)
  Interval raw_clearance, clearance;
  bool certified = false;  // clearance is a rigorous interval of width within the tolerance
  bool on_target = false;  // |c - target| <= tolerance, proven
  int steps = 0;
  int two_sided_tries = 0;  // long steps tried where c is flat (each accepted one is a step)
  int kept_tries = 0;       // rejected two-sided tries moved on to after the plain step (a part of it)
  int segment_tries = 0;    // segments tried on a slide (check_segment_above)
  bool continued = false;   // the advance continued from a higher target's pose (ApproachMemo)
  int cover_jumps = 0;      // deep-zone jumps taken (to the cover's contact or the octree's)
  std::uint64_t zone_cubes = 0;  // cubes of the zone's octree classified (deep_zone_contact)
  std::string reason;      // why not certified / not on target
  std::uint64_t sphere_tests = 0, triangle_sweeps = 0, clearance_cells = 0;
};

// Work shared by the levels of one approach (one frame, one direction) when they are placed in
// descending target order (doc/poses.md, "Levels of one approach"):
//  * the exact first contact with a swept surface and its raw certificate (the same for level 0
//    and every surface-started level), reused as is;
//  * the last pose on target: its advance proved c > its target on every farther pose, so a
//    lower target's advance may continue from it instead of from its own start.
struct ApproachMemo {
  struct Contact {
    const SweepMesh* swept = nullptr;
    bool hit = false;
    double lambda = 0.0;
    ClearanceResult certificate;
    ClearanceFrontier frontier;
  };
  struct OnTarget {
    double target = 0.0, lambda = 0.0;
    ClearanceResult certificate;
    ClearanceFrontier frontier;
  };
  std::optional<Contact> contact;
  std::optional<OnTarget> last;
  // The cells of the approach's first branch and bound that started without a frontier (0: none
  // yet): what a cold start costs here, against which a frontier to take over is weighed.
  std::uint64_t cold_cells = 0;
};

// Level indices in descending target order: the order in which the levels of one approach are
// placed with a shared ApproachMemo (ties keep their index order).
std::vector<std::size_t> descending_target_order(const std::vector<double>& targets);

// `swept` is the surface swept against for the raw pose: the offset (start Offset), the fixed
// surface (start Surface), unused for start Far (may be null). When polishing, a raw pose whose
// certificate is neither on target nor above it restarts the advance far away. `memo` (optional):
// the approach's shared work, read and updated; levels must then come in descending target order.
PoseOutcome place_pose(const ApproachSetup& setup, const OrientationFrame& frame, const SweepMesh* swept,
                       const Vec3& dir, double target, const PoseOptions& options, ApproachMemo* memo = nullptr);

}  // namespace cdbench
