#include "score/bench_plot.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "score/scoring.h"
#include "util/atomic_file.h"
#include "util/gnuplot.h"
#include "util/number_format.h"

namespace cdbench {

namespace {
// A name on one line of plot.dat or errors.txt: a line break in a plugin's name would start a line
// that gnuplot reads as data, so control characters become spaces (the scripts quote the name).
std::string one_line(std::string name) {
  for (char& c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  return name;
}
}  // namespace

BenchPlotFiles write_bench_plot_files(const std::string& dir) {
  const std::vector<BenchSummaryImpl> impls = read_bench_summary(dir + "/summary.json");
  // One data block per implementation: percent of max penetration (or the level's place), mean us,
  // median us, p95 us, BV tests, p5 us, the level's name.
  std::ostringstream data, errors;
  errors << std::left << std::setw(21) << "impl" << std::setw(10) << "level" << std::setw(9) << "% maxpen" << std::setw(7)
         << "poses" << std::setw(7) << "FP" << std::setw(7) << "FN" << std::setw(10) << "missed*" << std::setw(11)
         << "ambiguous" << "max distance error (relative)\n";
  std::vector<std::string> names;
  std::vector<bool> counted;  // whether the implementation reports its own BV tests
  bool timed = false;         // some level has a time
  // Levels without a target (a user's poses grouped by a level column, or none: `cdbench certify`)
  // have no percentage: then the levels are placed by their order, named on the axis (the 7th column).
  bool by_percent = true;
  for (const BenchSummaryImpl& impl : impls)
    for (const LevelScore& l : impl.levels) by_percent = by_percent && std::isfinite(l.percent_of_max_penetration);
  for (const BenchSummaryImpl& impl : impls) {
    names.push_back(impl.name);
    counted.push_back(impl.counts_tests);
    data << "# " << one_line(names.back()) << "\n";
    for (std::size_t k = 0; k < impl.levels.size(); ++k) {
      const LevelScore& l = impl.levels[k];
      timed = timed || std::isfinite(l.mean_us);
      std::string label = one_line(l.level);
      for (char& c : label)
        if (c == '"') c = '\'';
      data << std::setprecision(10) << (by_percent ? l.percent_of_max_penetration : static_cast<double>(k)) << " "
           << l.mean_us << " " << l.median_us << " " << l.p95_us << " " << l.mean_bv_tests << " " << l.p05_us << " \""
           << label << "\"\n";
      errors << std::left << std::setw(21) << one_line(names.back()) << std::setw(10) << l.level << std::setw(9)
             << std::setprecision(4) << l.percent_of_max_penetration << std::setw(7) << l.poses << std::setw(7)
             << l.false_positives << std::setw(7) << l.false_negatives << std::setw(10) << l.missed_or_contained
             << std::setw(11) << l.ambiguous
             << (l.distance_answers > 0 ? number_text(l.max_distance_error, 3) + " (" +
                                              number_text(l.max_relative_distance_error, 3) + ")"
                                        : std::string("-"))
             << "\n";
    }
    data << "\n\n";
  }
  errors << "* surface-only libraries: penetrating poses reported free (mover inside the solid, or a miss)\n";
  write_file_atomically(dir + "/plot.dat", [&](std::ostream& out) { out << data.str(); });
  write_file_atomically(dir + "/errors.txt", [&](std::ostream& out) { out << errors.str(); });

  std::ostringstream gp;
  const std::string xtics = by_percent ? "" : ":xtic(7)";
  const auto plots = [&](const std::string& term, const std::string& ext) {
    const auto series = [&](int column) {
      std::ostringstream p;
      bool first = true;
      for (std::size_t i = 0; i < names.size(); ++i) {
        if (column == 5 && !counted[i]) continue;
        // Colours repeat after 8 series: a different dash pattern and point type tell them apart.
        p << (first ? "" : ", ") << "'plot.dat' index " << i << " using 1:" << column << xtics << " with linespoints lc "
          << (i % 8 + 1) << " dt " << (i / 8 + 1) << " pt " << (i % 13 + 1) << " title " << gnuplot_string(names[i]);
        first = false;
      }
      return p.str();
    };
    gp << "set terminal " << term << "\n";
    gp << "set grid\nset key outside right\n";
    if (by_percent) gp << "set xlabel 'level (% of the maximum penetration; < 0: penetrating)'\n";
    else gp << "set xlabel 'level (as in the pose set; some have no target)'\nset offsets 0.5, 0.5, 0, 0\n";
    gp << "set logscale y\n";
    gp << "set output 'time_vs_level." << ext << "'\nset ylabel 'mean query time (us)'\n";
    gp << "set title 'Static collision query time vs distance'\n";
    if (timed) gp << "plot " << series(2) << "\n";
    else gp << "set label 1 'no times given' at graph 0.5, 0.5 center\nunset logscale y\nplot [0:1] [0:1] NaN notitle\nunset label 1\nset logscale y\n";
    // The paper's figures: mean time per level with a band for the spread (5th to 95th percentile).
    gp << "set output 'time_band_vs_level." << ext << "'\nset ylabel 'query time (us): mean, band 5-95 %'\n";
    gp << "set title 'Static collision query time vs distance, with its spread'\n";
    if (timed) {
      gp << "plot ";
      for (std::size_t i = 0; i < names.size(); ++i)
        gp << (i ? ", " : "") << "'plot.dat' index " << i << " using 1:6:4 with filledcurves lc " << (i % 8 + 1)
           << " fs transparent solid 0.15 noborder notitle, 'plot.dat' index " << i
           << " using 1:2" << xtics << " with linespoints lc " << (i % 8 + 1) << " dt " << (i / 8 + 1) << " pt " << (i % 13 + 1)
           << " title " << gnuplot_string(names[i]);
      gp << "\n";
    } else {
      gp << "set label 1 'no times given' at graph 0.5, 0.5 center\nunset logscale y\nplot [0:1] [0:1] NaN notitle\nunset label 1\nset logscale y\n";
    }
    gp << "set output 'bv_tests_vs_level." << ext << "'\nset ylabel 'mean bounding-volume tests'\n";
    gp << "set title 'Bounding-volume tests vs distance'\n";
    if (series(5).empty()) gp << "set label 1 'no bounding-volume tests given' at graph 0.5, 0.5 center\nunset logscale y\nplot [0:1] [0:1] NaN notitle\nunset label 1\n";
    else gp << "plot " << series(5) << "\n";
    gp << "unset logscale y\n";
  };
  plots("pngcairo size 1000,600 noenhanced", "png");
  plots("svg size 1000,600 noenhanced", "svg");
  write_file_atomically(dir + "/plot.gp", [&](std::ostream& out) { out << gp.str(); });
  BenchPlotFiles files;
  files.errors = errors.str();
  for (const char* stem : {"time_vs_level", "time_band_vs_level", "bv_tests_vs_level"})
    for (const char* ext : {".png", ".svg"}) files.figures.push_back(std::string(stem) + ext);
  return files;
}

}  // namespace cdbench
