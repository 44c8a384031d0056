#pragma once
// Counts in the headers of text mesh formats (OFF's vertex and face counts, PLY's element counts),
// shared by the OFF reader (text_readers.cpp) and the PLY pre-check (file_structure.cpp).
#include <charconv>
#include <string_view>
#include <system_error>

namespace cdbench {

// A count: decimal digits only (no sign, no exponent, no '0x'), at most 18 of them, so that it
// fits a long long with room for the callers' size arithmetic. False otherwise.
inline bool parse_count(std::string_view t, long long& value) {
  if (t.empty() || t.size() > 18) return false;
  for (char c : t)
    if (c < '0' || c > '9') return false;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), value);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

}  // namespace cdbench
