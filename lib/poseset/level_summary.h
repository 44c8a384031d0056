#pragma once
// Per-level counts of a pose set (for poseset.json and the printed table), from its rows.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/aabb.h"
#include "poseset/pose_csv.h"

namespace cdbench {

struct LevelSummary {
  std::size_t poses = 0, certified = 0, on_target = 0, no_contact = 0;
  double raw_error_max = 0.0, raw_error_sum = 0.0, steps_sum = 0.0;
  std::size_t placed() const { return poses - no_contact; }
};

// tol: the absolute tolerance of "on target" (|c - target| <= tol by the certificate).
std::vector<LevelSummary> summarize_levels(const std::vector<PoseRow>& rows, std::size_t levels, double tol);

// Sets a poseset.json level entry's counts from its summary: poses, certified, on_target,
// no_contact, raw_placement_error {max, mean} and mean_polish_steps (means over placed poses).
void set_level_counts(nlohmann::json& level, const LevelSummary& summary);

// What a user should read about poses left `uncertified:tolerance-not-reached` (their intervals are
// rigorous, only wider): how many, their widest interval against the tolerance, and, where the
// doubles' rounding at the fixed mesh's coordinates is a fair part of the tolerance (about
// kRoundingPerMagnitude of the largest coordinate of its box `fixed_box` in every interval, measured on
// tetrahedra 10^7-10^8 from the origin: doc/poses.md, "Far from the origin"), that the mesh lies
// too far out for that tolerance and what to ask for instead; elsewhere `otherwise` (the work
// limit's hint). Empty when no row has that status.
inline constexpr double kRoundingPerMagnitude = 5e-14;
std::string tolerance_not_reached_note(const std::vector<PoseRow>& rows, double tolerance, double diagonal,
                                       const Aabb& fixed_box, const std::string& otherwise);

}  // namespace cdbench
