#pragma once
// `cdbench certify`: the certified clearance of every pose of a user's pose file, written as a
// pose-set bundle (poses.csv + poseset.json) that bench, score and any bundle reader accept.
// Parallel (poses handed out one at a time; poses sharing a rotation share its mover tree),
// journaled (DIR/certify.journal: an interrupted run continues with `resume`), deterministic
// (poses.csv depends only on the inputs and options). See doc/validate-your-library.md.
#include <cstdint>
#include <string>
#include <vector>

#include "core/interval.h"
#include "core/triangle_mesh.h"
#include "poseset/user_poses.h"

namespace cdbench {

struct CertifyRequest {
  std::string fixed_path, mover_path;       // mover_path: the fixed path when the mover is the fixed mesh
  const TriangleMesh* fixed = nullptr;      // valid closed solids
  const TriangleMesh* mover = nullptr;
  bool mover_is_fixed = true;
  std::string poses_path;                   // the user's file (its SHA-256 goes into the run key)
  const UserPoseFile* poses = nullptr;
  double tolerance_relative = 1e-6;         // of the fixed mesh's diagonal: the width of penetrating intervals
  double max_penetration_tolerance = 1e-6;  // for the max penetration in poseset.json (percentages)
  std::uint64_t max_cells = 400000;         // branch-and-bound work limit per pose (then reported)
  bool resume = false;
  std::string command_line;
};

struct CertifyLevelCounts {
  std::string spec;
  double target;
  std::size_t poses = 0, certified = 0, separated = 0, penetrating = 0, straddling = 0;
  double clearance_min, clearance_max;  // over the poses' lower / upper ends
};

struct CertifyRunResult {
  std::size_t poses = 0, certified = 0, resumed = 0;
  double tolerance = 0.0, diagonal = 0.0;
  Interval max_penetration;
  std::vector<CertifyLevelCounts> levels;
  double seconds_max_penetration = 0.0, seconds_poses = 0.0, seconds_total = 0.0;
  std::string note;  // why poses are tolerance-not-reached (tolerance_not_reached_note); empty if none
};

// Writes out_dir/poses.csv and out_dir/poseset.json (atomically; the journal is removed after).
CertifyRunResult run_certify(const CertifyRequest& request, const std::string& out_dir);

}  // namespace cdbench
