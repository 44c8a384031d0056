#pragma once
// Parsing of --levels lists: signed distances, absolute ("-0.5,0.2") or as a percentage of the
// certified maximum penetration ("-80%"), and ranges "FROM:TO:STEP" in either unit ("-25%:25%:5%").
#include <string>
#include <vector>

namespace cdbench {

struct LevelSpec {
  double value = 0.0;     // as written: an absolute distance, or a percentage when `percent`
  bool percent = false;
  std::string text;       // the item as it appears in the list (for messages and manifests)
};

// Throws InputError naming the offending item. Ranges include TO when it is hit within 1e-9 of a step.
std::vector<LevelSpec> parse_level_list(const std::string& list);

// InputError naming the first level whose text is listed twice (a pose set's levels must differ).
void check_distinct_levels(const std::vector<LevelSpec>& levels);

// Absolute signed distance of a level given the maximum penetration.
double level_distance(const LevelSpec& level, double max_penetration);

}  // namespace cdbench
