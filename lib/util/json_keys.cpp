#include "util/json_keys.h"

#include <fstream>

namespace cdbench {

nlohmann::json parse_json_file(const std::string& path, const std::string& hint) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read" + (hint.empty() ? std::string() : " (" + hint + ")"));
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": not valid JSON (" + std::string(e.what()) + ")");
  }
}

}  // namespace cdbench
