#include "poseset_summary.h"

#include <algorithm>
#include <cmath>

namespace cdbench::cli {

std::vector<LevelSummary> summarize_levels(const std::vector<PoseRow>& rows, std::size_t levels, double tol) {
  std::vector<LevelSummary> s(levels);
  for (const PoseRow& r : rows) {
    if (r.level < 0 || static_cast<std::size_t>(r.level) >= levels) continue;
    LevelSummary& x = s[static_cast<std::size_t>(r.level)];
    ++x.poses;
    if (r.status == "certified") ++x.certified;
    if (r.status == "uncertified:no-contact") ++x.no_contact;
    if (!std::isnan(r.clearance_lo) && r.clearance_lo >= r.target - tol && r.clearance_hi <= r.target + tol) ++x.on_target;
    if (!std::isnan(r.raw_clearance_lo)) {
      const double e = std::max(std::abs(r.raw_clearance_lo - r.target), std::abs(r.raw_clearance_hi - r.target));
      x.raw_error_max = std::max(x.raw_error_max, e);
      x.raw_error_sum += e;
      x.steps_sum += r.polish_steps;
    }
  }
  return s;
}

}  // namespace cdbench::cli

#include <iomanip>

namespace cdbench::cli {

void print_level_table(std::ostream& out, const nlohmann::json& ps, double diag) {
  out << std::left << std::setw(14) << "level" << std::setw(14) << "target" << std::setw(9) << "poses" << std::setw(11)
      << "certified" << std::setw(11) << "on-target" << std::setw(11) << "no-contact" << std::setw(15) << "raw-err/diag"
      << "steps\n";
  for (const auto& l : ps["levels"]) {
    out << std::left << std::setw(14) << l["spec"].get<std::string>() << std::setw(14) << std::setprecision(6)
        << l["target"].get<double>() << std::setw(9) << l["poses"].get<std::size_t>() << std::setw(11)
        << l["certified"].get<std::size_t>() << std::setw(11) << l["on_target"].get<std::size_t>() << std::setw(11)
        << l["no_contact"].get<std::size_t>() << std::setw(15) << std::setprecision(3)
        << l["raw_placement_error"]["mean"].get<double>() / diag << std::setprecision(3)
        << l["mean_polish_steps"].get<double>() << "\n";
  }
}

}  // namespace cdbench::cli
