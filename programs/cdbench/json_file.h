#pragma once
// Reading a JSON file of another command's output, with errors that name the file.
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "util/error.h"

namespace cdbench::cli {

// `hint` completes the "cannot be read" message (e.g. which command writes the file).
inline nlohmann::json read_json_file(const std::string& path, const std::string& hint) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot be read (" + hint + ")");
  try {
    return nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError(path + ": not valid JSON (" + std::string(e.what()) + ")");
  }
}

}  // namespace cdbench::cli
