#pragma once
// Typed access to the keys of a JSON document we wrote, for the one reader of each file: every
// missing key or wrong type is an InputError naming the file and the key's path ("levels[2].d"),
// never a library exception or undefined behaviour (counts are checked before any cast).
#include <cmath>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "util/error.h"

namespace cdbench {

class JsonKeys {
 public:
  explicit JsonKeys(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw InputError(file_ + ": key '" + path + "' " + what);
  }
  const nlohmann::json& at(const nlohmann::json& j, const std::string& key, const std::string& path) const {
    if (!j.is_object() || !j.contains(key)) throw InputError(file_ + ": missing key '" + path + key + "'");
    return j[key];
  }
  // A number; null is NaN when null_ok.
  double number(const nlohmann::json& j, const std::string& key, const std::string& path, bool null_ok = false) const {
    const nlohmann::json& v = at(j, key, path);
    if (null_ok && v.is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!v.is_number()) fail(path + key, "is not a number");
    return v.get<double>();
  }
  // A non-negative integer that fits 2^53 (an exact double), as counts are written.
  std::uint64_t count(const nlohmann::json& j, const std::string& key, const std::string& path) const {
    const nlohmann::json& v = at(j, key, path);
    if (v.is_number_unsigned()) return v.get<std::uint64_t>();
    const double x = v.is_number() ? v.get<double>() : -1.0;
    if (!(x >= 0.0 && x <= 9007199254740992.0 && std::floor(x) == x)) fail(path + key, "is not a count (an integer >= 0)");
    return static_cast<std::uint64_t>(x);
  }
  bool boolean(const nlohmann::json& j, const std::string& key, const std::string& path) const {
    const nlohmann::json& v = at(j, key, path);
    if (!v.is_boolean()) fail(path + key, "is not true or false");
    return v.get<bool>();
  }
  std::string text(const nlohmann::json& j, const std::string& key, const std::string& path) const {
    const nlohmann::json& v = at(j, key, path);
    if (!v.is_string()) fail(path + key, "is not a string");
    return v.get<std::string>();
  }
  const nlohmann::json& array(const nlohmann::json& j, const std::string& key, const std::string& path) const {
    const nlohmann::json& v = at(j, key, path);
    if (!v.is_array()) fail(path + key, "is not a list");
    return v;
  }

 private:
  std::string file_;
};

// Parses a whole file; InputError naming it when it cannot be opened or is not JSON.
nlohmann::json parse_json_file(const std::string& path, const std::string& hint);

}  // namespace cdbench
