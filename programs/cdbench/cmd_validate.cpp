// cdbench validate POSESET... [--reference CERTIFIED] -o DIR: any pose set against the certified
// ground truth (lib/validate/validate_run.h, doc/float-pipeline.md).
#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "commands.h"
#include "mesh_loading.h"
#include "poseset/poseset_manifest.h"
#include "util/error.h"
#include "util/gnuplot.h"
#include "util/number_format.h"
#include "validate/validate_run.h"

namespace cdbench::cli {
namespace {

struct ValidateCliOptions {
  std::vector<std::string> posesets;
  std::string reference, out;
  double tolerance = 1e-6;
  bool offsets = false, completeness = false;
  int threads = 0;
};

std::string pct(double x) {
  if (!std::isfinite(x)) return "-";
  std::ostringstream s;
  s << std::setprecision(3) << 100.0 * x << "%";
  return s.str();
}

void print_table(const ValidateResult& v) {
  const double mp = v.max_penetration.lo;
  std::cout << std::left << std::setw(10) << "level" << std::setw(8) << "poses" << std::setw(8) << "placed" << std::setw(10)
            << "certified" << std::setw(11) << "err mean" << std::setw(11) << "err median" << std::setw(11) << "|err| p95"
            << std::setw(11) << "|err| max" << std::setw(7) << "wrong" << std::setw(13) << "missed(n/a)" << std::setw(11)
            << "band/voxel" << "ms/pose: set, certified, certificate\n";
  for (const LevelValidation& l : v.levels) {
    std::ostringstream band, times;
    band << (l.offset.checked && v.voxel > 0 ? std::to_string(l.offset.band / v.voxel).substr(0, 5) : "-");
    const auto ms = [](double s) { return s < 0 ? std::string("-") : std::to_string(1e3 * s).substr(0, 7); };
    times << ms(l.seconds_per_pose) << ", " << ms(l.reference_seconds_per_pose) << ", " << ms(l.certify_seconds_per_pose);
    std::cout << std::setw(10) << l.spec << std::setw(8) << l.poses << std::setw(8) << l.placed << std::setw(10) << l.certified
              << std::setw(11) << pct(l.error_mean / mp) << std::setw(11) << pct(l.error_median / mp) << std::setw(11)
              << pct(l.error_p95 / mp) << std::setw(11) << pct(l.error_max / mp) << std::setw(7) << l.wrong_sign
              << std::setw(13) << (std::to_string(l.missed_contact) + " (" + std::to_string(l.missed_undecided) + ")")
              << std::setw(11) << band.str() << times.str() << "\n";
  }
  std::cout << std::right;
}

int run_validate_cmd(const ValidateCliOptions& opt) {
  std::unique_ptr<tbb::global_control> threads;
  if (opt.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, opt.threads);
  const PoseSetManifest first = read_poseset_manifest(opt.posesets.front());
  for (const std::string& dir : opt.posesets) {
    const PoseSetManifest m = read_poseset_manifest(dir);
    if (m.fixed.sha256 != first.fixed.sha256 || m.mover.sha256 != first.mover.sha256)
      throw InputError(dir + ": made from other meshes than " + opt.posesets.front() + " (validate one mesh at a time)");
  }
  const std::string fixed_path = locate_mesh(first.fixed, opt.posesets.front());
  const std::string mover_path = first.mover_is_fixed ? "" : locate_mesh(first.mover, opt.posesets.front());
  LoadedMesh fixed, mover;
  if (!load_solids(fixed_path, mover_path, &fixed, &mover)) return kExitInvalidMesh;
  std::vector<ValidateResult> runs;
  std::vector<std::string> names;
  for (std::size_t k = 0; k < opt.posesets.size(); ++k) {
    ValidateRequest rq;
    rq.poseset = opt.posesets[k];
    rq.reference = opt.reference;
    rq.fixed = &fixed.validated.mesh;
    rq.mover = first.mover_is_fixed ? rq.fixed : &mover.validated.mesh;
    rq.tolerance_relative = opt.tolerance;
    rq.offsets = opt.offsets || opt.completeness;
    rq.completeness = opt.completeness;
    names.push_back(std::filesystem::path(rq.poseset).lexically_normal().filename().string());
    if (names.back().empty()) names.back() = std::filesystem::path(rq.poseset).parent_path().filename().string();
    rq.out = opt.posesets.size() == 1 ? opt.out : opt.out + "/" + std::to_string(k) + "-" + names.back();
    runs.push_back(run_validate(rq));
    const ValidateResult& v = runs.back();
    std::cout << "pose set: " << rq.poseset << " (pipeline " << v.pipeline
              << (v.voxel > 0 ? ", voxel " + number_text(v.voxel / v.diagonal, 4) + " x diagonal" : "")
              << ")\ncertified max penetration [" << number_text(v.max_penetration.lo) << ", "
              << number_text(v.max_penetration.hi)
              << "]; errors c - target in % of it; missed: first contacts skipped (n/a: undecidable)\n";
    print_table(v);
    std::cout << "written: " << rq.out << "/validation.csv, " << rq.out << "/validation.json (" << std::fixed
              << std::setprecision(1) << v.seconds_total << std::defaultfloat << " s)\n";
  }
  write_validation_plots(opt.out, runs, names);
  if (!gnuplot_available()) {
    std::cerr << "cdbench validate: note: gnuplot not found; the plots' script is " << opt.out << "/plot.gp\n";
  } else if (run_gnuplot(opt.out, "plot.gp") != GnuplotRun::Ok) {
    throw InputError("gnuplot failed on " + opt.out + "/plot.gp");
  }
  std::cout << "plots: " << opt.out << "/error_distribution_*.png|svg"
            << (runs.size() > 1 ? ", " + opt.out + "/error_vs_voxel.png|svg" : std::string()) << "\n";
  return kExitOk;
}

}  // namespace

void register_validate(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<ValidateCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "validate",
      "Any pose set in the bundle format (cdbench poses --pipeline float, FCL's, another tool's) against the "
      "certified ground truth: every pose's clearance certified against the original fixed surface, then per level "
      "the target error c - target (mean, median, p95, max; in % of the certified max penetration and of the "
      "diagonal), wrong-sign poses, missed first contacts (a separated pose past the exact first contact of its "
      "approach; with --reference, a penetrating pose past the certified first crossing), the certified band of "
      "float offsets kept in the bundle (--offsets), and time per pose. Several pose sets (e.g. grid resolutions) give a plot of "
      "error against voxel size. Writes DIR/validation.csv, DIR/validation.json (DIR/<k>-<name>/ for several) and "
      "gnuplot figures.");
  cmd->add_option("poseset", opt->posesets, "pose-set directories of one mesh")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--reference", opt->reference, "a certified pose set of the same request (cdbench poses)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--tolerance", opt->tolerance, "width of penetrating certificates, relative to the diagonal")
      ->capture_default_str()
      ->check(CLI::Range(1e-12, 1e-1));
  cmd->add_flag("--offsets", opt->offsets,
                "also certify the band of each float offset kept in the bundle (every point within d +- band; about "
                "0.1 ms per face and thread: minutes for fine grids)");
  cmd->add_flag("--completeness", opt->completeness,
                "also certify each float offset's completeness (no component of the level missed; expensive)");
  cmd->add_option("--threads", opt->threads, "worker threads (0: all cores)")->capture_default_str()->check(CLI::Range(0, 1024));
  cmd->add_option("-o,--output", opt->out, "output directory")->required();
  cmd->callback([opt, &exit_code]() { exit_code = run_validate_cmd(*opt); });
}

}  // namespace cdbench::cli
