#include "poseset/poseset_manifest.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include "util/error.h"
#include "util/json_keys.h"
#include "util/sha256.h"

namespace cdbench {

nlohmann::json to_json(const MeshRecord& m) {
  return {{"path", m.path},
          {"sha256", m.sha256},
          {"vertices", m.vertices},
          {"faces", m.faces},
          {"diagonal", m.diagonal},
          {"reference_point", {m.reference_point.x(), m.reference_point.y(), m.reference_point.z()}}};
}

MeshRecord mesh_record(const std::string& path, const std::string& sha256, const TriangleMesh& mesh,
                       const Eigen::Vector3d& reference_point) {
  MeshRecord r;
  r.path = path;
  r.sha256 = sha256;
  r.vertices = mesh.vertices.size();
  r.faces = mesh.faces.size();
  r.diagonal = mesh.bbox().diagonal();
  r.reference_point = reference_point;
  return r;
}

namespace {

MeshRecord mesh_record(const JsonKeys& k, const nlohmann::json& j, const std::string& key) {
  const nlohmann::json& m = k.at(j, key, "");
  MeshRecord r;
  r.path = k.text(m, "path", key + ".");
  r.sha256 = k.text(m, "sha256", key + ".");
  r.vertices = static_cast<std::size_t>(k.count(m, "vertices", key + "."));
  r.faces = static_cast<std::size_t>(k.count(m, "faces", key + "."));
  r.diagonal = k.number(m, "diagonal", key + ".");
  return r;
}

}  // namespace

PoseSetManifest read_poseset_manifest(const std::string& dir) {
  const std::string file = dir + "/poseset.json";
  PoseSetManifest m;
  m.dir = dir;
  m.json = parse_json_file(file, "not a pose-set directory? cdbench poses and certify write one");
  const JsonKeys k(file);
  const auto format = m.json.is_object() ? m.json.find("format") : m.json.end();
  if (!m.json.is_object() || format == m.json.end() || *format != "cdbench-poseset")
    throw InputError(file + ": not a cdbench pose set (format is not cdbench-poseset)");
  if (k.number(m.json, "format_version", "") != 1.0) throw InputError(file + ": format_version is not 1");
  m.fixed = mesh_record(k, m.json, "fixed");
  m.mover = mesh_record(k, m.json, "mover");
  m.mover_is_fixed = k.boolean(m.json, "mover_is_fixed", "");
  const nlohmann::json& mp = k.at(k.at(m.json, "max_penetration", ""), "interval", "max_penetration.");
  if (!mp.is_array() || mp.size() != 2 || !mp[0].is_number() || !mp[1].is_number())
    throw InputError(file + ": key 'max_penetration.interval' is not a pair of numbers");
  m.max_penetration_lo = mp[0].get<double>();
  m.max_penetration_hi = mp[1].get<double>();
  if (!(std::isfinite(m.max_penetration_lo) && std::isfinite(m.max_penetration_hi) && 0.0 <= m.max_penetration_lo &&
        m.max_penetration_lo <= m.max_penetration_hi))
    throw InputError(file + ": key 'max_penetration.interval' is not an interval of finite numbers >= 0");
  const nlohmann::json& levels = k.at(m.json, "levels", "");
  if (!levels.is_array() || levels.empty()) throw InputError(file + ": key 'levels' is not a non-empty list");
  for (std::size_t l = 0; l < levels.size(); ++l) {
    const std::string path = "levels[" + std::to_string(l) + "].";
    LevelRecord r;
    r.spec = k.text(levels[l], "spec", path);
    r.target = k.number(levels[l], "target", path, true);
    m.levels.push_back(r);
  }
  const nlohmann::json& cert = k.at(m.json, "certification", "");
  m.tolerance = k.number(cert, "tolerance", "certification.");
  m.diagonal = k.number(cert, "diagonal", "certification.");
  if (!(m.tolerance > 0.0 && std::isfinite(m.tolerance)) || !(m.diagonal > 0.0 && std::isfinite(m.diagonal)))
    throw InputError(file + ": certification.tolerance and certification.diagonal must be finite and > 0");
  return m;
}

std::vector<PoseRow> read_poseset_rows(const PoseSetManifest& m) {
  const std::string file = m.dir + "/poses.csv";
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": cannot be read");
  std::vector<PoseRow> rows = read_pose_csv(in, file);
  for (const PoseRow& r : rows)
    if (r.level < 0 || static_cast<std::size_t>(r.level) >= m.levels.size())
      throw InputError(file + ": pose " + std::to_string(r.pose) + " has level " + std::to_string(r.level) + ", but " +
                       m.dir + "/poseset.json lists " + std::to_string(m.levels.size()) + " levels");
  return rows;
}

std::string locate_mesh(const MeshRecord& mesh, const std::string& poseset_dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::string found;
  std::string looked = "the current directory";
  if (fs::is_regular_file(mesh.path, ec)) {
    found = mesh.path;
  } else if (fs::path(mesh.path).is_relative()) {
    fs::path dir = fs::weakly_canonical(fs::absolute(poseset_dir, ec), ec);
    looked += ", " + dir.string() + " and its parent directories";
    for (; found.empty(); dir = dir.parent_path()) {
      const fs::path candidate = dir / mesh.path;
      if (fs::is_regular_file(candidate, ec)) found = candidate.string();
      if (dir == dir.parent_path()) break;
    }
  }
  if (found.empty())
    throw InputError(poseset_dir + ": mesh " + mesh.path + " not found (looked from " + looked +
                     "; a pose set records the path it was made with)");
  if (sha256_file(found) != mesh.sha256)
    throw InputError(found + ": its content differs from the pose set's (SHA-256 mismatch); " + poseset_dir +
                     " was made from another version of it");
  return found;
}

}  // namespace cdbench
