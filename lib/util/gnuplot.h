#pragma once
// gnuplot for the commands' figures (`cdbench plot`, `cdbench validate`): one place that quotes
// text for its scripts and runs it, without a shell, so that any directory name and any
// implementation or level name is safe (a quote in a path broke `sh -c "cd '...'"`).
#include <string>

namespace cdbench {

// s as a gnuplot single-quoted string: no escapes are processed there, and a quote is doubled.
std::string gnuplot_string(const std::string& s);

enum class GnuplotRun { Ok, NotFound, Failed };

// Runs `gnuplot script` in the directory dir (the script's relative paths are relative to it);
// its output and errors go to ours. NotFound when no gnuplot can be started (PATH).
GnuplotRun run_gnuplot(const std::string& dir, const std::string& script);

// Whether `gnuplot --version` runs (quietly).
bool gnuplot_available();

}  // namespace cdbench
