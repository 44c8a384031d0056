#include "offset/level_list.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include "util/error.h"
#include "util/number_format.h"

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
  return std::max(floor, p > 0.0 ? std::min(tolerance / p, kReportedMaxPenetrationWidth) : kReportedMaxPenetrationWidth);
}

void check_distinct_distances(const std::vector<LevelSpec>& levels, const std::vector<double>& distances) {
  std::vector<std::size_t> order(levels.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return distances[a] < distances[b]; });
  for (std::size_t k = 1; k < order.size(); ++k) {
    const std::size_t a = std::min(order[k - 1], order[k]), b = std::max(order[k - 1], order[k]);
    if (distances[a] != distances[b]) continue;
    const bool unscaled = (levels[a].percent && levels[a].value != 0.0) || (levels[b].percent && levels[b].value != 0.0);
    throw InputError("--levels: levels '" + levels[a].text + "' and '" + levels[b].text + "' both lie at d = " +
                     number_text(distances[a] + 0.0) +  // + 0.0: -0 reads as 0
                     (unscaled && distances[a] == 0.0
                          ? " (percentages of the maximum penetration, whose certified lower end is 0 here: the "
                            "solid is thinner than the tolerance resolves; ask for a smaller --tolerance, or give "
                            "absolute levels)"
                          : "") +
                     "; levels must lie at distinct distances");
  }
}

std::string max_penetration_scale_note(const std::vector<LevelSpec>& levels, double lo, double hi,
                                       bool tolerance_reached, double asked_width) {
  if (tolerance_reached ||
      std::none_of(levels.begin(), levels.end(), [](const LevelSpec& l) { return l.percent && l.value != 0.0; }))
    return "";
  return "the maximum penetration's search stopped at its memory bound (width asked: " + number_text(asked_width, 3) +
         " x diagonal): percentage levels are of its lower end " + number_text(lo) + ", and M may be up to " +
         number_text(hi / lo, 3) + " times that; absolute levels do not depend on M";
}

std::string percentage_resolution_note(const std::vector<LevelSpec>& levels, const std::vector<double>& distances,
                                       double tol, double diagonal) {
  std::ptrdiff_t nearest = -1;
  for (std::size_t l = 0; l < levels.size(); ++l)
    if (levels[l].percent && levels[l].value != 0.0 &&
        (nearest < 0 || std::abs(distances[l]) < std::abs(distances[static_cast<std::size_t>(nearest)])))
      nearest = static_cast<std::ptrdiff_t>(l);
  if (nearest < 0) return "";
  const double d = std::abs(distances[static_cast<std::size_t>(nearest)]);
  if (!(tol > 0.5 * d) || !(d > 0.0) || !(diagonal > 0.0)) return "";
  return "level '" + levels[static_cast<std::size_t>(nearest)].text + "' lies " + number_text(d, 3) +
         " from the surface, within twice the tolerance " + number_text(tol, 3) +
         ": the solid is thin for this tolerance and such poses are hardly told from the surface's; --tolerance " +
         number_text(0.1 * d / diagonal, 1) + " resolves it to a tenth";
}

void check_level_reach(const LevelSpec& level, double d, double diagonal) {
  if (std::abs(d) <= kMaxLevelDiagonals * diagonal) return;
  throw InputError("--levels: level '" + level.text + "' lies " + number_text(std::abs(d) / diagonal, 3) +
                   " diagonals from the surface; levels up to " + number_text(kMaxLevelDiagonals) +
                   " diagonals away (|d| <= " + number_text(kMaxLevelDiagonals * diagonal, 6) +
                   " here) are placed: farther ones cost ever more to certify, and from about 1e7 diagonals "
                   "doubles cannot hold them to the tolerance");
}

double estimated_offset_faces(double d, double diagonal, double radius_relative) {
  const double r = radius_relative * diagonal, reach = 0.5 * diagonal + std::max(d, 0.0);
  return 4.0 * M_PI * reach * reach / (r * r);
}

void check_offset_level_size(const std::string& name, double d, double diagonal, double radius_relative) {
  if (!(d > 0.0)) return;  // inward levels lie inside F: the estimate is of outward ones
  const double faces = estimated_offset_faces(d, diagonal, radius_relative);
  if (faces <= kMaxOffsetFaces) return;
  const double r = radius_relative * diagonal;
  const double farthest = r * std::sqrt(kMaxOffsetFaces / (4.0 * M_PI)) - 0.5 * diagonal;
  throw InputError("--levels: the offset at level '" + name + "' (d = " + number_text(d, 6) + ") would need about " +
                   number_text(faces, 2) + " faces at the mesher's facet size " + number_text(r, 3) +
                   " (--mesher-radius " + number_text(radius_relative) + " x diagonal); at most " +
                   number_text(kMaxOffsetFaces) + " are meshed" +
                   (farthest > 0.0 ? " (levels up to d = " + number_text(farthest, 4) + " here)" : std::string()) +
                   ": raise --mesher-radius or choose a nearer level");
}

void check_distinct_levels(const std::vector<LevelSpec>& levels) {
  std::set<std::string> seen;
  for (const LevelSpec& l : levels)
    if (!seen.insert(l.text).second) throw InputError("--levels: level '" + l.text + "' is listed twice");
}

}  // namespace cdbench
