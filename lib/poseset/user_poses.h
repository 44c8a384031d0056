#pragma once
// Poses written by any tool, read for `cdbench certify`: a CSV whose header names its columns:
// `pose` (a non-negative integer id, unique) and either the matrix form `r00 ... r22,tx,ty,tz`
// (row-major R, x_world = R x + t) or the quaternion form `qw,qx,qy,qz,tx,ty,tz`; optional
// `target` (a requested signed clearance, copied to the bundle) and `level` (a group index);
// other columns are ignored (listed). Errors name the file, the line and the column.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace cdbench {

struct UserPose {
  std::uint64_t pose = 0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // as certified: the stored matrix, or fl(R(q / |q|))
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double target;     // NaN without a `target` column
  std::int64_t level = -1;  // -1 without a `level` column
  std::size_t line = 0;     // 1-based line in the file
};

enum class RotationForm { Matrix, Quaternion };

struct UserPoseFile {
  std::vector<UserPose> poses;  // in file order
  RotationForm form = RotationForm::Matrix;
  bool has_target = false, has_level = false;
  std::vector<std::string> ignored_columns;
};

// Throws InputError naming the line: a missing or duplicate header column, a wrong column count,
// a non-finite number, a singular R (|det R| <= 1e-12 |r0| |r1| |r2|), a zero quaternion, a
// duplicate pose id, no rows.
UserPoseFile read_user_poses(std::istream& in, const std::string& name);
UserPoseFile read_user_poses_file(const std::string& path);

// R from a quaternion (w, x, y, z), normalized in doubles first; the formula's rounding makes R
// orthonormal only to a few ulps, which does not matter: the stored R is what is certified.
Eigen::Matrix3d rotation_from_quaternion(double w, double x, double y, double z);

}  // namespace cdbench
