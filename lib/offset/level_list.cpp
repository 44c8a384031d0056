#include "offset/level_list.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include "util/error.h"

namespace cdbench {
namespace {

bool parse_value(const std::string& item, double& value, bool& percent) {
  std::string s = item;
  percent = !s.empty() && s.back() == '%';
  if (percent) s.pop_back();
  if (s.empty()) return false;
  char* end = nullptr;
  value = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(value);
}

std::string format_item(double v, bool percent) {
  std::ostringstream os;
  os.precision(12);
  os << v << (percent ? "%" : "");
  return os.str();
}

}  // namespace

std::vector<LevelSpec> parse_level_list(const std::string& list) {
  std::vector<LevelSpec> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.empty()) throw InputError("--levels: empty item in '" + list + "'");
    const std::size_t c1 = item.find(':');
    if (c1 == std::string::npos) {
      LevelSpec l;
      if (!parse_value(item, l.value, l.percent))
        throw InputError("--levels: '" + item + "' is not a number or a percentage (e.g. -0.5 or -80%)");
      l.text = item;
      out.push_back(l);
      if (out.size() > 10000) throw InputError("--levels: more than 10000 levels in all");
      continue;
    }
    const std::size_t c2 = item.find(':', c1 + 1);
    if (c2 == std::string::npos || item.find(':', c2 + 1) != std::string::npos)
      throw InputError("--levels: range '" + item + "' must be FROM:TO:STEP");
    double from, to, step;
    bool pf, pt, ps;
    if (!parse_value(item.substr(0, c1), from, pf) || !parse_value(item.substr(c1 + 1, c2 - c1 - 1), to, pt) ||
        !parse_value(item.substr(c2 + 1), step, ps))
      throw InputError("--levels: range '" + item + "' has a part that is not a number");
    if (pf != pt || pf != ps)
      throw InputError("--levels: range '" + item + "' mixes absolute values and percentages");
    if (!(step > 0)) throw InputError("--levels: range '" + item + "' needs a positive step");
    if (to < from) throw InputError("--levels: range '" + item + "' runs backwards (FROM > TO)");
    const double n = std::floor((to - from) / step + 1e-9);
    if (n > 10000) throw InputError("--levels: range '" + item + "' has more than 10000 levels");
    for (int k = 0; k <= static_cast<int>(n); ++k) {
      LevelSpec l;
      l.value = from + k * step;
      if (std::abs(l.value) < 1e-12 * std::max(std::abs(from), std::abs(to))) l.value = 0.0;  // exact 0 in ranges
      l.percent = pf;
      l.text = format_item(l.value, pf);
      out.push_back(l);
    }
    if (out.size() > 10000) throw InputError("--levels: more than 10000 levels in all");
  }
  if (out.empty()) throw InputError("--levels: no level given");
  return out;
}

double level_distance(const LevelSpec& level, double max_penetration) {
  return level.percent ? level.value / 100.0 * max_penetration : level.value;
}

double max_penetration_tolerance_for(const std::vector<LevelSpec>& levels, double tolerance, double floor) {
  double p = 0.0;
  for (const LevelSpec& l : levels)
    if (l.percent) p = std::max(p, std::abs(l.value) / 100.0);
  return std::max(floor, p > 0.0 ? tolerance / p : kReportedMaxPenetrationWidth);
}

void check_distinct_levels(const std::vector<LevelSpec>& levels) {
  std::set<std::string> seen;
  for (const LevelSpec& l : levels)
    if (!seen.insert(l.text).second) throw InputError("--levels: level '" + l.text + "' is listed twice");
}

}  // namespace cdbench
