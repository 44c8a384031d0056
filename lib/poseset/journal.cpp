#include "poseset/journal.h"

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iterator>

#include "poseset/pose_csv.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/json_keys.h"

namespace cdbench {
namespace {

// Each journal line is a poses.csv row followed by ",#" and the FNV-1a hash of the row in 16 hex
// digits: a line damaged on disk (a bit flip that still parses as numbers) is recomputed, not trusted.
std::string row_hash(const std::string& row) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : row) h = (h ^ c) * 1099511628211ull;
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace

std::map<std::uint64_t, std::string> read_journal_rows(const std::string& path) {
  std::map<std::uint64_t, std::string> rows;
  std::ifstream in(path, std::ios::binary);
  const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t start = 0, line_no = 0;
  while (start < content.size()) {
    const std::size_t end = content.find('\n', start);
    if (end == std::string::npos) break;  // cut short
    const std::string stored = content.substr(start, end - start);
    start = end + 1;
    ++line_no;
    const std::size_t mark = stored.rfind(",#");
    if (mark == std::string::npos || stored.size() - mark != 18 || row_hash(stored.substr(0, mark)) != stored.substr(mark + 2))
      continue;  // damaged: its pose is computed again
    const std::string line = stored.substr(0, mark) + "\n";
    try {
      rows[parse_pose_row(line, path + ":" + std::to_string(line_no)).pose] = line;
    } catch (const InputError&) {
      // A damaged line: its pose is computed again.
    }
  }
  return rows;
}

PoseJournal::PoseJournal(const std::string& dir, const std::string& stem, const nlohmann::json& run_key, bool resume,
                         const std::string& command)
    : path_(dir + "/" + stem + ".journal"), key_path_(dir + "/" + stem + ".journal.json") {
  if (std::filesystem::exists(path_)) {
    if (!resume)
      throw InputError(dir + " holds an interrupted run (" + stem + ".journal): pass --resume to continue it, or remove " +
                       "the journal to start over");
    nlohmann::json old;
    try {
      old = parse_json_file(key_path_, "");
    } catch (const InputError&) {
      throw InputError(key_path_ + ": unreadable; cannot tell which run the journal belongs to");
    }
    if (old != run_key)
      throw InputError("--resume: the journal in " + dir + " belongs to a run with other inputs or options (cdbench " +
                       command + "; " + key_path_ + ")");
    done_ = read_journal_rows(path_);
  }
  write_file_atomically(key_path_, [&](std::ostream& out) { out << std::setw(2) << run_key << "\n"; });
  out_.open(path_, std::ios::app | std::ios::binary);
  if (!out_) throw InputError(path_ + ": cannot open for writing");
  // For the resume tests only: die (as from a kill or power loss) after this many appends.
  if (const char* k = std::getenv("CDBENCH_TEST_KILL_AFTER_APPENDS")) kill_after_ = std::strtoull(k, nullptr, 10);
}

void PoseJournal::append(const std::vector<std::string>& lines) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const std::string& l : lines) {
    const std::string row = !l.empty() && l.back() == '\n' ? l.substr(0, l.size() - 1) : l;
    out_ << row << ",#" << row_hash(row) << "\n";
  }
  out_.flush();
  if (!out_) throw InputError(path_ + ": write failed (disk full?)");
  if (kill_after_ > 0 && ++appends_ >= kill_after_) std::raise(SIGKILL);
}

void PoseJournal::remove() {
  out_.close();
  std::error_code ec;
  std::filesystem::remove(path_, ec);
  std::filesystem::remove(key_path_, ec);
}

}  // namespace cdbench
