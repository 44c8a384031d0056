#include "floatpipe/float_poseset.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>

#include "distance/signed_distance.h"
#include "floatpipe/grid_offsets.h"
#include "mesh/write_mesh.h"
#include "offset/level_list.h"
#include "placement/place_pose.h"
#include "placement/rotation_groups.h"
#include "poseset/pose_csv.h"
#include "poseset/poseset_manifest.h"
#include "sampling/sampling.h"
#include "util/atomic_file.h"
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

// Triangles per leaf of the float offsets' sphere trees: the float sweep's cheap shadow test
// rejects most leaf pairs, and a shallower tree means fewer sphere tests and a faster build
// (armadillo, grid 256, 5,000 poses: placement 2.9 -> 2.0 s). The mover keeps one per leaf:
// eight there too made the placement 1.5x slower (64 triangle pairs per leaf pair).
constexpr std::uint32_t kFloatLeaf = 8;

std::vector<LevelSpec> checked_levels(const FloatPoseSetRequest& opt) {
  std::vector<LevelSpec> specs = parse_level_list(opt.levels);
  check_distinct_levels(specs);
  check_sampling_names(opt.direction_sampling, opt.orientation_sampling);
  if (opt.voxel < 0.0 || !std::isfinite(opt.voxel)) throw InputError("--voxel: expected a size > 0");
  if (opt.voxel == 0.0 && (opt.grid < 8 || opt.grid > 4096))
    throw InputError("--grid: expected 8 to 4096 cells along the longest side, found " + std::to_string(opt.grid));
  return specs;
}

// A file-name form of a level's text ("-25%" -> "m25pct").
std::string level_file_name(const std::string& text) {
  std::string s = "float_";
  for (char c : text) {
    if (c == '-') s += 'm';
    else if (c == '+') s += 'p';
    else if (c == '%') s += "pct";
    else if (c == '.') s += 'p';
    else if (std::isalnum(static_cast<unsigned char>(c))) s += c;
    else s += '_';
  }
  return s + ".off";
}

}  // namespace

void check_float_poseset_request(const FloatPoseSetRequest& request) { checked_levels(request); }

bool float_first_contact(const SweepMesh& level, const SweepMesh& swept_mover, const Vec3& dir, double* lambda) {
  if (level.faces.empty()) return false;
  // The swept mover sits at t0 + t (-dir); the least such t is the first contact from +dir.
  const FloatMeshContact c = first_contact_along_line_float(level, swept_mover, -dir);
  if (!c.hit) return false;
  *lambda = -c.t;
  return true;
}

FloatPoseSetResult build_float_poseset(const FloatPoseSetRequest& opt) {
  const std::vector<LevelSpec> specs = checked_levels(opt);
  Timer total;
  const TriangleMesh& fixed = *opt.fixed.mesh;
  const bool mover_is_fixed = opt.mover.path.empty();
  const TriangleMesh& mover = mover_is_fixed ? fixed : *opt.mover.mesh;
  const std::string fixed_sha = sha256_file(opt.fixed.path);
  const std::string mover_sha = mover_is_fixed ? fixed_sha : sha256_file(opt.mover.path);

  FloatPoseSetResult res;
  const double diag = fixed.bbox().diagonal();
  res.diagonal = diag;
  res.voxel = opt.voxel > 0.0 ? opt.voxel : voxel_for_grid(fixed, opt.grid);
  // The max depth first (percentage levels need it): a grid 4x coarser with the whole interior
  // (1/64 of the voxels) finds the deep region; the deepest point of the fine lattice near it is
  // found with exact distances (deepest_lattice_point). The fine grid then only samples the band
  // the levels need, inside and out: on a thick solid most of the interior is never sampled.
  Timer t_grid;
  const SignedDistance sdf(fixed);
  const double cells = (fixed.bbox().hi - fixed.bbox().lo).maxCoeff() / res.voxel;
  if (!(cells <= 4096.0))  // as --grid; OpenVDB refused far finer grids with an exception of its own
    throw InputError("--voxel: " + number_text(res.voxel, 6) + " gives " + number_text(cells, 4) +
                     " cells along the bounding box's longest side; the float pipeline takes at most 4096");
  {
    const GridSdf coarse(fixed, {(cells >= 64.0 ? 4.0 : 1.0) * res.voxel, 0.0});
    const LatticeDepth deep = deepest_lattice_point(
        coarse, res.voxel, [&](const Vec3& p) { return sdf.unsigned_distance(p).mid(); },
        [&](const Vec3& p) { return sdf.side(p) < 0; });
    res.max_depth = deep.depth;
  }
  if (!(res.max_depth > 0.0) &&
      std::any_of(specs.begin(), specs.end(), [](const LevelSpec& l) { return l.percent && l.value != 0.0; }))
    throw InputError("--levels: percentage levels need the grid's maximum depth, and no lattice point at voxel " +
                     number_text(res.voxel, 6) +
                     " lies inside the solid (its walls are thinner than the grid resolves): use a finer --grid or "
                     "--voxel, or absolute levels");
  std::vector<double> targets(specs.size());
  double reach_out = 0.0, reach_in = 0.0;
  for (std::size_t l = 0; l < specs.size(); ++l) {
    targets[l] = level_distance(specs[l], res.max_depth);
    reach_out = std::max(reach_out, targets[l]);
    reach_in = std::max(reach_in, -targets[l]);
  }
  check_distinct_distances(specs, targets);
  if (reach_out / res.voxel > 4096.0)
    throw InputError("--levels: the outermost level lies " + number_text(reach_out / res.voxel, 4) +
                     " voxels outside; the float pipeline samples at most 4096 voxels out (use a larger --voxel)");
  const GridSdf grid(fixed, {res.voxel, reach_out, reach_in});
  res.seconds_grid = t_grid.seconds();
  std::cerr << "cdbench poses: float pipeline: grid voxel " << number_text(res.voxel, 6) << " ("
            << number_text(diag / res.voxel, 4) << " per diagonal), " << grid.active_voxels() << " active voxels in "
            << std::fixed << std::setprecision(2) << res.seconds_grid << std::defaultfloat
            << " s; max depth on the lattice " << number_text(res.max_depth, 9) << std::endl;

  // Iso-surfaces, one per level (levels in parallel; OpenVDB parallelizes within one too).
  const std::size_t L = specs.size();
  std::vector<std::unique_ptr<SweepMesh>> level_mesh(L);
  std::vector<double> level_seconds(L);
  std::vector<std::string> level_files(L);
  // The output folder only once the grid exists: a request that fails before leaves nothing.
  prepare_output_directory(opt.out);
  if (opt.keep_offsets) prepare_output_directory(opt.out + "/offsets");
  Timer t_iso;
  tbb::parallel_for(std::size_t(0), L, [&](std::size_t l) {
    Timer t;
    TriangleMesh m = grid.isosurface(targets[l]);
    if (opt.keep_offsets && !m.faces.empty()) {
      level_files[l] = "offsets/" + level_file_name(specs[l].text);
      write_off(m, opt.out + "/" + level_files[l]);
    }
    level_mesh[l] = std::make_unique<SweepMesh>(make_sweep_mesh(std::move(m.vertices), std::move(m.faces), {kFloatLeaf}, false));
    level_seconds[l] = t.seconds();
  });
  res.seconds_isosurfaces = t_iso.seconds();

  // Approaches: the mover's frame per orientation (as the certified pipeline's), one float sweep
  // per level.
  // The mover's own sweep tree without oriented boxes: the float sweeps read spheres and boxes only.
  const ApproachSetup setup = make_approach_setup(
      sdf, mover, std::make_shared<const SweepMesh>(make_sweep_mesh(mover.vertices, mover.faces, {}, false)));
  const std::vector<Vec3> dirs = sample_directions(opt.direction_sampling, opt.directions);
  const std::vector<Eigen::Quaterniond> rots = sample_orientations(opt.orientation_sampling, opt.orientations, opt.seed);
  const std::uint64_t N = dirs.size(), K = rots.size();
  std::vector<PoseRow> rows(N * K * L);
  std::vector<std::atomic<std::uint64_t>> level_ns(L);
  Progress progress("float poses", N * K);
  Timer t_poses;
  // Approaches handed out one at a time; an orientation's frame is shared by its approaches.
  std::vector<Eigen::Matrix3d> rotation_of(N * K);
  std::vector<std::size_t> approaches(N * K);
  for (std::uint64_t a = 0; a < N * K; ++a) {
    rotation_of[a] = rots[a / N].toRotationMatrix();
    approaches[a] = a;
  }
  const auto make_frame = [&](const Eigen::Matrix3d& R) { return make_orientation_frame(setup, R); };
  for_each_pose_by_rotation<OrientationFrame>(rotation_of, approaches, make_frame, [&](std::size_t a, const OrientationFrame& frame) {
    const std::uint64_t o = a / N, d = a % N;
    for (std::size_t l = 0; l < L; ++l) {
      PoseRow& row = rows[a * L + l];
      row.pose = a * L + l;
      row.level = static_cast<int>(l);
      row.target = targets[l];
      row.R = frame.orientation.R;
      row.dir = dirs[d];
      row.orientation = o;
      row.direction = d;
      const double nan = std::numeric_limits<double>::quiet_NaN();
      row.clearance_lo = row.clearance_hi = row.raw_clearance_lo = row.raw_clearance_hi = nan;
      Timer t;
      double lambda = 0.0;
      if (float_first_contact(*level_mesh[l], frame.swept, dirs[d], &lambda)) {
        row.lambda = lambda;
        row.t = pose_translation(frame, dirs[d], lambda);
        row.status = PoseStatus::Float;
      } else {
        row.lambda = nan;
        row.t = Vec3::Constant(nan);
        // An empty iso-surface: the level lies deeper than the grid's max depth.
        row.status = level_mesh[l]->faces.empty() ? PoseStatus::OffsetEmpty : PoseStatus::NoContact;
      }
      level_ns[l] += static_cast<std::uint64_t>(t.seconds() * 1e9);
    }
    progress.advance();
  });
  progress.finish();
  res.seconds_poses = t_poses.seconds();

  write_file_atomically(opt.out + "/poses.csv", [&](std::ostream& out) {
    out << kPoseCsvHeader << "\n";
    for (const PoseRow& r : rows) out << format_pose_row(r);
  });

  nlohmann::json ps;
  ps["format"] = "cdbench-poseset";
  ps["format_version"] = 1;
  ps["pipeline"] = "float";
  ps["fixed"] = to_json(mesh_record(opt.fixed.path, fixed_sha, fixed, setup.fixed_ref));
  ps["mover"] = to_json(mesh_record(mover_is_fixed ? opt.fixed.path : opt.mover.path, mover_sha, mover, setup.mover_ref));
  ps["mover_is_fixed"] = mover_is_fixed;
  ps["max_penetration"] = {{"interval", {res.max_depth, res.max_depth}},
                           {"method", "deepest point of the grid's lattice near a 4x coarser grid's deepest samples, exact distances "
                                      "(uncertified; too small by up to about a voxel)"}};
  ps["levels"] = nlohmann::json::array();
  for (std::size_t l = 0; l < L; ++l) {
    std::uint64_t placed = 0;
    for (std::uint64_t a = 0; a < N * K; ++a) placed += rows[a * L + l].status == PoseStatus::Float;
    res.placed += placed;
    res.no_contact += N * K - placed;
    const double sec = 1e-9 * static_cast<double>(level_ns[l].load());
    ps["levels"].push_back({{"index", l},
                            {"spec", specs[l].text},
                            {"target", targets[l]},
                            {"fraction_of_max_penetration", res.max_depth > 0 ? targets[l] / res.max_depth : 0.0},
                            {"target_over_diagonal", targets[l] / diag},
                            {"start", "float sweep from far"},
                            {"float_offset",
                             {{"file", level_files[l].empty() ? nlohmann::json() : nlohmann::json(level_files[l])},
                              {"faces", level_mesh[l]->faces.size()},
                              {"seconds", level_seconds[l]}}},
                            {"poses", N * K},
                            {"placed", placed},
                            {"no_contact", N * K - placed},
                            {"thread_seconds", sec}});
  }
  ps["sampling"] = {{"directions", {{"kind", opt.direction_sampling}, {"count", N}}},
                    {"orientations", {{"kind", opt.orientation_sampling}, {"count", K}, {"seed", opt.seed}}},
                    {"pose_index", "(orientation * directions + direction) * levels + level"}};
  ps["shard"] = {{"index", 0}, {"count", 1}, {"first_approach", 0}, {"end_approach", N * K}};
  // No certificate in this pipeline; the tolerance is the one `cdbench validate` certifies with.
  ps["certification"] = {{"certified", false}, {"tolerance_relative", 1e-6}, {"tolerance", 1e-6 * diag}, {"diagonal", diag}};
  ps["grid"] = {{"voxel", res.voxel},
                {"cells_along_longest_side", cells},
                {"voxels_per_diagonal", diag / res.voxel},
                {"grid_option", opt.voxel > 0.0 ? nlohmann::json() : nlohmann::json(opt.grid)},
                {"active_voxels", grid.active_voxels()},
                {"library", "OpenVDB meshToSignedDistanceField (float32) + volumeToMesh (adaptivity 0)"}};
  ps["placement"] = {{"reference_point", "bounding-box centre"},
                     {"transform", "x_world = R x + t, R row-major"},
                     {"approach", "mover from +dir moving along -dir to its first contact with the level's iso-surface "
                                  "(sphere trees, triangle sweeps in doubles)"}};
  ps["generator"] = {{"name", "cdbench"}, {"version", CDBENCH_VERSION}, {"command_line", opt.command_line}};
  res.seconds_total = total.seconds();
  ps["timings"] = {{"grid", res.seconds_grid},
                   {"isosurfaces", res.seconds_isosurfaces},
                   {"poses", res.seconds_poses},
                   {"poses_per_second", res.seconds_poses > 0 ? (N * K * L) / res.seconds_poses : 0.0},
                   {"total", res.seconds_total}};
  write_file_atomically(opt.out + "/poseset.json", [&](std::ostream& out) { out << std::setw(2) << ps << "\n"; });
  res.poseset = ps;
  res.directions = N;
  res.orientations = K;
  res.levels = L;
  return res;
}

}  // namespace cdbench
