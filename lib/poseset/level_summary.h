#pragma once
// Per-level counts of a pose set (for poseset.json and the printed table), from its rows.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <vector>

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

}  // namespace cdbench
