// cdbench score POSESET ANSWERS.csv -o DIR: verdicts of any implementation's answers.
#include <iomanip>
#include <iostream>
#include <memory>

#include "commands.h"
#include "poseset/poseset_manifest.h"
#include "score/answers_csv.h"
#include "score/scoring.h"
#include "util/atomic_file.h"
#include "util/error.h"

namespace cdbench::cli {
namespace {

struct ScoreCliOptions {
  std::string poseset, answers, out, name = "answers";
  bool surface_only = false, strict = false;
};

std::string first_ids(const std::vector<std::uint64_t>& ids) {
  std::string s;
  for (std::size_t i = 0; i < ids.size() && i < 10; ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
  return s + (ids.size() > 10 ? ", ..." : "");
}

int run_score(const ScoreCliOptions& opt) {
  const PoseSetManifest ps = read_poseset_manifest(opt.poseset);
  const std::vector<PoseRow> rows = placed_rows(read_poseset_rows(ps));
  if (rows.empty()) throw InputError(opt.poseset + "/poses.csv: no placed poses");
  const AnswerFile file = read_answers_file(opt.answers);
  const MatchedAnswers matched = match_answers(file, rows);
  prepare_output_directory(opt.out);

  std::vector<ImplScore> scores = {score_answers(opt.name, ps, rows, matched.by_row, opt.surface_only)};
  scores[0].counts_tests = file.has_bv_tests;
  nlohmann::json duplicates = nlohmann::json::array();
  for (const auto& [pose, line] : file.duplicates) duplicates.push_back({{"pose", pose}, {"line", line}});
  const nlohmann::json extra = {{"answers_file", opt.answers},
                                {"unknown_poses", matched.unknown},
                                {"missing_poses", matched.missing},
                                {"duplicate_answers", duplicates}};
  write_file_atomically(opt.out + "/results.csv", [&](std::ostream& out) { write_results_csv(out, rows, scores); });
  const nlohmann::json summary = summary_json(ps, rows.size(), scores, extra);
  write_file_atomically(opt.out + "/summary.json", [&](std::ostream& out) { out << std::setw(2) << summary << "\n"; });

  std::cout << "pose set: " << opt.poseset << " (" << rows.size() << " placed poses)\nanswers:  " << opt.answers << " ("
            << file.answers.size() << " poses" << (file.has_distance ? ", distances" : "")
            << (file.has_time ? ", times" : "") << (file.has_bv_tests ? ", BV tests" : "") << ")\n";
  print_score_table(std::cout, scores);
  bool problems = false;
  if (!matched.unknown.empty()) {
    std::cout << "unknown:  " << matched.unknown.size() << " answers name poses not in the pose set: "
              << first_ids(matched.unknown) << "\n";
    problems = true;
  }
  if (!file.duplicates.empty()) {
    std::cout << "duplicate: " << file.duplicates.size() << " answers repeat a pose (the first is scored), e.g. pose "
              << file.duplicates[0].first << " at line " << file.duplicates[0].second << "\n";
    problems = true;
  }
  if (!matched.missing.empty()) {
    std::cout << "missing:  " << matched.missing.size() << " placed poses have no answer: " << first_ids(matched.missing)
              << "\n";
    problems = true;
  }
  std::cout << "results: " << opt.out << "/results.csv, " << opt.out << "/summary.json (plots: cdbench plot " << opt.out
            << ")\n";
  std::size_t wrong = 0;
  for (const LevelScore& l : scores[0].levels) wrong += l.false_positives + l.false_negatives;
  if (opt.strict && (wrong > 0 || problems)) {
    std::cerr << "cdbench: error: " << wrong << " answers contradict a certificate"
              << (problems ? ", and some answers are unknown, repeated or missing" : "") << " (--strict)\n";
    return kExitInvalidMesh;
  }
  return kExitOk;
}

}  // namespace

void register_score(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<ScoreCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "score",
      "Score the answers of any collision implementation against a pose set's certificates, as 'cdbench bench' "
      "does for its own: ANSWERS.csv has a header with pose,collides and optionally distance, time_ns, bv_tests, "
      "triangle_tests. Verdicts per pose (a certified clearance below 0 must collide, above 0 must not; an interval "
      "containing 0 is ambiguous), distance errors against the certified interval, times per level. Unknown, "
      "repeated and missing poses are reported. Writes DIR/results.csv and DIR/summary.json (cdbench plot DIR).");
  cmd->add_option("poseset", opt->poseset, "a pose-set directory (cdbench poses or certify)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("answers", opt->answers, "CSV of answers")->required();
  cmd->add_option("--name", opt->name, "the implementation's name in the outputs")->capture_default_str();
  cmd->add_flag("--surface-only", opt->surface_only,
                "the implementation tests surfaces only: a miss on a penetrating pose is 'missed-or-contained' (the "
                "mover may lie wholly inside), not a false negative");
  cmd->add_flag("--strict", opt->strict, "exit 1 when an answer contradicts a certificate or answers are unknown, "
                                         "repeated or missing");
  cmd->add_option("-o,--output", opt->out, "output directory")->required();
  cmd->callback([opt, &exit_code]() { exit_code = run_score(*opt); });
}

}  // namespace cdbench::cli
