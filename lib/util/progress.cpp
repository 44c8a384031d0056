#include "util/progress.h"

#include <unistd.h>

#include <cstdio>

namespace cdbench {

bool Progress::enabled() { return isatty(STDERR_FILENO) == 1; }

Progress::Progress(std::string label, std::uint64_t total)
    : label_(std::move(label)),
      total_(total),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_),
      active_(enabled()) {}

Progress::~Progress() { finish(); }

void Progress::advance(std::uint64_t n) {
  done_.fetch_add(n, std::memory_order_relaxed);
  const auto now = std::chrono::steady_clock::now();
  // Cheap unlocked check first; the lock only serialises actual drawing. Without a terminal (a
  // log, a batch job) a plain line every 30 s shows that long work is alive.
  if (now - last_draw_ < (active_ ? std::chrono::milliseconds(200) : std::chrono::milliseconds(30000))) return;
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || finished_) return;
  last_draw_ = now;
  draw(false);
}

void Progress::set_detail(const std::string& detail) {
  std::lock_guard<std::mutex> lock(mutex_);
  detail_ = detail;
}

void Progress::start_heartbeat() {
  if (heartbeat_.joinable()) return;
  heartbeat_ = std::thread([this] {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_cv_.wait_for(lock, std::chrono::milliseconds(active_ ? 200 : 1000), [this] { return stop_; })) {
      lock.unlock();
      advance(0);  // draws when due
      lock.lock();
    }
  });
}

void Progress::finish() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  stop_cv_.notify_all();
  if (heartbeat_.joinable()) heartbeat_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  finished_ = true;
  // Only a run long enough to have drawn anything leaves a final line.
  if (active_ && last_draw_ != start_) draw(true);
}

void Progress::draw(bool final_line) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::uint64_t done = done_.load(std::memory_order_relaxed);
  if (total_ > 0) {
    const double frac = static_cast<double>(done) / static_cast<double>(total_);
    // No estimate before the first step is done.
    char eta[48] = "ETA ?";
    if (frac > 0) std::snprintf(eta, sizeof eta, "ETA %.0fs", elapsed * (1.0 / frac - 1.0));
    std::fprintf(stderr, active_ ? "\r%s: %5.1f%% (%llu/%llu) %.0fs elapsed, %s %s\033[K" : "%s: %5.1f%% (%llu/%llu) %.0fs elapsed, %s %s", label_.c_str(),
                 100.0 * frac, static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_),
                 elapsed, eta, detail_.c_str());
  } else {
    std::fprintf(stderr, active_ ? "\r%s: %llu, %.1fs elapsed %s\033[K" : "%s: %llu, %.1fs elapsed %s", label_.c_str(),
                 static_cast<unsigned long long>(done), elapsed, detail_.c_str());
  }
  if (final_line || !active_) std::fputc('\n', stderr);
  std::fflush(stderr);
}

}  // namespace cdbench
