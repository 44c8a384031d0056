#pragma once
// Answers of any collision implementation to a pose set, for `cdbench score`: a CSV with a header
// `pose,collides[,distance][,time_ns][,bv_tests][,triangle_tests]` (any order; other columns are
// ignored). `collides` is 0/1 or true/false.
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "score/scoring.h"

namespace cdbench {

struct AnswerFile {
  std::map<std::uint64_t, Answer> answers;   // by pose id
  std::map<std::uint64_t, std::size_t> line;  // the line of each answer
  std::vector<std::pair<std::uint64_t, std::size_t>> duplicates;  // (pose, line) of repeated ids
  bool has_distance = false, has_time = false, has_bv_tests = false;
  std::vector<std::string> ignored_columns;
};

// InputError naming the line for a malformed header or row (wrong column count, a `collides`
// that is not 0/1/true/false, a negative count, a non-finite time).
AnswerFile read_answers_file(const std::string& path);

struct MatchedAnswers {
  std::vector<std::optional<Answer>> by_row;  // per pose-set row
  std::vector<std::uint64_t> unknown;         // ids not in the pose set (ascending)
  std::vector<std::uint64_t> missing;         // placed poses without an answer (ascending)
};
MatchedAnswers match_answers(const AnswerFile& file, const std::vector<PoseRow>& rows);

}  // namespace cdbench
