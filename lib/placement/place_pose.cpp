#include "placement/place_pose.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include "core/interval.h"
#include "distance/point_triangle_distance.h"
#include "distance/triangle_distance.h"
#include "mesh/components.h"
#include "placement/advance.h"
#include "util/timer.h"

namespace cdbench {
namespace {

// PolishEvent::seconds: a stopwatch only while a trace is being taken.
std::optional<Timer> trace_timer(const PoseOptions& o) {
  return o.trace ? std::optional<Timer>(std::in_place) : std::nullopt;
}

// The Lipschitz steps' relative margin: |d| is 1 only up to rounding (doc/poses.md, "Polishing").
constexpr double kStepMargin = 1e-9;

// The two-sided rule (doc/poses.md, "Long steps where c is flat"): c > target on every pose of a
// stretch of length h whose end poses' certificates have gaps a and b (lower end minus target),
// with the relative margin and twice the rounding slack of the poses.
bool gaps_cover(double a, double b, double h, double slack) { return (a + b) * (1.0 - kStepMargin) - 2.0 * slack >= h; }

// A lower end at the stretch's far end for which gaps_cover(a, lower - target, h, slack) holds
// (ClearanceOptions::floor: a little above the least such).
double far_end_floor(double target, double a, double h, double slack) {
  return target - a + (h + 2.0 * slack) / (1.0 - kStepMargin) + kStepMargin * h;
}

double max_distance(const std::vector<Vec3>& v, const Vec3& c) {
  double r = 0.0;
  for (const Vec3& p : v) r = std::max(r, (p - c).norm());
  return r * (1.0 + 1e-12);
}

// The barycentrics (beta, gamma) on the placed mover face `face` (pose t) of its point nearest to
// the fixed triangle A: at an exact first contact of that pair, the contact point. A hint only
// (clearance.h): any point of the face is a valid one.
// (beta, gamma) of a point q of the placed triangle b0, b0 + e1, b0 + e2: q = b0 + beta e1 + gamma e2
// in the least-squares sense, clamped into the triangle.
std::array<double, 2> bary_on(const Vec3& b0, const Vec3& e1, const Vec3& e2, const Vec3& q) {
  const Vec3 w = q - b0;
  const double a11 = e1.dot(e1), a12 = e1.dot(e2), a22 = e2.dot(e2), det = a11 * a22 - a12 * a12;
  if (!(det > 0.0)) return {1.0 / 3, 1.0 / 3};
  double beta = (a22 * e1.dot(w) - a12 * e2.dot(w)) / det, gamma = (a11 * e2.dot(w) - a12 * e1.dot(w)) / det;
  beta = std::clamp(beta, 0.0, 1.0);
  gamma = std::clamp(gamma, 0.0, 1.0 - beta);
  return {beta, gamma};
}

std::array<double, 2> contact_point_on_mover(const Triangle& A, const OrientationFrame& frame, std::uint32_t face,
                                             const Vec3& t) {
  const PlacedView P = frame.orientation.placed_view(t);
  const Face& f = (*frame.orientation.faces)[face];
  Vec3 p, q;
  triangle_triangle_closest_points(A[0], A[1], A[2], P[f[0]], P[f[1]], P[f[2]], &p, &q);
  return bary_on(P[f[0]], P[f[1]] - P[f[0]], P[f[2]] - P[f[0]], q);
}

// The point of the mover's face `face` placed at t nearest to x.
std::array<double, 2> point_on_mover_near(const OrientationFrame& frame, std::uint32_t face, const Vec3& t,
                                          const Vec3& x) {
  const PlacedView P = frame.orientation.placed_view(t);
  const Face& f = (*frame.orientation.faces)[face];
  const Vec3 q = closest_point_on_triangle(x, P[f[0]], P[f[1]], P[f[2]]);
  return bary_on(P[f[0]], P[f[1]] - P[f[0]], P[f[2]] - P[f[0]], q);
}

void set_hint(ClearanceOptions& o, const std::array<double, 2>& bary, std::uint32_t face) {
  o.hint_face = face;
  o.hint_beta = bary[0];
  o.hint_gamma = bary[1];
}

// A bound on |fl(t0 + lambda d) - (t0 + lambda d)| (two roundings per coordinate, with or without
// FMA) for every pose with |lambda| up to `magnitude`: the margin of every step of the advance.
double pose_rounding_slack(const OrientationFrame& frame, double magnitude) {
  return 8.0 * 0x1p-52 * (frame.t0.cwiseAbs().maxCoeff() + magnitude);
}

// The clearance at the exact first contact with F itself, from the sweep alone (doc/poses.md, "The
// touching pose from the sweep"). The swept mover P0 + lambda* d (P0 = fl(fl(R x) + t0), lambda*
// exact) touches F and, for every lambda > lambda*, has a surface disjoint from F's that came from
// far outside: its clearance is 0 exactly. The pose's mover (exact transform R x + t) is within
// rho = delta(t0) + |t - t0 - lambda* d| of it vertex by vertex, a double evaluation delta(t)
// further, and c is 1-Lipschitz in the vertices. `hint`: the contact point on the mover, kept as
// the result's argmin for the next certificate of the advance.
ClearanceResult touching_certificate(const OrientationFrame& frame, const Vec3& dir, const mpq_class& lambda_exact,
                                     double lambda, double tolerance, std::uint32_t face,
                                     const std::array<double, 2>& hint) {
  // |lambda - lambda*| rounded up (get_d is within a relative 2^-52 of the rational).
  const mpq_class gap = abs(lambda_exact - mpq_class(lambda));
  const double dl = round_up(gap.get_d() * (1.0 + 1e-15));
  const double slack = pose_rounding_slack(frame, std::abs(lambda));
  ClearanceResult r;
  r.transform_error = frame.orientation.transform_error(pose_translation(frame, dir, lambda));
  // |d| <= 1 + 2^-52 (a normalised double vector): the factor covers it and the sums' rounding.
  const double w =
      round_up((frame.orientation.transform_error(frame.t0) + slack + dl + r.transform_error) * (1.0 + 1e-14));
  r.clearance = {-w, w};
  r.tolerance_reached = 2.0 * w <= tolerance;
  r.argmin_face = face;
  r.argmin_beta = hint[0];
  r.argmin_gamma = hint[1];
  return r;
}

// The median of a mesh's edge lengths (each face's three edges; 0 for an empty mesh).
double median_edge_length(const TriangleMesh& m) {
  if (m.faces.empty()) return 0.0;
  std::vector<double> len(3 * m.faces.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m.faces.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      for (int k = 0; k < 3; ++k)
        len[3 * i + k] = (m.vertices[m.faces[i][k]] - m.vertices[m.faces[i][(k + 1) % 3]]).norm();
  });
  // The element of rank n/2, found on all threads: lengths are >= 0, whose bit patterns order as
  // the numbers do, so a histogram of the top 16 bits names the bucket holding that rank, and only
  // that bucket is selected from (the same value as nth_element over all: 0.04 s serial at 832K
  // faces).
  const auto bits = [&](std::size_t i) {
    std::uint64_t b;
    std::memcpy(&b, &len[i], sizeof b);
    return b;
  };
  using Histogram = std::vector<std::size_t>;
  const Histogram count = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, len.size(), 65536), Histogram(),
      [&](const tbb::blocked_range<std::size_t>& r, Histogram h) {
        if (h.empty()) h.assign(65536, 0);
        for (std::size_t i = r.begin(); i != r.end(); ++i) ++h[bits(i) >> 48];
        return h;
      },
      [](Histogram a, const Histogram& b) {
        if (a.empty()) return b;
        for (std::size_t k = 0; k < b.size(); ++k) a[k] += b[k];
        return a;
      });
  std::size_t rank = len.size() / 2, bucket = 0;
  while (rank >= count[bucket]) rank -= count[bucket++];
  std::vector<double> in_bucket;
  in_bucket.reserve(count[bucket]);
  for (std::size_t i = 0; i < len.size(); ++i)
    if (bits(i) >> 48 == bucket) in_bucket.push_back(len[i]);
  std::nth_element(in_bucket.begin(), in_bucket.begin() + static_cast<std::ptrdiff_t>(rank), in_bucket.end());
  return in_bucket[rank];
}

// The advance's poses since its start or last jump, for the slope of c on a slide (a heuristic: it
// only aims steps). The secants over one or two steps that gate the two-sided and segment steps are
// mostly the noise of loose certificates there (up to 3/8 of the gap wide, while a step closes a
// few per cent of it: spool with pinion moving, slopes 0.02-0.1 read as 0 to 0.6). Back to the
// latest pose whose gap was kSpanGaps times the present one, c has fallen about three gaps against
// about a gap of certificate widths.
class SlideHistory {
 public:
  void clear() { poses_.clear(); }
  void add(double lambda, double gap, double mid_gap) { poses_.push_back({lambda, gap, mid_gap}); }
  // The secant of c's midpoints from that pose to this one (lambda, gap = c_lo - target, mid_gap =
  // c_mid - target), at least 0; -1 when none of the last kMaxBack poses had such a gap.
  double slope(double lambda, double gap, double mid_gap) const {
    const std::size_t stop = poses_.size() > kMaxBack ? poses_.size() - kMaxBack : 0;
    for (std::size_t j = poses_.size(); j-- > stop;)
      if (poses_[j].gap >= kSpanGaps * gap && poses_[j].lambda > lambda)
        return std::max(0.0, (poses_[j].mid_gap - mid_gap) / (poses_[j].lambda - lambda));
    return -1.0;
  }
  // The least-squares slope of c's midpoints against lambda over the last kFitPoses poses (c's
  // fall per unit advanced), at least 0; -1 with fewer poses. Where the gap holds still, no span
  // resolves (a slide at 1/100 along a wall, a few per cent of the gap a step): the midpoints' noise
  // is up to 3/8 of the gap each, and the secants over one or two steps read it as slopes of 0 to
  // 0.6, while the fit over eight steps of about two gaps each sees through it.
  double fitted_slope() const {
    if (poses_.size() < kFitPoses) return -1.0;
    const std::size_t first = poses_.size() - kFitPoses;
    double ml = 0.0, mc = 0.0;
    for (std::size_t j = first; j < poses_.size(); ++j) ml += poses_[j].lambda, mc += poses_[j].mid_gap;
    ml /= static_cast<double>(kFitPoses);
    mc /= static_cast<double>(kFitPoses);
    double cov = 0.0, var = 0.0;
    for (std::size_t j = first; j < poses_.size(); ++j) {
      cov += (poses_[j].lambda - ml) * (poses_[j].mid_gap - mc);
      var += (poses_[j].lambda - ml) * (poses_[j].lambda - ml);
    }
    return var > 0.0 ? std::max(0.0, cov / var) : -1.0;
  }
  // 8: 6 and 10 within 3 % of it (doc/performance.md, "Slides fitted over eight poses").
  static constexpr std::size_t kFitPoses = 8;
  // 4: measured against 3 and 8 (doc/performance.md, "Slopes over a span").
  static constexpr double kSpanGaps = 4.0;
  static constexpr std::size_t kMaxBack = 128;

 private:
  struct Pose {
    double lambda, gap, mid_gap;
  };
  std::vector<Pose> poses_;
};

// Where a pose may jump across a plateau (PoseOptions::deep_cover): the level's cover, asked once
// per pose; where that ran out of its budget, the zone's octree about the mover's path, as often as
// its budget allows, and where its contact was not worth a jump, that octree on long plateaus.
class DeepZoneJumps {
 public:
  DeepZoneJumps(const PoseOptions& o, double target)
      : options_(o),
        target_(target),
        has_cover_(o.deep_cover && target < 0.0 && o.deep_cover->target() == target),
        use_cover_(has_cover_),
        memo_(o.deep_zone_memo && o.deep_zone_memo->target() == target ? o.deep_zone_memo : nullptr),
        // The octree also where the level has no cover (shallower than a fifth of M) but a memo.
        use_octree_(target < 0.0 && o.deep_zone_cubes > 0 && (has_cover_ || memo_)) {}

  bool active() const { return use_cover_ || use_octree_; }

  // The latest contact lambda of the mover moving along -dir with the deep zone, at or below
  // `lambda` (NaN: none known). worth: contacts at or above it are not worth a jump; gap: the
  // certified clearance minus the target at lambda; flat: the steps c has been flat for;
  // flat_slope: c's fall over those steps or the last two, the lesser, divided by the advance;
  // cells: the pose's certificate cells so far; the octree's cubes are added to *zone_cubes.
  double contact(const ApproachSetup& setup, const OrientationFrame& frame, const Vec3& dir, double lambda,
                 double gap, int flat, double flat_slope, double worth, double lambda_far, std::uint64_t cells,
                 std::uint64_t* zone_cubes) {
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    const double pose_slack = pose_rounding_slack(frame, lambda_far);
    contact_face_ = -1;
    if (use_cover_) {
      if (const DeepCover* cover = options_.deep_cover->get()) {
        use_cover_ = false;
        const double lk = deep_cover_contact(*cover, frame.orientation, frame.t0, dir, pose_slack, lambda_far, worth,
                                             &frame.swept);
        // A contact not worth a jump: the cover's cubes (up to about half |target| across) already
        // hold the mover, beside a zone thinner than they are (anchor with spool moving, -35 %: a
        // plateau 1e-3 |target| above a thin rod of zone, 3,507 steps). The octree about the path,
        // whose leaves follow the gap, may still cross it; asked on a long plateau only. Likewise
        // after a jump (since session 75): the cubes may stop the mover a plateau before the zone,
        // or beside a line that never reaches it (pinion through spool at -25 %: 120 steps at
        // 0.1-0.14 |target| above the target, then out of F's far side: `no-contact`).
        cover_asked_ = true;
        return lk;
      }
      use_cover_ = false;
    }
    if (!use_octree_) return kNaN;
    // The cover ran out of its budget, or was asked already: the zone's octree about the mover's
    // path. The mover's surface is at least the gap from the zone here (c is 1-Lipschitz in space),
    // and a kept cube reaches at most twice its half-diagonal beyond it: with leaves of a quarter
    // of the gap the search clears this pose and stops where the mover comes within about half the
    // gap of the zone. A cube with clips (DeepClip) is held to the zone's part of it, tight where F
    // is flat across it, so its leaves are three gaps: on thin machined parts' plateaus the search
    // then stops about where the mover really comes near the zone at a fraction of the cubes
    // (doc/performance.md, "Clipped cubes"). Its budget is the pose's own work so far
    // (PoseOptions::deep_zone_cubes_per_cell), tried again once that has doubled: a query that runs
    // out costs at most a few times the advance it could have spared. A pose flat for kPlateauSteps
    // steps is on a plateau that pays for a query before that (PoseOptions::deep_zone_min_cubes),
    // if c fell by at most kPlateauSlope of the advance over them or over the last two: c falling
    // faster is a slide that meets the zone a few gaps on (about gap / slope), while the query
    // refines the zone about the whole stretch of the mover within a gap of it (an L-shaped sheet
    // bracket: 20,000 cubes a pose to jump two gaps; doc/performance.md, "Slides are not
    // plateaus").
    // A level without a cover (shallower than a fifth of M) asks only once on a plateau: there
    // jumps save thin shells thousands of steps, while before it, and where the zone is a sheet in
    // a thin wall, a query costs more than it saves (doc/performance.md, "Shallow levels" and
    // "Oriented boxes in the zone's octree").
    if (!has_cover_ && flat < kPlateauSteps) return kNaN;
    // After the cover, only from kAfterCoverSteps flat steps: on armadillo's -25 % poses queries
    // after 4 jumped a few gaps on short flat stretches at 16 % more time.
    if (cover_asked_ && flat < kAfterCoverSteps) return kNaN;
    const ZonePlateau plateau = !(flat_slope <= kPlateauSlope) ? ZonePlateau::none
                                : flat >= kLongPlateauSteps    ? ZonePlateau::long_plateau
                                : flat >= kPlateauSteps        ? ZonePlateau::plateau
                                                               : ZonePlateau::none;
    const std::uint64_t budget = deep_zone_query_budget(options_, cells, tried_, plateau);
    if (budget == 0) return kNaN;
    // A query that ran out is held and continued by the next try (with twice the budget) rather
    // than started again, with its own leaves while they are at most 1.2 times the size this gap
    // gives: on a plateau the gap barely changes (doc/performance.md, "Held queries").
    const double fine = kFineLeafGaps * gap;
    const auto ask = [&](HeldZoneQuery& q, double clipped) {
      const bool keep = q.held() && q.cell_size() <= kHeldLeafGrowth * fine;
      return deep_zone_contact(*setup.fixed, target_, keep ? q.cell_size() : fine, frame.orientation, frame.t0, dir,
                               pose_slack, lambda_far, lambda, worth, budget, memo_,
                               keep ? q.clipped_cell_size() : clipped, &q, &frame.swept);
    };
    DeepZoneContact z = ask(clipped_query_, kClippedLeafGaps * gap);
    *zone_cubes += z.cubes;
    if (z.complete && !(z.lambda < worth)) {
      // Clipped leaves of three gaps found the zone within two: their clips may be loose (a curved
      // wall: thin shells). Asked again with every leaf a quarter of the gap before giving up.
      z = ask(fine_query_, 0.0);
      *zone_cubes += z.cubes;
    }
    if (!z.complete) {
      tried_ = budget;
      return kNaN;
    }
    if (!(z.lambda < worth)) use_octree_ = false;  // the zone is within two gaps: no more tries
    contact_face_ = z.face;
    contact_centre_ = z.cube_centre;
    return z.lambda;
  }

  // Where the last contact() that returned a number met the zone (the octree's: its mover face and
  // cube; -1 for the cover's): a hint for the landing's certificate.
  std::int64_t contact_face() const { return contact_face_; }
  const Vec3& contact_centre() const { return contact_centre_; }

  static constexpr double kFineLeafGaps = 0.25, kClippedLeafGaps = 3.0, kHeldLeafGrowth = 1.2;
  // A pose flat for this many steps is on a plateau (a level without a cover asks from then on).
  // A plateau within a tenth of |target| above it asks after kNearPlateauSteps (place_pose;
  // doc/performance.md, "Shallow levels"). 4 since session 57 (8 before; doc/performance.md,
  // "Where a jumped pose's time goes": thin parts 4-8 % fewer instructions, armadillo 1.4 % more).
  // kNearPlateauSteps 20 since session 75 (64 before): rotor's levels just shallower than a fifth
  // of M slide 0.05-0.08 |target| above it for 60 steps and more before one jump ends them (rotor
  // -17 %: 17.4 -> 8.7x FCL); 16 and below cost spool and cactus 8-70 % (doc/performance.md,
  // "Near-target plateaus asked sooner").
  static constexpr int kPlateauSteps = 4, kNearPlateauSteps = 20, kAfterCoverSteps = 16;
  // A plateau this long gets PoseOptions::deep_zone_long_plateau_cubes_per_cell (16 steps: half the
  // gain on the repaired shells, doc/performance.md, "Long plateaus' budget").
  static constexpr int kLongPlateauSteps = 8;
  // Thin machined parts' plateaus (rotor -20 %, alone or with pinion moving) at their fourth
  // step: c fell by at most 1/16 of the advance over the run or over its last two steps, mostly
  // both (some plateaus begin with the end of a fall); glancing slides (a sheet bracket, thin
  // shells) by 0.1-0.4 over both.
  static constexpr double kPlateauSlope = 1.0 / 16;

 private:
  const PoseOptions& options_;
  double target_;
  const bool has_cover_;  // the level has a cover (deep_cover_wanted), asked or not
  bool use_cover_;        // not asked yet in this pose
  DeepCubeMemo* memo_;
  bool use_octree_;
  bool cover_asked_ = false;  // the cover's contact was asked in this pose (jumped to or not)
  std::uint64_t tried_ = 0;  // the budget of the octree's last query that ran out (0: none yet)
  HeldZoneQuery clipped_query_, fine_query_;  // queries that ran out, to be continued
  std::int64_t contact_face_ = -1;
  Vec3 contact_centre_ = Vec3::Zero();
};

}  // namespace

bool separated_steps_by_certificates(const ApproachSetup& setup, double target, const PoseOptions& options) {
  return target > 0.0 && !(options.separated_advance && target <= setup.advance_target_limit);
}

bool deep_cover_wanted(double target, double max_penetration) {
  return target < 0.0 && max_penetration > 0.0 && -target >= 0.2 * max_penetration;
}

DeepCoverOptions deep_cover_options(double target, std::uint64_t approaches) {
  constexpr std::uint64_t kMaxCells = 150000, kCellsPerApproach = 1000;
  DeepCoverOptions o;
  o.cell_size = 0.5 * std::abs(target);
  o.max_cells = approaches >= kMaxCells / kCellsPerApproach ? kMaxCells : kCellsPerApproach * approaches;
  return o;
}

LevelDeepZone make_level_deep_zone(const SignedDistance& fixed, double target, double max_penetration, bool polish,
                                   std::uint64_t approaches) {
  LevelDeepZone z;
  const bool deep = deep_cover_wanted(target, max_penetration);
  if (deep) z.step_relative_tolerance = kDeepStepRelativeTolerance;
  if (!polish || !(target < 0.0)) return z;
  if (deep)
    z.cover = std::make_unique<LazyDeepCover>(fixed, target, deep_cover_options(target, approaches));
  z.memo = std::make_unique<DeepCubeMemo>(target);
  return z;
}

std::uint64_t deep_zone_query_budget(const PoseOptions& options, std::uint64_t cells, std::uint64_t tried,
                                     ZonePlateau plateau) {
  const std::uint64_t least = std::max<std::uint64_t>(options.deep_zone_min_cubes, 1);
  const double per_cell = plateau == ZonePlateau::long_plateau ? options.deep_zone_long_plateau_cubes_per_cell
                                                               : options.deep_zone_cubes_per_cell;
  double by_work = per_cell * static_cast<double>(cells);
  if (plateau != ZonePlateau::none) by_work = std::max(by_work, static_cast<double>(least));
  const std::uint64_t budget = by_work >= static_cast<double>(options.deep_zone_cubes)
                                   ? options.deep_zone_cubes
                                   : static_cast<std::uint64_t>(by_work);
  // Once the budget reaches its cap, one last query at the cap even if that is less than double.
  const bool last_at_cap = budget == options.deep_zone_cubes && tried < budget;
  if (budget < least || (budget < 2 * tried && !last_at_cap)) return 0;
  return budget;
}

PoseOptions LevelDeepZone::options(const PoseOptions& base) const& {
  PoseOptions o = base;
  o.deep_cover = cover.get();
  o.deep_zone_memo = memo.get();
  o.step_relative_tolerance = step_relative_tolerance;
  return o;
}

Vec3 pose_translation(const OrientationFrame& f, const Vec3& dir, double lambda) {
  return Vec3(f.t0[0] + lambda * dir[0], f.t0[1] + lambda * dir[1], f.t0[2] + lambda * dir[2]);
}

// F's planes from which their steps are tried at separated targets too (ApproachSetup::
// separated_planes).
constexpr std::size_t kSeparatedPlanesMin = 128;

double long_face_share(const TriangleMesh& m) {
  if (m.faces.empty()) return 0.0;
  const double limit_sq = 0.0625 * m.bbox().diagonal() * m.bbox().diagonal();
  std::size_t n = 0;
  for (const Face& f : m.faces) {
    const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
    n += std::max({(a - b).squaredNorm(), (b - c).squaredNorm(), (c - a).squaredNorm()}) > limit_sq;
  }
  return static_cast<double>(n) / static_cast<double>(m.faces.size());
}

bool long_faces_keep_sweep_trees(const TriangleMesh& fixed, const TriangleMesh& mover) {
  const bool same = mover.vertices == fixed.vertices && mover.faces == fixed.faces;
  const double fixed_share = long_face_share(fixed);
  return std::max(fixed_share, same ? fixed_share : long_face_share(mover)) >= 0.25;
}

void attach_surface_sweep(ApproachSetup& setup, const SweepMesh& surface) {
  const TriangleMesh& F = setup.fixed->mesh();
  if (surface.vertices != F.vertices || surface.faces != F.faces)
    throw std::invalid_argument("attach_surface_sweep: the sweep mesh is not the fixed surface");
  setup.surface = &surface;
}

ApproachSetup make_approach_setup(const SignedDistance& fixed, const TriangleMesh& mover,
                                  std::shared_ptr<const SweepMesh> mover_sweep) {
  if (mover_sweep && (mover_sweep->vertices != mover.vertices || mover_sweep->faces != mover.faces))
    throw std::invalid_argument("make_approach_setup: the sweep mesh is not the mover's");
  ApproachSetup s;
  s.fixed = &fixed;
  s.mover = &mover;
  s.components = component_representatives(mover);
  const Aabb mover_box = mover.bbox();
  s.fixed_ref = fixed.bbox().center();
  s.mover_ref = mover_box.center();
  s.fixed_radius = max_distance(fixed.mesh().vertices, s.fixed_ref);
  s.mover_radius = max_distance(mover.vertices, s.mover_ref);
  const bool same = mover.vertices == fixed.mesh().vertices && mover.faces == fixed.mesh().faces;
  {
    // The pairs within reach of a target tau lie in a band about the contact about sqrt(R tau)
    // across (R a curvature radius, here the smaller diagonal), holding some R tau / e^2 triangles
    // of median edge e: the advance pays while tau/e is at most 12 and (tau/e)(D/e) at most 1650
    // (measured on armadillo and its subdivisions and bunny00: doc/poses.md).
    const double e_fixed = median_edge_length(fixed.mesh());
    const double e = same ? e_fixed : std::min(e_fixed, median_edge_length(mover));
    const double D = std::min(fixed.bbox().diagonal(), mover_box.diagonal());
    s.advance_target_limit = D > 0.0 ? std::min(12.0 * e, 1650.0 * e * e / D) : 0.0;
  }
  const double fixed_share = long_face_share(fixed.mesh());
  s.keep_sweep_trees = long_faces_keep_sweep_trees(fixed.mesh(), mover);
  // Only a convex F: there the planes' bound is exact wherever s < 0. A non-convex F's hull faces
  // bound only the parts of a penetration near them.
  s.hull = hull_planes_for(fixed.mesh());
  s.support = support_planes_for(s.hull, mover);
  // Where the separated advance is dear: its sliver pairs near a crossing grow with the square of
  // the sides, the planes' walk hardly (instructions of 40 approaches of pins and a rod against
  // themselves, doc/performance.md, "The planes at separated levels": 64 sides +22 %, 200 -7 %,
  // 500 -53 %, 1,000 -46 %).
  s.separated_planes = s.support && fixed_share >= 0.25 && s.support->planes().size() >= kSeparatedPlanesMin;
  s.mover_sweep = mover_sweep ? std::move(mover_sweep)
                              : std::make_shared<const SweepMesh>(make_sweep_mesh(mover.vertices, mover.faces));
  return s;
}

bool refits_mover_boxes(const TriangleMesh& mover) { return mover.faces.size() >= (std::size_t(1) << 18); }

OrientationFrame make_orientation_frame(const ApproachSetup& setup, const Eigen::Matrix3d& R) {
  OrientationFrame f;
  const Vec3 rc = R * setup.mover_ref;
  f.t0 = setup.fixed_ref - rc;
  // The box tree and the sweep tree at once. The sweep tree is carried from the mover's own
  // (O(nodes)). The box tree is built anew (median splits of the rotated centroids) for movers of
  // fewer than 2^18 faces; larger ones get their own sweep tree's shape refitted to the
  // rotated vertices (O(nodes), on all threads): at 832,000 faces a build was half of a frame's
  // cost, while the refitted boxes, a little looser, cost 2-3 % more pose work at 52,000 faces
  // (doc/performance.md, "An orientation's frame").
  f.orientation = rotate_mover(*setup.mover, R);
  tbb::parallel_invoke([&] {
                         if (setup.mover_sweep && refits_mover_boxes(*setup.mover))
                           f.orientation.boxes = refit_triangle_boxes(setup.mover_sweep->tree, f.orientation.rotated,
                                                                      *f.orientation.faces);
                         else
                           build_mover_boxes(f.orientation);
                       },
                       [&] {
                         f.swept = setup.mover_sweep
                                       ? placed_sweep_mesh(*setup.mover_sweep, R, f.t0, f.orientation.placed(f.t0),
                                                           f.orientation.transform_error(f.t0))
                                       : make_sweep_mesh(f.orientation.placed(f.t0), setup.mover->faces);
                       });
  return f;
}

const char* to_string(PoseStart s) {
  switch (s) {
    case PoseStart::Offset: return "offset";
    case PoseStart::Surface: return "surface";
    case PoseStart::Far: return "far";
  }
  return "?";
}

const char* to_string(PolishPurpose p) {
  switch (p) {
    case PolishPurpose::contact: return "contact";
    case PolishPurpose::far_start: return "far-start";
    case PolishPurpose::landing: return "landing";
    case PolishPurpose::planes: return "planes";
    case PolishPurpose::advance: return "advance";
    case PolishPurpose::segment_end: return "segment-end";
    case PolishPurpose::two_sided: return "two-sided";
    case PolishPurpose::step: return "step";
    case PolishPurpose::tighten: return "tighten";
    case PolishPurpose::report: return "report";
  }
  return "?";
}

const char* to_string(StartPolicy p) { return p == StartPolicy::Offsets ? "offset" : "auto"; }

PoseStart planned_start(double target, bool polish, StartPolicy policy, double band) {
  if (target == 0.0) return PoseStart::Surface;
  if (!polish) return PoseStart::Offset;
  if (policy == StartPolicy::Offsets && !(target < 0.0 && target > -kNearSurfaceBands * band)) return PoseStart::Offset;
  return target < 0.0 ? PoseStart::Surface : PoseStart::Far;
}

bool fallback_start(double target, bool polish, PoseStart* start) {
  if (!polish) return false;
  *start = planned_start(target, polish, StartPolicy::NoOffsets);
  return true;
}

std::vector<std::size_t> descending_target_order(const std::vector<double>& targets) {
  std::vector<std::size_t> order(targets.size());
  for (std::size_t l = 0; l < order.size(); ++l) order[l] = l;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return targets[a] > targets[b]; });
  return order;
}

PoseOutcome place_pose(const ApproachSetup& setup, const OrientationFrame& frame, const SweepMesh* swept,
                       const Vec3& dir, double target, const PoseOptions& options, ApproachMemo* memo) {
  PoseOutcome out;
  if (memo && memo->last && !(memo->last->target > target))
    throw std::invalid_argument("place_pose: an approach's levels must come in descending target order");
  // Where the bounding spheres are apart by more than |target| and separating further: every
  // farther pose has c > target, so the advance may start there.
  const double lambda_far =
      setup.fixed_radius + setup.mover_radius + std::abs(target) + 1e-3 * (setup.fixed_radius + setup.mover_radius);
  const bool far_start = options.start == PoseStart::Far;
  if (far_start && !options.polish) throw std::invalid_argument("place_pose: a far start needs polishing");
  ClearanceOptions copt;
  copt.tolerance = 0.5 * options.tolerance;  // leaves room for the target band below
  copt.max_cells = options.max_cells;
  copt.try_distance_path = target >= 0.0;  // see adopt() below
  ClearanceFrontier frontier;  // the previous certificate's search, a warm start for the next pose
  ClearanceFrontier segment_end;  // a segment's leaves at its end (check_segment_above)
  copt.frontier = &frontier;
  // Separated targets: the pair traversals (separated advance, pair-distance path) on the sweep
  // trees when F's is attached, until a separated advance finds that their oriented boxes do not
  // pay (ObbTrial): the box trees, built per orientation with world-aligned splits, are then
  // cheaper for this pose's other traversals (rounded parts); on long, tilted triangles (machined
  // parts) the oriented boxes prune most pairs. Penetrating targets: on the sweep trees too. Their
  // pair-distance path runs only where the mover may lie apart (a deep-zone jump's landing, a far
  // start, the poses after one certified apart), and there the box trees of a thin tube's 4-long
  // slivers overlap most of F: one landing outside bunny00 visited 4.9 million pairs (1.9 s; the
  // level's 39 other poses took about 2.3 s), 1,366 on the sweep trees (doc/performance.md,
  // "Landings apart on the sweep trees"). The touching target keeps the box trees: its pose is
  // certified by the sweep, and this path runs there only when that certificate falls short of
  // the tolerance (far from the origin).
  const SweepTrees trees{setup.surface, &frame.swept, frame.t0};
  if (setup.surface && target != 0.0) copt.sweep_trees = &trees;
  // Penetrating targets with a convex F: its supporting planes step and certify, where they pay
  // (support_planes_for; doc/poses.md, "Supporting planes").
  const SupportPlanes* support = options.support_planes && target < 0.0 ? setup.support.get() : nullptr;
  copt.support = support;
  // Their steps at separated targets too where F's faces are long (ApproachSetup::
  // separated_planes: a finely faceted rod or pin, whose sliver pairs make the separated advance
  // dear). Tried before it; the certificates there keep the pair paths.
  const SupportPlanes* step_planes =
      options.support_planes && (target < 0.0 || setup.separated_planes) ? setup.support.get() : nullptr;
  HalfspaceSeeds seeds;  // the planes' members per mover triangle, over this pose's steps
  copt.support_seeds = step_planes ? &seeds : nullptr;
  copt.support_trees = step_planes ? &trees : nullptr;  // its oriented boxes for the planes' walks
  copt.hull = options.support_planes && target < 0.0 ? setup.hull.get() : nullptr;
  // A frontier taken over from a higher level (below) is worth it up to this many times the cells
  // of a cold start (about 25 us per cold cell, 4 us per re-evaluated warm one; doc/performance.md).
  constexpr std::uint64_t kColdCellsPerWarm = 6;
  // A deep-zone jump this many |target| long or shorter keeps the frontier (jump_to below). 4 since
  // session 58 (2 before; spool and spool with pinion -1 % instructions, rotor with pinion -0.3 %,
  // the rest within 0.1 %; 3, 6 and 8 measured too: doc/performance.md, "Segments tried again").
  constexpr double kWarmJumpTargets = 4.0;
  // Steps proved over a segment (below; doc/poses.md, "Steps proved over a segment"): tried on a
  // slide, where the slope of c over a span of poses (SlideHistory) is at most 1/8 or, without
  // such a span, the secant over the last two steps stays within [1/64, 1/8] and within a factor
  // of 2 of the previous step's (rotor's plateaus, flat or falling in bursts, seldom qualify);
  // aimed at 0.8 of the way to the crossing the slope predicts, at most 512 gaps (64 until session
  // 73: a near-target slide of rotor at -17 % took 44 segments of 64 gaps in one pose, 452 ms);
  // a try may evaluate as many cells as the two-sided steps it replaces would re-evaluate (k gaps:
  // about k/2 steps of this certificate's cells, twice over), at least 256. Measured on spool's
  // and rotor's -20 % poses, with pinion moving too (doc/performance.md, "Steps proved over a
  // segment").
  constexpr double kSegmentSlopeMin = 1.0 / 64, kSegmentSlopeMax = 1.0 / 8, kSegmentAim = 0.8;
  // A span's slope below this aims as if it were this (at most kMaxSegmentGaps anyway).
  constexpr double kSegmentSlopeFloor = 1.0 / 1024;
  constexpr double kMaxSegmentGaps = 512.0;
  // A segment aimed from a fitted slope (SlideHistory::fitted_slope) spans at most this many gaps:
  // 32 against 16, 24, 48 and 64 (doc/performance.md, "Slides fitted over eight poses").
  constexpr double kFittedSegmentGaps = 32.0;
  // A floor after a fall (below): c's fitted slope at most this after a fall steeper than that.
  constexpr double kFloorFitSlope = 1.0 / 32, kFloorFallSlope = 1.0 / 8;
  constexpr std::uint64_t kMinSegmentBudget = 256;
  constexpr double kSegmentRetryGap = 0.5;
  bool last_loose = false;
  // Certificates that ran out of cells short of their tolerance. Past kMaxExhausted the advance
  // stops and the pose is reported uncertified ("tolerance-not-reached"): a width the cells cannot
  // beat is almost always rounding (a part far from the origin, a tolerance near the doubles'
  // resolution there; doc/poses.md), and every further step would cost the whole cell budget.
  constexpr int kMaxExhausted = 3;
  int exhausted = 0;
  // The state a certificate leaves for the next one of the advance.
  const auto adopt = [&](const ClearanceResult& r) {
    if (r.argmin_face >= 0)  // the next, nearby pose starts from this minimum
      set_hint(copt, {r.argmin_beta, r.argmin_gamma}, static_cast<std::uint32_t>(r.argmin_face));
    if (r.nearest_pair_fixed >= 0) {  // and the pair-distance path from this nearest pair
      copt.hint_pair_fixed = r.nearest_pair_fixed;
      copt.hint_pair_mover = r.nearest_pair_mover;
    }
    // Once the mover certainly penetrates, the next poses of the advance (deeper along the line)
    // almost surely do too: the pair-distance path would search long for an intersecting pair
    // only to hand over to the branch and bound, which decides every case on its own. So for every
    // pose of a penetrating target: its first certificate follows a step of |target| from the
    // touching pose (or starts from an offset at the target), deep inside.
    copt.try_distance_path = target >= 0.0 && !(r.clearance.hi < 0.0);
  };
  // maybe_apart: a pose that may lie outside F although the target is < 0 (a deep-zone jump's
  // landing: a cover's cubes reach up to |target| beyond the zone, the octree's clipped leaves up
  // to about three gaps, so the mover may land still outside F; a restart far away). The
  // pair-distance path is tried first there: the branch and bound resolves the smooth minimum of a
  // distance slowly (dino at -12 %: 284,142 cells for one landing, and the warm starts from that
  // frontier ran out of cells). A step's certificate is loose (PoseOptions::step_relative_tolerance;
  // tighter where a separated target steps by certificates); the reported pose's not.
  const bool certificate_steps = separated_steps_by_certificates(setup, target, options);
  const double step_width = certificate_steps
                                ? std::min(options.step_relative_tolerance, kSeparatedStepRelativeTolerance)
                                : options.step_relative_tolerance;
  const auto certify = [&](PolishPurpose why, double lambda, bool loose, bool maybe_apart = false) {
    if (maybe_apart) copt.try_distance_path = true;
    copt.relative_tolerance = loose ? step_width : 0.0;
    copt.target = target;
    last_loose = loose;
    const Vec3 t = pose_translation(frame, dir, lambda);
    const bool cold = !frontier.valid;
    const auto started = trace_timer(options);
    const ClearanceResult r = certify_clearance(*setup.fixed, *setup.mover, setup.components, frame.orientation, t, copt);
    out.clearance_cells += r.cells;
    if (options.trace) {
      PolishEvent e;
      e.seconds = started->seconds();
      e.purpose = why;
      e.target = target;
      e.lambda = lambda;
      e.clearance = r.clearance;
      e.loose = loose;
      e.warm = !cold;
      e.work = r.cells;
      (*options.trace)(e);
    }
    if (!r.tolerance_reached && (r.rounding_floor || r.cells >= copt.max_cells)) ++exhausted;
    if (memo && cold && !r.separated && memo->cold_cells == 0) memo->cold_cells = std::max<std::uint64_t>(r.cells, 1);
    adopt(r);
    return r;
  };
  ClearanceResult c;
  if (!far_start) {
    if (swept == nullptr) throw std::invalid_argument("place_pose: no surface to sweep against");
    if (memo && memo->contact && memo->contact->swept == swept) {
      // The same raw pose as an earlier level's: its contact and certificate, taken over as they
      // were. The certificate, at full width, is valid for every level; where the branch and bound
      // made it (not the sweep), its far cells' margins followed the first level's target, so a
      // level placed alone may get another interval for the same pose (the levels of an approach
      // are always placed together, so the output does not depend on it).
      const ApproachMemo::Contact& k = *memo->contact;
      if (!k.hit) {
        out.reason = "no-contact";
        return out;
      }
      out.lambda_raw = out.lambda = k.lambda;
      c = k.certificate;
      frontier = k.frontier;
      adopt(c);
    } else {
      const Vec3 v = -dir;
      const MeshContact mc = first_contact_along_line(*swept, frame.swept, v);
      out.sphere_tests = mc.sphere_tests;
      out.triangle_sweeps = mc.triangle_sweeps;
      if (memo) memo->contact = ApproachMemo::Contact{swept, mc.hit, 0.0, {}, {}};
      if (!mc.hit) {
        out.reason = "no-contact";
        return out;
      }
      // The swept mover sits at t0 + t_contact v = t0 - t_contact d.
      const mpq_class lambda_exact = -exact_contact_time(*swept, frame.swept, v, mc);
      out.lambda_raw = out.lambda = lambda_exact.get_d();
      // The contact point (the contact pair's nearest points at the pose) holds the least
      // clearance: the certificate's upper end from the start, found without subdividing to it.
      const std::array<double, 2> contact = contact_point_on_mover(swept->triangle(mc.fixed_face), frame,
                                                                   mc.moving_face, pose_translation(frame, dir, out.lambda));
      set_hint(copt, contact, mc.moving_face);
      c = touching_certificate(frame, dir, lambda_exact, out.lambda, copt.tolerance, mc.moving_face, contact);
      // Against F itself the sweep certifies the pose; otherwise (an offset), or when the rounding
      // of t would not fit the tolerance, a certificate against F.
      if (swept != setup.surface || !c.tolerance_reached) c = certify(PolishPurpose::contact, out.lambda, false);
      if (memo) {
        memo->contact->lambda = out.lambda;
        memo->contact->certificate = c;
        memo->contact->frontier = frontier;
      }
    }
  } else {
    // Far away only the lower end matters (the first step); the raw clearance is then a wider
    // certified interval.
    out.lambda_raw = out.lambda = lambda_far;
    c = certify(PolishPurpose::far_start, out.lambda, true);
  }
  out.contact = true;
  out.raw_clearance = c.clearance;
  // The advance passed the far side of F without reaching the target: c > target on the whole line.
  const auto missed = [&] {
    out.contact = false;
    out.reason = "no-contact";
    return out;
  };
  const auto within = [&](const Interval& x) {
    return x.lo >= target - options.tolerance && x.hi <= target + options.tolerance;
  };
  if (options.polish) {
    if (!within(c.clearance) && !(c.clearance.lo > target)) {
      // Neither on target nor provably before the crossing: start far away.
      out.lambda = lambda_far;
      c = certify(PolishPurpose::far_start, out.lambda, false, true);
    }
    if (memo && memo->last && memo->last->lambda < out.lambda && memo->last->certificate.clearance.lo > target &&
        !within(c.clearance)) {
      // A higher target's pose on this line: c > that target > this one on every farther pose,
      // and c(lambda) > this target, so the advance continues from there.
      const ApproachMemo::OnTarget& k = *memo->last;
      out.continued = true;
      out.lambda = k.lambda;
      c = k.certificate;
      // And its frontier, a warm start for the first step: its cells are re-evaluated only where
      // they matter (restale first), far cheaper than a cold search from the mover's root. Not
      // when it holds many times the cells of this approach's cold start: after a long step each
      // needs re-evaluation (about 4 us each, a cold cell about 25 us: pinion, bunny00).
      if (memo->cold_cells == 0 || k.frontier.cells.size() <= kColdCellsPerWarm * memo->cold_cells)
        frontier = k.frontier;
      else
        frontier.valid = false;
      last_loose = false;
      adopt(c);
    }
    // A jump to lk, the latest contact of the moving mover with a cover of the deep zone: every
    // pose beyond it has its surface outside the zone, so c > target there. Kept only when the
    // certificate there is on the target or provably before the crossing (c(lk) >= target holds,
    // but a certificate of a pose exactly at the target could straddle it).
    const auto jump_to = [&](double lk) {
      const double lambda0 = out.lambda;
      const ClearanceResult c0 = c;
      const ClearanceFrontier f0 = frontier;
      const bool loose0 = last_loose;  // c0's width, restored with it
      // After a short jump (at most kWarmJumpTargets |target|) the frontier's cells, sized by the
      // depths about the mover, mostly still decide: a warm start re-evaluates them where they
      // matter (rotor with pinion, jumps of 0.4-1.8 |target|: 2-3 ms a certificate instead of 4-8 ms
      // cold; doc/performance.md, "Where a jumped pose's time goes"). After a long
      // one nearly every cell is stale and its splits sit where the mover was: a cold start is
      // as cheap or cheaper (jumps of 3-20 |target|: about equal, or warm up to 40 % slower). A
      // heuristic; either certificate is rigorous.
      if (lambda0 - lk > kWarmJumpTargets * std::abs(target)) frontier.valid = false;
      out.lambda = lk;
      // Loose, as a step's certificate: a landing still above the target is proved so at a
      // fraction of the cells, and the next steps' warm starts re-evaluate a smaller frontier (a
      // full-width landing's cells were refined to the tolerance about its minimum: the repaired
      // mannequin-devil's -20 % poses 18,600 -> 11,400 cells; doc/performance.md, "Loose
      // landings"). Full width where it may be on the target.
      c = certify(PolishPurpose::landing, out.lambda, true, true);
      if (c.clearance.hi <= target + options.tolerance) c = certify(PolishPurpose::landing, out.lambda, false, true);
      if (!within(c.clearance) && !(c.clearance.lo > target)) {
        out.lambda = lambda0;
        c = c0;
        frontier = f0;
        last_loose = loose0;
        adopt(c);
      } else {
        ++out.cover_jumps;
      }
    };
    // The previous pose of the advance, for the slope of c (a heuristic: it only picks steps).
    double prev_lambda = 0.0, prev_mid = 0.0;
    bool have_prev = false;
    double prev2_lambda = 0.0, prev2_mid = 0.0;  // the pose before that
    bool have_prev2 = false;
    int flat_steps = 0, near_flat = 0;
    double near_flat_gap = 0.0;  // the gap when the present run of near-flat steps began
    // Where the present runs of flat and near-flat steps began (lambda, mid of c), for their slope.
    double flat_from[2] = {0.0, 0.0}, near_from[2] = {0.0, 0.0};
    DeepZoneJumps jumps(options, target);
    bool segments_pay = true;  // until a segment's search runs out of its budget
    // The gap when they last stopped paying (below).
    double segments_stopped_gap = 0.0;
    int segment_retries = 0;  // times segments were tried again after one ran out of its budget
    double last_slope = 1.0;   // the previous step's two-step secant slope
    SlideHistory history;
    while (!within(c.clearance) && out.steps < options.max_steps && exhausted < kMaxExhausted) {
      // The clearance is 1-Lipschitz in lambda (|d| = 1 up to rounding, covered by the relative
      // margin; the rounding of t by the absolute one): stepping by c_lo - target cannot pass the
      // first crossing.
      const double slack = pose_rounding_slack(frame, std::abs(out.lambda));
      const double gap = c.clearance.lo - target;
      const double step = gap * (1.0 - kStepMargin) - slack;
      if (!(step > 0.0)) {
        if (last_loose) {  // a loose certificate: tighten it before giving up
          c = certify(PolishPurpose::tighten, out.lambda, false);
          continue;
        }
        break;
      }
      if (step_planes) {
        // The planes' step where it beats this certificate's, chained without certificates while
        // it stays longer than the tolerance (Newton's method on a piecewise-linear c: a few steps).
        const auto planes_step = [&] {
          return halfspace_advance(*step_planes, frame.orientation, pose_translation(frame, dir, out.lambda), dir, target,
                                   pose_rounding_slack(frame, 2.0 * lambda_far), out.lambda + lambda_far, &seeds,
                                   &trees, copt.hint_face);
        };
        HalfspaceAdvance a = planes_step();
        if (a.h > step) {
          for (;;) {
            if (a.face >= 0) set_hint(copt, {a.beta, a.gamma}, static_cast<std::uint32_t>(a.face));
            out.lambda -= a.h;
            ++out.steps;
            if (out.lambda <= -lambda_far) return missed();
            if (a.h <= options.tolerance || out.steps >= options.max_steps) break;
            a = planes_step();
            if (!(a.h > 0.0)) break;
          }
          c = certify(PolishPurpose::planes, out.lambda, false);
          continue;
        }
      }
      if (target > 0.0 && !certificate_steps) {
        // c > target > 0: the mover's surface is outside F and apart from it. Advance by the pair
        // traversal's reach bound (advance.h), pose after pose without a certificate while the
        // steps stay longer than the tolerance, then certify where it stops (doc/poses.md).
        double h = step;  // the Lipschitz step this certificate proves: h > 0 on the first pass
        for (;;) {
          const double h_max = out.lambda + lambda_far;  // not beyond the far side of the object
          const SeparatedAdvance a =
              separated_advance(*setup.fixed, frame.orientation, pose_translation(frame, dir, out.lambda), dir, target,
                                pose_rounding_slack(frame, std::abs(out.lambda) + h_max), h_max, copt.hint_pair_fixed,
                                copt.hint_pair_mover, copt.sweep_trees);
          if (!a.oriented_paid && !setup.keep_sweep_trees) copt.sweep_trees = nullptr;
          if (a.h >= h_max) return missed();  // no pair comes within reach before the far side
          h = std::max(h, a.h);
          if (a.fixed_face >= 0) {
            copt.hint_pair_fixed = a.fixed_face;
            copt.hint_pair_mover = a.mover_face;
          }
          if (!(h > 0.0)) break;
          out.lambda -= h;
          ++out.steps;
          if (h <= options.tolerance || out.steps >= options.max_steps) break;
          h = 0.0;
        }
        c = certify(PolishPurpose::advance, out.lambda, false);
        continue;
      }
      const double mid = 0.5 * (c.clearance.lo + c.clearance.hi);
      const double slope = have_prev ? std::max(0.0, (prev_mid - mid) / (prev_lambda - out.lambda)) : 1.0;
      // A plateau: c flat (secant slope below 1/2) for two steps while still a tenth of |target|
      // or more above it. There, once per pose, a jump to the first contact with the deep zone's
      // cover (where the cover ran out of its budget, to the contact with its octree about the
      // mover's path, as often as its budget allows). Not before: where c falls steeply, or slowly
      // but near the target, the crossing is a few steps away and a query would cost more than it
      // saves (doc/performance.md). Thin parts' plateaus lie at about a tenth (rotor -20 %:
      // 0.08-0.12 |target|; at a fifth, as before 2026-11-28, they were not crossed).
      flat_steps = slope < 0.5 && mid - target > 0.1 * std::abs(target) ? flat_steps + 1 : 0;
      if (flat_steps == 1) flat_from[0] = prev_lambda, flat_from[1] = prev_mid;
      // Flat within a tenth of |target| too: asked only once that has lasted kNearPlateauSteps
      // (a long plateau just above the target: repaired thin shells' poses of 1,300-1,900 steps;
      // rotor's blades at levels just shallower than a fifth of M).
      near_flat = slope < 0.5 ? near_flat + 1 : 0;
      // A plateau keeps its gap; a slide (c falling at a few per cent of the advance, each
      // two-sided step closing a part of the gap) shrinks it step by step towards its crossing:
      // the run starts again whenever the gap has fallen to an eighth. (Rotor with pinion: a slide
      // of 64 steps from 0.1 |target| to 5 tolerances asked the octree for 26 ms and jumped 5
      // gaps. Restarting at every halving cost the repaired lion-head 6 % more steps, at an
      // eighth 0.4 %.)
      if (near_flat <= 1 || gap < 0.125 * near_flat_gap) {
        near_flat_gap = gap;
        near_flat = std::min(near_flat, 1);
        near_from[0] = prev_lambda, near_from[1] = prev_mid;
      }
      // Sooner on a floor after a fall: c flat over the last poses (their fitted slope at most
      // kFloorFitSlope) after falling steeply (the slope over a span, back to a pose with 4 times
      // the gap, above kFloorFallSlope). The mover's part in a wall has reached its saturated depth
      // just above the target and stays there until the mover meets the deep zone, which the
      // query finds (the thin tube against spool at -18 %: 20 two-sided steps of 250-450 cells on
      // such floors; doc/performance.md, "Floors after a fall"). A slide that merely slows
      // keeps kNearPlateauSteps (asked after 8 flat steps there too, spool's poses cost 4 % more).
      // Where a span resolves it, c's slope over it: here for the floors, below for the long steps.
      const double span_slope = history.slope(out.lambda, gap, mid - target);
      const auto on_floor = [&] {
        if (near_flat < static_cast<int>(SlideHistory::kFitPoses) || !options.floor_queries) return false;
        const double fit = history.fitted_slope();
        return fit >= 0.0 && fit <= kFloorFitSlope && span_slope > kFloorFallSlope;
      };
      const double* run_from = flat_from;
      if (flat_steps < 2 && (near_flat >= DeepZoneJumps::kNearPlateauSteps || on_floor())) {
        flat_steps = near_flat;
        run_from = near_from;
      }
      // The secant over the last two steps: for segment steps (below), and whether a flat run is
      // a plateau or a slide (DeepZoneJumps). Loose certificates make the one-step secant jump
      // between 0 and 0.6 on a slide (spool), the two-step one much less.
      const double slope2 = have_prev2 ? std::max(0.0, (prev2_mid - mid) / (prev2_lambda - out.lambda)) : 1.0;
      if (flat_steps >= 2 && jumps.active()) {
        // Worth a jump only beyond what one two-sided step proves.
        const double worth = out.lambda - 2.0 * std::max(0.0, c.clearance.lo - target);
        // c's fall over the flat run or over its last two steps, whichever is less, over the advance.
        const double run_slope = std::min(slope2, (run_from[1] - mid) / (run_from[0] - out.lambda));
        const std::uint64_t cubes_before = out.zone_cubes;
        const auto started = trace_timer(options);
        const double cover_before = options.trace && options.deep_cover ? options.deep_cover->seconds() : 0.0;
        const double lk = jumps.contact(setup, frame, dir, out.lambda, gap, flat_steps, run_slope, worth, lambda_far,
                                        out.clearance_cells, &out.zone_cubes);
        if (options.trace && (!std::isnan(lk) || out.zone_cubes > cubes_before)) {
          PolishEvent e;
          // The level's cover, if this query built it, is setup, not the query's.
          const double cover_built = options.deep_cover ? options.deep_cover->seconds() - cover_before : 0.0;
          e.seconds = std::max(0.0, started->seconds() - cover_built);
          e.kind = PolishEvent::Kind::zone_query;
          e.target = target;
          e.lambda = out.lambda;
          e.to = lk;
          e.work = out.zone_cubes - cubes_before;
          (*options.trace)(e);
        }
        if (!std::isnan(lk)) {
          if (!(lk > -lambda_far)) return missed();  // the line never meets the zone
          if (lk < worth) {
            // The landing's certificate starts from the mover's point at the zone's cube it met:
            // likely inside F, so that its first cell lowers the upper end at once and the pair
            // path, which only looks for a crossing pair there, is skipped (hint_inside,
            // clearance.cpp). The previous pose's deepest point had moved on with the jump, often
            // out of the part it was deep in. A hint only.
            if (jumps.contact_face() >= 0) {
              const auto f = static_cast<std::uint32_t>(jumps.contact_face());
              set_hint(copt, point_on_mover_near(frame, f, pose_translation(frame, dir, lk), jumps.contact_centre()), f);
            }
            jump_to(lk);
            history.clear();
            have_prev = false;
            have_prev2 = false;
            flat_steps = near_flat = 0;
            continue;
          }
        }
      }
      prev2_lambda = prev_lambda;
      prev2_mid = prev_mid;
      have_prev2 = have_prev;
      prev_lambda = out.lambda;
      prev_mid = mid;
      have_prev = true;
      bool advanced = false;
      // (slope2 is 1 without two previous poses: outside the band.)
      const bool in_band = slope2 >= kSegmentSlopeMin && slope2 <= kSegmentSlopeMax;
      const bool steady = in_band && slope2 <= 2.0 * last_slope && last_slope <= 2.0 * slope2;
      last_slope = slope2;
      // Where a span resolves it, its slope aims both kinds of long step and gates the segments
      // (spool with pinion moving: 4.6 % fewer instructions, doc/performance.md, "Slopes over a
      // span"); elsewhere the secants above, as before.
      history.add(out.lambda, gap, mid - target);
      const bool spanned = span_slope >= 0.0;
      // Where none does, the fit over the last poses, aiming at most kFittedSegmentGaps (the fit
      // of a slide that holds its gap reads about 0).
      const double fit = spanned || !options.fitted_segments ? -1.0 : history.fitted_slope();
      const bool fitted = fit >= 0.0 && fit <= kSegmentSlopeMax;
      const double segment_slope = spanned  ? std::max(span_slope, kSegmentSlopeFloor)
                                   : fitted ? std::max(fit, kSegmentAim / kFittedSegmentGaps)
                                            : slope2;
      const bool segment_due =
          spanned ? span_slope > 0.0 && span_slope <= kSegmentSlopeMax : steady || fitted;
      // A segment that ran out of its budget was mostly aimed across the crossing (a slope
      // underestimated by loose certificates); once the gap has fallen to kSegmentRetryGap of what
      // it was then, the crossing is nearer and the slope better known: segments are tried again
      // (spool -20 %: 35 -> 24 steps a pose; doc/performance.md, "Segments tried again"), and
      // again after each failure (once per pose until session 85: pinion moving against spool
      // -20 % slid at 1/20-1/10 for 80 two-sided steps after its retry failed; 16 % faster a pose,
      // the rest unchanged; doc/performance.md, "Segments retried after every failure").
      if (!segments_pay && gap < kSegmentRetryGap * segments_stopped_gap &&
          (options.segment_retries < 0 || segment_retries < options.segment_retries)) {
        segments_pay = true;
        ++segment_retries;
      }
      if (options.segment_steps && segments_pay && target < 0.0 && segment_due && frontier.valid) {
        // A steady slide: a step of many gaps, proved over the whole segment from this
        // certificate's frontier (check_segment_above), then certified at its end as any step.
        double k = std::min(kMaxSegmentGaps, kSegmentAim / segment_slope);
        while (k >= 3.0) {
          const double h = std::min(k * gap, out.lambda + lambda_far);  // not beyond the far side
          if (!(h > 1.2 * step)) break;  // no longer than a plain step there
          const Vec3 ta = pose_translation(frame, dir, out.lambda), tb = pose_translation(frame, dir, out.lambda - h);
          // The exact poses t0 + x d, x in [lambda - h, lambda], lie within the slack of the
          // computed ends' segment; twice the transform's rounding, as a certificate is widened.
          const double pad = round_up(pose_rounding_slack(frame, std::abs(out.lambda) + h) +
                                      2.0 * std::max(frame.orientation.transform_error(ta),
                                                     frame.orientation.transform_error(tb)));
          const std::uint64_t budget =
              std::max(kMinSegmentBudget, static_cast<std::uint64_t>(k * static_cast<double>(c.cells)));
          const auto started = trace_timer(options);
          const SegmentCheck check =
              check_segment_above(*setup.fixed, frame.orientation, frontier, ta, tb, pad, target, budget, &segment_end);
          ++out.segment_tries;
          if (options.trace) {
            PolishEvent e;
            e.seconds = started->seconds();
            e.kind = PolishEvent::Kind::segment;
            e.target = target;
            e.lambda = out.lambda;
            e.to = out.lambda - h;
            e.verdict = check.verdict;
            e.work = check.cells;
            e.budget = budget;
            (*options.trace)(e);
          }
          if (check.verdict == SegmentVerdict::above) {
            out.lambda -= h;
            // Its certificate starts from the search's leaves there, not from this frontier shifted
            // by h (doc/poses.md, "The certificate at a segment's end").
            if (segment_end.valid) std::swap(frontier, segment_end);
            c = certify(PolishPurpose::segment_end, out.lambda, true);
            advanced = true;
            break;
          }
          if (check.verdict == SegmentVerdict::undecided) {
            segments_pay = false;  // until the gap has fallen to kSegmentRetryGap of this one
            segments_stopped_gap = gap;
            break;
          }
          k *= 0.25;  // below the target about the middle: try a quarter of the way
        }
      }
      // A rejected two-sided try: its pose and certificate, for the plain step that follows.
      bool rejected_try = false;
      double rejected_lambda = 0.0;
      ClearanceResult rejected;
      if (!advanced && options.two_sided_steps && slope < 0.5) {
        // Where c is flat, a step of up to twice the gap, proved from both ends: on [l - h, l],
        // c >= max(c(l) - (l - x), c(l - h) - (x - l + h)) > target when the two gaps add up to
        // more than h (same margins as one step, for both ends).
        // The aim: h where the two gaps, predicted with the slope, add up to h / 0.9.
        const double h = 0.9 * 2.0 * gap / (1.0 + (spanned ? span_slope : slope));
        if (h > 1.2 * step && out.lambda - h >= -lambda_far) {
          const double slack2 = pose_rounding_slack(frame, std::abs(out.lambda) + h);
          // Its search goes on past the loose width until its lower end is enough for the step
          // (or its upper end proves it cannot be): a refused try costs its certificate and a
          // plain step (doc/poses.md, "The far end's floor").
          copt.floor = far_end_floor(target, gap, h, slack2);
          ClearanceResult c2 = certify(PolishPurpose::two_sided, out.lambda - h, true);
          copt.floor = -std::numeric_limits<double>::infinity();
          ++out.two_sided_tries;
          if (gaps_cover(gap, c2.clearance.lo - target, h, slack2)) {
            out.lambda -= h;
            c = std::move(c2);
            advanced = true;
          } else {
            rejected_try = true;
            rejected_lambda = out.lambda - h;
            rejected = std::move(c2);
          }
        }
      }
      if (!advanced) {
        out.lambda -= step;
        if (out.lambda < -lambda_far) return missed();
        c = certify(PolishPurpose::step, out.lambda, true);
        // The same two-sided rule between this pose (l') and the rejected try's (l - h, below it):
        // where their two gaps cover [l - h, l'], the pose moves on to l - h with the try's
        // certificate, one certificate saved (doc/poses.md, "A rejected try kept").
        if (rejected_try) {
          const double hole = out.lambda - rejected_lambda;
          const double slack2 = pose_rounding_slack(frame, std::abs(out.lambda) + hole);
          if (hole > 0.0 && gaps_cover(c.clearance.lo - target, rejected.clearance.lo - target, hole, slack2)) {
            out.lambda = rejected_lambda;
            c = std::move(rejected);
            ++out.kept_tries;
          }
        }
      }
      ++out.steps;
      if (c.clearance.hi <= target + options.tolerance && last_loose)
        c = certify(PolishPurpose::report, out.lambda, false);  // near the end: the reported certificate
    }
    if (last_loose) c = certify(PolishPurpose::report, out.lambda, false);  // stopped early: report a full-width certificate
  }
  if (memo && options.polish && c.tolerance_reached && within(c.clearance))
    memo->last = ApproachMemo::OnTarget{target, out.lambda, c, frontier};
  out.t = pose_translation(frame, dir, out.lambda);
  out.clearance = c.clearance;
  out.certified = c.tolerance_reached;
  out.on_target = within(c.clearance);
  if (!out.certified) out.reason = "tolerance-not-reached";
  else if (options.polish && !out.on_target) out.reason = "polish-stalled";
  return out;
}

}  // namespace cdbench
