// cdbench bench POSESET [--impl LIST] [--repeat N] -o DIR: time static collision queries over a
// pose set and check every answer against the pose's certified clearance.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "collide/collision_impl.h"
#include "commands.h"
#include "mesh_loading.h"
#include "poseset/poseset_manifest.h"
#include "score/bench_loop.h"
#include "score/scoring.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/progress.h"

namespace cdbench::cli {
namespace {

struct BenchCliOptions {
  std::string poseset, impls, out;  // impls empty: every available implementation
  int repeat = 5;
  bool pin = true;
};

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

const TriangleMesh& load_valid(const MeshRecord& m, const std::string& poseset, std::unique_ptr<LoadedMesh>& holder) {
  const std::string path = locate_mesh(m, poseset);
  holder = std::make_unique<LoadedMesh>(load_mesh(path));
  if (!holder->validated.report.valid()) throw InputError(path + ": not a valid closed solid");
  return holder->validated.mesh;
}

int run_bench(const BenchCliOptions& opt) {
  const std::vector<std::string> names = opt.impls.empty() ? collision_impl_names() : split_list(opt.impls);
  if (names.empty()) throw InputError("--impl: empty list");
  for (const std::string& n : names)
    if (!make_collision_impl(n)) {
      std::string known;
      for (const std::string& k : collision_impl_names(true)) known += (known.empty() ? "" : ", ") + k;
      throw InputError("--impl: unknown implementation '" + n + "' (available: " + known + ")");
    }
  const PoseSetManifest ps = read_poseset_manifest(opt.poseset);
  std::unique_ptr<LoadedMesh> fixed_holder, mover_holder;
  const TriangleMesh& fixed = load_valid(ps.fixed, opt.poseset, fixed_holder);
  const TriangleMesh& mover = load_valid(ps.mover, opt.poseset, mover_holder);
  const std::vector<PoseRow> rows = placed_rows(read_poseset_rows(ps));
  if (rows.empty()) throw InputError(opt.poseset + "/poses.csv: no placed poses");
  prepare_output_directory(opt.out);
  if (opt.pin) pin_to_current_core();

  std::vector<ImplScore> scores;
  Progress progress("bench", names.size() * rows.size());
  BenchOptions bo;
  bo.repeat = opt.repeat;
  for (const std::string& name : names) {
    auto impl = make_collision_impl(name);
    scores.push_back(bench_implementation(*impl, fixed, mover, ps, rows, bo, &progress));
  }
  progress.finish();
  write_file_atomically(opt.out + "/results.csv", [&](std::ostream& out) { write_results_csv(out, rows, scores); });
  const nlohmann::json summary = summary_json(ps, rows.size(), scores, {{"repeat", opt.repeat}});
  write_file_atomically(opt.out + "/summary.json", [&](std::ostream& out) { out << std::setw(2) << summary << "\n"; });

  std::cout << "pose set: " << opt.poseset << " (" << rows.size() << " placed poses), median of " << opt.repeat
            << " runs per query, one pinned thread\n";
  print_score_table(std::cout, scores);
  std::cout << "build seconds:";
  for (const ImplScore& s : scores) std::cout << " " << s.name << " " << std::setprecision(3) << s.build_seconds;
  std::cout << "\nresults: " << opt.out << "/results.csv, " << opt.out << "/summary.json (plots: cdbench plot " << opt.out
            << ")\n";
  for (const ImplScore& s : scores)
    for (const LevelScore& l : s.levels)
      if (!s.surface_only && l.false_positives + l.false_negatives > 0) {
        std::cerr << "cdbench: error: " << s.name << " answered against a certificate (see results.csv)\n";
        return kExitInternal;
      }
  return kExitOk;
}

}  // namespace

void register_bench(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<BenchCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench",
      "Time static collision queries over a pose set (each implementation built once; every pose run several "
      "times, the median kept; one pinned thread) and check every answer against the pose's certified clearance: "
      "clearance_hi < 0 must collide, clearance_lo > 0 must not. Writes DIR/results.csv and DIR/summary.json.");
  cmd->add_option("poseset", opt->poseset, "a pose-set directory (cdbench poses)")->required()->check(CLI::ExistingDirectory);
  std::string all;
  for (const std::string& n : collision_impl_names()) all += (all.empty() ? "" : ",") + n;
  cmd->add_option("--impl", opt->impls,
                  "comma-separated implementations (default: all available: " + all +
                      "; also cgal-exact, the slow exact reference)");
  cmd->add_option("--repeat", opt->repeat, "runs per query (the median is kept)")->capture_default_str()->check(CLI::Range(1, 1000));
  cmd->add_flag("!--no-pin", opt->pin, "do not pin the thread to one core");
  cmd->add_option("-o,--output", opt->out, "output directory")->required();
  cmd->callback([opt, &exit_code]() { exit_code = run_bench(*opt); });
}

}  // namespace cdbench::cli
