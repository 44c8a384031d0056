#include "score/scoring.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "util/json_keys.h"
#include "util/number_format.h"

namespace cdbench {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double pos = p * static_cast<double>(v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(pos);
  return i + 1 < v.size() ? v[i] + (pos - static_cast<double>(i)) * (v[i + 1] - v[i]) : v[i];
}

nlohmann::json maybe(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); }

}  // namespace

std::vector<PoseRow> placed_rows(std::vector<PoseRow> rows) {
  std::vector<PoseRow> out;
  for (PoseRow& r : rows)
    if (std::isfinite(r.t.x()) && std::isfinite(r.t.y()) && std::isfinite(r.t.z()) && std::isfinite(r.clearance_lo) &&
        std::isfinite(r.clearance_hi))
      out.push_back(std::move(r));
  return out;
}

ImplScore score_answers(const std::string& name, const PoseSetManifest& m, const std::vector<PoseRow>& rows,
                        std::vector<std::optional<Answer>> answers, bool surface_only) {
  ImplScore s;
  s.name = name;
  s.surface_only = surface_only;
  s.answers = std::move(answers);
  s.verdicts.assign(rows.size(), Verdict::Ok);
  s.levels.resize(m.levels.size());
  std::vector<std::vector<double>> times(m.levels.size());
  std::vector<double> bv(m.levels.size(), 0.0), tri(m.levels.size(), 0.0);
  std::vector<std::size_t> bv_n(m.levels.size(), 0), tri_n(m.levels.size(), 0);
  for (std::size_t l = 0; l < m.levels.size(); ++l) {
    LevelScore& ls = s.levels[l];
    ls.level = m.levels[l].spec;
    ls.target = m.levels[l].target;
    ls.percent_of_max_penetration = 100.0 * ls.target / m.max_penetration_lo;
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const PoseRow& r = rows[i];
    LevelScore& ls = s.levels[static_cast<std::size_t>(r.level)];
    ++ls.poses;
    if (!s.answers[i]) {
      ++ls.missing;
      continue;
    }
    const Answer& a = *s.answers[i];
    ++ls.answered;
    const Verdict v = classify(r.clearance_lo, r.clearance_hi, a.collides, surface_only);
    s.verdicts[i] = v;
    ls.false_positives += v == Verdict::FalsePositive;
    ls.false_negatives += v == Verdict::FalseNegative;
    ls.missed_or_contained += v == Verdict::MissedOrContained;
    ls.ambiguous += v == Verdict::Ambiguous;
    const std::size_t l = static_cast<std::size_t>(r.level);
    if (std::isfinite(a.time_ns)) times[l].push_back(a.time_ns);
    if (a.bv_tests >= 0) bv[l] += static_cast<double>(a.bv_tests), ++bv_n[l];
    if (a.triangle_tests >= 0) tri[l] += static_cast<double>(a.triangle_tests), ++tri_n[l];
    // Distance answers on separated poses (where the clearance is the distance between the
    // surfaces): how far outside the certified interval they fall.
    if (std::isfinite(a.distance) && r.clearance_lo > 0.0) {
      ++ls.distance_answers;
      const double e = std::max({a.distance - r.clearance_hi, r.clearance_lo - a.distance, 0.0});
      ls.max_distance_error = std::max(ls.max_distance_error, e);
      ls.max_relative_distance_error = std::max(ls.max_relative_distance_error, e / r.clearance_lo);
    }
  }
  for (std::size_t l = 0; l < m.levels.size(); ++l) {
    LevelScore& ls = s.levels[l];
    double sum = 0.0;
    for (double t : times[l]) sum += t;
    ls.mean_us = times[l].empty() ? kNaN : sum / static_cast<double>(times[l].size()) / 1e3;
    ls.median_us = percentile(times[l], 0.5) / 1e3;
    ls.p05_us = percentile(times[l], 0.05) / 1e3;
    ls.p95_us = percentile(times[l], 0.95) / 1e3;
    ls.mean_bv_tests = bv_n[l] ? bv[l] / static_cast<double>(bv_n[l]) : kNaN;
    ls.mean_triangle_tests = tri_n[l] ? tri[l] / static_cast<double>(tri_n[l]) : kNaN;
  }
  return s;
}

nlohmann::json summary_json(const PoseSetManifest& m, std::size_t poses, const std::vector<ImplScore>& impls,
                            const nlohmann::json& extra) {
  nlohmann::json summary;
  summary["format"] = "cdbench-bench";
  summary["poseset"] = m.dir;
  summary["poses"] = poses;
  summary["max_penetration"] = m.max_penetration_lo;
  for (const auto& [k, v] : extra.items()) summary[k] = v;
  summary["implementations"] = nlohmann::json::array();
  for (const ImplScore& s : impls) {
    nlohmann::json j = {{"name", s.name},
                        {"build_seconds", maybe(s.build_seconds)},
                        {"detects_containment", !s.surface_only},
                        {"counts_tests", s.counts_tests},
                        {"levels", nlohmann::json::array()}};
    for (const LevelScore& l : s.levels)
      j["levels"].push_back({{"level", l.level},
                             {"target", maybe(l.target)},
                             {"percent_of_max_penetration", maybe(l.percent_of_max_penetration)},
                             {"poses", l.poses},
                             {"answered", l.answered},
                             {"missing", l.missing},
                             {"false_positives", l.false_positives},
                             {"false_negatives", l.false_negatives},
                             {"missed_or_contained", l.missed_or_contained},
                             {"ambiguous", l.ambiguous},
                             {"mean_us", maybe(l.mean_us)},
                             {"median_us", maybe(l.median_us)},
                             {"p05_us", maybe(l.p05_us)},
                             {"p95_us", maybe(l.p95_us)},
                             {"mean_bv_tests", maybe(l.mean_bv_tests)},
                             {"mean_triangle_tests", maybe(l.mean_triangle_tests)},
                             {"distance_answers", l.distance_answers},
                             {"max_distance_error", l.max_distance_error},
                             {"max_relative_distance_error", l.max_relative_distance_error}});
    summary["implementations"].push_back(j);
  }
  return summary;
}

std::vector<BenchSummaryImpl> read_bench_summary(const std::string& path) {
  const nlohmann::json s = parse_json_file(path, "run 'cdbench bench' or 'cdbench score' first");
  const JsonKeys k(path);
  const auto format = s.is_object() ? s.find("format") : s.end();
  if (!s.is_object() || format == s.end() || *format != "cdbench-bench")
    throw InputError(path + ": not a cdbench benchmark summary (format is not cdbench-bench)");
  std::vector<BenchSummaryImpl> out;
  const nlohmann::json& impls = k.array(s, "implementations", "");
  for (std::size_t i = 0; i < impls.size(); ++i) {
    const std::string where = "implementations[" + std::to_string(i) + "].";
    BenchSummaryImpl impl;
    impl.name = k.text(impls[i], "name", where);
    impl.counts_tests = k.boolean(impls[i], "counts_tests", where);
    const nlohmann::json& levels = k.array(impls[i], "levels", where);
    for (std::size_t j = 0; j < levels.size(); ++j) {
      const std::string w = where + "levels[" + std::to_string(j) + "].";
      const nlohmann::json& l = levels[j];
      LevelScore ls;
      ls.level = k.text(l, "level", w);
      ls.target = k.number(l, "target", w, true);
      ls.percent_of_max_penetration = k.number(l, "percent_of_max_penetration", w, true);
      ls.poses = static_cast<std::size_t>(k.count(l, "poses", w));
      ls.false_positives = static_cast<std::size_t>(k.count(l, "false_positives", w));
      ls.false_negatives = static_cast<std::size_t>(k.count(l, "false_negatives", w));
      ls.missed_or_contained = static_cast<std::size_t>(k.count(l, "missed_or_contained", w));
      ls.ambiguous = static_cast<std::size_t>(k.count(l, "ambiguous", w));
      ls.mean_us = k.number(l, "mean_us", w, true);
      ls.median_us = k.number(l, "median_us", w, true);
      // p05_us: summaries written before it was added have none (NaN: no band in the plots).
      ls.p05_us = l.contains("p05_us") ? k.number(l, "p05_us", w, true) : std::numeric_limits<double>::quiet_NaN();
      ls.p95_us = k.number(l, "p95_us", w, true);
      ls.mean_bv_tests = k.number(l, "mean_bv_tests", w, true);
      ls.mean_triangle_tests = k.number(l, "mean_triangle_tests", w, true);
      ls.distance_answers = static_cast<std::size_t>(k.count(l, "distance_answers", w));
      ls.max_distance_error = k.number(l, "max_distance_error", w, true);
      ls.max_relative_distance_error = k.number(l, "max_relative_distance_error", w, true);
      impl.levels.push_back(ls);
    }
    out.push_back(std::move(impl));
  }
  return out;
}

void write_results_csv(std::ostream& out, const std::vector<PoseRow>& rows, const std::vector<ImplScore>& impls) {
  out << "pose,level,target,clearance_lo,clearance_hi,impl,time_ns,collides,distance,bv_tests,triangle_tests,verdict\n";
  for (const ImplScore& s : impls)
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (!s.answers[i]) continue;
      const PoseRow& r = rows[i];
      const Answer& a = *s.answers[i];
      char buf[512];
      std::snprintf(buf, sizeof buf, "%llu,%d,%.17g,%.17g,%.17g,%s,%.0f,%d,%.17g,%lld,%lld,%s\n",
                    static_cast<unsigned long long>(r.pose), r.level, r.target, r.clearance_lo, r.clearance_hi,
                    s.name.c_str(), a.time_ns, a.collides ? 1 : 0, a.distance, static_cast<long long>(a.bv_tests),
                    static_cast<long long>(a.triangle_tests), to_string(s.verdicts[i]));
      out << buf;
    }
}

void print_score_table(std::ostream& out, const std::vector<ImplScore>& impls) {
  const auto num = [](double x, int prec) {
    if (!std::isfinite(x)) return std::string("-");
    std::ostringstream os;
    os << std::fixed << std::setprecision(prec) << x;
    return os.str();
  };
  out << std::left << std::setw(21) << "impl" << std::setw(24) << "level" << std::setw(7) << "poses" << std::setw(11)
      << "mean us" << std::setw(11) << "median us" << std::setw(11) << "p95 us" << std::setw(11) << "BV tests"
      << std::setw(6) << "FP" << std::setw(6) << "FN" << std::setw(9) << "missed*" << std::setw(11) << "ambiguous"
      << "missing\n";
  for (const ImplScore& s : impls)
    for (const LevelScore& l : s.levels)
      out << std::left << std::setw(21) << s.name << std::setw(24) << l.level << std::setw(7) << l.poses << std::setw(11)
          << num(l.mean_us, 2) << std::setw(11) << num(l.median_us, 2) << std::setw(11) << num(l.p95_us, 2)
          << std::setw(11) << num(l.mean_bv_tests, 0) << std::setw(6) << l.false_positives << std::setw(6)
          << l.false_negatives << std::setw(9) << l.missed_or_contained << std::setw(11) << l.ambiguous << l.missing
          << "\n";
  out << "* surface-only implementations: penetrating poses reported free (a mover inside the solid, or a real miss)\n";
  for (const ImplScore& s : impls)
    for (const LevelScore& l : s.levels)
      if (l.distance_answers > 0)
        out << "distance " << s.name << " level " << l.level << ": " << l.distance_answers
            << " separated poses, max error outside the certified interval " << number_text(l.max_distance_error, 6)
            << " (relative " << number_text(l.max_relative_distance_error, 6) << ")\n";
}

}  // namespace cdbench
