// cdbench certify FIXED [--mover M] POSES.csv -o DIR: certified clearances of any poses.
#include <tbb/global_control.h>

#include <iomanip>
#include <iostream>
#include <memory>

#include "commands.h"
#include "mesh_loading.h"
#include "number_text.h"
#include "poseset/certify_run.h"
#include "poseset/user_poses.h"
#include "util/interrupt.h"

namespace cdbench::cli {
namespace {

struct CertifyCliOptions {
  std::string fixed, mover, poses, out;
  double tolerance = 1e-6, max_penetration_tolerance = 1e-6;
  std::uint64_t max_cells = 400000;
  int threads = 0;
  bool resume = false;
  std::string command_line;
};

int run_certify_command(const CertifyCliOptions& opt) {
  std::unique_ptr<tbb::global_control> threads;
  if (opt.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, opt.threads);
  const UserPoseFile file = read_user_poses_file(opt.poses);  // bad rows: an error before any work
  LoadedMesh fixed, mover;
  if (!load_solids(opt.fixed, opt.mover, &fixed, &mover)) return kExitInvalidMesh;
  CertifyRequest rq;
  rq.fixed_path = opt.fixed;
  rq.mover_path = opt.mover.empty() ? opt.fixed : opt.mover;
  rq.fixed = &fixed.validated.mesh;
  rq.mover = opt.mover.empty() ? &fixed.validated.mesh : &mover.validated.mesh;
  rq.mover_is_fixed = opt.mover.empty();
  rq.poses_path = opt.poses;
  rq.poses = &file;
  rq.tolerance_relative = opt.tolerance;
  rq.max_penetration_tolerance = opt.max_penetration_tolerance;
  rq.max_cells = opt.max_cells;
  rq.resume = opt.resume;
  rq.command_line = opt.command_line;
  const CertifyRunResult r = run_certify(rq, opt.out);
  mark_outputs_complete();  // poses.csv and poseset.json are in place

  std::cout << "poses:           " << opt.poses << " (" << r.poses << " poses, "
            << (file.form == RotationForm::Matrix ? "rotation matrices" : "quaternions") << ")\n";
  if (!file.ignored_columns.empty()) {
    std::cout << "ignored columns:";
    for (const std::string& c : file.ignored_columns) std::cout << " " << c;
    std::cout << "\n";
  }
  if (r.resumed) std::cout << "resumed:         " << r.resumed << " poses from the journal\n";
  std::cout << "max penetration: [" << number_text(r.max_penetration.lo) << ", " << number_text(r.max_penetration.hi)
            << "]\ntolerance:       " << r.tolerance << " (" << opt.tolerance << " x diagonal)\n";
  std::cout << std::left << std::setw(28) << "level" << std::setw(8) << "poses" << std::setw(11) << "certified"
            << std::setw(11) << "separated" << std::setw(13) << "penetrating" << std::setw(11) << "straddle0"
            << "clearance range\n";
  for (const CertifyLevelCounts& l : r.levels) {
    std::cout << std::left << std::setw(28) << l.spec << std::setw(8) << l.poses << std::setw(11) << l.certified
              << std::setw(11) << l.separated << std::setw(13) << l.penetrating << std::setw(11) << l.straddling;
    // A level index the file skips has no poses, so no range.
    if (l.poses == 0) std::cout << "-\n";
    else std::cout << "[" << number_text(l.clearance_min, 9) << ", " << number_text(l.clearance_max, 9) << "]\n";
  }
  std::cout << "time:            " << std::fixed << std::setprecision(1) << r.seconds_total << " s (max penetration "
            << r.seconds_max_penetration << " s, poses " << r.seconds_poses << " s)\n";
  std::cout << "pose set:        " << opt.out << "/poses.csv, " << opt.out << "/poseset.json\n";
  if (r.certified < r.poses) {
    std::cerr << "cdbench: error: " << r.note << "\n";
    return kExitInvalidMesh;
  }
  return kExitOk;
}

}  // namespace

void register_certify(CLI::App& app, int& exit_code, const std::string& command_line) {
  auto opt = std::make_shared<CertifyCliOptions>();
  opt->command_line = command_line;
  CLI::App* cmd = app.add_subcommand(
      "certify",
      "The certified clearance of every pose of POSES.csv (written by any tool) against the fixed solid: a rigorous "
      "interval, a few ulps wide when the mover is apart from the fixed solid, at most the tolerance wide when it "
      "penetrates. POSES.csv has a header with 'pose' and either r00..r22,tx,ty,tz (row-major R, x_world = R x + t) "
      "or qw,qx,qy,qz,tx,ty,tz; optional 'target' and 'level' columns group the poses. R is certified as stored "
      "(the affine map it is, orthonormal or not). Writes DIR/poses.csv and DIR/poseset.json (a pose-set bundle "
      "for bench and score); an interrupted run continues with --resume.");
  cmd->add_option("fixed", opt->fixed, "the fixed closed mesh")->required();
  cmd->add_option("poses", opt->poses, "CSV of poses")->required();
  cmd->add_option("--mover", opt->mover, "the moving closed mesh (default: the fixed mesh)");
  cmd->add_option("--tolerance", opt->tolerance, "width of penetrating intervals, relative to the fixed mesh's diagonal")
      ->capture_default_str()
      ->check(CLI::Range(1e-12, 1.0));
  cmd->add_option("--max-penetration-tolerance", opt->max_penetration_tolerance,
                  "tolerance of the max penetration in poseset.json, relative to the diagonal")
      ->capture_default_str()
      ->check(CLI::Range(1e-12, 1.0));
  cmd->add_option("--max-cells", opt->max_cells, "branch-and-bound work limit per pose")->capture_default_str();
  cmd->add_flag("--resume", opt->resume, "continue an interrupted run in DIR (same inputs and options)");
  cmd->add_option("--threads", opt->threads, "worker threads (0: all cores)")->capture_default_str()->check(CLI::Range(0, 1024));
  cmd->add_option("-o,--output", opt->out, "output directory")->required();
  cmd->callback([opt, &exit_code]() { exit_code = run_certify_command(*opt); });
}

}  // namespace cdbench::cli
