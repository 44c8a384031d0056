#include "poseset/user_poses.h"

#include <Eigen/LU>  // determinant

#include <cmath>
#include <fstream>
#include <limits>
#include <map>

#include "poseset/csv_fields.h"
#include "mesh/validate_mesh.h"  // kMaxCoordinate
#include "util/error.h"
#include "util/number_format.h"

namespace cdbench {

Eigen::Matrix3d rotation_from_quaternion(double w, double x, double y, double z) {
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  w /= n, x /= n, y /= n, z /= n;
  Eigen::Matrix3d R;
  R << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return R;
}

UserPoseFile read_user_poses(std::istream& in, const std::string& name) {
  UserPoseFile file;
  std::string line;
  std::size_t line_no = 0;
  const std::vector<std::string> header = read_csv_header(in, &line_no);
  if (header.empty()) throw InputError(name + ": empty file (expected a header line naming the columns)");
  const std::string header_where = name + ":" + std::to_string(line_no);
  const std::map<std::string, std::size_t> column = csv_columns(header, header_where);
  const auto has = [&](const char* c) { return column.count(c) > 0; };
  static const char* const kMatrix[] = {"r00", "r01", "r02", "r10", "r11", "r12", "r20", "r21", "r22"};
  static const char* const kQuat[] = {"qw", "qx", "qy", "qz"};
  static const char* const kT[] = {"tx", "ty", "tz"};
  bool any_matrix = false, all_matrix = true, any_quat = false, all_quat = true;
  for (const char* c : kMatrix) any_matrix |= has(c), all_matrix &= has(c);
  for (const char* c : kQuat) any_quat |= has(c), all_quat &= has(c);
  const auto missing = [&](const char* const* names, std::size_t n) {
    std::string s;
    for (std::size_t i = 0; i < n; ++i)
      if (!has(names[i])) s += (s.empty() ? "" : ",") + std::string(names[i]);
    return s;
  };
  const std::string expected = " (expected pose, then r00..r22,tx,ty,tz or qw,qx,qy,qz,tx,ty,tz)";
  if (!has("pose")) throw InputError(header_where + ": no 'pose' column" + expected);
  if (any_matrix && any_quat) throw InputError(header_where + ": both a rotation matrix and a quaternion" + expected);
  if (any_matrix && !all_matrix) throw InputError(header_where + ": rotation columns missing: " + missing(kMatrix, 9));
  if (any_quat && !all_quat) throw InputError(header_where + ": quaternion columns missing: " + missing(kQuat, 4));
  if (!any_matrix && !any_quat) throw InputError(header_where + ": no rotation columns" + expected);
  if (!has("tx") || !has("ty") || !has("tz"))
    throw InputError(header_where + ": translation columns missing: " + missing(kT, 3));
  file.form = any_matrix ? RotationForm::Matrix : RotationForm::Quaternion;
  file.has_target = has("target");
  file.has_level = has("level");
  for (const std::string& h : header) {
    bool known = h == "pose" || h == "target" || h == "level";
    for (const char* c : kMatrix) known |= file.form == RotationForm::Matrix && h == c;
    for (const char* c : kQuat) known |= file.form == RotationForm::Quaternion && h == c;
    for (const char* c : kT) known |= h == c;
    if (!known) file.ignored_columns.push_back(h);
  }

  std::map<std::uint64_t, std::size_t> seen;  // pose id -> line
  while (std::getline(in, line)) {
    ++line_no;
    if (is_blank_line(line)) continue;
    const std::string where = name + ":" + std::to_string(line_no);
    const std::vector<std::string> f = split_csv_fields(line);
    if (f.size() != header.size())
      throw InputError(where + ": expected " + std::to_string(header.size()) + " columns (as the header), found " +
                       std::to_string(f.size()));
    const auto num = [&](const char* c) { return parse_finite_field(f[column.at(c)], where, c); };
    UserPose p;
    p.line = line_no;
    p.pose = parse_index_field(f[column.at("pose")], where, "pose");
    const auto [it, fresh] = seen.emplace(p.pose, line_no);
    if (!fresh)
      throw InputError(where + ": pose " + std::to_string(p.pose) + " again (first at line " + std::to_string(it->second) + ")");
    if (file.form == RotationForm::Matrix) {
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) p.R(i, j) = num(kMatrix[3 * i + j]);
      const double scale = p.R.row(0).norm() * p.R.row(1).norm() * p.R.row(2).norm();
      const double det = p.R.determinant();
      if (!(std::abs(det) > 1e-12 * scale))
        throw InputError(where + ": the rotation matrix is singular or nearly so (det = " + std::to_string(det) +
                         "): no rigid or affine placement");
    } else {
      const double w = num("qw"), x = num("qx"), y = num("qy"), z = num("qz");
      const double n2 = w * w + x * x + y * y + z * z;
      if (!(n2 > 1e-200) || !std::isfinite(n2))
        throw InputError(where + ": the quaternion (qw,qx,qy,qz) is zero or out of range: no rotation");
      p.R = rotation_from_quaternion(w, x, y, z);
    }
    p.t = Eigen::Vector3d(num("tx"), num("ty"), num("tz"));
    // The meshes' supported range (validate_mesh.h): far beyond it squared distances overflow and
    // no interval arithmetic holds the clearance (1e155 gave [1.8e308, inf]).
    if (!(p.t.cwiseAbs().maxCoeff() <= kMaxCoordinate))
      throw InputError(where + ": the translation (" + shortest_number_text(p.t.x()) + ", " +
                       shortest_number_text(p.t.y()) + ", " + shortest_number_text(p.t.z()) +
                       ") is outside the supported range |t| <= " + number_text(kMaxCoordinate));
    // An empty target (a pose without one, as in a file mixing both) reads as NaN.
    const bool target_given = file.has_target && !f[column.at("target")].empty();
    p.target = target_given ? parse_double_field(f[column.at("target")], where, "target")
                            : std::numeric_limits<double>::quiet_NaN();
    if (file.has_target && std::isinf(p.target)) throw InputError(where + ": column target is infinite");
    if (file.has_level) {
      const std::uint64_t l = parse_index_field(f[column.at("level")], where, "level");
      if (l > 1000000) throw InputError(where + ": column level is above 1000000");
      p.level = static_cast<std::int64_t>(l);
    }
    file.poses.push_back(p);
  }
  if (file.poses.empty()) throw InputError(name + ": no poses after the header");
  return file;
}

UserPoseFile read_user_poses_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read");
  return read_user_poses(in, path);
}

}  // namespace cdbench
