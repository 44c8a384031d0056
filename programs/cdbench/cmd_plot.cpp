// cdbench plot DIR: gnuplot figures of a benchmark's summary.json (PNG and SVG) and an error table.
#include <iostream>
#include <memory>

#include "commands.h"
#include "score/bench_plot.h"
#include "util/error.h"
#include "util/gnuplot.h"

namespace cdbench::cli {
namespace {

struct PlotCliOptions {
  std::string dir;
};

int run_plot(const PlotCliOptions& opt) {
  if (!gnuplot_available()) throw InputError("gnuplot not found (Debian: apt-get install gnuplot-nox)");
  const BenchPlotFiles files = write_bench_plot_files(opt.dir);
  if (run_gnuplot(opt.dir, "plot.gp") != GnuplotRun::Ok) throw InputError("gnuplot failed on " + opt.dir + "/plot.gp");
  std::cout << files.errors;
  for (const std::string& f : files.figures) std::cout << "plot: " << opt.dir << "/" << f << "\n";
  std::cout << "errors: " << opt.dir << "/errors.txt\n";
  return kExitOk;
}

}  // namespace

void register_plot(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<PlotCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "plot",
      "Plots of a benchmark (cdbench bench): mean query time and bounding-volume tests vs level (% of the maximum "
      "penetration) per implementation, PNG and SVG, with gnuplot; and the error table (errors.txt).");
  cmd->add_option("dir", opt->dir, "a benchmark output directory")->required()->check(CLI::ExistingDirectory);
  cmd->callback([opt, &exit_code]() { exit_code = run_plot(*opt); });
}

}  // namespace cdbench::cli
