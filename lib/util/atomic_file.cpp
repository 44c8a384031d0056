#include "util/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
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

}  // namespace

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
