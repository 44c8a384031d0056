#pragma once
// The figures of a benchmark (`cdbench plot`): from its summary.json, the data blocks, the error
// table and the gnuplot script (mean query time, its 5-95 % band and bounding-volume tests against
// the level, per implementation, PNG and SVG). Running gnuplot is the caller's (util/gnuplot.h).
#include <string>
#include <vector>

namespace cdbench {

struct BenchPlotFiles {
  std::string errors;                // the error table, as written to errors.txt
  std::vector<std::string> figures;  // the file names the script writes (in dir)
};

// Reads dir/summary.json (InputError naming the file and key when it is not a bench summary) and
// writes dir/plot.dat, dir/errors.txt and dir/plot.gp (atomically). Implementation names are
// quoted for gnuplot, so that any name is safe.
BenchPlotFiles write_bench_plot_files(const std::string& dir);

}  // namespace cdbench
