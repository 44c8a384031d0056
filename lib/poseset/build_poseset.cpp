#include "poseset/build_poseset.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>

#include <tbb/collaborative_call_once.h>
#include <tbb/parallel_invoke.h>

#include "distance/depth_bound.h"
#include "distance/max_penetration.h"
#include "mesh/read_mesh.h"
#include "offset/level_list.h"
#include "placement/place_pose.h"
#include "poseset/journal.h"
#include "poseset/level_summary.h"
#include "poseset/pose_csv.h"
#include "poseset/poseset_manifest.h"
#include "sampling/sampling.h"
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
struct Shard {
  std::uint64_t index = 0, count = 1;
};

Shard parse_shard(const std::string& s) {
  const auto slash = s.find('/');
  Shard r;
  try {
    if (slash == std::string::npos) throw std::invalid_argument("");
    std::size_t a = 0, b = 0;
    r.index = std::stoull(s.substr(0, slash), &a);
    r.count = std::stoull(s.substr(slash + 1), &b);
    if (a != slash || b != s.size() - slash - 1) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw InputError("--shard: expected I/N with 0 <= I < N, found '" + s + "'");
  }
  if (r.count == 0 || r.index >= r.count) throw InputError("--shard: expected I/N with 0 <= I < N, found '" + s + "'");
  return r;
}

// Rows of an earlier run's journal, whole approaches only (an approach's rows are written
// together; a cut approach is computed again).
std::map<std::uint64_t, std::string> whole_approaches(std::map<std::uint64_t, std::string> rows, std::size_t levels) {
  std::map<std::uint64_t, std::size_t> per_approach;
  for (const auto& [pose, line] : rows) ++per_approach[pose / levels];
  for (auto it = rows.begin(); it != rows.end();)
    it = per_approach[it->first / levels] == levels ? std::next(it) : rows.erase(it);
  return rows;
}
struct CheckedOptions {
  std::vector<LevelSpec> specs;
  Shard shard;
};

CheckedOptions check_options(const PoseSetRequest& opt) {
  CheckedOptions c;
  c.specs = parse_level_list(opt.levels);
  c.shard = parse_shard(opt.shard);
  check_sampling_names(opt.direction_sampling, opt.orientation_sampling);
  check_distinct_levels(c.specs);
  if (opt.parallel_mesher && opt.start != StartPolicy::Offsets && !opt.no_polish)
    throw InputError("--parallel-mesher: offsets are meshed only with --start offset (or --no-polish)");
  // A run keeps its shard's rows in memory (about 0.87 KB each) until poses.csv is written:
  // a request far beyond that is an error now rather than an out-of-memory stop after the setup.
  const double approaches = static_cast<double>(opt.directions) * static_cast<double>(opt.orientations);
  const double poses = std::ceil(approaches / static_cast<double>(c.shard.count)) * static_cast<double>(c.specs.size());
  if (poses > kMaxPosesPerRun)
    throw InputError("the request has " + number_text(poses, 3) + " poses per shard (" + std::to_string(opt.directions) +
                     " directions x " + std::to_string(opt.orientations) + " orientations x " +
                     std::to_string(c.specs.size()) + " levels / " + std::to_string(c.shard.count) +
                     " shards); at most " + number_text(kMaxPosesPerRun) +
                     " per run: split it into more shards (--shard I/N, then cdbench merge) or ask for fewer");
  return c;
}

// The spread of the approaches' costs and what it allows on more threads than this machine has:
// the poses phase's modelled speed-up on T threads: the same hand-out (dynamic_makespan), each
// approach costing what it did here, and the orientations' frames, which threads that wait for one
// help to build, as if built by all T at once. A model, not a measurement (doc/performance.md).
nlohmann::json approach_timings(const std::vector<double>& seconds, const std::vector<double>& frame_seconds) {
  nlohmann::json j = nlohmann::json::object();
  if (seconds.empty()) return j;
  std::vector<double> sorted = seconds;
  std::sort(sorted.begin(), sorted.end());
  const double frames = std::accumulate(frame_seconds.begin(), frame_seconds.end(), 0.0);
  const double sum = std::accumulate(sorted.begin(), sorted.end(), 0.0);
  const auto quantile = [&](double q) { return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))]; };
  j["count"] = seconds.size();
  j["thread_seconds"] = sum;  // without the frames
  j["frame_thread_seconds"] = frames;
  j["median"] = quantile(0.5);
  j["p99"] = quantile(0.99);
  j["max"] = sorted.back();
  nlohmann::json model = nlohmann::json::array();
  for (int t : {2, 4, 8, 16, 32, 64}) {
    const double makespan = dynamic_makespan(seconds, t) + frames / t;
    model.push_back({{"threads", t}, {"speedup", makespan > 0.0 ? (sum + frames) / makespan : 0.0}});
  }
  j["modelled_speedup"] = model;
  return j;
}

}  // namespace

void check_poseset_request(const PoseSetRequest& request) { check_options(request); }

PoseSetResult build_poseset(const PoseSetRequest& opt) {
  const CheckedOptions checked = check_options(opt);
  const std::vector<LevelSpec>& specs = checked.specs;
  const Shard shard = checked.shard;
  Timer total;
  const TriangleMesh& fixed_mesh = *opt.fixed.mesh;
  const bool mover_is_fixed = opt.mover.path.empty();
  const std::string mover_path = mover_is_fixed ? opt.fixed.path : opt.mover.path;
  const TriangleMesh& mover = mover_is_fixed ? fixed_mesh : *opt.mover.mesh;
  prepare_output_directory(opt.out);

  // Work that does not depend on the levels' distances runs beside what does, so that many
  // threads are not left to one phase's serial parts: the files' hashes (serial: 0.04 s for a
  // 42 MB file) and F's sweep mesh (its tree's top is split on one thread) while the distance's tree
  // is built; the pose stage's setup (the mover's sweep mesh when it is not F, F's supporting
  // planes, the mover's components) while the maximum penetration is certified. (armadillo, the
  // issue's 512-pose request: 0.15 s of the setup's 0.5 s on one thread ran beside; doc/performance.md.)
  std::string fixed_sha, mover_sha;
  std::optional<SignedDistance> sdf_holder;
  std::shared_ptr<const SweepMesh> surface;
  tbb::parallel_invoke(
      [&] {
        fixed_sha = sha256_file(opt.fixed.path);
        mover_sha = mover_is_fixed ? fixed_sha : sha256_file(opt.mover.path);
      },
      [&] { sdf_holder.emplace(fixed_mesh); },
      // F's own sweep mesh: the first contact of surface starts, and (with the mover's) the trees
      // of the separated advance and of the pair-distance path.
      [&] { surface = std::make_shared<const SweepMesh>(make_sweep_mesh(fixed_mesh.vertices, fixed_mesh.faces)); });
  const SignedDistance& sdf = *sdf_holder;
  const double diag = sdf.bbox().diagonal();
  double seconds_mp = 0.0;
  const double mp_tol = max_penetration_tolerance_for(specs, opt.tolerance, opt.max_penetration_tolerance);
  std::optional<MaxPenetrationResult> mp_holder;
  std::optional<ApproachSetup> setup_holder;
  tbb::parallel_invoke([&] { mp_holder.emplace(timed_max_penetration(sdf, mp_tol, &seconds_mp)); },
                       [&] {
                         // The same tree serves as the mover's own when the mover is the fixed mesh
                         // (the default).
                         const bool same_mesh = mover.vertices == fixed_mesh.vertices && mover.faces == fixed_mesh.faces;
                         setup_holder.emplace(make_approach_setup(sdf, mover, same_mesh ? surface : nullptr));
                         attach_surface_sweep(*setup_holder, *surface);
                       });
  const MaxPenetrationResult& mp = *mp_holder;
  ApproachSetup& setup = *setup_holder;
  const bool polish = !opt.no_polish;
  const double tol = opt.tolerance * diag;

  // Levels: targets and where their poses start (doc/poses.md): the exact first contact with the
  // surface itself (level 0; d < 0 by default), far away (d > 0 by default), or the first contact
  // with a certified offset at d + 2 band (--start offset) or at d (no polishing).
  const std::size_t L = specs.size();
  std::vector<double> targets(L), swept(L);
  std::vector<PoseStart> start(L);
  std::vector<std::string> level_note(L);
  const double band = opt.band_tolerance * diag;
  bool near_surface_starts = false;
  for (std::size_t l = 0; l < L; ++l) {
    targets[l] = level_distance(specs[l], mp.depth.lo);
    check_level_reach(specs[l], targets[l], diag);
    start[l] = planned_start(targets[l], polish, opt.start, band);
    swept[l] = start[l] == PoseStart::Offset && polish ? targets[l] + 2.0 * band : targets[l];
    if (opt.start == StartPolicy::Offsets && polish && targets[l] < 0.0 && start[l] == PoseStart::Surface) {
      near_surface_starts = true;
      level_note[l] = "target within " + number_text(kNearSurfaceBands) +
                      " bands of the surface: polished from the first contact with the surface, no offset";
      std::cerr << "cdbench poses: note: level " << specs[l].text << ": " << level_note[l] << std::endl;
    }
  }

  check_distinct_distances(specs, targets);
  const std::string resolution_note = percentage_resolution_note(specs, targets, tol, diag);
  if (!resolution_note.empty()) std::cerr << "cdbench poses: note: " << resolution_note << std::endl;

  // Run identity: a resumed run must be the same run.
  nlohmann::json run_key = {{"fixed_sha256", fixed_sha},
                            {"mover_sha256", mover_sha},
                            {"levels", opt.levels},
                            {"directions", opt.directions},
                            {"orientations", opt.orientations},
                            {"direction_sampling", opt.direction_sampling},
                            {"orientation_sampling", opt.orientation_sampling},
                            {"seed", opt.seed},
                            {"tolerance", opt.tolerance},
                            {"band_tolerance", opt.band_tolerance},
                            {"polish", polish},
                            {"start", to_string(opt.start)},
                            {"max_steps", opt.max_steps},
                            {"shard", opt.shard},
                            {"generator", std::string("cdbench ") + CDBENCH_VERSION}};
  OffsetOptions offset_options;
  offset_options.tolerance_relative = opt.band_tolerance;
  offset_options.parallel_mesher = opt.parallel_mesher;
  // Absent for the default mesher, so that earlier runs still resume.
  if (opt.parallel_mesher) run_key["offset_mesher"] = mesher_name(offset_options);
  // Levels that --start offset starts at the surface (planned_start; earlier binaries swept an
  // offset for them): recorded, so that such a journal is never resumed or merged with the other
  // start. Absent otherwise, so that other runs still resume.
  if (near_surface_starts) run_key["near_surface_start_bands"] = kNearSurfaceBands;
  // Penetrating levels: the deep zone's cover, built by the first pose that finds c flat
  // (PoseOptions::deep_cover; deterministic, so the poses do not depend on which pose that is).
  // Where a cover runs out of its budget, the zone's octree about each pose's path, its verdicts
  // shared by the level's poses (DeepCubeMemo: the same poses, less work).
  std::vector<LevelDeepZone> zones;
  const std::uint64_t request_approaches = static_cast<std::uint64_t>(opt.directions) * opt.orientations;
  for (std::size_t l = 0; l < L; ++l)
    zones.push_back(make_level_deep_zone(sdf, targets[l], mp.depth.lo, polish, request_approaches));
  // Levels with a cover jump across plateaus (since 2026-11-27, session 29: 1), and to its octree
  // about the mover's path where the cover runs out of its budget (since 2026-11-28, session 30:
  // 2; with the octree's cap of 4,000,000 cubes and a last query at it since session 31: 3; with
  // clipped cubes, plateaus from a tenth of |target| and queries of at least 20,000 cubes since
  // session 33: 4; with the octree's triangle tests without the clip-edge axes and covers of at
  // most 1,000 cubes per approach of the request since session 35: 5; with queries that ran out
  // continued by the next try since session 36: 6; with a query's floor of 20,000 cubes from 4
  // flat steps instead of 8 since session 57: 7; with the octree asked on a long plateau after a
  // cover contact not worth a jump since session 59: 8; the floor only where c fell by at most
  // 1/16 of the advance over the flat steps or the last two, since session 65: 9; the octree asked
  // on a plateau of 16 flat steps after a jump to the cover's contact too, since session 75: 10;
  // queries on a plateau of 8 flat steps with 16 cubes a certificate cell instead of 4, since
  // session 81: 11; the steps' certificates at a looser width, kDeepStepRelativeTolerance, since
  // session 84: 12):
  // their poses may differ within the tolerance from earlier binaries', whose journals must
  // therefore not be resumed or merged with them. Absent otherwise, so that other runs still
  // resume.
  if (std::any_of(zones.begin(), zones.end(), [](const LevelDeepZone& z) { return z.cover != nullptr; }))
    run_key["deep_zone_jumps"] = 12;
  // Penetrating levels shallower than a fifth of M (no cover) jump to the octree's contact too since
  // session 48 after 32 flat steps (1), since session 49 after 8 (2), since session 57 after 4 (3),
  // since session 65 only where c fell by at most 1/16 of the advance over them or the last two (4),
  // with 16 cubes a certificate cell on a plateau of 8 such steps since session 81 (5); absent
  // otherwise.
  if (std::any_of(zones.begin(), zones.end(), [](const LevelDeepZone& z) { return z.memo && !z.cover; }))
    run_key["shallow_zone_jumps"] = 5;
  // Plateaus within a tenth of |target| above it ask the zone too once 64 steps long (session 48:
  // 1; since session 57 steps over which the gap has not fallen to an eighth, and a jump of at
  // most 2 |target| keeps the certificate's frontier: 2; since session 58 a jump of at most 4
  // |target|: 3; after 20 such steps instead of 64 since session 75: 4; after 8 on a floor after a
  // steep fall since session 89: 5), and the octree walks the
  // mover's oriented boxes (session 49: 1; since session 50 a split cube's children classified at
  // once, counted against the budget together: 2; since session 52 the test before a split
  // without the clipped extents, so other cubes split: 3; since session 80 undecided cubes the
  // mover comes near dropped by the regions beyond F's faces, so contacts may be later: 4): every
  // polished penetrating level; absent otherwise.
  if (std::any_of(zones.begin(), zones.end(), [](const LevelDeepZone& z) { return z.memo != nullptr; })) {
    run_key["near_target_jumps"] = 5;
    run_key["oriented_zone_octree"] = 4;
  }
  // Penetrating levels' certificates since 2026-11-28 (session 34: no pair-distance path, leaves
  // of one face and hopeless boxes split unevaluated, 2; stale cells re-bounded by their last depth
  // bound's weights, 3; depth bounds from near-point distances since session 36, 4; cells with an
  // outside centre split without a depth bound that cannot or seldom sets them aside, session 53,
  // 5; cells centred outside and across F bounded between the planes of the faces they cross,
  // session 54, 6; steps proved over a segment on slides, session 55, 7; the nearest triangle's own
  // bound from near-point distances, a stale cell re-bounded by its corners only, a segment
  // search's splits limited below each frontier cell, session 56, 8; their distance queries with
  // near-point ends, session 56, 9; segments tried again once the gap has halved after one ran out
  // of its budget, session 58, 10; cells bounded by the planes of nearby faces that support F, for
  // any F, and faces on a supporting plane found before mapped to it unscanned, session 65, 11;
  // long steps aimed, and segments gated, by the slope of c over a span of poses, session 70, 12;
  // segments of up to 512 gaps instead of 64, session 73, 13; a deep-zone jump's landing and a
  // restart far away certified by the pair-distance path first, session 75, 14; a landing certified
  // from the mover's point at the zone's cube it met, without the pair path where that point lies
  // inside F, session 78, 15; a landing certified at a step's loose width first, full width only
  // where it may be on the target, session 81, 16; a landing not kept restores whether the
  // certificate before it was loose, so that it is tightened when it must be, session 81, 17;
  // steps over a segment tried again after every failure once the gap has halved, session 85, 18;
  // a segment's needle cells split across their length as a certificate's, and segments aimed by
  // a slope fitted over eight poses where no span resolves one, session 89, 19; a segment's
  // certificate at its end warm-started from the segment search's leaves there, session 91, 20;
  // their pair-distance path, where the mover may lie apart, on the sweep trees, session 92, 21;
  // a rejected two-sided try's pose and certificate taken after the plain step that follows where
  // the two certificates' gaps cover the poses between them, session 97, 22; a two-sided try's
  // search continued past the loose width until its lower end is enough for the step, 23):
  // their intervals, and so the polished poses, may differ within the tolerance from earlier
  // binaries'. Absent otherwise.
  if (std::any_of(targets.begin(), targets.end(), [](double t) { return t < 0.0; }))
    run_key["penetrating_certificates"] = 24;
  // Every certificate since 2026-11-29 (session 37) sets cells far outside F aside by a lower bound
  // of their centre's distance alone (1): intervals and polishing steps, rarely poses, may differ
  // within the tolerance from earlier binaries', whose journals have no such key.
  run_key["far_cells"] = 1;
  // Every certificate since session 86 lists at most 32 of F's triangles for a split cell's
  // children and for a separating plane (64 before): cells may be bounded and split otherwise, so
  // intervals and polishing steps, and so poses, may differ within the tolerance.
  run_key["candidate_list_length"] = kCandidateListLength;
  // Every certificate since 2026-12-03 (session 69) with tighter rounding bounds for near points and
  // placed cell corners, stopping at a cell smaller than its own rounding (1): intervals and
  // polishing steps, rarely poses, may differ within the tolerance from earlier binaries'.
  run_key["rounding_bounds"] = 1;
  // Every run since session 76 finds F's supporting planes by a tree over its vertices within a
  // budget that grows with F (1): the same planes where the scan of every vertex stayed within its
  // budget, planes where it did not (bunny00, refined_elephant, armadillo x16, finely faceted
  // tubes), whose certificates and poses may then differ within the tolerance.
  run_key["hull_plane_search"] = 1;
  // Every certificate since session 76 stops measuring a cell's distance to F beyond 1.125 times a
  // positive threshold (1): the same cells set aside, so the same poses wherever compared; keyed
  // because a cell's lower bound, kept in a warm start's frontier, may differ.
  run_key["capped_cell_distances"] = 1;
  // F's distance tree and the sweep trees (F's, each orientation's mover's) split by the
  // surface-area heuristic since session 90 (1): the distance tree's capped gathers (the sparse
  // depth bound's triangles) and the queries' tie-breaks see triangles in another order, the deep
  // zone's octree walks other volumes, so bounds, the maximum penetration's interval, steps and
  // poses may differ within the tolerance from earlier binaries'.
  run_key["surface_area_trees"] = 1;
  // Movers of at least 2^18 faces since session 73: each orientation's box tree is the mover's own
  // tree's shape refitted (1), so poses may differ within the tolerance from earlier binaries';
  // absent for smaller movers, whose poses are unchanged.
  if (refits_mover_boxes(mover)) run_key["refitted_mover_boxes"] = 1;
  // The levels' targets (since session 77): a percentage level's moves with the certified maximum
  // penetration's lower end, which another binary's bounds may find a few ulps away; a journal
  // whose targets differ is not resumed or merged (earlier journals lack the key).
  run_key["targets"] = targets;
  // Separated levels beyond the separated advance's reach step by certificates of a tighter width
  // since session 84 (kSeparatedStepRelativeTolerance: 1), so their poses may differ within the
  // tolerance from earlier binaries'; absent otherwise, so that other runs still resume.
  if (std::any_of(targets.begin(), targets.end(),
                  [&](double t) { return separated_steps_by_certificates(setup, t, PoseOptions{}); }))
    run_key["separated_certificate_steps"] = 1;
  // Every certificate since session 93 keeps the depth bound of a cell centred on F, exactly (1)
  // or up to rounding (2) (kOnSurfaceDepthBounds; it had none, or one weighted by rounding): the
  // pose sets compared were byte-identical, but a certificate, and so a polished pose, may differ
  // within the tolerance from earlier binaries'.
  run_key["on_surface_depth_bounds"] = kOnSurfaceDepthBounds;
  PoseJournal journal(opt.out, "poses", run_key, opt.resume, "poses");
  std::map<std::uint64_t, std::string> done_rows = whole_approaches(journal.done(), L);

  // Offsets of the levels that start from one (reused across runs by their own manifest).
  OffsetSetRequest req = make_offset_request(opt.fixed, sdf, mp, mp_tol, seconds_mp, fixed_sha,
                                            opt.out + "/offsets");
  std::vector<std::ptrdiff_t> offset_of(L, -1);  // index in the offset set
  for (std::size_t l = 0; l < L; ++l) {
    if (start[l] != PoseStart::Offset) continue;
    offset_of[l] = static_cast<std::ptrdiff_t>(req.distances.size());
    req.names.push_back(polish ? specs[l].text + "+2band" : specs[l].text);
    req.distances.push_back(swept[l]);
  }
  req.options = offset_options;
  req.log_prefix = "cdbench poses: ";
  std::cerr << "cdbench poses: max penetration [" << number_text(mp.depth.lo) << ", " << number_text(mp.depth.hi)
            << "]; " << (req.distances.empty() ? std::string("no offset meshes needed (--start ") + to_string(opt.start) + ")"
                                                : "offsets for " + std::to_string(req.distances.size()) + " of " +
                                                      std::to_string(L) + " level(s) in " + req.out_dir)
            << std::endl;
  const std::string scale_note =
      max_penetration_scale_note(specs, mp.depth.lo, mp.depth.hi, mp.tolerance_reached, mp_tol);
  if (!scale_note.empty()) std::cerr << "cdbench poses: note: " << scale_note << std::endl;
  Timer t_offsets;
  const OffsetSetResult offsets = write_offset_set(req);
  const double seconds_offsets = t_offsets.seconds();
  std::vector<std::unique_ptr<SweepMesh>> level_mesh(L);
  for (std::size_t l = 0; l < L; ++l) {
    if (offset_of[l] < 0) continue;
    const OffsetSetLevel& level = offsets.levels[static_cast<std::size_t>(offset_of[l])];
    if (level.status == OffsetStatus::Certified) {
      // Its mesh from the file (a reused level exists only there).
      const TriangleMesh m = read_triangle_mesh(req.out_dir + "/" + level.file);
      level_mesh[l] = std::make_unique<SweepMesh>(make_sweep_mesh(m.vertices, m.faces));
    } else if (level.status == OffsetStatus::Original) {
      // d' within one band of the surface: F itself is that offset (band |d'|), so its first contact
      // is the surface start (valid for targets <= 0, and the raw pose without polishing). With
      // polishing, swept offsets this close are not asked for (planned_start).
      start[l] = targets[l] <= 0.0 || !polish ? PoseStart::Surface : PoseStart::Far;
      level_note[l] = "offset within one band of the surface: the surface itself";
    } else if (level.status == OffsetStatus::Failed) {
      // The level's poses must not depend on an offset that could not be certified.
      if (fallback_start(targets[l], polish, &start[l])) {
        level_note[l] = std::string("offset failed; conservative advance from the ") +
                        (start[l] == PoseStart::Surface ? "first contact with the surface" : "far start");
        std::cerr << "cdbench poses: note: level " << specs[l].text << ": " << level_note[l] << std::endl;
      }
    }
    // Empty: no point that deep (or far) exists on this side; its rows say so.
  }
  // The surface a level's poses are swept against (none for a far start).
  const auto swept_surface = [&](std::size_t l) -> const SweepMesh* {
    return start[l] == PoseStart::Surface ? surface.get() : level_mesh[l].get();
  };

  // Sampling.
  const std::vector<Vec3> dirs = sample_directions(opt.direction_sampling, opt.directions);
  const std::vector<Eigen::Quaterniond> rots = sample_orientations(opt.orientation_sampling, opt.orientations, opt.seed);
  const std::uint64_t N = dirs.size(), K = rots.size();
  const std::uint64_t approaches = N * K;
  const std::uint64_t first = approaches * shard.index / shard.count;
  const std::uint64_t last = approaches * (shard.index + 1) / shard.count;

  PoseOptions po;
  po.tolerance = tol;
  po.polish = polish;
  po.max_steps = opt.max_steps;

  // Pending approaches in order; an orientation's frame is built by the first thread that needs it
  // and freed after its last approach.
  std::vector<std::uint64_t> pending;
  for (std::uint64_t a = first; a < last; ++a)
    if (!done_rows.count(a * L)) pending.push_back(a);
  if (!done_rows.empty())
    std::cerr << "cdbench poses: resuming: " << (last - first - pending.size()) << " of " << (last - first)
              << " approaches already certified" << std::endl;
  struct LazyFrame {
    tbb::collaborative_once_flag once;  // threads waiting for a frame help build its trees
    std::unique_ptr<OrientationFrame> frame;
    std::atomic<std::uint64_t> left{0};
  };
  std::vector<LazyFrame> frames(K);
  for (std::uint64_t a : pending) ++frames[a / N].left;
  Progress progress("poses", pending.size() * L);
  std::vector<std::atomic<std::uint64_t>> level_ns(L);  // thread time per level
  // Per level: deep-zone jumps taken, and cubes of the zone's octree classified for them.
  std::vector<std::atomic<std::uint64_t>> level_jumps(L), level_zone_cubes(L);
  // Thread time per approach, without the frame it built, and per orientation's frame (the scaling
  // model, approach_timings).
  std::vector<double> approach_seconds(pending.size()), frame_seconds(K, 0.0);
  Timer t_poses;
  std::mutex journal_mutex;
  // Levels in descending target order within an approach (place_pose's memo).
  const std::vector<std::size_t> descending_levels = descending_target_order(targets);
  parallel_for_dynamic(pending.size(), [&](std::size_t i) {
    const std::uint64_t a = pending[i], o = a / N;
    Timer t_approach;
    bool built_frame = false;
    LazyFrame& lazy = frames[o];
    tbb::collaborative_call_once(lazy.once, [&] {
      Timer t_frame;
      lazy.frame = std::make_unique<OrientationFrame>(make_orientation_frame(setup, rots[o].toRotationMatrix()));
      frame_seconds[o] = t_frame.seconds();
      built_frame = true;
    });
    const OrientationFrame& frame = *lazy.frame;
    const Vec3& dir = dirs[a % N];
    std::vector<std::string> lines(L);
    ApproachMemo memo;  // the levels of this approach share their raw contact and continue each other's advance
    for (const std::size_t l : descending_levels) {
      PoseRow row;
      row.pose = a * L + l;
      row.level = static_cast<int>(l);
      row.target = targets[l];
      row.R = frame.orientation.R;
      row.dir = dir;
      row.orientation = o;
      row.direction = a % N;
      // A row without a pose: its values are NaN, its status says why.
      const auto unplaced = [&row](PoseStatus why) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        row.t = Vec3::Constant(nan);
        row.clearance_lo = row.clearance_hi = row.raw_clearance_lo = row.raw_clearance_hi = row.lambda = nan;
        row.status = why;
      };
      const SweepMesh* swept_against = swept_surface(l);
      if (!swept_against && start[l] != PoseStart::Far) {
        const OffsetStatus offset = offsets.levels[static_cast<std::size_t>(offset_of[l])].status;
        unplaced(offset == OffsetStatus::Empty ? PoseStatus::OffsetEmpty : PoseStatus::OffsetFailed);
      } else {
        PoseOptions level_po = zones[l].options(po);
        level_po.start = start[l];
        Timer t_pose;
        const PoseOutcome p = place_pose(setup, frame, swept_against, dir, targets[l], level_po, &memo);
        level_ns[l] += static_cast<std::uint64_t>(t_pose.seconds() * 1e9);
        level_jumps[l] += static_cast<std::uint64_t>(p.cover_jumps);
        level_zone_cubes[l] += p.zone_cubes;
        if (!p.contact) {
          unplaced(PoseStatus::NoContact);
        } else {
          row.t = p.t;
          row.lambda = p.lambda;
          row.clearance_lo = p.clearance.lo;
          row.clearance_hi = p.clearance.hi;
          row.raw_clearance_lo = p.raw_clearance.lo;
          row.raw_clearance_hi = p.raw_clearance.hi;
          row.polish_steps = p.steps;
          row.status = p.reason.empty() ? PoseStatus::Certified
                                        : parse_pose_status("uncertified:" + p.reason, "internal: place_pose's reason");
        }
      }
      lines[l] = format_pose_row(row);
      progress.advance();
    }
    if (--lazy.left == 0) lazy.frame.reset();
    approach_seconds[i] = std::max(0.0, t_approach.seconds() - (built_frame ? frame_seconds[o] : 0.0));
    // One write and flush per approach: an interruption loses at most the approaches in flight.
    journal.append(lines);
    std::lock_guard<std::mutex> lock(journal_mutex);
    for (std::size_t l = 0; l < L; ++l) done_rows[a * L + l] = std::move(lines[l]);
  });
  const std::uint64_t computed = pending.size() * L;
  progress.finish();
  const double seconds_poses = t_poses.seconds();

  // poses.csv: every row of this shard, in pose order.
  std::uint64_t expected = (last - first) * L, rows_written = 0;
  std::vector<PoseRow> shard_rows;
  write_file_atomically(opt.out + "/poses.csv", [&](std::ostream& out) {
    out << kPoseCsvHeader << "\n";
    for (const auto& [pose, line] : done_rows) {
      if (pose < first * L || pose >= last * L) continue;
      out << line;
      ++rows_written;
      shard_rows.push_back(parse_pose_row(line, journal.path()));
    }
  });
  // poses.csv is in place: an interrupt before poseset.json is removes it (the journal stays).
  std::optional<RemovedIfInterrupted> pair(std::in_place, opt.out + "/poses.csv");
  if (rows_written != expected)
    throw InputError("internal: " + std::to_string(rows_written) + " rows for " + std::to_string(expected) + " poses");

  const std::vector<LevelSummary> summary = summarize_levels(shard_rows, L, tol);
  nlohmann::json ps;
  ps["format"] = "cdbench-poseset";
  ps["format_version"] = 1;
  ps["fixed"] = to_json(mesh_record(opt.fixed.path, fixed_sha, fixed_mesh, setup.fixed_ref));
  ps["mover"] = to_json(mesh_record(mover_path, mover_sha, mover, setup.mover_ref));
  ps["mover_is_fixed"] = mover_is_fixed;
  ps["max_penetration"] = {{"interval", {mp.depth.lo, mp.depth.hi}},
                           {"point", {mp.point.x(), mp.point.y(), mp.point.z()}},
                           {"relative_tolerance", mp_tol}};
  ps["levels"] = nlohmann::json::array();
  for (std::size_t l = 0; l < L; ++l) {
    const LevelSummary& x = summary[l];
    nlohmann::json swept_offset;  // null: the level's poses use no offset
    if (offset_of[l] >= 0) {
      const OffsetSetLevel& o = offsets.levels[static_cast<std::size_t>(offset_of[l])];
      swept_offset = {{"d", swept[l]},
                      {"status", to_string(o.status)},
                      {"file", o.file.empty() ? nlohmann::json() : nlohmann::json("offsets/" + o.file)},
                      {"epsilon", o.epsilon},
                      {"faces", o.faces}};
    }
    ps["levels"].push_back({{"index", l},
                            {"spec", specs[l].text},
                            {"target", targets[l]},
                            {"fraction_of_max_penetration", targets[l] / mp.depth.lo},
                            {"target_over_diagonal", targets[l] / diag},
                            {"start", to_string(start[l])},
                            {"start_note", level_note[l]},
                            {"swept_offset", swept_offset}});
    set_level_counts(ps["levels"].back(), x);
  }
  ps["sampling"] = {{"directions", {{"kind", opt.direction_sampling}, {"count", N}}},
                    {"orientations", {{"kind", opt.orientation_sampling}, {"count", K}, {"seed", opt.seed}}},
                    {"pose_index", "(orientation * directions + direction) * levels + level"}};
  ps["shard"] = {{"index", shard.index}, {"count", shard.count}, {"first_approach", first}, {"end_approach", last}};
  ps["certification"] = {{"tolerance_relative", opt.tolerance}, {"tolerance", tol}, {"diagonal", diag}};
  ps["polishing"] = {{"enabled", polish},
                     {"max_steps", opt.max_steps},
                     {"band_tolerance_relative", opt.band_tolerance},
                     {"swept_offset_shift", polish ? 2.0 * opt.band_tolerance * diag : 0.0}};
  ps["placement"] = {{"reference_point", "bounding-box centre"},
                     {"transform", "x_world = R x + t, R row-major"},
                     {"approach", "mover from +dir moving along -dir"}};
  ps["generator"] = {{"name", "cdbench"}, {"version", CDBENCH_VERSION}, {"command_line", opt.command_line}};
  ps["run_key"] = run_key;
  nlohmann::json level_timings = nlohmann::json::array();
  for (std::size_t l = 0; l < L; ++l) {
    const double sec = 1e-9 * static_cast<double>(level_ns[l].load());
    const double n = static_cast<double>(pending.size());
    nlohmann::json cover;  // null: not built (no pose of the level found c flat)
    const LazyDeepCover* lazy = zones[l].cover.get();
    if (const DeepCover* k = lazy ? lazy->peek() : nullptr) {
      cover = {{"complete", k->complete}, {"cubes", k->cells}, {"boxes", k->boxes.size()},
               {"seconds", lazy->seconds()}};
      std::cerr << "cdbench poses: level " << specs[l].text << ": deep-zone cover ";
      if (k->complete)
        std::cerr << "built, " << k->cells << " cubes, " << k->boxes.size() << " boxes, " << number_text(lazy->seconds(), 3)
                  << " s" << std::endl;
      else  // given up before its finer octree levels were evaluated (build_deep_cover)
        std::cerr << "not built: it would take more than its budget of "
                  << lazy->options().max_cells << " cubes ("
                  << (k->cells == 0 ? std::string("predicted at once") : "given up after " + std::to_string(k->cells))
                  << "); jumps across plateaus use the octree about each mover's path" << std::endl;
    }
    level_timings.push_back({{"spec", specs[l].text},
                             {"thread_seconds", sec},
                             {"poses_per_thread_second", sec > 0 ? n / sec : 0.0},
                             {"deep_cover", cover},
                             {"deep_zone_jumps", level_jumps[l].load()},
                             {"deep_zone_octree_cubes", level_zone_cubes[l].load()}});
  }
  ps["timings"] = {{"approaches", approach_timings(approach_seconds, frame_seconds)},
                   {"max_penetration", seconds_mp},
                   {"levels", level_timings},
                   {"offsets", seconds_offsets},
                   {"poses", seconds_poses},
                   {"poses_computed", computed},
                   {"poses_per_second", seconds_poses > 0 ? computed / seconds_poses : 0.0},
                   {"total", total.seconds()}};
  write_file_atomically(opt.out + "/poseset.json", [&](std::ostream& out) { out << std::setw(2) << ps << "\n"; });
  pair.reset();
  journal.remove();

  PoseSetResult result;
  result.poseset = ps;
  result.directions = N;
  result.orientations = K;
  result.levels = L;
  result.computed = computed;
  result.sharded = shard.count > 1;
  result.tolerance = tol;
  result.diagonal = diag;
  result.max_penetration = mp.depth;
  result.seconds_offsets = seconds_offsets;
  result.seconds_poses = seconds_poses;
  result.seconds_total = total.seconds();
  result.note = tolerance_not_reached_note(shard_rows, tol, diag, sdf.bbox(),
                                           "their certificates reached the branch and bound's work limit");
  return result;
}

}  // namespace cdbench
