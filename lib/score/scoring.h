#pragma once
// Scoring collision answers against a pose set's certificates, per level: the verdicts, distance
// errors against the certified interval, and times when given. Used by `cdbench bench` (answers
// timed by our harness) and `cdbench score` (answers from any implementation). This module
// writes summary.json and results.csv (format: doc/benchmark.md).
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "poseset/pose_csv.h"
#include "poseset/poseset_manifest.h"
#include "score/verdict.h"

namespace cdbench {

struct Answer {
  bool collides = false;
  double distance = std::numeric_limits<double>::quiet_NaN();  // NaN: not given
  double time_ns = std::numeric_limits<double>::quiet_NaN();   // NaN: not given
  std::int64_t bv_tests = -1, triangle_tests = -1;             // -1: not given
};

struct LevelScore {
  std::string level;
  double target = 0.0, percent_of_max_penetration = 0.0;  // NaN without a target
  std::size_t poses = 0, answered = 0, missing = 0;
  std::size_t false_positives = 0, false_negatives = 0, missed_or_contained = 0, ambiguous = 0;
  double mean_us, median_us, p05_us, p95_us;                // NaN without times
  double mean_bv_tests, mean_triangle_tests;                // NaN without counts
  std::size_t distance_answers = 0;                         // separated poses with a distance
  double max_distance_error = 0.0, max_relative_distance_error = 0.0;
};

struct ImplScore {
  std::string name;
  bool surface_only = true;   // (summary key detects_containment = !surface_only)
  bool counts_tests = false;  // reports its own BV tests
  double build_seconds = std::numeric_limits<double>::quiet_NaN();
  std::vector<LevelScore> levels;
  std::vector<std::optional<Answer>> answers;  // per row; empty: missing
  std::vector<Verdict> verdicts;               // per answered row
};

// answers[i] answers rows[i] (nullopt: missing).
ImplScore score_answers(const std::string& name, const PoseSetManifest& manifest, const std::vector<PoseRow>& rows,
                        std::vector<std::optional<Answer>> answers, bool surface_only);

// The bench summary (format cdbench-bench, read by `cdbench plot`); `extra` keys are merged in.
nlohmann::json summary_json(const PoseSetManifest& manifest, std::size_t poses, const std::vector<ImplScore>& impls,
                            const nlohmann::json& extra);
// summary.json read back (by `cdbench plot`): every key it needs checked, InputError naming the
// file and key otherwise. Null numbers (not measured) are NaN.
struct BenchSummaryImpl {
  std::string name;
  bool counts_tests = true;
  std::vector<LevelScore> levels;
};
std::vector<BenchSummaryImpl> read_bench_summary(const std::string& path);
// results.csv: one line per (implementation, pose).
void write_results_csv(std::ostream& out, const std::vector<PoseRow>& rows, const std::vector<ImplScore>& impls);
// The per-level table on stdout.
void print_score_table(std::ostream& out, const std::vector<ImplScore>& impls);

// Rows of a pose set that have a pose (finite translation and clearance).
std::vector<PoseRow> placed_rows(std::vector<PoseRow> rows);

}  // namespace cdbench
