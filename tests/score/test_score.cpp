// Verdicts and scores of collision answers against certificates; answer files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "score/answers_csv.h"
#include "score/bench_plot.h"
#include "score/scoring.h"
#include "util/error.h"

namespace cdbench {
namespace {

TEST(Verdict, FollowsTheCertificate) {
  EXPECT_EQ(classify(-0.2, -0.1, true, true), Verdict::Ok);
  EXPECT_EQ(classify(-0.2, -0.1, false, false), Verdict::FalseNegative);
  EXPECT_EQ(classify(-0.2, -0.1, false, true), Verdict::MissedOrContained);
  EXPECT_EQ(classify(0.1, 0.2, true, true), Verdict::FalsePositive);
  EXPECT_EQ(classify(0.1, 0.2, false, false), Verdict::Ok);
  EXPECT_EQ(classify(-1e-9, 1e-9, false, false), Verdict::Ambiguous);
  EXPECT_EQ(classify(0.0, 1e-9, true, false), Verdict::Ambiguous);  // touching: either answer
}

PoseSetManifest manifest() {
  PoseSetManifest m;
  m.max_penetration_lo = m.max_penetration_hi = 2.0;
  m.levels = {{"-50%", -1.0}, {"10%", 0.2}};
  return m;
}

PoseRow row(std::uint64_t id, int level, double lo, double hi) {
  PoseRow r;
  r.pose = id;
  r.level = level;
  r.clearance_lo = lo;
  r.clearance_hi = hi;
  return r;
}

TEST(Summary, ReadsWhatItWritesAndNamesAWrongKey) {
  ImplScore s = score_answers("x", manifest(), {row(0, 0, -1.0, -0.99)}, {Answer{true}}, true);
  const std::string dir = testing::TempDir();
  std::ofstream(dir + "/summary.json") << summary_json(manifest(), 1, {s}, {}).dump(2);
  const std::vector<BenchSummaryImpl> r = read_bench_summary(dir + "/summary.json");
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].name, "x");
  ASSERT_EQ(r[0].levels.size(), 2u);
  EXPECT_EQ(r[0].levels[0].poses, 1u);
  EXPECT_TRUE(std::isnan(r[0].levels[0].mean_us));  // null: not timed
  nlohmann::json j = summary_json(manifest(), 1, {s}, {});
  j["implementations"][0]["levels"][1]["false_positives"] = -3;
  std::ofstream(dir + "/summary.json") << j.dump();
  try {
    read_bench_summary(dir + "/summary.json");
    ADD_FAILURE() << "a negative count was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("implementations[0].levels[1].false_positives' is not a count"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(dir + "/summary.json") << "{\"format\": 7}";
  EXPECT_THROW(read_bench_summary(dir + "/summary.json"), InputError);
}

// A line break in an implementation's name (a plugin names itself) must not start a line of plot.dat
// that gnuplot would read as data: every line is a comment, numbers and a quoted level name, or empty.
TEST(Summary, PlotDataKeepsAnyNameOnItsCommentLine) {
  const ImplScore s = score_answers("evil\n1 2 3 4 5 6\r", manifest(), {row(0, 0, -1.0, -0.99)}, {Answer{true}}, true);
  const std::string dir = testing::TempDir() + "/plot_names";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/summary.json") << summary_json(manifest(), 1, {s}, {}).dump(2);
  write_bench_plot_files(dir);
  std::ifstream in(dir + "/plot.dat");
  std::string line;
  int comments = 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      ++comments;
      EXPECT_EQ(line, "# evil 1 2 3 4 5 6 ");
      continue;
    }
    // Six numbers (nan for an untimed level), then the level's name in double quotes.
    const std::size_t quote = line.find('"');
    ASSERT_NE(quote, std::string::npos) << line;
    EXPECT_EQ(line.back(), '"') << line;
    EXPECT_EQ(line.find('"', quote + 1), line.size() - 1) << line;
    std::istringstream fields(line.substr(0, quote));
    std::string field;
    int n = 0;
    while (fields >> field) {
      char* end = nullptr;
      std::strtod(field.c_str(), &end);
      EXPECT_EQ(*end, '\0') << "not a data line: " << line;
      ++n;
    }
    EXPECT_EQ(n, 6) << line;
  }
  EXPECT_EQ(comments, 1);
}

TEST(Score, CountsExactlyTheWrongAnswersPerLevel) {
  const std::vector<PoseRow> rows = {row(0, 0, -1.0, -0.99), row(1, 0, -1.0, -0.99), row(2, 1, 0.2, 0.2001),
                                     row(3, 1, 0.2, 0.2001), row(4, 1, 0.2, 0.2001)};
  std::vector<std::optional<Answer>> a(rows.size());
  a[0] = Answer{true, NAN, 100.0, 5, 1};
  a[1] = Answer{false, NAN, 300.0, 7, 1};   // false negative
  a[2] = Answer{true, 0.2, 50.0, 1, 0};     // false positive
  a[3] = Answer{false, 0.19, 70.0, 3, 0};   // distance 0.01 below the interval
  // a[4] missing
  const ImplScore s = score_answers("x", manifest(), rows, a, false);
  ASSERT_EQ(s.levels.size(), 2u);
  EXPECT_EQ(s.levels[0].false_negatives, 1u);
  EXPECT_EQ(s.levels[0].false_positives, 0u);
  EXPECT_DOUBLE_EQ(s.levels[0].mean_us, 0.2);
  EXPECT_DOUBLE_EQ(s.levels[0].mean_bv_tests, 6.0);
  EXPECT_DOUBLE_EQ(s.levels[0].percent_of_max_penetration, -50.0);
  EXPECT_EQ(s.levels[1].false_positives, 1u);
  EXPECT_EQ(s.levels[1].missing, 1u);
  EXPECT_EQ(s.levels[1].distance_answers, 2u);
  EXPECT_NEAR(s.levels[1].max_distance_error, 0.01, 1e-12);
  EXPECT_EQ(s.verdicts[1], Verdict::FalseNegative);
  EXPECT_EQ(score_answers("x", manifest(), rows, a, true).levels[0].missed_or_contained, 1u);
}

std::string write(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(Answers, UnknownMissingAndRepeatedPosesAreReported) {
  const AnswerFile f = read_answers_file(write("a.csv", "collides,pose,time_ns,note\n1,0,10,a\ntrue,7,,b\n0,0,5,c\n"));
  EXPECT_EQ(f.answers.size(), 2u);
  ASSERT_EQ(f.duplicates.size(), 1u);
  EXPECT_EQ(f.duplicates[0].second, 4u);
  EXPECT_TRUE(std::isnan(f.answers.at(7).time_ns));
  const std::vector<PoseRow> rows = {row(0, 0, -1, -0.9), row(1, 0, -1, -0.9)};
  const MatchedAnswers m = match_answers(f, rows);
  EXPECT_EQ(m.unknown, std::vector<std::uint64_t>{7});
  EXPECT_EQ(m.missing, std::vector<std::uint64_t>{1});
  EXPECT_TRUE(m.by_row[0]->collides);
}

TEST(Answers, ErrorsNameTheLine) {
  const auto error = [](const std::string& text) {
    try {
      read_answers_file(write("b.csv", text));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("pose,distance\n").find("must name 'pose' and 'collides'"), std::string::npos);
  EXPECT_NE(error("pose,collides\n0,yes\n").find("b.csv:2: column collides is not 0, 1, true or false"), std::string::npos);
  EXPECT_NE(error("pose,collides,time_ns\n0,1,-4\n").find("b.csv:2: column time_ns is negative"), std::string::npos);
  EXPECT_NE(error("pose,collides\n0,1\n1\n").find("b.csv:3: expected 2 columns"), std::string::npos);
  EXPECT_NE(error("pose,collides,bv_tests\n0,1,2.5\n").find("b.csv:2: column bv_tests is not a non-negative integer"),
            std::string::npos);
}

}  // namespace
}  // namespace cdbench
