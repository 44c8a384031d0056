#include "validate/validate_run.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

#include "distance/max_penetration.h"
#include "distance/signed_distance.h"
#include "mesh/components.h"
#include "mesh/read_mesh.h"
#include "mesh/validate_mesh.h"
#include "offset/certify_band.h"
#include "offset/certify_completeness.h"
#include "placement/clearance.h"
#include "placement/mover.h"
#include "placement/place_pose.h"
#include "placement/rotation_groups.h"
#include "placement/unknown_pose.h"
#include "poseset/poseset_manifest.h"
#include "sweep/mesh_sweep.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/gnuplot.h"
#include "util/number_format.h"
#include "util/progress.h"
#include "util/timer.h"

namespace cdbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool finite(const Eigen::Vector3d& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

const char* to_text(Tristate t) { return t == Tristate::Yes ? "1" : t == Tristate::No ? "0" : ""; }

// Seconds per pose of a level as the bundle's own pipeline recorded it: the float pipeline's
// levels[l].thread_seconds, the certified pipeline's timings.levels[l].poses_per_thread_second.
double recorded_seconds_per_pose(const nlohmann::json& ps, std::size_t l, std::size_t poses) {
  const auto& levels = ps.find("levels");
  if (levels != ps.end() && levels->is_array() && l < levels->size()) {
    const auto ts = (*levels)[l].find("thread_seconds");
    if (ts != (*levels)[l].end() && ts->is_number() && poses > 0) return ts->get<double>() / static_cast<double>(poses);
  }
  const auto timings = ps.find("timings");
  if (timings != ps.end() && timings->is_object()) {
    const auto tl = timings->find("levels");
    if (tl != timings->end() && tl->is_array() && l < tl->size()) {
      const auto r = (*tl)[l].find("poses_per_thread_second");
      if (r != (*tl)[l].end() && r->is_number() && r->get<double>() > 0) return 1.0 / r->get<double>();
    }
  }
  return -1.0;
}

std::string pipeline_of(const nlohmann::json& ps) {
  const auto p = ps.find("pipeline");
  if (p != ps.end() && p->is_string()) return p->get<std::string>();
  const auto src = ps.find("source");
  if (src != ps.end() && src->is_object() && src->value("kind", "") == "certify") return "certify";
  const auto pol = ps.find("polishing");
  if (pol != ps.end()) return "certified";
  return "unknown";
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(std::floor(pos));
  const double f = pos - static_cast<double>(i);
  return i + 1 < v.size() ? v[i] * (1.0 - f) + v[i + 1] * f : v[i];
}

OffsetValidation validate_offset(const SignedDistance& sdf, const std::string& dir, const nlohmann::json& level,
                                 double d, double voxel, bool completeness) {
  OffsetValidation r;
  const auto fo = level.find("float_offset");
  if (fo == level.end() || !fo->is_object()) return r;
  const auto file = fo->find("file");
  if (d == 0.0) return r;  // a band is defined for d != 0 only
  if (file == fo->end() || !file->is_string())
    throw InputError(dir + ": --offsets, but its float offsets were not kept (cdbench poses --pipeline float --keep-offsets)");
  Timer t;
  r.file = file->get<std::string>();
  const std::string path = dir + "/" + r.file;
  if (!std::filesystem::exists(path)) throw InputError(path + ": the float offset named in poseset.json is missing");
  const TriangleMesh m = read_triangle_mesh(path);
  r.faces = m.faces.size();
  BandOptions bo;
  // A face is split only until its bound is within a tenth of a voxel: the band is reported to
  // that accuracy (an upper bound either way), at a fraction of the cost of a tight one.
  bo.target = 0.1 * (voxel > 0 ? voxel : 1e-3 * sdf.bbox().diagonal());
  bo.max_split_depth = 2;
  const BandResult band = certify_band(sdf, m, d, bo);
  r.checked = band.faces_touching == 0;
  r.band = r.checked ? band.epsilon : kNaN;
  if (completeness && r.checked) {
    const ValidatedMesh v = validate_mesh(m);
    if (!v.report.valid()) {
      r.completeness = "not a valid closed surface (" + v.report.errors.front().kind + ")";
    } else {
      const CompletenessResult c = certify_completeness(sdf, v.mesh, d, band.epsilon);
      r.completeness = c.complete ? "complete"
                       : !c.missed.empty() ? "missed " + std::to_string(c.missed.size())
                                           : "unresolved " + std::to_string(c.unresolved.size()) + budget_note(c);
    }
  }
  r.seconds = t.seconds();
  return r;
}

}  // namespace

ValidateResult run_validate(const ValidateRequest& rq) {
  Timer total;
  ValidateResult res;
  const PoseSetManifest man = read_poseset_manifest(rq.poseset);
  const std::vector<PoseRow> rows = read_poseset_rows(man);
  std::map<std::uint64_t, PoseRow> ref_rows;
  nlohmann::json ref_json;
  if (!rq.reference.empty()) {
    const PoseSetManifest ref = read_poseset_manifest(rq.reference);
    if (ref.fixed.sha256 != man.fixed.sha256 || ref.mover.sha256 != man.mover.sha256)
      throw InputError(rq.reference + ": the reference pose set was made from other meshes than " + rq.poseset +
                       " (SHA-256 of the fixed or moving mesh differs)");
    for (PoseRow& r : read_poseset_rows(ref)) ref_rows.emplace(r.pose, std::move(r));
    ref_json = ref.json;
  }
  prepare_output_directory(rq.out);

  res.pipeline = pipeline_of(man.json);
  if (man.json.contains("grid") && man.json["grid"].is_object()) res.voxel = man.json["grid"].value("voxel", 0.0);
  const SignedDistance sdf(*rq.fixed);
  res.diagonal = sdf.bbox().diagonal();
  res.tolerance = rq.tolerance_relative * res.diagonal;
  MaxPenetrationOptions mpo;
  mpo.relative_tolerance = rq.max_penetration_tolerance;
  res.max_penetration = certified_max_penetration(sdf, mpo).depth;

  // Float offsets kept in the bundle: their certified band against their own level.
  const std::size_t L = man.levels.size();
  res.levels.resize(L);
  Timer t_off;
  for (std::size_t l = 0; l < L; ++l) {
    res.levels[l].spec = man.levels[l].spec;
    res.levels[l].target = man.levels[l].target;
    if (rq.offsets)
      res.levels[l].offset = validate_offset(sdf, rq.poseset, man.json["levels"][l], man.levels[l].target, res.voxel,
                                             rq.completeness);
  }
  res.seconds_offsets = t_off.seconds();

  // Poses: certificates, grouped by rotation; the tunnel test for separated poses.
  res.poses.resize(rows.size());
  std::vector<Eigen::Matrix3d> rotations(rows.size());
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const PoseRow& r = rows[i];
    PoseValidation& p = res.poses[i];
    p.pose = r.pose;
    p.level = r.level;
    p.target = r.target;
    p.clearance = {kNaN, kNaN};
    p.error = kNaN;
    p.placed = finite(r.t) && r.R.allFinite();
    if (p.placed) {
      rotations[i] = r.R;
      todo.push_back(i);
    }
  }
  const std::vector<std::uint32_t> components = component_representatives(*rq.mover);
  const SweepMesh fixed_sweep = make_sweep_mesh(rq.fixed->vertices, rq.fixed->faces);
  struct RotationState {
    MoverOrientation orientation;
    SweepMesh rotated;  // the mover at fl(R x), for sweeps from a pose (translated_sweep_mesh)
  };
  const auto make_state = [&](const Eigen::Matrix3d& R) {
    RotationState s{make_mover_orientation(*rq.mover, R), {}};
    s.rotated = make_sweep_mesh(s.orientation.rotated, rq.mover->faces);
    return s;
  };
  // As `cdbench certify` (placement/unknown_pose.h).
  const UnknownPoseOptions unknown(sdf, *rq.mover, res.tolerance, rq.max_cells);
  const ClearanceOptions& co = unknown.options();
  const bool long_faces = long_faces_keep_sweep_trees(*rq.fixed, *rq.mover);
  std::vector<std::atomic<std::uint64_t>> level_ns(L);
  std::atomic<std::uint64_t> sweep_ns{0};
  const double slack = 1e-9 * res.diagonal;
  const double mp = res.max_penetration.lo;
  Progress progress("validate", todo.size());
  Timer t_cert;
  for_each_pose_by_rotation<RotationState>(rotations, todo, make_state, [&](std::size_t i, const RotationState& s) {
    const PoseRow& r = rows[i];
    PoseValidation& p = res.poses[i];
    Timer t;
    // As `cdbench certify`: with long faces the pair-distance path on the sweep trees (the mover's
    // placed at t = 0 here), whose oriented boxes prune sliver pairs (speed only).
    const SweepTrees trees{&fixed_sweep, &s.rotated, Vec3::Zero()};
    ClearanceOptions pose_options = co;
    if (long_faces) pose_options.sweep_trees = &trees;
    const ClearanceResult c = certify_clearance(sdf, *rq.mover, components, s.orientation, r.t, pose_options);
    level_ns[static_cast<std::size_t>(r.level)] += static_cast<std::uint64_t>(t.seconds() * 1e9);
    p.clearance = c.clearance;
    p.certified = reaches_tolerance(c, co.tolerance);
    p.error = 0.5 * (c.clearance.lo + c.clearance.hi) - r.target;
    p.wrong_sign = (r.target < 0.0 && c.clearance.lo > 0.0) || (r.target > 0.0 && c.clearance.hi < 0.0);
    if (!finite(r.dir) || r.dir.squaredNorm() == 0.0) {
      p.missed_contact = Tristate::Unknown;
    } else if (r.target >= 0.0) {
      // Separated or touching target: the exact first contact of the pose's own approach line
      // (the mover at the pose swept along -dir; a time t < 0 lies back along +dir). A certainly
      // separated pose past it went through the solid.
      Timer ts;
      const SweepMesh moved = translated_sweep_mesh(s.rotated, r.t);
      const MeshContact mc = first_contact_along_line(fixed_sweep, moved, -r.dir);
      sweep_ns += static_cast<std::uint64_t>(ts.seconds() * 1e9);
      const bool past = mc.hit && mc.t.hi < 0.0;
      p.past_first_contact = past ? -mc.t.hi * r.dir.norm() : 0.0;
      p.missed_contact = past && c.clearance.lo > 0.0 ? Tristate::Yes : Tristate::No;
      // A penetrating or touching pose far past its first contact may have skipped it: proven by
      // a witness, a point of the approach between the first contact and the pose where the
      // mover is certainly separated again, or certainly deeper than at the pose (then the pose
      // is not on the first crossing of its own depth). Where to look is a heuristic (poses more
      // than 5 % of the max penetration past it, 7 evenly spaced points); certificates decide.
      if (past && p.missed_contact == Tristate::No && p.past_first_contact > 0.05 * mp) {
        ClearanceOptions wo = pose_options;
        wo.tolerance = 1e-4 * res.diagonal;
        wo.frontier = nullptr;
        for (int k = 1; k <= 7 && p.missed_contact == Tristate::No; ++k) {
          const double back = -mc.t.hi * k / 8.0;
          const Vec3 tk(r.t[0] + back * r.dir[0], r.t[1] + back * r.dir[1], r.t[2] + back * r.dir[2]);
          const Interval w = certify_clearance(sdf, *rq.mover, components, s.orientation, tk, wo).clearance;
          if (w.lo > 0.0 || w.hi < c.clearance.lo) p.missed_contact = Tristate::Yes;
        }
      }
    } else {
      // Penetrating target: the reference pose of the same approach is the first crossing of the
      // reference's target. The pose skipped the first crossing of its own target d when it lies
      // past a point certainly deeper than d (the reference pose) and is itself certainly
      // shallower than d: the approach had crossed d and come back out. (A pose on a later
      // crossing that is also too deep is not provable this way; it shows as a target error.)
      const auto it = ref_rows.find(r.pose);
      if (it == ref_rows.end() || it->second.status != PoseStatus::Certified || it->second.R != r.R ||
          it->second.dir != r.dir || !finite(it->second.t)) {
        p.missed_contact = Tristate::Unknown;
      } else {
        const PoseRow& ref = it->second;
        const bool past = (r.t - ref.t).dot(r.dir) < -slack;
        const bool came_back = ref.clearance_hi < r.target && c.clearance.lo > r.target;
        p.missed_contact = past && came_back ? Tristate::Yes : Tristate::No;
      }
    }
    progress.advance();
  });
  progress.finish();
  res.seconds_certify = t_cert.seconds();
  res.seconds_sweeps = 1e-9 * static_cast<double>(sweep_ns.load());

  // Per level.
  std::vector<std::vector<double>> errors(L), abs_errors(L), pasts(L);
  for (const PoseValidation& p : res.poses) {
    LevelValidation& lv = res.levels[static_cast<std::size_t>(p.level)];
    ++lv.poses;
    if (!p.placed) continue;
    ++lv.placed;
    lv.certified += p.certified;
    lv.wrong_sign += p.wrong_sign;
    lv.missed_contact += p.missed_contact == Tristate::Yes;
    lv.missed_undecided += p.missed_contact == Tristate::Unknown;
    if (!std::isnan(p.past_first_contact)) {
      pasts[static_cast<std::size_t>(p.level)].push_back(p.past_first_contact);
      lv.past_first_contact += p.past_first_contact > res.tolerance;
    }
    if (!std::isnan(p.target)) {
      errors[static_cast<std::size_t>(p.level)].push_back(p.error);
      abs_errors[static_cast<std::size_t>(p.level)].push_back(std::abs(p.error));
    }
  }
  std::vector<std::size_t> ref_level_poses(L, 0);
  for (const auto& [id, r] : ref_rows)
    if (static_cast<std::size_t>(r.level) < L) ++ref_level_poses[static_cast<std::size_t>(r.level)];
  for (std::size_t l = 0; l < L; ++l) {
    LevelValidation& lv = res.levels[l];
    const std::vector<double>& e = errors[l];
    double sum = 0.0;
    for (double x : e) sum += x;
    lv.error_mean = e.empty() ? kNaN : sum / static_cast<double>(e.size());
    lv.error_median = e.empty() ? kNaN : quantile(e, 0.5);
    lv.error_p95 = e.empty() ? kNaN : quantile(abs_errors[l], 0.95);
    lv.error_max = e.empty() ? kNaN : *std::max_element(abs_errors[l].begin(), abs_errors[l].end());
    lv.past_p95 = pasts[l].empty() ? kNaN : quantile(pasts[l], 0.95);
    lv.past_max = pasts[l].empty() ? kNaN : *std::max_element(pasts[l].begin(), pasts[l].end());
    lv.seconds_per_pose = recorded_seconds_per_pose(man.json, l, lv.poses);
    if (!ref_json.is_null()) lv.reference_seconds_per_pose = recorded_seconds_per_pose(ref_json, l, ref_level_poses[l]);
    lv.certify_seconds_per_pose = lv.placed ? 1e-9 * static_cast<double>(level_ns[l].load()) / lv.placed : 0.0;
  }

  // validation.csv and validation.json.
  write_file_atomically(rq.out + "/validation.csv", [&](std::ostream& out) {
    out << "pose,level,target,clearance_lo,clearance_hi,error,wrong_sign,missed_contact,past_first_contact\n";
    for (const PoseValidation& p : res.poses)
      out << p.pose << ',' << p.level << ',' << number_text(p.target) << ',' << number_text(p.clearance.lo) << ','
          << number_text(p.clearance.hi) << ',' << number_text(p.error) << ',' << (p.wrong_sign ? 1 : 0) << ','
          << (p.placed ? to_text(p.missed_contact) : "") << ',' << number_text(p.past_first_contact) << '\n';
  });
  const auto num = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
  nlohmann::json j;
  j["format"] = "cdbench-validation";
  j["format_version"] = 1;
  j["poseset"] = rq.poseset;
  j["reference"] = rq.reference.empty() ? nlohmann::json() : nlohmann::json(rq.reference);
  j["pipeline"] = res.pipeline;
  j["voxel"] = res.voxel > 0 ? nlohmann::json(res.voxel) : nlohmann::json();
  j["fixed"] = {{"path", man.fixed.path}, {"sha256", man.fixed.sha256}};
  j["max_penetration"] = {res.max_penetration.lo, res.max_penetration.hi};
  j["diagonal"] = res.diagonal;
  j["tolerance"] = res.tolerance;
  j["definitions"] = {
      {"error", "midpoint of the certified clearance interval - target (interval width <= tolerance)"},
      {"wrong_sign", "target < 0 but certainly separated (clearance_lo > 0), or target > 0 but certainly penetrating"},
      {"missed_contact",
       "target >= 0: certainly separated and past the exact first contact of its own approach line with the fixed "
       "surface (it went through the solid), or more than 5% of the max penetration past that first contact with a "
       "witness point between them where the mover is certainly separated or certainly deeper than at the pose; "
       "target < 0: past the reference's certified pose of the same approach, "
       "which is certainly deeper than the target, while certainly shallower than the target itself (the approach "
       "crossed the target and came back out). Unknown without an approach direction, or for target < 0 without a "
       "reference"},
      {"past_first_contact",
       "target >= 0: a certified lower bound of the distance along the approach from the exact first contact of the "
       "pose's own approach line with the fixed surface to the pose (0 when the pose is not past it); the level "
       "counts poses past it by more than the tolerance"}};
  j["levels"] = nlohmann::json::array();
  for (const LevelValidation& lv : res.levels) {
    const OffsetValidation& o = lv.offset;
    j["levels"].push_back(
        {{"spec", lv.spec},
         {"target", num(lv.target)},
         {"poses", lv.poses},
         {"placed", lv.placed},
         {"certified", lv.certified},
         {"wrong_sign", lv.wrong_sign},
         {"missed_contact", lv.missed_contact},
         {"missed_contact_undecided", lv.missed_undecided},
         {"past_first_contact", {{"poses", lv.past_first_contact}, {"p95", num(lv.past_p95)}, {"max", num(lv.past_max)},
                                 {"max_over_diagonal", num(lv.past_max / res.diagonal)}}},
         {"error", {{"mean", num(lv.error_mean)}, {"median", num(lv.error_median)}, {"p95_abs", num(lv.error_p95)}, {"max_abs", num(lv.error_max)}}},
         {"error_over_max_penetration",
          {{"mean", num(lv.error_mean / mp)}, {"median", num(lv.error_median / mp)}, {"p95_abs", num(lv.error_p95 / mp)}, {"max_abs", num(lv.error_max / mp)}}},
         {"error_over_diagonal",
          {{"mean", num(lv.error_mean / res.diagonal)}, {"median", num(lv.error_median / res.diagonal)}, {"p95_abs", num(lv.error_p95 / res.diagonal)}, {"max_abs", num(lv.error_max / res.diagonal)}}},
         {"seconds_per_pose", {{"pipeline", num(lv.seconds_per_pose)}, {"reference_certified", num(lv.reference_seconds_per_pose)}, {"validation_certificate", lv.certify_seconds_per_pose}}},
         {"float_offset", o.file.empty() ? nlohmann::json()
                                         : nlohmann::json{{"file", o.file}, {"faces", o.faces}, {"band", num(o.band)},
                                                          {"band_over_diagonal", num(o.band / res.diagonal)},
                                                          {"band_over_voxel", res.voxel > 0 ? num(o.band / res.voxel) : nlohmann::json()},
                                                          {"completeness", o.completeness.empty() ? nlohmann::json() : nlohmann::json(o.completeness)},
                                                          {"seconds", o.seconds}}}});
  }
  res.seconds_total = total.seconds();
  j["timings"] = {{"offsets", res.seconds_offsets}, {"certificates", res.seconds_certify}, {"sweeps_thread_seconds", res.seconds_sweeps}, {"total", res.seconds_total}};
  write_file_atomically(rq.out + "/validation.json", [&](std::ostream& out) { out << std::setw(2) << j << "\n"; });
  res.json = j;
  return res;
}

void write_validation_plots(const std::string& dir, const std::vector<ValidateResult>& runs,
                            const std::vector<std::string>& names) {
  // Error distribution per level (first run... every run: one file per run): |c - target| as a %
  // of the max penetration, sorted, against the fraction of poses (a cumulative distribution).
  std::ostringstream gp;
  gp << "set datafile separator ','\nset key outside right\nset grid\n";
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const ValidateResult& v = runs[k];
    const double mp = v.max_penetration.lo;
    const std::string data = "errors_" + std::to_string(k) + ".csv";
    std::vector<std::vector<double>> per_level(v.levels.size());
    for (const PoseValidation& p : v.poses) {
      const double pct = 100.0 * std::abs(p.error) / mp;  // inf for a target beyond a double's range of M
      if (p.placed && std::isfinite(pct)) per_level[static_cast<std::size_t>(p.level)].push_back(pct);
    }
    write_file_atomically(dir + "/" + data, [&](std::ostream& out) {
      out << "level,fraction,abs_error_pct_max_penetration\n";
      for (std::size_t l = 0; l < per_level.size(); ++l) {
        std::vector<double>& e = per_level[l];
        std::sort(e.begin(), e.end());
        for (std::size_t i = 0; i < e.size(); ++i)
          out << l << ',' << number_text((i + 1.0) / e.size(), 6) << ',' << number_text(e[i], 9) << '\n';
        out << "\n\n";  // gnuplot data blocks, one per level
      }
    });
    for (const char* term : {"pngcairo size 900,600", "svg size 900,600"}) {
      const std::string ext = std::string(term).substr(0, 3) == "png" ? "png" : "svg";
      gp << "set terminal " << term << "\nset output 'error_distribution_" << k << "." << ext << "'\n"
         << "set title " << gnuplot_string("|c - target| per level: " + names[k]) << " noenhanced\n"
         << "set xlabel '|c - target| (% of the certified max penetration)'\nset ylabel 'fraction of poses'\n";
      // Only levels with a positive error (log x): a level without a target (a user's poses
      // certified without a target column) has none, and gnuplot refuses a plot with no point.
      std::string series;
      for (std::size_t l = 0; l < v.levels.size(); ++l)
        if (std::any_of(per_level[l].begin(), per_level[l].end(), [](double e) { return e > 0.0; }))
          series += (series.empty() ? "" : ", ") + ("'" + data + "' index " + std::to_string(l)) +
                    " using 3:2 with lines lw 2 title " + gnuplot_string(v.levels[l].spec) + " noenhanced";
      if (series.empty())
        gp << "set label 1 'no level has a target with a finite error: nothing to plot' at graph 0.5, 0.5 center\n"
           << "plot [0:1] [0:1] NaN notitle\nunset label 1\n";
      else
        gp << "set logscale x\nplot " << series << "\nunset logscale x\n";
    }
  }
  // Error against the voxel size, when several gridded runs are given.
  std::vector<std::size_t> gridded;
  for (std::size_t k = 0; k < runs.size(); ++k)
    if (runs[k].voxel > 0) gridded.push_back(k);
  if (gridded.size() >= 2) {
    std::sort(gridded.begin(), gridded.end(), [&](std::size_t a, std::size_t b) { return runs[a].voxel < runs[b].voxel; });
    const std::size_t L = runs[gridded.front()].levels.size();
    write_file_atomically(dir + "/error_vs_voxel.csv", [&](std::ostream& out) {
      out << "level,voxel_over_diagonal,p95_abs_error_pct_max_penetration,max_abs_error_pct_max_penetration\n";
      for (std::size_t l = 0; l < L; ++l) {
        for (std::size_t k : gridded) {
          const ValidateResult& v = runs[k];
          if (l >= v.levels.size()) continue;
          out << l << ',' << number_text(v.voxel / v.diagonal, 9) << ','
              << number_text(100.0 * v.levels[l].error_p95 / v.max_penetration.lo, 9) << ','
              << number_text(100.0 * v.levels[l].error_max / v.max_penetration.lo, 9) << '\n';
        }
        out << "\n\n";
      }
    });
    for (const char* term : {"pngcairo size 900,600", "svg size 900,600"}) {
      const std::string ext = std::string(term).substr(0, 3) == "png" ? "png" : "svg";
      gp << "set terminal " << term << "\nset output 'error_vs_voxel." << ext << "'\n"
         << "set title 'p95 of |c - target| against the grid voxel'\nset xlabel 'voxel / diagonal'\n"
         << "set ylabel 'p95 |c - target| (% of max penetration)'\nset logscale xy\nplot ";
      for (std::size_t l = 0; l < L; ++l)
        gp << (l ? ", " : "") << "'error_vs_voxel.csv' index " << l << " using 2:3 with linespoints lw 2 title "
           << gnuplot_string(runs[gridded.front()].levels[l].spec) << " noenhanced";
      gp << "\nunset logscale xy\n";
    }
  }
  write_file_atomically(dir + "/plot.gp", [&](std::ostream& out) { out << gp.str(); });
}

}  // namespace cdbench
