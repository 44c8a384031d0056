// The pose pipeline against FCL's translational conservative advancement, on the approaches of a
// pose set made by `cdbench poses` (validation/bench_poses.sh runs both):
//  - our exact first contact of the mover with the fixed surface (sphere trees, exact sweeps);
//  - fcl::detail::conservativeAdvancementMeshOriented (OBBRSS, TranslationMotion) on the same
//    approach, from the same far start to the mirrored far end;
//  - how far FCL's contact is from the exact one, and the certified pose rate of the pose set;
//  - on lines the exact sweep proves to miss, any contact FCL claims, certified at its pose (a
//    penetrating one would contradict the sweep: exit 1);
//  - per level, the certified polished pose on the same approaches (the pose set's own start and
//    tolerance), timed in the same run, and its ratio to FCL's conservative advancement; and the
//    work behind that time, which does not move with the machine's load (certificate cells,
//    two-sided and segment tries, deep-zone jumps and octree cubes a pose): A/B runs compare it.
// Usage: bench_poses POSESET_DIR [--approaches M] [--no-separated-advance] [--no-sweep-certificate]
//                    [--no-support-planes] [--no-deep-cover] [--no-zone-octree] [--per-pose]
//                    [--trace FILE]
//   --no-separated-advance: targets > 0 advance by a certificate per step (the former way), for A/B.
//   --no-sweep-certificate: the touching pose certified by a branch and bound (the former way), A/B.
//   --no-support-planes: penetrating targets of a convex F without its supporting planes, A/B.
//   --no-deep-cover: penetrating targets without the deep zone's cover (no jumps across plateaus), A/B.
//   --no-zone-octree: where a cover runs out of its budget, no octree about the mover's path, A/B.
//   --per-pose: a line per polished pose (approach, level): its time and work, to find the poses
//     that hold a level's time. A level's deep-zone cover is built in the first pose that needs
//     it; that pose's line leaves the build out and names it (it is setup, as in the level's row).
//   --trace FILE: a CSV row per event of each polished pose (PolishEvent: every certificate with
//     what it was for, its lambda in full precision, its interval and cells; every segment tried,
//     with its verdict; every deep-zone query), to see where a slow pose's steps go.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "collide/fcl_model.h"
#include "fcl_ca.h"
#include "mesh/read_mesh.h"
#include "mesh/validate_mesh.h"
#include "poseset/poseset_manifest.h"
#include "placement/place_pose.h"
#include "sampling/sampling.h"
#include "util/atomic_file.h"
#include "util/number_format.h"
#include "util/timer.h"
#include "guarded_main.h"

using namespace cdbench;
// Below this share of the timed wall time on its core, the timing thread was held up by other
// processes (bench_poses says so): an idle machine measured 98.7-99.6 %, one sharing both cores
// with a CI run 61-88 % (doc/performance.md, "Loaded machines").
constexpr double kLoadedShare = 0.9;

namespace {

// One timed stretch on both clocks: the wall (util's Timer) and the timing thread's CPU time.
struct Stretch {
  Timer wall;
  ThreadCpuTimer cpu;
};

TriangleMesh load(const std::string& path) { return validate_mesh(read_polygon_soup(path)).mesh; }

const char* kTraceHeader = "approach,level,event,purpose,target,lambda,to,clearance_lo,clearance_hi,loose,warm,verdict,work,budget,ms\n";

// A --trace row: the event of approach `a` at level `level` (doubles in full precision, so that a
// pose reproduces).
std::string trace_row(std::size_t a, const std::string& level, const PolishEvent& e) {
  const bool cert = e.kind == PolishEvent::Kind::certificate, seg = e.kind == PolishEvent::Kind::segment;
  const char* event = cert ? "certificate" : seg ? "segment" : "zone-query";
  std::string row = std::to_string(a) + "," + level + "," + event + "," + (cert ? to_string(e.purpose) : "") + "," +
                    number_text(e.target) + "," + number_text(e.lambda) + "," + (cert ? "" : number_text(e.to)) + ",";
  row += cert ? number_text(e.clearance.lo) + "," + number_text(e.clearance.hi) : ",";
  row += std::string(",") + (cert ? (e.loose ? "1" : "0") : "") + "," + (cert ? (e.warm ? "1" : "0") : "") + "," +
         (seg ? to_string(e.verdict) : "") + "," + std::to_string(e.work) + "," + (seg ? std::to_string(e.budget) : "") +
         "," + number_text(1e3 * e.seconds, 6) + "\n";
  return row;
}

// A --trace event's kind for the time breakdown: a certificate's purpose, a segment's verdict.
std::string trace_kind(const PolishEvent& e) {
  if (e.kind == PolishEvent::Kind::certificate) return to_string(e.purpose);
  if (e.kind == PolishEvent::Kind::segment) return std::string("segment ") + to_string(e.verdict);
  return "zone query";
}

}  // namespace

static int run(int argc, char** argv) {
  const char* usage =
      "usage: bench_poses POSESET_DIR [--approaches M] [--no-separated-advance] [--no-sweep-certificate]\n"
      "       [--no-support-planes] [--no-deep-cover] [--no-zone-octree] [--per-pose] [--trace FILE]\n"
      "  times certified polished poses of a pose set made by `cdbench poses` against FCL's conservative\n"
      "  advancement on the same approaches (M: how many, default 200); the --no-* switches select\n"
      "  former ways (A/B): the separated advance and the touching certificate by certificates, no\n"
      "  supporting planes, no built deep-zone cover, no deep-zone octree about the mover's path;\n"
      "  --per-pose: a line per polished pose (approach, level) with its time and work\n"
      "  --trace FILE: a CSV row per certificate, segment try and deep-zone query of each polished pose\n";
  if (argc >= 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    std::fputs(usage, stdout);
    return 0;
  }
  if (argc < 2 || argv[1][0] == '-') {
    std::fputs(usage, stderr);
    return 2;
  }
  const std::string dir = argv[1];
  std::size_t wanted = 200;
  bool separated_advance = true, no_sweep_certificate = false, support_planes = true, deep_covers = true,
       zone_octree = true, per_pose = false;
  std::string trace_path;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--approaches") == 0 && i + 1 < argc) wanted = std::stoul(argv[++i]);
    else if (std::strcmp(argv[i], "--no-separated-advance") == 0) separated_advance = false;  // A/B
    else if (std::strcmp(argv[i], "--no-sweep-certificate") == 0) no_sweep_certificate = true;  // A/B
    else if (std::strcmp(argv[i], "--no-support-planes") == 0) support_planes = false;  // A/B
    else if (std::strcmp(argv[i], "--no-deep-cover") == 0) deep_covers = false;  // A/B
    else if (std::strcmp(argv[i], "--no-zone-octree") == 0) zone_octree = false;  // A/B
    else if (std::strcmp(argv[i], "--per-pose") == 0) per_pose = true;
    else if (std::strcmp(argv[i], "--trace") == 0 && i + 1 < argc) trace_path = argv[++i];
    else {
      std::fprintf(stderr, "bench_poses: unknown option '%s'\n%s", argv[i], usage);
      return 2;
    }
  }
  if (!trace_path.empty()) check_output_path(trace_path);  // before the run, not after it
  // The manifest reader names the file and key of any problem; a mesh the pose set was made
  // from is found and checked by its SHA-256 (locate_mesh), and read once when it is also the mover.
  const PoseSetManifest manifest = read_poseset_manifest(dir);
  const nlohmann::json& ps = manifest.json;
  const TriangleMesh fixed_mesh = load(locate_mesh(manifest.fixed, dir));
  const TriangleMesh mover = manifest.mover_is_fixed ? fixed_mesh : load(locate_mesh(manifest.mover, dir));
  const SignedDistance fixed(fixed_mesh);
  const double diag = fixed.bbox().diagonal();
  ApproachSetup setup = make_approach_setup(fixed, mover);
  const SweepMesh level0 = make_sweep_mesh(fixed_mesh.vertices, fixed_mesh.faces);
  if (!no_sweep_certificate) attach_surface_sweep(setup, level0);

  // The pose set's samples, regenerated exactly as `cdbench poses` makes them.
  const auto& s = ps["sampling"];
  const std::size_t N = s["directions"]["count"], K = s["orientations"]["count"];
  const std::vector<Vec3> dirs =
      s["directions"]["kind"] == "grid" ? sphere_grid(N) : sphere_fibonacci(N);
  const std::vector<Eigen::Quaterniond> rots = s["orientations"]["kind"] == "random"
                                                   ? rotations_random(K, s["orientations"]["seed"].get<std::uint64_t>())
                                                   : rotations_super_fibonacci(K);
  const std::size_t A = N * K, M = std::min(wanted, A);

  auto fcl_fixed = fcl_model<fcl::OBBRSS<double>>(fixed_mesh);
  auto fcl_mover = fcl_model<fcl::OBBRSS<double>>(mover);
  const double far = setup.fixed_radius + setup.mover_radius + 1e-3 * diag;
  // The pose set's levels as `cdbench poses` placed them.
  const std::size_t L = ps["levels"].size();
  std::vector<double> level_target(L), level_seconds(L, 0.0);
  std::vector<std::size_t> level_certified(L, 0), level_steps(L, 0), level_jumps(L, 0), level_zone_cubes(L, 0);
  // The work behind ms/pose, in units that do not depend on the machine's load (for A/B runs).
  std::vector<std::size_t> level_cells(L, 0), level_two_sided(L, 0), level_kept(L, 0), level_segments(L, 0);
  std::vector<PoseStart> level_start(L);
  std::vector<std::unique_ptr<SweepMesh>> level_offset(L);
  PoseOptions po;
  po.tolerance = ps["certification"]["tolerance"].get<double>();
  po.polish = ps["polishing"]["enabled"].get<bool>();
  po.max_steps = ps["polishing"]["max_steps"].get<int>();
  po.separated_advance = separated_advance;
  po.support_planes = support_planes;
  if (!zone_octree) po.deep_zone_cubes = 0;
  for (std::size_t l = 0; l < L; ++l) {
    const auto& e = ps["levels"][l];
    level_target[l] = e["target"].get<double>();
    const std::string start = e.value("start", std::string("offset"));
    level_start[l] = start == "surface" ? PoseStart::Surface : start == "far" ? PoseStart::Far : PoseStart::Offset;
    if (level_start[l] == PoseStart::Offset && e["swept_offset"].is_object() && e["swept_offset"]["file"].is_string()) {
      const TriangleMesh m = load(dir + "/" + e["swept_offset"]["file"].get<std::string>());
      level_offset[l] = std::make_unique<SweepMesh>(make_sweep_mesh(m.vertices, m.faces));
    }
  }
  const std::vector<std::size_t> descending = descending_target_order(level_target);
  // The penetrating levels' deep-zone covers, built when a pose first needs one, as in `cdbench
  // poses` (their build time is reported apart, with the other setup).
  std::vector<LevelDeepZone> level_zone;
  const double max_penetration = ps["max_penetration"]["interval"][0].get<double>();
  for (std::size_t l = 0; l < L; ++l)
    level_zone.push_back(make_level_deep_zone(fixed, level_target[l], max_penetration, deep_covers && po.polish, A));
  double t_exact = 0.0, t_fcl = 0.0, max_over = 0.0, max_under = 0.0;
  // The timing thread's CPU time over the wall time of the same timed stretches (poses that built a
  // level's cover left out: its build may run on other threads): the share of the time it ran.
  double timed_cpu = 0.0, timed_wall = 0.0;
  // The same thread's CPU time of FCL's advancement and of each level's poses (a cover's build
  // taken off at its wall time: the thread builds it, TBB's workers helping), for ratios that
  // hold under load.
  double t_fcl_cpu = 0.0;
  std::vector<double> level_cpu(L, 0.0);
  std::uint64_t node_tests = 0, leaf_sweeps = 0;  // the exact first contact's work
  std::size_t differ = 0, overshoot = 0, both = 0, fcl_miss = 0;
  std::size_t exact_miss = 0, fcl_only = 0, fcl_only_contradicting = 0, fcl_only_grazing = 0;
  // Where the two disagree, the certified clearance decides: at the exact contact it must enclose 0
  // (touching), a hair before it be positive (no earlier contact), and at FCL's contact, if FCL
  // went past, be negative (FCL's pose penetrates).
  std::size_t checked = 0, exact_confirmed = 0, fcl_penetrating = 0;
  ClearanceOptions copt;
  copt.tolerance = 1e-6 * diag;
  const auto clearance_at = [&](const OrientationFrame& f, const Vec3& d, double lambda) {
    const Vec3 t = pose_translation(f, d, lambda);
    // As `cdbench certify`: with long faces the pair-distance path on the sweep trees (a thin
    // tube's slivers about bunny00 took 30 s of this check on the box trees).
    const SweepTrees trees{&level0, &f.swept, f.t0};
    ClearanceOptions o = copt;
    if (setup.keep_sweep_trees) o.sweep_trees = &trees;
    return certify_clearance(fixed, mover, setup.components, f.orientation, t, o).clearance;
  };
  // --trace: rows gathered here, written whole at the end.
  std::string trace_text = kTraceHeader;
  std::size_t trace_approach = 0, trace_level_index = 0;
  std::string trace_level;
  // Each level's traced time by kind of event (seconds, events).
  std::vector<std::map<std::string, std::pair<double, std::size_t>>> traced(L);
  const PolishTrace tracer = [&](const PolishEvent& e) {
    trace_text += trace_row(trace_approach, trace_level, e);
    auto& kind = traced[trace_level_index][trace_kind(e)];
    kind.first += e.seconds;
    ++kind.second;
  };
  std::size_t current_orientation = static_cast<std::size_t>(-1);
  std::unique_ptr<OrientationFrame> frame;
  for (std::size_t k = 0; k < M; ++k) {
    const std::size_t a = k * A / M;  // spread over the whole set
    const std::size_t o = a / N;
    const Vec3& d = dirs[a % N];
    if (o != current_orientation) {
      frame = std::make_unique<OrientationFrame>(make_orientation_frame(setup, rots[o].toRotationMatrix()));
      current_orientation = o;
    }
    Stretch timed;
    const MeshContact c = first_contact_along_line(level0, frame->swept, -d);
    const double lambda_exact = c.hit ? -exact_contact_time(level0, frame->swept, -d, c).get_d() : NAN;
    const double exact_seconds = timed.wall.seconds();
    timed_cpu += timed.cpu.seconds();
    t_exact += exact_seconds;
    timed_wall += exact_seconds;
    node_tests += c.sphere_tests;
    leaf_sweeps += c.triangle_sweeps;

    double lambda_ca = 0.0, seconds_ca = 0.0;
    timed = Stretch();
    const bool hit = fcl_ca_contact(*fcl_fixed, *fcl_mover, *frame, d, far, &lambda_ca, &seconds_ca);
    const double fcl_cpu = timed.cpu.seconds();
    timed_cpu += fcl_cpu;
    t_fcl_cpu += fcl_cpu;
    timed_wall += timed.wall.seconds();
    t_fcl += seconds_ca;
    // As `cdbench poses` places them: descending targets, sharing the contact and continuing the
    // advance from the previous level's pose (place_pose's memo); each level timed with its share.
    ApproachMemo memo;
    for (const std::size_t l : descending) {
      const SweepMesh* swept = level_start[l] == PoseStart::Surface ? &level0 : level_offset[l].get();
      if (level_start[l] == PoseStart::Offset && !swept) continue;  // the level had no offset
      PoseOptions lpo = level_zone[l].options(po);
      lpo.start = level_start[l];
      if (!trace_path.empty()) {
        lpo.trace = &tracer;
        trace_approach = a;
        trace_level_index = l;
        trace_level = ps["levels"][l]["spec"].get<std::string>();
      }
      const double cover_before = level_zone[l].cover ? level_zone[l].cover->seconds() : 0.0;
      timed = Stretch();
      const PoseOutcome p = place_pose(setup, *frame, swept, d, level_target[l], lpo, &memo);
      // A level's cover is built inside the first pose that needs it: setup, left out of the
      // pose's time (and named on its --per-pose line).
      const double cover_built = level_zone[l].cover ? level_zone[l].cover->seconds() - cover_before : 0.0;
      const double pose_wall = timed.wall.seconds(), pose_cpu = timed.cpu.seconds();
      if (cover_built == 0.0) {
        timed_cpu += pose_cpu;
        timed_wall += pose_wall;
      }
      level_cpu[l] += std::max(0.0, pose_cpu - cover_built);
      const double pose_seconds = std::max(0.0, pose_wall - cover_built);
      level_seconds[l] += pose_seconds;
      level_certified[l] += p.contact && p.certified && p.on_target;
      level_steps[l] += static_cast<std::size_t>(p.steps);
      level_jumps[l] += static_cast<std::size_t>(p.cover_jumps);
      level_zone_cubes[l] += static_cast<std::size_t>(p.zone_cubes);
      level_cells[l] += static_cast<std::size_t>(p.clearance_cells);
      level_two_sided[l] += static_cast<std::size_t>(p.two_sided_tries);
      level_kept[l] += static_cast<std::size_t>(p.kept_tries);
      level_segments[l] += static_cast<std::size_t>(p.segment_tries);
      if (per_pose) {
        char built[96] = "";
        if (cover_built > 0.0)
          std::snprintf(built, sizeof built, " (the level's cover built in this pose, %.3f ms, not counted)",
                        1e3 * cover_built);
        std::printf("pose approach %zu level %s: %.3f ms, steps %d, cells %llu, two-sided %d, segments %d, jumps %d, "
                    "cubes %llu%s%s\n",
                    a, ps["levels"][l]["spec"].get<std::string>().c_str(),
                    1e3 * pose_seconds, p.steps,
                    static_cast<unsigned long long>(p.clearance_cells), p.two_sided_tries, p.segment_tries,
                    p.cover_jumps, static_cast<unsigned long long>(p.zone_cubes),
                    p.certified && p.on_target ? "" : " (not certified on target)", built);
      }
    }
    if (!c.hit) {
      // The exact sweep proves the line misses; FCL claiming a contact there is checked by a
      // certificate at its pose: c > 0 refutes FCL; c < 0 would contradict the sweep (an error,
      // exit 1); an interval holding 0 is a graze within the certificate's width.
      ++exact_miss;
      if (hit) {
        ++fcl_only;
        const Interval at = clearance_at(*frame, d, lambda_ca);
        if (at.hi < 0.0) ++fcl_only_contradicting;
        else if (!(at.lo > 0.0)) ++fcl_only_grazing;
      }
      continue;
    }
    const double lambda_fcl = hit ? lambda_ca : NAN;
    const double err = lambda_fcl - lambda_exact;  // < 0: FCL moved past the exact first contact
    if (!hit || std::abs(err) > 1e-6 * diag) {
      ++checked;
      const Interval at = clearance_at(*frame, d, lambda_exact);
      const Interval before = clearance_at(*frame, d, lambda_exact + 1e-6 * diag);
      // Touching up to the rounding of t (ulps) and the certificate's width.
      if (at.lo <= 1e-9 * diag && at.hi >= -1e-9 * diag && before.lo > 0.0) ++exact_confirmed;
      if (hit && err < 0 && clearance_at(*frame, d, lambda_fcl).hi < 0.0) ++fcl_penetrating;
    }
    if (!hit) {
      ++fcl_miss;
      continue;
    }
    ++both;
    if (std::abs(err) > 1e-6 * diag) ++differ;
    if (err < -1e-6 * diag) ++overshoot;
    max_over = std::max(max_over, -err);
    max_under = std::max(max_under, err);
  }
  if (!trace_path.empty()) write_file_atomically(trace_path, [&](std::ostream& os) { os << trace_text; });
  const double pps = ps["timings"]["poses_per_second"].get<double>();
  const std::size_t levels = ps["levels"].size();
  std::printf("pose set %s: %zu faces, %zu directions x %zu orientations x %zu levels\n", dir.c_str(),
              fixed_mesh.faces.size(), N, K, levels);
  std::printf("certified poses per second (cdbench poses, its own run): %.1f\n", pps);
  std::printf("%-52s %12s\n", "per approach, one thread", "ms");
  std::printf("%-52s %12.3f\n", "cdbench exact first contact (sphere trees)", 1e3 * t_exact / M);
  std::printf("%-52s %12.3f\n", "FCL conservativeAdvancementMeshOriented (OBBRSS)", 1e3 * t_fcl / M);
  std::printf("ratio FCL CA / exact first contact: %.2f\n", t_fcl / t_exact);
  std::printf("exact first contact per approach: %.0f node pairs bounded, %.0f triangle pairs swept\n",
              static_cast<double>(node_tests) / M, static_cast<double>(leaf_sweeps) / M);
  std::printf("ratio certified pose (all levels, polished; cdbench poses' own run, all threads) / FCL CA, per pose: %.2f\n",
              (1.0 / pps) / (t_fcl / M));
  std::printf("\ncertified polished pose per approach, same %zu approaches, same run, one thread:\n", M);
  std::printf("%-12s %-8s %12s %12s %14s %14s %14s\n", "level", "start", "ms/pose", "poses/s", "certified", "mean steps",
              "pose / FCL CA");
  double all = 0.0;
  for (std::size_t l = 0; l < L; ++l) {
    all += level_seconds[l];
    std::printf("%-12s %-8s %12.3f %12.1f %9zu/%-4zu %14.2f %14.2f\n", ps["levels"][l]["spec"].get<std::string>().c_str(),
                to_string(level_start[l]), 1e3 * level_seconds[l] / M, M / level_seconds[l], level_certified[l], M,
                static_cast<double>(level_steps[l]) / M, (level_seconds[l] / M) / (t_fcl / M));
  }
  std::printf("%-12s %-8s %12.3f %12.1f %14s %14s %14.2f\n", "all", "", 1e3 * all / (M * L), M * L / all, "", "",
              (all / (M * L)) / (t_fcl / M));
  // Wall times read high where other processes took the timing thread's core (a CI run, a build):
  // said here, with its share, so that a loaded run's figures are not quoted as the machine's.
  const double share = timed_wall > 0.0 ? timed_cpu / timed_wall : 1.0;
  const bool loaded = share < kLoadedShare;
  std::printf("timing thread on its core %.1f %% of the timed wall time%s\n", 100.0 * share,
              loaded ? " (other processes shared the cores: the times above read high; repeat on an idle machine)" : "");
  // The ratios again on that thread's CPU time: preemption left out of both sides.
  std::printf("pose / FCL CA on the timing thread's CPU time:");
  double all_cpu = 0.0;
  for (std::size_t l = 0; l < L; ++l) {
    all_cpu += level_cpu[l];
    std::printf(" %s %.2f,", ps["levels"][l]["spec"].get<std::string>().c_str(), level_cpu[l] / t_fcl_cpu);
  }
  std::printf(" all %.2f\n", (all_cpu / L) / t_fcl_cpu);
  if (loaded)
    std::fprintf(stderr, "bench_poses: warning: the timing thread ran %.1f %% of the timed wall time: the machine was loaded\n",
                 100.0 * share);
  for (std::size_t l = 0; l < L; ++l) {
    // Levels shallower than a fifth of M have no cover but may still jump by the zone's octree.
    if (!level_zone[l].cover && level_jumps[l] == 0 && level_zone_cubes[l] == 0) continue;
    const std::string spec = ps["levels"][l]["spec"].get<std::string>();
    std::printf("deep-zone jumps %s: %zu; octree cubes %zu (in ms/pose)", spec.c_str(), level_jumps[l], level_zone_cubes[l]);
    if (!level_zone[l].cover)
      std::printf("; no cover (shallower than a fifth of M)\n");
    else if (const DeepCover* k = level_zone[l].cover->peek())
      std::printf("; built cover (setup, not in ms/pose): %s, %llu cubes, %zu boxes, %.3f s\n",
                  k->complete ? "complete" : "budget exhausted, not used", static_cast<unsigned long long>(k->cells),
                  k->boxes.size(), level_zone[l].cover->seconds());
    else
      std::printf("; built cover not needed (no pose found c flat)\n");
  }
  for (std::size_t l = 0; l < L; ++l)
    std::printf("work a pose %s: certificate cells %.0f, two-sided tries %.2f (rejected, then kept %.2f), segment tries "
                "%.2f, jumps %.2f, octree cubes %.0f\n",
                ps["levels"][l]["spec"].get<std::string>().c_str(), static_cast<double>(level_cells[l]) / M,
                static_cast<double>(level_two_sided[l]) / M, static_cast<double>(level_kept[l]) / M,
                static_cast<double>(level_segments[l]) / M,
                static_cast<double>(level_jumps[l]) / M, static_cast<double>(level_zone_cubes[l]) / M);
  // --trace: where each level's time went, by kind of event, the costliest first (the rest: steps'
  // arithmetic, planes' steps, the trace's own rows). Wall times: they move with the load.
  for (std::size_t l = 0; l < L && !trace_path.empty(); ++l) {
    if (traced[l].empty()) continue;
    std::vector<std::pair<std::string, std::pair<double, std::size_t>>> kinds(traced[l].begin(), traced[l].end());
    std::stable_sort(kinds.begin(), kinds.end(),
                     [](const auto& x, const auto& y) { return x.second.first > y.second.first; });
    const double total = level_seconds[l];
    double events = 0.0;
    std::printf("time a pose %s, traced:", ps["levels"][l]["spec"].get<std::string>().c_str());
    for (const auto& [kind, v] : kinds) {
      events += v.first;
      std::printf(" %s %.3f ms (%.0f %%, %zu, %.3f ms each);", kind.c_str(), 1e3 * v.first / M,
                  total > 0.0 ? 100.0 * v.first / total : 0.0, v.second, 1e3 * v.first / static_cast<double>(v.second));
    }
    std::printf(" the rest %.3f ms\n", 1e3 * std::max(0.0, total - events) / M);
  }
  std::printf("approaches %zu, contact found by both %zu, FCL found none %zu\n", M, both, fcl_miss);
  std::printf("lines the exact sweep proves to miss: %zu; FCL found a contact on %zu of them: certified at FCL's pose "
              "apart %zu, grazing (c's interval holds 0) %zu, penetrating %zu (contradicts the sweep)\n",
              exact_miss, fcl_only, fcl_only - fcl_only_grazing - fcl_only_contradicting, fcl_only_grazing,
              fcl_only_contradicting);
  std::printf("FCL contact differs from the exact one by > 1e-6 diag: %zu (%.1f%%), past it: %zu; max past %.3g, "
              "max short %.3g (x diag: %.3g, %.3g)\n",
              differ, both ? 100.0 * differ / both : 0.0, overshoot, max_over, max_under, max_over / diag,
              max_under / diag);
  std::printf("disagreements checked with certified clearances: %zu; exact contact confirmed (c encloses 0 there, "
              "c > 0 just before): %zu; FCL pose past the contact certified penetrating: %zu\n",
              checked, exact_confirmed, fcl_penetrating);
  if (fcl_only_contradicting > 0) {
    std::fprintf(stderr, "bench_poses: error: %zu lines the exact sweep proves to miss hold a certified penetrating pose\n",
                 fcl_only_contradicting);
    return 1;
  }
  return 0;
}

int main(int argc, char** argv) { return guarded_main("bench_poses", run, argc, argv); }
