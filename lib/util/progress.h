#pragma once
// Progress on stderr for long work: on a terminal a line redrawn a few times per second; otherwise
// (logs, batch jobs, CI) a plain line every 30 s, so short runs print nothing. Safe to call from
// many threads.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace cdbench {

class Progress {
 public:
  // total == 0: an open-ended task (shows a count and the elapsed time only).
  Progress(std::string label, std::uint64_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void advance(std::uint64_t n = 1);
  // Replaces the free-text detail shown after the counter (e.g. the current bound).
  void set_detail(const std::string& detail);
  // Draws at the same pace without advance() calls, from a thread of its own until finish(): for
  // steps that run for minutes inside a library (an offset level's mesher) and would leave the
  // line silent.
  void start_heartbeat();
  void finish();

  static bool enabled();  // true when stderr is a terminal (redrawn line)

 private:
  void draw(bool final_line);

  std::string label_;
  std::uint64_t total_;
  std::atomic<std::uint64_t> done_{0};
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::mutex mutex_;
  std::string detail_;
  bool active_;
  bool finished_ = false;
  std::thread heartbeat_;
  std::condition_variable stop_cv_;
  bool stop_ = false;  // under mutex_
};

}  // namespace cdbench
