#pragma once
// The journal of a long pose computation (`cdbench poses`, `cdbench certify`): finished rows of
// poses.csv are appended and flushed as they are certified, so that an interrupted run loses only
// the rows in flight. DIR/<stem>.journal holds the rows, DIR/<stem>.journal.json the run key (the
// inputs and options that identify the run). A resumed run must present the same key.
#include <cstdint>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace cdbench {

class PoseJournal {
 public:
  // An existing journal is an InputError unless `resume` (then its key must equal `run_key`);
  // `command` names the command in the messages. Opens the journal for appending.
  PoseJournal(const std::string& dir, const std::string& stem, const nlohmann::json& run_key, bool resume,
              const std::string& command);

  // Complete, parseable rows of the earlier run by pose id (a line cut by the interruption or
  // damaged is dropped: its pose is computed again).
  const std::map<std::uint64_t, std::string>& done() const { return done_; }
  std::map<std::uint64_t, std::string>& done() { return done_; }

  // Appends rows (formatted lines of poses.csv) with one flush; thread-safe. Throws InputError
  // when the write fails (disk full).
  void append(const std::vector<std::string>& lines);

  // After the final outputs are written.
  void remove();

  const std::string& path() const { return path_; }

 private:
  std::string path_, key_path_;
  std::map<std::uint64_t, std::string> done_;
  std::ofstream out_;
  std::mutex mutex_;
  std::uint64_t appends_ = 0, kill_after_ = 0;
};

// Rows of a journal file (complete, parseable lines only), by pose id.
std::map<std::uint64_t, std::string> read_journal_rows(const std::string& path);

}  // namespace cdbench
