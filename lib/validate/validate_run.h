#pragma once
// `cdbench validate`: any pose set in the bundle format (the float pipeline's, FCL's, another
// tool's) measured against the certified ground truth (doc/float-pipeline.md, "Validation"):
//  * every placed pose's clearance certified against the original fixed surface;
//  * per level: the target error c - target, wrong-sign poses, missed first contacts;
//  * for float offsets kept in the bundle: their certified band against their level;
//  * time per pose of the set's own pipeline beside the certified one (with a reference).
// The certificates are those of `cdbench certify` (placement/clearance.h); what is counted from
// them is stated with each field below.
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/interval.h"
#include "core/triangle_mesh.h"

namespace cdbench {

struct ValidateRequest {
  std::string poseset;    // a bundle directory
  std::string reference;  // optional: a certified pose set of the same request (same meshes, sampling)
  const TriangleMesh* fixed = nullptr;  // the bundle's meshes, loaded and valid (SHA-256 checked by the caller)
  const TriangleMesh* mover = nullptr;
  double tolerance_relative = 1e-6;      // width of penetrating certificates, x diagonal
  double max_penetration_tolerance = 1e-6;
  std::uint64_t max_cells = 400000;
  bool offsets = false;                  // certify the bands of float offsets kept in the bundle (costly)
  bool completeness = false;             // and their completeness (expensive)
  std::string out;                       // output directory
};

// Per-pose verdicts. missed_contact: Yes / No, or Unknown when it cannot be decided (no approach
// direction in the bundle, or a penetrating target without a reference pose).
enum class Tristate { No, Yes, Unknown };

struct PoseValidation {
  std::uint64_t pose = 0;
  int level = 0;
  double target = 0.0;
  Interval clearance;    // certified; NaN for rows without a pose
  bool placed = false, certified = false;
  double error = 0.0;    // midpoint of the clearance - target
  bool wrong_sign = false;
  Tristate missed_contact = Tristate::Unknown;
  // Targets >= 0 with an approach direction: how far the pose lies past the exact first contact of
  // its own approach line with the fixed surface (a certified lower bound; 0 when not past); NaN
  // otherwise. A touching or separated pose "on" its first contact has 0 up to its own error; a
  // placement that skipped the first contact (a tunnel, or a later contact reported) has more.
  double past_first_contact = std::numeric_limits<double>::quiet_NaN();
};

struct OffsetValidation {
  bool checked = false;
  std::string file;
  std::size_t faces = 0;
  double band = 0.0;  // certified: every point of the offset lies within [d - band, d + band]
  std::string completeness;  // "complete", "missed N", "unresolved N" (with "(cell budget reached after M cells)"
                             // when the search stopped at its budget), or "" (not checked)
  double seconds = 0.0;
};

struct LevelValidation {
  std::string spec;
  double target = 0.0;
  std::size_t poses = 0, placed = 0, certified = 0, wrong_sign = 0, missed_contact = 0, missed_undecided = 0;
  // Of c - target over placed poses: signed mean and median, p95 and max of |c - target|.
  double error_mean = 0.0, error_median = 0.0, error_p95 = 0.0, error_max = 0.0;
  // Targets >= 0: poses past their exact first contact by more than the tolerance, and the p95
  // and max of that distance.
  std::size_t past_first_contact = 0;
  double past_p95 = 0.0, past_max = 0.0;
  double seconds_per_pose = -1.0;            // the set's own placement, from its poseset.json (-1: unknown)
  double reference_seconds_per_pose = -1.0;  // the reference's certified placement
  double certify_seconds_per_pose = 0.0;     // this validation's certificate
  OffsetValidation offset;
};

struct ValidateResult {
  std::string pipeline;  // poseset.json "pipeline", or "certified" / "certify" / "unknown"
  Interval max_penetration;  // certified, of the fixed mesh
  double diagonal = 0.0, tolerance = 0.0, voxel = 0.0;  // voxel: 0 when the set has no grid
  std::vector<PoseValidation> poses;
  std::vector<LevelValidation> levels;
  double seconds_certify = 0.0, seconds_sweeps = 0.0, seconds_offsets = 0.0, seconds_total = 0.0;
  nlohmann::json json;  // as written to validation.json
};

// Writes out/validation.csv and out/validation.json (atomically). InputError for unreadable
// bundles or a reference made from other meshes.
ValidateResult run_validate(const ValidateRequest& request);

// gnuplot data and script for the plots (error distribution per level; error against the voxel
// size when several validations are given): writes dir/plot.gp and its data files; the caller runs
// gnuplot. `runs` are validations of pose sets of one mesh.
void write_validation_plots(const std::string& dir, const std::vector<ValidateResult>& runs,
                            const std::vector<std::string>& names);

}  // namespace cdbench
