#pragma once
// Shared by the libFuzzer targets. The contract under test: every input either reads, or throws
// cdbench::InputError (a clear message for the user). Any other exception escapes the target and
// libFuzzer reports it as a crash, as it does for sanitizer findings, hangs and large allocations.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace cdbench::fuzz {

// A private folder for readers that take a path (made once per process, removed when the
// process exits normally; a crash leaves it, with the input that made it). Never destroyed before
// that removal runs: the path outlives static destruction.
inline const std::string& scratch_dir() {
  static const std::string* dir = [] {
    const char* t = std::getenv("TMPDIR");
    std::string pattern = std::string(t && *t ? t : "/tmp") + "/cdbench-fuzz-XXXXXX";
    if (!mkdtemp(pattern.data())) std::abort();
    auto* path = new std::string(pattern);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(scratch_dir(), ec);
    });
    return path;
  }();
  return *dir;
}

inline std::string write_scratch(const std::string& name, const std::string& bytes) {
  const std::string path = scratch_dir() + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) std::abort();
  return path;
}

// The first byte selects what the rest is.
inline std::string payload(const std::uint8_t* data, std::size_t size) {
  return size > 1 ? std::string(reinterpret_cast<const char*>(data) + 1, size - 1) : std::string();
}

}  // namespace cdbench::fuzz
