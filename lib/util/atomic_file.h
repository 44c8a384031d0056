#pragma once
// Whole-file output that never leaves a half-written file under the final name: the content goes
// to a temporary file in the same directory, which is renamed over the target only when complete.
#include <functional>
#include <ostream>
#include <string>

namespace cdbench {

// Calls write(stream) on a temporary file next to `path`, then renames it to `path`.
// On any failure (the callback throws, the disk is full, the directory is missing) the temporary
// file is removed, `path` is left as it was, and an InputError naming the file is thrown.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// An output written whole that belongs with another still to come (poses.csv before its
// poseset.json): while this lives, an interrupt (util/interrupt.h) removes it, so that an
// interrupted run never leaves one without the other. Destroy it once the second is written (on
// an error the first stays, and the error is reported).
class RemovedIfInterrupted {
 public:
  explicit RemovedIfInterrupted(std::string path);
  ~RemovedIfInterrupted();
  RemovedIfInterrupted(const RemovedIfInterrupted&) = delete;
  RemovedIfInterrupted& operator=(const RemovedIfInterrupted&) = delete;

 private:
  std::string path_;
  int slot_;
};

// Same, for producers that can only write to a path (e.g. a library's own writer).
// write(tmp_path) must create tmp_path and return false (or throw) on failure.
void write_path_atomically(const std::string& path, const std::function<bool(const std::string&)>& write);

// For runs that write their outputs only when their work is done: fail before the work, not after.
// prepare_output_directory creates `dir` (and its parents) if missing and checks that a file can be
// created in it; check_output_path checks that write_file_atomically(path, ...) could write `path`
// (its directory exists and takes a new file; `path` is not a directory). Both throw an InputError
// naming the path and the reason; neither leaves anything behind but the created directory.
void prepare_output_directory(const std::string& dir);
void check_output_path(const std::string& path);

}  // namespace cdbench
