// The CSV readers: poses.csv, the journal of interrupted runs, user pose files (certify) and
// answer files (score). First byte: which reader. A poses.csv row that reads must survive the
// writer: format, read again, format again gives the same line.
#include <sstream>

#include "fuzz_support.h"
#include "poseset/journal.h"
#include "poseset/pose_csv.h"
#include "poseset/user_poses.h"
#include "score/answers_csv.h"
#include "util/error.h"

namespace {

void check_round_trip(const cdbench::PoseRow& row) {
  const std::string line = cdbench::format_pose_row(row);
  const cdbench::PoseRow again = cdbench::parse_pose_row(line, "round trip");
  if (cdbench::format_pose_row(again) != line) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string bytes = cdbench::fuzz::payload(data, size);
  try {
    switch (data[0] % 4) {
      case 0: {
        std::istringstream in(bytes);
        for (const cdbench::PoseRow& r : cdbench::read_pose_csv(in, "fuzz.csv")) check_round_trip(r);
        break;
      }
      case 1: {
        std::istringstream in(bytes);
        cdbench::read_user_poses(in, "fuzz.csv");
        break;
      }
      case 2: {
        const cdbench::AnswerFile f = cdbench::read_answers_file(cdbench::fuzz::write_scratch("answers.csv", bytes));
        std::vector<cdbench::PoseRow> rows(3);
        for (std::size_t i = 0; i < rows.size(); ++i) rows[i].pose = i;
        cdbench::match_answers(f, rows);
        break;
      }
      default: {
        // Lines that survive are rows the resumed run trusts: each must read as a row again.
        for (const auto& [pose, line] : cdbench::read_journal_rows(cdbench::fuzz::write_scratch("poses.journal", bytes)))
          if (cdbench::parse_pose_row(line, "journal").pose != pose) std::abort();
        break;
      }
    }
  } catch (const cdbench::InputError&) {
  }
  return 0;
}
