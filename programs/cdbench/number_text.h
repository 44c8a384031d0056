#pragma once
// Numbers as text for the commands' outputs (the library's formatter).
#include "util/number_format.h"

namespace cdbench::cli {
using cdbench::number_text;
using cdbench::shortest_number_text;
}  // namespace cdbench::cli
