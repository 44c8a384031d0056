#pragma once
// The per-level table of a pose set on stdout (counts: poseset/level_summary.h).
#include <cstddef>
#include <vector>

#include "poseset/level_summary.h"



#include <nlohmann/json.hpp>
#include <ostream>

namespace cdbench::cli {
// The per-level table of a poseset.json.
void print_level_table(std::ostream& out, const nlohmann::json& poseset, double diagonal);
}  // namespace cdbench::cli
