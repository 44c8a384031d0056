#include "poseset/poseset_manifest.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include "util/error.h"
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

namespace {

// A key of the document, with an error naming the file and the key's path when it is missing
// or of the wrong type.
class Keys {
 public:
  explicit Keys(std::string file) : file_(std::move(file)) {}
  const nlohmann::json& at(const nlohmann::json& j, const std::string& key, const std::string& path) const {
    if (!j.is_object() || !j.contains(key)) throw InputError(file_ + ": missing key '" + path + key + "'");
    return j[key];
  }
  double number(const nlohmann::json& j, const std::string& key, const std::string& path, bool null_ok = false) const {
    const nlohmann::json& v = at(j, key, path);
    if (null_ok && v.is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!v.is_number()) throw InputError(file_ + ": key '" + path + key + "' is not a number");
    return v.get<double>();
  }
  std::string text(const nlohmann::json& j, const std::string& key, const std::string& path) const {
    const nlohmann::json& v = at(j, key, path);
    if (!v.is_string()) throw InputError(file_ + ": key '" + path + key + "' is not a string");
    return v.get<std::string>();
  }
  MeshRecord mesh(const nlohmann::json& j, const std::string& key) const {
    const nlohmann::json& m = at(j, key, "");
    MeshRecord r;
    r.path = text(m, "path", key + ".");
    r.sha256 = text(m, "sha256", key + ".");
    r.vertices = static_cast<std::size_t>(number(m, "vertices", key + "."));
    r.faces = static_cast<std::size_t>(number(m, "faces", key + "."));
    r.diagonal = number(m, "diagonal", key + ".");
    return r;
  }

 private:
  std::string file_;
};

}  // namespace

PoseSetManifest read_poseset_manifest(const std::string& dir) {
  const std::string file = dir + "/poseset.json";
  std::ifstream in(file);
  if (!in) throw InputError(file + ": cannot be read (not a pose-set directory? cdbench poses and certify write one)");
  PoseSetManifest m;
  m.dir = dir;
  try {
    m.json = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError(file + ": not valid JSON (" + std::string(e.what()) + ")");
  }
  const Keys k(file);
  if (!m.json.is_object() || m.json.value("format", "") != "cdbench-poseset")
    throw InputError(file + ": not a cdbench pose set (format is not cdbench-poseset)");
  if (k.number(m.json, "format_version", "") != 1.0) throw InputError(file + ": format_version is not 1");
  m.fixed = k.mesh(m.json, "fixed");
  m.mover = k.mesh(m.json, "mover");
  const nlohmann::json& mif = k.at(m.json, "mover_is_fixed", "");
  m.mover_is_fixed = mif.is_boolean() && mif.get<bool>();
  const nlohmann::json& mp = k.at(k.at(m.json, "max_penetration", ""), "interval", "max_penetration.");
  if (!mp.is_array() || mp.size() != 2 || !mp[0].is_number() || !mp[1].is_number())
    throw InputError(file + ": key 'max_penetration.interval' is not a pair of numbers");
  m.max_penetration_lo = mp[0].get<double>();
  m.max_penetration_hi = mp[1].get<double>();
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

void check_mesh_unchanged(const MeshRecord& mesh, const std::string& what) {
  if (!std::filesystem::exists(mesh.path)) throw InputError(what + ": mesh " + mesh.path + " not found");
  if (sha256_file(mesh.path) != mesh.sha256)
    throw InputError(mesh.path + ": its content differs from the pose set's (SHA-256 mismatch); " + what +
                     " was made from another version of it");
}

}  // namespace cdbench
