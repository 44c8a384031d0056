#include "poseset/level_summary.h"

#include <algorithm>
#include <cmath>

#include "util/number_format.h"

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

std::string tolerance_not_reached_note(const std::vector<PoseRow>& rows, double tolerance, double diagonal,
                                       const Aabb& fixed_box, const std::string& otherwise) {
  std::size_t n = 0;
  double widest = 0.0;
  for (const PoseRow& r : rows) {
    if (r.status != PoseStatus::ToleranceNotReached) continue;
    ++n;
    if (r.clearance_hi - r.clearance_lo > widest) widest = r.clearance_hi - r.clearance_lo;
  }
  if (n == 0) return "";
  std::string note = std::to_string(n) + (n == 1 ? " pose is" : " poses are") +
                     " uncertified:tolerance-not-reached (rigorous intervals up to " + number_text(widest, 3) +
                     " wide, the tolerance " + number_text(tolerance, 3) + "): ";
  const double magnitude = fixed_box.max_abs();
  const double rounding = kRoundingPerMagnitude * magnitude;
  if (!(rounding >= 0.125 * tolerance) || !(diagonal > 0.0)) return note + otherwise;
  // A tolerance twice what was reached or the rounding, rounded up to one digit.
  const double wanted = 2.0 * std::max(widest, rounding) / diagonal;
  const double unit = std::pow(10.0, std::floor(std::log10(wanted)));
  return note + "the fixed mesh's coordinates reach " + number_text(magnitude, 3) + ", " +
         number_text(magnitude / diagonal, 2) + " times its diagonal, where the doubles' rounding alone is about " +
         number_text(rounding, 2) + " of every interval; translate the meshes towards the origin, or ask for " +
         "--tolerance " + number_text(std::ceil(wanted / unit * (1.0 - 1e-12)) * unit, 2) + " or more";
}

}  // namespace cdbench
