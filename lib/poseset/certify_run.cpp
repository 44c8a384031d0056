#include "poseset/certify_run.h"
#include "poseset/level_summary.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <nlohmann/json.hpp>

#include "distance/depth_bound.h"
#include "distance/max_penetration.h"
#include "distance/signed_distance.h"
#include "mesh/components.h"
#include "placement/clearance.h"
#include "placement/mover.h"
#include "placement/place_pose.h"
#include "placement/rotation_groups.h"
#include "placement/unknown_pose.h"
#include "poseset/journal.h"
#include "poseset/pose_csv.h"
#include "poseset/poseset_manifest.h"
#include "sweep/mesh_sweep.h"
#include "util/atomic_file.h"
#include "util/dynamic_parallel.h"
#include "util/error.h"
#include "util/number_format.h"
#include "util/progress.h"
#include "util/sha256.h"
#include "util/timer.h"

#ifndef CDBENCH_VERSION
#define CDBENCH_VERSION "unknown"
#endif

namespace cdbench {
namespace {

// Levels of the bundle: the file's `level` column, else its distinct targets, else one level.
// Returns each pose's level index.
std::vector<int> assign_levels(const UserPoseFile& file, std::vector<LevelRecord>* levels) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<int> of(file.poses.size(), 0);
  if (file.has_level) {
    std::int64_t top = 0;
    for (const UserPose& p : file.poses) top = std::max(top, p.level);
    levels->assign(static_cast<std::size_t>(top) + 1, LevelRecord{});
    std::vector<bool> first(levels->size(), true);
    for (std::size_t i = 0; i < file.poses.size(); ++i) {
      const UserPose& p = file.poses[i];
      LevelRecord& l = (*levels)[static_cast<std::size_t>(p.level)];
      of[i] = static_cast<int>(p.level);
      // The level's target: the poses' common one, else none.
      if (first[static_cast<std::size_t>(p.level)]) l.target = p.target;
      else if (!(l.target == p.target)) l.target = nan;
      first[static_cast<std::size_t>(p.level)] = false;
    }
    for (std::size_t l = 0; l < levels->size(); ++l)
      (*levels)[l].spec = "level " + std::to_string(l) + (std::isnan((*levels)[l].target) ? "" : " (target " + shortest_number_text((*levels)[l].target) + ")");
  } else if (file.has_target) {
    std::vector<double> targets;
    bool untargeted = false;
    for (const UserPose& p : file.poses) std::isnan(p.target) ? void(untargeted = true) : targets.push_back(p.target);
    std::sort(targets.begin(), targets.end());
    targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
    for (double t : targets) levels->push_back({shortest_number_text(t), t});
    if (untargeted) levels->push_back({"no target", nan});
    for (std::size_t i = 0; i < file.poses.size(); ++i) {
      const double t = file.poses[i].target;
      of[i] = std::isnan(t) ? static_cast<int>(targets.size())
                            : static_cast<int>(std::lower_bound(targets.begin(), targets.end(), t) - targets.begin());
    }
  } else {
    levels->push_back({"all", nan});
  }
  return of;
}

}  // namespace

CertifyRunResult run_certify(const CertifyRequest& rq, const std::string& out_dir) {
  Timer total;
  CertifyRunResult result;
  const UserPoseFile& file = *rq.poses;
  prepare_output_directory(out_dir);

  const std::string fixed_sha = sha256_file(rq.fixed_path);
  const std::string mover_sha = rq.mover_is_fixed ? fixed_sha : sha256_file(rq.mover_path);
  // Where a quarter or more of either mesh's faces are long (a thin tube's slivers, a faceted rod),
  // the pair-distance path runs on the sweep trees (below).
  const bool sweep = long_faces_keep_sweep_trees(*rq.fixed, *rq.mover);
  nlohmann::json run_key = {{"fixed_sha256", fixed_sha},
                            {"mover_sha256", mover_sha},
                            {"poses_sha256", sha256_file(rq.poses_path)},
                            {"tolerance", rq.tolerance_relative},
                            {"max_cells", rq.max_cells},
                            {"generator", std::string("cdbench ") + CDBENCH_VERSION}};
  // Since session 92: separated poses' intervals may then be a few ulps wide where earlier binaries
  // ran out of the pair budget (doc/validate-your-library.md, "Widths"); their journals lack the key.
  if (sweep) run_key["sweep_tree_pairs"] = 1;
  // Since session 93 a cell centred on F keeps its depth bound: a mover resting face-on on a face
  // that does not support F, or coinciding with F, is certified where earlier binaries ran out of
  // cells (doc/poses.md, "Cells lying on F"); their journals lack the key or have 1.
  run_key["on_surface_depth_bounds"] = kOnSurfaceDepthBounds;
  // Since session 94 mover faces placed exactly onto F's faces are settled at s = 0 (1), and cells
  // of faces hinged on F's edges from outside at s >= 0 (2) (doc/poses.md, "Faces placed onto F's
  // faces", "Faces hinged on F's edges"), and since session 95 faces placed onto them up to
  // rounding at [-e, e] (3), and a pose that runs out of cells near F's vertices is tried again with
  // faces within an eighth of the tolerance settled (4), and since session 96 such a search stops
  // for that at ClearanceOptions::retry_probe_cells, run again whole only if the retry falls short
  // too (5): such poses' intervals differ from earlier binaries'.
  run_key["coincident_faces"] = 5;
  PoseJournal journal(out_dir, "certify", run_key, rq.resume, "certify");

  const SignedDistance sdf(*rq.fixed);
  result.diagonal = sdf.bbox().diagonal();
  result.tolerance = rq.tolerance_relative * result.diagonal;
  Timer t_mp;
  MaxPenetrationOptions mpo;
  mpo.relative_tolerance = rq.max_penetration_tolerance;
  const MaxPenetrationResult mp = certified_max_penetration(sdf, mpo);
  result.seconds_max_penetration = t_mp.seconds();
  result.max_penetration = mp.depth;

  std::vector<LevelRecord> levels;
  const std::vector<int> level_of = assign_levels(file, &levels);

  // Pending poses in file order (poses sharing a rotation share its mover tree); a row's
  // orientation index numbers the file's rotations in first-seen order.
  std::vector<std::size_t> pending, all(file.poses.size());
  std::vector<Eigen::Matrix3d> rotations(file.poses.size());
  for (std::size_t i = 0; i < file.poses.size(); ++i) {
    rotations[i] = file.poses[i].R;
    all[i] = i;
    if (!journal.done().count(file.poses[i].pose)) pending.push_back(i);
  }
  const std::vector<std::size_t> group = rotation_group_ids(rotations, all);
  result.resumed = file.poses.size() - pending.size();

  const std::vector<std::uint32_t> components = component_representatives(*rq.mover);
  // As `cdbench validate` (placement/unknown_pose.h).
  const UnknownPoseOptions unknown(sdf, *rq.mover, result.tolerance, rq.max_cells);
  const ClearanceOptions& co = unknown.options();
  Progress progress("certify", pending.size());
  Timer t_poses;
  // With long faces (`sweep`) the pair-distance path runs on the sweep trees: F's, and the mover's
  // carried to each rotation (placed at t = 0; a pose's shift from there is padded). Their oriented
  // boxes prune the sliver pairs whose world-aligned boxes overlap across the whole mesh (a thin
  // tube about bunny00: 40 separated poses 17.2 -> 0.3 s, 40 penetrating ones 14.4 -> 2.7 s).
  // Elsewhere the box trees: armadillo against itself took 5.4 s on them, 6.4 s on the sweep trees
  // (doc/performance.md, "Landings apart on the sweep trees"). Speed only.
  std::optional<SweepMesh> surface, mover_own;
  if (sweep) {
    surface = make_sweep_mesh(sdf.mesh().vertices, sdf.mesh().faces);
    mover_own = make_sweep_mesh(rq.mover->vertices, rq.mover->faces);
  }
  struct Frame {
    MoverOrientation orientation;
    SweepMesh swept;  // empty without `sweep`
  };
  const auto make_frame = [&](const Eigen::Matrix3d& R) {
    Frame f{make_mover_orientation(*rq.mover, R), {}};
    const Vec3 origin = Vec3::Zero();
    if (sweep)
      f.swept = placed_sweep_mesh(*mover_own, R, origin, f.orientation.placed(origin),
                                  f.orientation.transform_error(origin));
    return f;
  };
  for_each_pose_by_rotation<Frame>(rotations, pending, make_frame, [&](std::size_t i, const Frame& frame) {
    const UserPose& p = file.poses[i];
    const MoverOrientation& orientation = frame.orientation;
    const SweepTrees trees{sweep ? &*surface : nullptr, &frame.swept, Vec3::Zero()};
    ClearanceOptions pose_options = co;
    if (sweep) pose_options.sweep_trees = &trees;
    const ClearanceResult c = certify_clearance(sdf, *rq.mover, components, orientation, p.t, pose_options);
    PoseRow row;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    row.pose = p.pose;
    row.level = level_of[i];
    row.target = p.target;
    row.R = p.R;
    row.t = p.t;
    row.dir = Eigen::Vector3d::Constant(nan);
    row.clearance_lo = row.raw_clearance_lo = c.clearance.lo;
    row.clearance_hi = row.raw_clearance_hi = c.clearance.hi;
    row.status = reaches_tolerance(c, result.tolerance) ? PoseStatus::Certified : PoseStatus::ToleranceNotReached;
    row.orientation = group[i];
    row.direction = 0;
    row.polish_steps = 0;
    row.lambda = nan;
    journal.append({format_pose_row(row)});
    progress.advance();
  });
  progress.finish();
  result.seconds_poses = t_poses.seconds();

  // The journal now holds every pose (earlier runs' rows and this run's, re-read so that both are
  // treated alike); poses.csv lists them by pose id.
  const std::map<std::uint64_t, std::string> rows_by_id = read_journal_rows(journal.path());
  if (rows_by_id.size() != file.poses.size())
    throw InputError("internal: the journal holds " + std::to_string(rows_by_id.size()) + " poses of " +
                     std::to_string(file.poses.size()));
  result.levels.resize(levels.size());
  for (std::size_t l = 0; l < levels.size(); ++l) {
    result.levels[l].spec = levels[l].spec;
    result.levels[l].target = levels[l].target;
    result.levels[l].clearance_min = HUGE_VAL;
    result.levels[l].clearance_max = -HUGE_VAL;
  }
  std::vector<PoseRow> parsed;
  parsed.reserve(rows_by_id.size());
  write_file_atomically(out_dir + "/poses.csv", [&](std::ostream& out) {
    out << kPoseCsvHeader << "\n";
    for (const auto& [id, line] : rows_by_id) {
      out << line;
      const PoseRow& r = parsed.emplace_back(parse_pose_row(line, journal.path()));
      CertifyLevelCounts& lc = result.levels[static_cast<std::size_t>(r.level)];
      ++lc.poses;
      const bool certified = r.status == PoseStatus::Certified;
      lc.certified += certified;
      result.certified += certified;
      lc.separated += r.clearance_lo > 0.0;
      lc.penetrating += r.clearance_hi < 0.0;
      lc.straddling += !(r.clearance_lo > 0.0) && !(r.clearance_hi < 0.0);
      lc.clearance_min = std::min(lc.clearance_min, r.clearance_lo);
      lc.clearance_max = std::max(lc.clearance_max, r.clearance_hi);
    }
  });
  // poses.csv is in place: an interrupt before poseset.json is removes it (the journal stays).
  std::optional<RemovedIfInterrupted> pair(std::in_place, out_dir + "/poses.csv");
  result.poses = rows_by_id.size();
  result.note = tolerance_not_reached_note(
      parsed, result.tolerance, result.diagonal, sdf.bbox(),
      "the branch and bound reached its work limit (--max-cells), or a pose lies so far out that rounding alone "
      "widens its interval");

  nlohmann::json ps;
  ps["format"] = "cdbench-poseset";
  ps["format_version"] = 1;
  const auto record = [&](const std::string& path, const std::string& sha, const TriangleMesh& m) {
    return to_json(mesh_record(path, sha, m, m.bbox().center()));
  };
  ps["fixed"] = record(rq.fixed_path, fixed_sha, *rq.fixed);
  ps["mover"] = record(rq.mover_path, mover_sha, *rq.mover);
  ps["mover_is_fixed"] = rq.mover_is_fixed;
  ps["max_penetration"] = {{"interval", {mp.depth.lo, mp.depth.hi}},
                           {"point", {mp.point.x(), mp.point.y(), mp.point.z()}},
                           {"relative_tolerance", rq.max_penetration_tolerance}};
  ps["levels"] = nlohmann::json::array();
  for (std::size_t l = 0; l < levels.size(); ++l) {
    const CertifyLevelCounts& lc = result.levels[l];
    const double t = levels[l].target;
    const auto maybe = [](double x) { return std::isnan(x) ? nlohmann::json() : nlohmann::json(x); };
    ps["levels"].push_back({{"index", l},
                            {"spec", levels[l].spec},
                            {"target", maybe(t)},
                            {"fraction_of_max_penetration", maybe(t / mp.depth.lo)},
                            {"target_over_diagonal", maybe(t / result.diagonal)},
                            {"start", "user"},
                            {"start_note", "poses given by the user (cdbench certify)"},
                            {"swept_offset", nullptr},
                            {"poses", lc.poses},
                            {"certified", lc.certified},
                            {"on_target", nullptr},
                            {"no_contact", 0},
                            {"separated", lc.separated},
                            {"penetrating", lc.penetrating},
                            {"straddling_zero", lc.straddling}});
  }
  ps["source"] = {{"kind", "certify"},
                  {"poses_file", rq.poses_path},
                  {"poses_sha256", run_key["poses_sha256"]},
                  {"rotation_form", file.form == RotationForm::Matrix ? "matrix" : "quaternion"},
                  {"ignored_columns", file.ignored_columns}};
  ps["shard"] = {{"index", 0}, {"count", 1}};
  ps["certification"] = {{"tolerance_relative", rq.tolerance_relative},
                         {"tolerance", result.tolerance},
                         {"diagonal", result.diagonal},
                         {"max_cells", rq.max_cells}};
  ps["polishing"] = {{"enabled", false}};
  ps["placement"] = {{"transform", "x_world = R x + t, R row-major; R as stored (certified as the affine map it is)"},
                     {"approach", "none (dir_x, dir_y, dir_z are nan)"}};
  ps["generator"] = {{"name", "cdbench"}, {"version", CDBENCH_VERSION}, {"command_line", rq.command_line}};
  ps["run_key"] = run_key;
  result.seconds_total = total.seconds();
  const double computed = static_cast<double>(pending.size());
  ps["timings"] = {{"max_penetration", result.seconds_max_penetration},
                   {"poses", result.seconds_poses},
                   {"poses_computed", pending.size()},
                   {"poses_per_second", result.seconds_poses > 0 ? computed / result.seconds_poses : 0.0},
                   {"total", result.seconds_total}};
  write_file_atomically(out_dir + "/poseset.json", [&](std::ostream& out) { out << std::setw(2) << ps << "\n"; });
  pair.reset();
  journal.remove();
  return result;
}

}  // namespace cdbench
