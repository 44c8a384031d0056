#include "poseset/level_summary.h"

#include <algorithm>
#include <cmath>

namespace cdbench {

std::vector<LevelSummary> summarize_levels(const std::vector<PoseRow>& rows, std::size_t levels, double tol) {
  std::vector<LevelSummary> s(levels);
  for (const PoseRow& r : rows) {
    if (r.level < 0 || static_cast<std::size_t>(r.level) >= levels) continue;
    LevelSummary& x = s[static_cast<std::size_t>(r.level)];
    ++x.poses;
    if (r.status == PoseStatus::Certified) ++x.certified;
    if (r.status == PoseStatus::NoContact) ++x.no_contact;
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

void set_level_counts(nlohmann::json& e, const LevelSummary& x) {
  const double placed = static_cast<double>(x.placed());
  e["poses"] = x.poses;
  e["certified"] = x.certified;
  e["on_target"] = x.on_target;
  e["no_contact"] = x.no_contact;
  e["raw_placement_error"] = {{"max", x.raw_error_max}, {"mean", placed > 0 ? x.raw_error_sum / placed : 0.0}};
  e["mean_polish_steps"] = placed > 0 ? x.steps_sum / placed : 0.0;
}

}  // namespace cdbench
