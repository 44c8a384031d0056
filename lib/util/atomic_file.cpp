#include "util/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <utility>

#include "util/error.h"
#include "util/interrupt.h"

namespace cdbench {
namespace {

std::string temporary_name(const std::string& path) {
  // The pid keeps concurrent writers of the same target apart; the same directory keeps rename atomic.
  return path + ".tmp." + std::to_string(static_cast<long>(getpid()));
}

// Creates and removes a file in `dir`: the only test of writability that also sees read-only mounts,
// ACLs and full quotas as the later write will.
void probe_directory(const std::string& dir, const std::string& named) {
  const std::string probe = temporary_name((dir.empty() ? std::string(".") : dir) + "/.cdbench-write-probe");
  const int slot = register_temporary_file(probe.c_str());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  const int err = errno;
  if (fd >= 0) {
    ::close(fd);
    std::remove(probe.c_str());
  }
  unregister_temporary_file(slot);
  if (fd < 0) throw InputError(named + ": cannot write there: " + std::strerror(err));
}

}  // namespace

void prepare_output_directory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  std::error_code stat_ec;  // a path that cannot even be looked at is refused too, not thrown past us
  if (!std::filesystem::is_directory(dir, stat_ec))
    throw InputError(dir + ": cannot create the output directory" + (ec ? ": " + ec.message() : std::string()));
  probe_directory(dir, dir + " (output directory)");
}

void check_output_path(const std::string& path) {
  if (path.empty()) throw InputError("an output file's name is empty");
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory, not an output file");
  const std::string parent = std::filesystem::path(path).parent_path().string();
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw InputError(path + ": cannot write there: no directory '" + parent + "'");
  probe_directory(parent, path);
}

void write_path_atomically(const std::string& path, const std::function<bool(const std::string&)>& write) {
  const std::string tmp = temporary_name(path);
  // Removed by the interrupt handler if a signal ends the process mid-write.
  struct Registration {
    int slot;
    ~Registration() { unregister_temporary_file(slot); }
  } registration{register_temporary_file(tmp.c_str())};
  bool ok = false;
  try {
    ok = write(tmp);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  if (!ok) {
    std::remove(tmp.c_str());
    throw InputError("cannot write '" + path + "'");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    throw InputError("cannot write '" + path + "': " + why);
  }
}

RemovedIfInterrupted::RemovedIfInterrupted(std::string path)
    : path_(std::move(path)), slot_(register_temporary_file(path_.c_str())) {}

RemovedIfInterrupted::~RemovedIfInterrupted() { unregister_temporary_file(slot_); }

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  write_path_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError("cannot create '" + tmp + "': " + std::strerror(errno));
    write(out);
    out.flush();
    if (!out) throw InputError("error while writing '" + tmp + "' (disk full?)");
    out.close();
    return static_cast<bool>(out);
  });
}

}  // namespace cdbench
