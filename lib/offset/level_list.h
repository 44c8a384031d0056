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

// How tightly the maximum penetration M must be certified (width relative to the diagonal) for a
// pose set whose percentage levels p are placed to `tolerance` (relative to the diagonal): a level
// at p·M is then known to |p|·width <= tolerance of p times the true M. Never below `floor` (the
// default width). When no level is a percentage no target depends on M, which is then only
// reported (the solid's scale, and absolute levels as fractions of it): kReportedMaxPenetrationWidth,
// or `floor` if wider. M is only the levels' scale: a thin tube's M has a 2-D plateau of deepest
// points that costs ~1/width^0.7 cells to certify (pipe: 1e-6 not reached in 67 s; 1e-4 in 1.3 s).
constexpr double kReportedMaxPenetrationWidth = 1e-4;
double max_penetration_tolerance_for(const std::vector<LevelSpec>& levels, double tolerance, double floor);

}  // namespace cdbench
