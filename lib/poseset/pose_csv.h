#pragma once
// Rows of poses.csv, the pose-set bundle's table (format: doc/pose-set-format.md). Every double is
// written with 17 significant digits, so that it reads back as the same double.
#include <Eigen/Core>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace cdbench {

// The header; the first 21 columns are fixed by the format, the rest are cdbench's extras.
extern const char* const kPoseCsvHeader;
constexpr int kPoseCsvColumns = 27;

// The status column: "certified", or "uncertified:<reason>" with the reasons of
// doc/pose-set-format.md.
enum class PoseStatus {
  Certified,
  NoContact,            // the approach never reaches the target (no pose)
  OffsetEmpty,          // the level lies deeper than the max penetration (no pose)
  OffsetFailed,         // the level's offset could not be certified (no pose; without polishing)
  ToleranceNotReached,  // the branch and bound hit its cell limit (rigorous, wider interval)
  PolishStalled,        // not within the tolerance of the target after the step limit
  Float,                // placed by the float pipeline (--pipeline float): no certificate
};
const char* to_string(PoseStatus s);
// InputError naming `where` for any other text.
PoseStatus parse_pose_status(const std::string& text, const std::string& where);

struct PoseRow {
  std::uint64_t pose = 0;       // global index: (orientation * directions + direction) * levels + level
  int level = 0;                // index into poseset.json "levels"
  double target = 0.0;          // requested signed clearance
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();    // x_world = R x + t; NaN when there is no pose
  Eigen::Vector3d dir = Eigen::Vector3d::Zero();  // unit approach direction
  double clearance_lo = 0.0, clearance_hi = 0.0;  // NaN when there is no pose
  PoseStatus status = PoseStatus::Certified;
  // Extras.
  std::uint64_t orientation = 0, direction = 0;
  double raw_clearance_lo = 0.0, raw_clearance_hi = 0.0;  // before polishing
  int polish_steps = 0;
  double lambda = 0.0;          // translation along dir from the reference placement
};

std::string format_pose_row(const PoseRow& row);  // one line, with the final newline
// Throws InputError (naming `where`) on a malformed line.
PoseRow parse_pose_row(const std::string& line, const std::string& where);
// All rows of a poses.csv stream; checks the header.
std::vector<PoseRow> read_pose_csv(std::istream& in, const std::string& name);

}  // namespace cdbench
