// cdbench bench POSESET [--impl LIST] [--repeat N] -o DIR: time static collision queries over a
// pose set and check every answer against the pose's certified clearance.
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "collide/collision_impl.h"
#include "commands.h"
#include "json_file.h"
#include "mesh_loading.h"
#include "poseset/pose_csv.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/progress.h"
#include "util/sha256.h"
#include "util/timer.h"

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

const TriangleMesh& load_valid(const nlohmann::json& m, const std::string& poseset, std::unique_ptr<LoadedMesh>& holder) {
  const std::string path = m["path"].get<std::string>();
  if (!std::filesystem::exists(path)) throw InputError(poseset + ": mesh " + path + " not found");
  if (sha256_file(path) != m["sha256"].get<std::string>())
    throw InputError(path + ": its content differs from the pose set's (SHA-256 mismatch)");
  holder = std::make_unique<LoadedMesh>(load_mesh(path));
  if (!holder->validated.report.valid()) throw InputError(path + ": not a valid closed solid");
  return holder->validated.mesh;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const double pos = p * (v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(pos);
  return i + 1 < v.size() ? v[i] + (pos - i) * (v[i + 1] - v[i]) : v[i];
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
  const nlohmann::json ps = read_json_file(opt.poseset + "/poseset.json", "not a pose-set directory?");
  if (ps.value("format", "") != "cdbench-poseset") throw InputError(opt.poseset + "/poseset.json: not a cdbench pose set");
  std::unique_ptr<LoadedMesh> fixed_holder, mover_holder;
  const TriangleMesh& fixed = load_valid(ps["fixed"], opt.poseset, fixed_holder);
  const TriangleMesh& mover = load_valid(ps["mover"], opt.poseset, mover_holder);
  std::ifstream csv(opt.poseset + "/poses.csv");
  if (!csv) throw InputError(opt.poseset + "/poses.csv: cannot be read");
  std::vector<PoseRow> rows;
  for (PoseRow& r : read_pose_csv(csv, opt.poseset + "/poses.csv"))
    if (std::isfinite(r.t.x()) && std::isfinite(r.clearance_lo)) rows.push_back(std::move(r));
  if (rows.empty()) throw InputError(opt.poseset + "/poses.csv: no placed poses");
  const double maxpen = ps["max_penetration"]["interval"][0].get<double>();

  std::error_code ec;
  std::filesystem::create_directories(opt.out, ec);
  if (!std::filesystem::is_directory(opt.out)) throw InputError(opt.out + ": cannot create the output directory");
  if (opt.pin) {  // one core: no migration between cores in the middle of a measurement
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(sched_getcpu() >= 0 ? sched_getcpu() : 0, &set);
    sched_setaffinity(0, sizeof set, &set);
  }

  struct Record {
    double ns;
    QueryAnswer answer;
  };
  std::map<std::string, std::vector<Record>> records;
  std::map<std::string, double> build_seconds;
  std::map<std::string, bool> containment, counts;
  Progress progress("bench", names.size() * rows.size());
  for (const std::string& name : names) {
    auto impl = make_collision_impl(name);
    Timer tb;
    impl->build(fixed, mover);
    build_seconds[name] = tb.seconds();
    containment[name] = impl->detects_containment();
    counts[name] = impl->counts_tests();
    for (const PoseRow& r : rows) impl->query(r.R, r.t);  // warm caches and branch predictors
    std::vector<Record>& rec = records[name];
    rec.resize(rows.size());
    std::vector<double> times(static_cast<std::size_t>(opt.repeat));
    for (std::size_t i = 0; i < rows.size(); ++i) {
      for (int k = 0; k < opt.repeat; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        rec[i].answer = impl->query(rows[i].R, rows[i].t);
        times[static_cast<std::size_t>(k)] =
            std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
      }
      std::nth_element(times.begin(), times.begin() + opt.repeat / 2, times.end());
      rec[i].ns = times[static_cast<std::size_t>(opt.repeat / 2)];
      progress.advance();
    }
  }
  progress.finish();

  // Verdicts against the certificates, per implementation and level.
  const auto verdict = [&](const PoseRow& r, const QueryAnswer& a, bool detects_containment, bool* contained) {
    *contained = false;
    if (r.clearance_hi < 0.0) {
      if (a.collides) return "ok";
      // Surface-only: a miss is containment when the surfaces are apart (an own tree tells, as it
      // tests the surfaces first; here the pose's depth exceeding its clearance band suffices to
      // flag it for a separate line rather than as a false negative).
      *contained = !detects_containment;
      return detects_containment ? "false-negative" : "missed-or-contained";
    }
    if (r.clearance_lo > 0.0) return a.collides ? "false-positive" : "ok";
    return "ambiguous";
  };
  std::ostringstream table;
  table << "pose,level,target,clearance_lo,clearance_hi,impl,time_ns,collides,distance,bv_tests,triangle_tests,verdict\n";
  nlohmann::json summary;
  summary["format"] = "cdbench-bench";
  summary["poseset"] = opt.poseset;
  summary["repeat"] = opt.repeat;
  summary["poses"] = rows.size();
  summary["max_penetration"] = maxpen;
  summary["implementations"] = nlohmann::json::array();
  for (const std::string& name : names) {
    const std::vector<Record>& rec = records[name];
    nlohmann::json impl_json = {{"name", name}, {"build_seconds", build_seconds[name]},
                                {"detects_containment", containment[name]}, {"counts_tests", counts[name]},
                                {"levels", nlohmann::json::array()}};
    for (std::size_t l = 0; l < ps["levels"].size(); ++l) {
      std::vector<double> t;
      double bv = 0.0, tri = 0.0;
      std::size_t fp = 0, fn = 0, missed = 0, ambiguous = 0, n = 0, with_distance = 0;
      double max_abs_error = 0.0, max_rel_error = 0.0;
      for (std::size_t i = 0; i < rows.size(); ++i) {
        if (static_cast<std::size_t>(rows[i].level) != l) continue;
        ++n;
        t.push_back(rec[i].ns);
        bv += static_cast<double>(rec[i].answer.bv_tests);
        tri += static_cast<double>(rec[i].answer.triangle_tests);
        bool contained = false;
        const std::string v = verdict(rows[i], rec[i].answer, containment[name], &contained);
        fp += v == "false-positive";
        fn += v == "false-negative";
        missed += v == "missed-or-contained";
        ambiguous += v == "ambiguous";
        // Distance answers against the certified interval, on separated poses (where the clearance
        // is the distance between the surfaces): how far outside the interval they fall.
        const double d = rec[i].answer.distance;
        if (std::isfinite(d) && rows[i].clearance_lo > 0.0) {
          ++with_distance;
          const double e = std::max({d - rows[i].clearance_hi, rows[i].clearance_lo - d, 0.0});
          max_abs_error = std::max(max_abs_error, e);
          max_rel_error = std::max(max_rel_error, e / rows[i].clearance_lo);
        }
      }
      double mean = 0.0;
      for (double x : t) mean += x;
      mean = n ? mean / n : NAN;
      const double target = ps["levels"][l]["target"].get<double>();
      impl_json["levels"].push_back({{"level", ps["levels"][l]["spec"]},
                                     {"target", target},
                                     {"percent_of_max_penetration", 100.0 * target / maxpen},
                                     {"poses", n},
                                     {"false_positives", fp},
                                     {"false_negatives", fn},
                                     {"missed_or_contained", missed},
                                     {"ambiguous", ambiguous},
                                     {"mean_us", mean / 1e3},
                                     {"median_us", percentile(t, 0.5) / 1e3},
                                     {"p95_us", percentile(t, 0.95) / 1e3},
                                     {"mean_bv_tests", n ? bv / n : NAN},
                                     {"distance_answers", with_distance},
                                     {"max_distance_error", max_abs_error},
                                     {"max_relative_distance_error", max_rel_error},
                                     {"mean_triangle_tests", n ? tri / n : NAN}});
    }
    summary["implementations"].push_back(impl_json);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      bool contained = false;
      const PoseRow& r = rows[i];
      char buf[512];
      std::snprintf(buf, sizeof buf, "%llu,%d,%.17g,%.17g,%.17g,%s,%.0f,%d,%.17g,%llu,%llu,%s\n",
                    static_cast<unsigned long long>(r.pose), r.level, r.target, r.clearance_lo, r.clearance_hi,
                    name.c_str(), rec[i].ns, rec[i].answer.collides ? 1 : 0, rec[i].answer.distance,
                    static_cast<unsigned long long>(rec[i].answer.bv_tests),
                    static_cast<unsigned long long>(rec[i].answer.triangle_tests),
                    verdict(r, rec[i].answer, containment[name], &contained));
      table << buf;
    }
  }
  write_file_atomically(opt.out + "/results.csv", [&](std::ostream& out) { out << table.str(); });
  write_file_atomically(opt.out + "/summary.json", [&](std::ostream& out) { out << std::setw(2) << summary << "\n"; });

  std::cout << "pose set: " << opt.poseset << " (" << rows.size() << " placed poses), median of " << opt.repeat
            << " runs per query, one pinned thread\n";
  std::cout << std::left << std::setw(21) << "impl" << std::setw(10) << "level" << std::setw(7) << "poses" << std::setw(11)
            << "mean us" << std::setw(11) << "median us" << std::setw(11) << "p95 us" << std::setw(11) << "BV tests"
            << std::setw(6) << "FP" << std::setw(6) << "FN" << std::setw(9) << "missed*" << "ambiguous\n";
  for (const auto& impl : summary["implementations"])
    for (const auto& l : impl["levels"])
      std::cout << std::left << std::setw(21) << impl["name"].get<std::string>() << std::setw(10)
                << l["level"].get<std::string>() << std::setw(7) << l["poses"].get<std::size_t>() << std::fixed
                << std::setprecision(2) << std::setw(11) << l["mean_us"].get<double>() << std::setw(11)
                << l["median_us"].get<double>() << std::setw(11) << l["p95_us"].get<double>() << std::setprecision(0)
                << std::setw(11) << l["mean_bv_tests"].get<double>() << std::defaultfloat << std::setw(6)
                << l["false_positives"].get<std::size_t>() << std::setw(6) << l["false_negatives"].get<std::size_t>()
                << std::setw(9) << l["missed_or_contained"].get<std::size_t>() << l["ambiguous"].get<std::size_t>()
                << "\n";
  std::cout << "* surface-only libraries: penetrating poses reported free (a mover inside the solid, or a real miss)\n";
  for (const auto& impl : summary["implementations"])
    for (const auto& l : impl["levels"])
      if (l["distance_answers"].get<std::size_t>() > 0)
        std::cout << "distance " << impl["name"].get<std::string>() << " level " << l["level"].get<std::string>() << ": "
                  << l["distance_answers"].get<std::size_t>() << " separated poses, max error outside the certified "
                  << "interval " << l["max_distance_error"].get<double>() << " (relative "
                  << l["max_relative_distance_error"].get<double>() << ")\n";
  std::cout << "build seconds:";
  for (const auto& impl : summary["implementations"])
    std::cout << " " << impl["name"].get<std::string>() << " " << std::setprecision(3) << impl["build_seconds"].get<double>();
  std::cout << "\nresults: " << opt.out << "/results.csv, " << opt.out << "/summary.json (plots: cdbench plot " << opt.out
            << ")\n";
  for (const auto& impl : summary["implementations"])
    for (const auto& l : impl["levels"])
      if (impl["detects_containment"].get<bool>() &&
          (l["false_positives"].get<std::size_t>() + l["false_negatives"].get<std::size_t>()) > 0) {
        std::cerr << "cdbench: error: " << impl["name"].get<std::string>()
                  << " answered against a certificate (see results.csv)\n";
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
