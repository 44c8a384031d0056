#include "util/gnuplot.h"

#include <spawn.h>
#include <sys/wait.h>
#include <fcntl.h>

#include <cerrno>
#include <vector>

extern char** environ;

namespace cdbench {
namespace {

// argv run by PATH in dir (none: ours), stdout and stderr to /dev/null when quiet. The exit
// status, or -1 when it could not be started. posix_spawnp: no shell, and safe in a process with
// threads (the child runs no code of ours).
int spawn_and_wait(const std::string& dir, std::vector<std::string> args, bool quiet) {
  posix_spawn_file_actions_t actions;
  if (posix_spawn_file_actions_init(&actions) != 0) return -1;
  bool ok = true;
  if (!dir.empty()) ok = posix_spawn_file_actions_addchdir_np(&actions, dir.c_str()) == 0;
  if (ok && quiet)
    ok = posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0) == 0 &&
         posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0) == 0;
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (ok) ok = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ) == 0;
  posix_spawn_file_actions_destroy(&actions);
  if (!ok) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  if (!WIFEXITED(status)) return -1;
  // 127: the child could not exec (glibc reports a missing program this way on some paths).
  return WEXITSTATUS(status) == 127 ? -1 : WEXITSTATUS(status);
}

}  // namespace

std::string gnuplot_string(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q += '\'';
    q += c;
  }
  return q + "'";
}

GnuplotRun run_gnuplot(const std::string& dir, const std::string& script) {
  const int status = spawn_and_wait(dir, {"gnuplot", script}, false);
  if (status < 0) return GnuplotRun::NotFound;
  return status == 0 ? GnuplotRun::Ok : GnuplotRun::Failed;
}

bool gnuplot_available() { return spawn_and_wait("", {"gnuplot", "--version"}, true) == 0; }

}  // namespace cdbench
