#pragma once
// Numbers as text for the commands' outputs.
#include <iomanip>
#include <sstream>
#include <string>

namespace cdbench::cli {

// With `digits` significant digits; 17 reads back as the same double.
inline std::string number_text(double x, int digits = 17) {
  std::ostringstream os;
  os << std::setprecision(digits) << x;
  return os.str();
}

}  // namespace cdbench::cli
