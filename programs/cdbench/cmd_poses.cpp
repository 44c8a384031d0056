// cdbench poses MESH --levels LIST --directions N --orientations K -o DIR: a certified pose set.
#include <tbb/global_control.h>

#include <iomanip>
#include <iostream>
#include <memory>

#include "commands.h"
#include "mesh_loading.h"
#include "number_text.h"
#include "floatpipe/float_poseset.h"
#include "poseset/build_poseset.h"
#include "poseset_summary.h"
#include "util/error.h"
#include "util/interrupt.h"

namespace cdbench::cli {
namespace {

struct PosesCliOptions {
  PoseSetRequest request;
  std::string mesh, mover;
  std::string start = "auto";  // --start, into request.start
  int threads = 0;
  std::string pipeline = "certified";
  int grid = 256;
  double voxel = 0.0;
  bool keep_offsets = false;
};

// --pipeline float: the paper's grid + marching cubes + float sweeps; no certificate.
int run_float_poses(const PosesCliOptions& opt) {
  FloatPoseSetRequest rq;
  static_cast<PoseSetSpec&>(rq) = opt.request;  // the spec both pipelines share
  rq.grid = opt.grid;
  rq.voxel = opt.voxel;
  rq.keep_offsets = opt.keep_offsets;
  if (opt.request.resume || opt.request.no_polish || opt.request.shard != "0/1" || opt.request.start != StartPolicy::NoOffsets ||
      opt.request.parallel_mesher)
    throw InputError("--pipeline float: --resume, --shard, --start, --parallel-mesher and --no-polish belong to the certified "
                     "pipeline");
  check_float_poseset_request(rq);
  LoadedMesh fixed, mover;
  if (!load_solids(opt.mesh, opt.mover, &fixed, &mover)) return kExitInvalidMesh;
  rq.fixed = mesh_source(fixed);
  if (!opt.mover.empty()) rq.mover = mesh_source(mover);
  const FloatPoseSetResult r = build_float_poseset(rq);
  std::cout << "fixed:           " << opt.mesh << " (" << fixed.validated.mesh.faces.size() << " faces, diagonal "
            << std::setprecision(9) << r.diagonal << ")\n";
  std::cout << "pipeline:        float (uncertified): grid voxel " << r.voxel << " (" << r.diagonal / r.voxel
            << " per diagonal), max depth on the lattice " << number_text(r.max_depth) << "\n";
  std::cout << "poses:           " << r.directions << " directions x " << r.orientations << " orientations x " << r.levels
            << " levels: " << r.placed << " placed, " << r.no_contact << " without contact\n";
  std::cout << "time:            " << std::fixed << std::setprecision(2) << r.seconds_total << " s (grid "
            << r.seconds_grid << " s, iso-surfaces " << r.seconds_isosurfaces << " s, poses " << r.seconds_poses
            << " s)" << std::defaultfloat << "\n";
  std::cout << "pose set:        " << rq.out << "/poses.csv, " << rq.out
            << "/poseset.json (status uncertified:float; certify with cdbench validate)\n";
  return kExitOk;
}

int run_poses(PosesCliOptions opt) {
  std::unique_ptr<tbb::global_control> threads;
  if (opt.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, opt.threads);
  if (opt.pipeline == "float") return run_float_poses(opt);
  check_poseset_request(opt.request);  // option errors before any work
  LoadedMesh fixed, mover;
  if (!load_solids(opt.mesh, opt.mover, &fixed, &mover)) return kExitInvalidMesh;
  PoseSetRequest& rq = opt.request;
  rq.fixed = mesh_source(fixed);
  if (!opt.mover.empty()) rq.mover = mesh_source(mover);
  const PoseSetResult r = build_poseset(rq);
  mark_outputs_complete();  // poses.csv and poseset.json are in place

  std::cout << "fixed:           " << opt.mesh << " (" << fixed.validated.mesh.faces.size() << " faces, diagonal "
            << std::setprecision(9) << r.diagonal << ")\n";
  std::cout << "mover:           " << (opt.mover.empty() ? opt.mesh + " (the fixed mesh)" : opt.mover) << "\n";
  std::cout << "max penetration: [" << number_text(r.max_penetration.lo) << ", " << number_text(r.max_penetration.hi)
            << "]\n";
  std::cout << "poses:           " << r.directions << " directions x " << r.orientations << " orientations x " << r.levels
            << " levels" << (r.sharded ? ", shard " + rq.shard : std::string()) << "; tolerance " << r.tolerance << " ("
            << rq.tolerance << " x diagonal); polishing " << (rq.no_polish ? "off" : "on") << "\n";
  print_level_table(std::cout, r.poseset, r.diagonal);
  const double rate = r.seconds_poses > 0 ? static_cast<double>(r.computed) / r.seconds_poses : 0.0;
  std::cout << "time:            " << std::fixed << std::setprecision(1) << r.seconds_total << " s (offsets "
            << r.seconds_offsets << " s, poses " << r.seconds_poses << " s, " << rate << " poses/s)" << std::defaultfloat
            << "\n";
  std::cout << "pose set:        " << rq.out << "/poses.csv, " << rq.out << "/poseset.json\n";
  if (!r.note.empty()) std::cerr << "cdbench poses: note: " << r.note << "\n";
  return kExitOk;
}

}  // namespace

void register_poses(CLI::App& app, int& exit_code, const std::string& command_line) {
  auto opt = std::make_shared<PosesCliOptions>();
  opt->request.command_line = command_line;
  CLI::App* cmd = app.add_subcommand(
      "poses",
      "A certified pose set: for every orientation x approach direction x level, the mover (rotated about its "
      "bbox centre, centres together) comes from far along +dir and moves along -dir to the first pose where its "
      "certified clearance reaches the level: from the exact first contact with the surface (exact sweeps on sphere "
      "trees) for levels <= 0, from far away for levels > 0 (or from certified offset surfaces: --start offset), by "
      "certified conservative advancement, until the clearance is within the tolerance of the target; every pose "
      "gets a rigorous clearance interval against the original surface. Writes DIR/poses.csv, DIR/poseset.json "
      "(and DIR/offsets/ with --start offset; format: doc/pose-set-format.md). An interrupted run continues with "
      "--resume.");
  cmd->add_option("mesh", opt->mesh, "the fixed closed mesh")->required();
  cmd->add_option("--mover", opt->mover, "the moving closed mesh (default: the fixed mesh)");
  cmd->add_option("--levels", opt->request.levels,
                  "comma-separated target clearances: absolute (-0.5), % of the certified maximum penetration "
                  "(-25%), ranges FROM:TO:STEP; 0 = touching")
      ->required();
  cmd->add_option("--directions", opt->request.directions, "approach directions on S^2")->capture_default_str()->check(CLI::Range(1, 10000000));
  cmd->add_option("--orientations", opt->request.orientations, "orientations in SO(3)")->capture_default_str()->check(CLI::Range(1, 10000000));
  cmd->add_option("--direction-sampling", opt->request.direction_sampling, "fibonacci (low discrepancy) or grid (latitude-longitude)")
      ->capture_default_str();
  cmd->add_option("--orientation-sampling", opt->request.orientation_sampling, "super-fibonacci (deterministic, uniform) or random (seeded)")
      ->capture_default_str();
  cmd->add_option("--seed", opt->request.seed, "seed of random orientations")->capture_default_str();
  cmd->add_option("--tolerance", opt->request.tolerance, "certification and polishing tolerance, relative to the fixed mesh's diagonal")
      ->capture_default_str()
      ->check(CLI::Range(1e-12, 1e-1));
  cmd->add_option("--band-tolerance", opt->request.band_tolerance, "offset surfaces' band tolerance, relative to the diagonal")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 0.1));
  cmd->add_option("--start", opt->start,
                  "where the conservative advance of each pose starts. auto: level 0 and penetrating levels at the "
                  "exact first contact with the surface itself, separated levels far away (no offset meshes). "
                  "offset: every level != 0 at the exact first contact with a certified offset at level + 2 bands "
                  "(computed into DIR/offsets, reused across runs). Without polishing, levels != 0 always use "
                  "their own offset")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "offset"}))
      ->each([opt](const std::string& s) {
        opt->request.start = s == "offset" ? StartPolicy::Offsets : StartPolicy::NoOffsets;
      });
  cmd->add_flag("--parallel-mesher", opt->request.parallel_mesher,
                "with --start offset: mesh each offset candidate with CGAL's Mesh_3 on all threads instead of "
                "Surface_mesher on one; certified all the same, but the offsets and the poses that start from them "
                "are not reproducible bit for bit (cdbench offset --parallel-mesher)");
  cmd->add_flag("--no-polish", opt->request.no_polish, "keep the raw placement (first contact with the level's own offset)");
  cmd->add_option("--max-steps", opt->request.max_steps, "polishing steps per pose before it is reported as stalled")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--shard", opt->request.shard, "compute only part I of N (0 <= I < N) of the approaches; 'cdbench merge' joins shards")
      ->capture_default_str();
  cmd->add_flag("--resume", opt->request.resume, "continue an interrupted run in DIR (same inputs and options)");
  cmd->add_option("--pipeline", opt->pipeline,
                  "certified: every pose certified (the default). float: the paper's pipeline, uncertified and fast: "
                  "the signed distance on a grid (OpenVDB), an iso-surface per level by marching cubes, float sweeps "
                  "(doc/float-pipeline.md); levels in % refer to the grid's max depth")
      ->capture_default_str()
      ->check(CLI::IsMember({"certified", "float"}));
  cmd->add_option("--grid", opt->grid, "float pipeline: grid cells along the bounding box's longest side")
      ->capture_default_str()
      ->check(CLI::Range(8, 4096));
  cmd->add_option("--voxel", opt->voxel, "float pipeline: absolute voxel size (overrides --grid)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--keep-offsets", opt->keep_offsets,
                "float pipeline: write each level's marching-cubes surface to DIR/offsets/ (for inspection and "
                "'cdbench validate --offsets')");
  cmd->add_option("--threads", opt->threads, "worker threads (0: all cores)")->capture_default_str()->check(CLI::Range(0, 1024));
  cmd->add_option("-o,--output", opt->request.out, "output directory")->required();
  cmd->callback([opt, &exit_code]() { exit_code = run_poses(*opt); });
}

}  // namespace cdbench::cli
