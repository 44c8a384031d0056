#pragma once
// The pose-set builder of `cdbench poses` (doc/poses.md, format: doc/pose-set-format.md): levels
// from a level list and the certified max penetration, offsets where a level starts from one
// (reused across runs), sampled orientations x directions, the approach loop (parallel, no
// barrier), the journal (resume) and shards; writes out/poses.csv and out/poseset.json.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "core/interval.h"
#include "offset/offset_set.h"
#include "placement/place_pose.h"
#include "sampling/pose_set_spec.h"

namespace cdbench {

// The most poses one run (one shard) computes: its rows stay in memory until poses.csv is written
// (about 0.87 KB each with their parsed copy, measured; doc/poses.md).
constexpr double kMaxPosesPerRun = 1e7;

// The certified pipeline's request: the pose set's spec and its own options.
struct PoseSetRequest : PoseSetSpec {
  std::string shard = "0/1";
  bool resume = false, no_polish = false;
  StartPolicy start = StartPolicy::NoOffsets;  // --start auto | offset
  double tolerance = 1e-6;       // certification tolerance, relative to the fixed mesh's diagonal
  double band_tolerance = 1e-3;  // offsets' band tolerance, relative
  // Offsets' candidates by Mesh_3 on all threads (OffsetOptions::parallel_mesher): certified all the
  // same, but the offsets, and so the poses that start from them, are not reproducible bit for bit.
  bool parallel_mesher = false;
  // The least width of the max penetration (relative); percentage levels loosen it to what their
  // targets need (max_penetration_tolerance_for).
  double max_penetration_tolerance = 1e-6;
  int max_steps = kDefaultMaxSteps;
};

struct PoseSetResult {
  nlohmann::json poseset;  // as written to out/poseset.json
  std::uint64_t directions = 0, orientations = 0, levels = 0, computed = 0;
  bool sharded = false;
  double tolerance = 0.0, diagonal = 0.0;
  Interval max_penetration;
  double seconds_offsets = 0.0, seconds_poses = 0.0, seconds_total = 0.0;
  std::string note;  // why poses are tolerance-not-reached (tolerance_not_reached_note); empty if none
};

// InputError naming the option (levels, shard, sampling names): call before loading meshes.
void check_poseset_request(const PoseSetRequest& request);
// InputError for bad options (before any work) and unusable inputs.
PoseSetResult build_poseset(const PoseSetRequest& request);

}  // namespace cdbench
