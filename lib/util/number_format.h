#pragma once
// Numbers as text for outputs: one formatter for the library and the commands.
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <sstream>
#include <string>

namespace cdbench {

// With `digits` significant digits; 17 reads back as the same double.
inline std::string number_text(double x, int digits = 17) {
  std::ostringstream os;
  os << std::setprecision(digits) << x;
  return os.str();
}

// The shortest text (up to 17 digits) that reads back as the same double: 0.1, not
// 0.10000000000000001 (labels, level names).
inline std::string shortest_number_text(double x) {
  for (int digits = 1; digits < 17; ++digits) {
    const std::string s = number_text(x, digits);
    if (std::strtod(s.c_str(), nullptr) == x) return s;
  }
  return number_text(x, 17);
}

}  // namespace cdbench
