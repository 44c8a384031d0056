// The level-list parser (`--levels`): each level that parses has a finite distance.
#include <cmath>

#include "fuzz_support.h"
#include "offset/level_list.h"
#include "util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    for (const cdbench::LevelSpec& l : cdbench::parse_level_list(text))
      if (!std::isfinite(cdbench::level_distance(l, 0.25))) std::abort();
  } catch (const cdbench::InputError&) {
  }
  return 0;
}
