#pragma once
// poseset.json of a pose-set bundle, typed (format: doc/pose-set-format.md). Readers of a bundle
// (bench, score, validate) go through read_poseset_manifest, which checks the format and the keys
// they need and names the file and key of any problem.
#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/triangle_mesh.h"
#include "poseset/pose_csv.h"

namespace cdbench {

struct MeshRecord {
  std::string path, sha256;
  std::size_t vertices = 0, faces = 0;
  double diagonal = 0.0;
  Eigen::Vector3d reference_point = Eigen::Vector3d::Zero();
};
nlohmann::json to_json(const MeshRecord& m);
// The record of a mesh used by a pose set (diagonal of its bounding box, its reference point).
MeshRecord mesh_record(const std::string& path, const std::string& sha256, const TriangleMesh& mesh,
                       const Eigen::Vector3d& reference_point);

struct LevelRecord {
  std::string spec;
  double target = std::numeric_limits<double>::quiet_NaN();  // NaN (JSON null): no common target
};

struct PoseSetManifest {
  std::string dir;
  MeshRecord fixed, mover;
  bool mover_is_fixed = false;
  double max_penetration_lo = 0.0, max_penetration_hi = 0.0;
  std::vector<LevelRecord> levels;
  double tolerance = 0.0, diagonal = 0.0;  // certification tolerance (absolute), fixed bbox diagonal
  nlohmann::json json;                     // the whole document
};

// DIR/poseset.json; InputError naming the file and key when it is not a version-1 pose set.
PoseSetManifest read_poseset_manifest(const std::string& dir);

// DIR/poses.csv, checked against the manifest (level indices in range).
std::vector<PoseRow> read_poseset_rows(const PoseSetManifest& manifest);

// The file of a mesh the pose set in `poseset_dir` was made from, checked to have the same content
// (SHA-256). The recorded path is as `cdbench poses` was given it, so relative to the directory it
// ran in: when it is not found from the current directory, a relative path is looked for from
// `poseset_dir` and each of its parent directories (the first file found there decides; its
// content is checked as well, so another file cannot stand in for it). InputError naming the pose
// set, the path and the places looked in, or the mismatch.
std::string locate_mesh(const MeshRecord& mesh, const std::string& poseset_dir);

}  // namespace cdbench
