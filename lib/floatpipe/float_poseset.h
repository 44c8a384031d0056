#pragma once
// The paper's float pipeline (`cdbench poses --pipeline float`, doc/float-pipeline.md): the fixed
// mesh's signed distance on a grid, an iso-surface per level by marching cubes, and for every
// orientation x direction the mover swept in from far along +dir to its first contact with the
// level's iso-surface (sphere trees, triangle sweeps in doubles: first_contact_along_line_float).
// The same sampling, pose indices and bundle format as the certified pipeline; every placed row
// has status uncertified:float and no clearance interval (`cdbench validate` certifies them).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "sampling/pose_set_spec.h"
#include "sweep/mesh_sweep.h"

namespace cdbench {

// The float pipeline's request: the pose set's spec and its grid.
struct FloatPoseSetRequest : PoseSetSpec {
  int grid = 256;      // cells along the bounding box's longest side (used when voxel == 0)
  double voxel = 0.0;  // absolute voxel size; 0: from grid
  bool keep_offsets = false;  // write DIR/offsets/float_<level>.off (for inspection and validate --offsets)
};

struct FloatPoseSetResult {
  nlohmann::json poseset;  // as written to out/poseset.json
  std::uint64_t directions = 0, orientations = 0, levels = 0, placed = 0, no_contact = 0;
  double voxel = 0.0, diagonal = 0.0, max_depth = 0.0;
  double seconds_grid = 0.0, seconds_isosurfaces = 0.0, seconds_poses = 0.0, seconds_total = 0.0;
};

// The option checks of build_float_poseset (levels, sampling names, grid): call before loading meshes.
void check_float_poseset_request(const FloatPoseSetRequest& request);
FloatPoseSetResult build_float_poseset(const FloatPoseSetRequest& request);

// The float placement of one approach: lambda (translation along dir from the reference
// placement) of the mover's first contact with `level` coming from far along +dir; false when the
// line misses it. `swept_mover` is the mover placed at the reference translation t0.
bool float_first_contact(const SweepMesh& level, const SweepMesh& swept_mover, const Vec3& dir, double* lambda);

}  // namespace cdbench
