#include "score/answers_csv.h"

#include <cmath>
#include <fstream>

#include "poseset/csv_fields.h"
#include "util/error.h"

namespace cdbench {

AnswerFile read_answers_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read");
  AnswerFile file;
  std::string line;
  std::size_t line_no = 0;
  const std::vector<std::string> header = read_csv_header(in, &line_no);
  if (header.empty()) throw InputError(path + ": empty file (expected a header: pose,collides[,distance][,time_ns][,bv_tests])");
  const std::string hw = path + ":" + std::to_string(line_no);
  const std::map<std::string, std::size_t> col = csv_columns(header, hw);
  for (const std::string& h : header)
    if (h != "pose" && h != "collides" && h != "distance" && h != "time_ns" && h != "bv_tests" && h != "triangle_tests")
      file.ignored_columns.push_back(h);
  if (!col.count("pose") || !col.count("collides"))
    throw InputError(hw + ": the header must name 'pose' and 'collides' (pose,collides[,distance][,time_ns][,bv_tests])");
  file.has_distance = col.count("distance") > 0;
  file.has_time = col.count("time_ns") > 0;
  file.has_bv_tests = col.count("bv_tests") > 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (is_blank_line(line)) continue;
    const std::string where = path + ":" + std::to_string(line_no);
    const std::vector<std::string> f = split_csv_fields(line);
    if (f.size() != header.size())
      throw InputError(where + ": expected " + std::to_string(header.size()) + " columns (as the header), found " +
                       std::to_string(f.size()));
    const std::uint64_t pose = parse_index_field(f[col.at("pose")], where, "pose");
    Answer a;
    const std::string& c = f[col.at("collides")];
    if (c == "1" || c == "true" || c == "True" || c == "TRUE") a.collides = true;
    else if (c == "0" || c == "false" || c == "False" || c == "FALSE") a.collides = false;
    else throw InputError(where + ": column collides is not 0, 1, true or false: '" + c + "'");
    // Optional values may be empty (not measured for this pose).
    const auto optional = [&](const char* name) -> const std::string* {
      const auto it = col.find(name);
      return it == col.end() || f[it->second].empty() ? nullptr : &f[it->second];
    };
    if (const std::string* s = optional("distance")) a.distance = parse_double_field(*s, where, "distance");
    if (const std::string* s = optional("time_ns")) {
      a.time_ns = parse_finite_field(*s, where, "time_ns");
      if (a.time_ns < 0) throw InputError(where + ": column time_ns is negative");
    }
    for (const char* name : {"bv_tests", "triangle_tests"})
      if (const std::string* s = optional(name)) {
        const std::uint64_t n = parse_index_field(*s, where, name);
        (std::string(name) == "bv_tests" ? a.bv_tests : a.triangle_tests) = static_cast<std::int64_t>(n);
      }
    if (file.answers.count(pose)) {
      file.duplicates.push_back({pose, line_no});
      continue;
    }
    file.answers[pose] = a;
    file.line[pose] = line_no;
  }
  return file;
}

MatchedAnswers match_answers(const AnswerFile& file, const std::vector<PoseRow>& rows) {
  MatchedAnswers m;
  m.by_row.resize(rows.size());
  std::map<std::uint64_t, std::size_t> row_of;
  for (std::size_t i = 0; i < rows.size(); ++i) row_of[rows[i].pose] = i;
  for (const auto& [pose, a] : file.answers) {
    const auto it = row_of.find(pose);
    if (it == row_of.end()) m.unknown.push_back(pose);
    else m.by_row[it->second] = a;
  }
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (!m.by_row[i]) m.missing.push_back(rows[i].pose);
  return m;
}

}  // namespace cdbench
