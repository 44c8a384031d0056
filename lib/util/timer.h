#pragma once
#include <chrono>
#include <ctime>

namespace cdbench {

// Wall-clock stopwatch in seconds.
class Timer {
 public:
  Timer() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

// CPU time of the calling thread in seconds (POSIX CLOCK_THREAD_CPUTIME_ID). Beside the wall time
// of the same stretch, the share of it the thread ran: below 1 where other processes took its core
// (a benchmark's times then read high; validation/bench_poses reports the share).
class ThreadCpuTimer {
 public:
  ThreadCpuTimer() : start_(now()) {}
  double seconds() const { return now() - start_; }

 private:
  static double now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }
  double start_;
};

}  // namespace cdbench
