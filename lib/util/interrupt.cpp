#include "util/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>

namespace cdbench {
namespace {

constexpr int kSlots = 256;
std::atomic<const char*> g_temporary[kSlots];
const char* g_hint = "";
std::atomic<bool> g_complete{false};

void write_text(const char* s) {
  const ssize_t ignored = ::write(STDERR_FILENO, s, std::strlen(s));
  (void)ignored;
}

// Only async-signal-safe calls: unlink, write, _exit.
extern "C" void on_interrupt(int sig) {
  if (g_complete.load()) return;  // nothing left to lose: let the run finish
  for (auto& slot : g_temporary)
    if (const char* p = slot.load()) ::unlink(p);
  write_text(sig == SIGINT ? "\ncdbench: interrupted (SIGINT); " : "\ncdbench: terminated (SIGTERM); ");
  write_text("no output was left half-written. ");
  write_text(g_hint);
  write_text("\n");
  ::_exit(128 + sig);
}

}  // namespace

void install_interrupt_handlers(const char* hint) {
  g_hint = hint;
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  std::signal(SIGXFSZ, SIG_IGN);
}

void mark_outputs_complete() { g_complete.store(true); }

int register_temporary_file(const char* path) {
  for (int i = 0; i < kSlots; ++i) {
    const char* expected = nullptr;
    if (g_temporary[i].compare_exchange_strong(expected, path)) return i;
  }
  return -1;
}

void unregister_temporary_file(int slot) {
  if (slot >= 0) g_temporary[slot].store(nullptr);
}

}  // namespace cdbench
