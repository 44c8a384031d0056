#include "offset/offset_set.h"

#include "offset/level_list.h"
#include "offset/offset_manifest.h"

#include <tbb/parallel_for.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>

#include "mesh/write_mesh.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/number_format.h"
#include "util/progress.h"
#include "util/sha256.h"
#include "util/timer.h"

#ifndef CDBENCH_VERSION
#define CDBENCH_VERSION "unknown"
#endif

namespace cdbench {
namespace {

std::string file_name(std::size_t index, const std::string& text) {
  std::string s;
  for (char c : text) s += c == '-' ? std::string("m") : c == '%' ? std::string("pct") : c == '.' ? std::string("p") : std::string(1, c);
  std::ostringstream os;
  os << "offset_" << std::setw(2) << std::setfill('0') << index << "_" << s << ".off";
  return os.str();
}

}  // namespace

MaxPenetrationResult timed_max_penetration(const SignedDistance& sdf, double relative_tolerance, double* seconds) {
  MaxPenetrationOptions mpo;
  mpo.relative_tolerance = relative_tolerance;
  Timer t;
  MaxPenetrationResult mp = certified_max_penetration(sdf, mpo);
  *seconds = t.seconds();
  return mp;
}

OffsetSetRequest make_offset_request(const MeshSource& source, const SignedDistance& sdf,
                                     const MaxPenetrationResult& max_penetration, double max_penetration_tolerance,
                                     double seconds_max_penetration, const std::string& input_sha,
                                     const std::string& out_dir) {
  OffsetSetRequest req;
  req.source = source;
  req.sdf = &sdf;
  req.max_penetration = &max_penetration;
  req.max_penetration_tolerance = max_penetration_tolerance;
  req.seconds_max_penetration = seconds_max_penetration;
  req.mesh_path = source.path;
  req.input_sha = input_sha;
  req.out_dir = out_dir;
  return req;
}

OffsetSetResult write_offset_set(const OffsetSetRequest& r) {
  Timer total;
  const SignedDistance& sdf = *r.sdf;
  const MaxPenetrationResult& mp = *r.max_penetration;
  const double diag = sdf.bbox().diagonal();
  // A level too far out to mesh is an error before anything is written.
  for (std::size_t i = 0; i < r.distances.size(); ++i)
    check_offset_level_size(r.names[i], r.distances[i], diag, r.options.radius_relative);
  prepare_output_directory(r.out_dir);
  OffsetOptions oo = r.options;
  std::mutex log_mutex;
  if (r.verbose)
    oo.log = [&](const std::string& line) {
      std::lock_guard<std::mutex> lock(log_mutex);
      std::cerr << r.log_prefix << line << std::endl;
    };
  std::ostringstream option_key;
  option_key << CDBENCH_VERSION << "|" << number_text(oo.tolerance_relative) << "|" << number_text(oo.radius_relative) << "|"
             << number_text(oo.distance_over_tolerance) << "|" << oo.max_attempts << "|" << oo.seeds << "|"
             << number_text(r.max_penetration_tolerance) << (oo.local_repair ? "|repair" : "")
             << (oo.parallel_mesher ? std::string("|") + mesher_name(oo) : std::string());  // the default's key as before

  // Reuse: levels of an earlier run with the same input, level and options, whose file is intact.
  const std::string manifest_path = r.out_dir + "/manifest.json";
  const PreviousOffsets previous = read_offset_manifest(manifest_path);
  if (!previous.ignored_because.empty())
    std::cerr << "cdbench: note: not reusing any level of " << manifest_path << ": " << previous.ignored_because << "\n";

  nlohmann::json head;
  head["format"] = "cdbench-offsets";
  head["format_version"] = 1;
  head["generator"] = std::string("cdbench ") + CDBENCH_VERSION;
  head["input"] = {{"path", r.mesh_path},
                   {"sha256", r.input_sha},
                   {"vertices", r.source.mesh->vertices.size()},
                   {"faces", r.source.mesh->faces.size()},
                   {"diagonal", diag}};
  head["max_penetration"] = {{"interval", {mp.depth.lo, mp.depth.hi}},
                             {"point", {mp.point.x(), mp.point.y(), mp.point.z()}},
                             {"relative_tolerance", r.max_penetration_tolerance}};
  head["options"] = {{"tolerance_relative", oo.tolerance_relative},
                     {"tolerance", oo.tolerance_relative * diag},
                     {"mesher_radius_relative", oo.radius_relative},
                     {"mesher_distance_over_tolerance", oo.distance_over_tolerance},
                     {"max_attempts", oo.max_attempts},
                     {"local_repair", oo.local_repair},
                     {"seeds", oo.seeds},
                     {"mesher", mesher_name(oo)}};
  // The manifest is rewritten after each computed level (levels done so far, "finished": false), so
  // that an interrupted run's levels are reused by the next one; the last write has them all.
  std::mutex manifest_mutex;
  const auto manifest_of = [&](const std::vector<nlohmann::json>& done, bool finished) {
    nlohmann::json m = head;
    m["finished"] = finished;
    m["levels"] = nlohmann::json::array();
    for (nlohmann::json e : done) {
      if (e.is_null()) continue;
      e.erase("seconds");  // timings vary between runs: kept out of the manifest
      m["levels"].push_back(e);
    }
    return m;
  };
  const std::size_t n = r.distances.size();
  std::vector<nlohmann::json> entries(n);
  std::vector<OffsetSetLevel> typed(n);
  const auto key_of = [&](std::size_t i) { return r.input_sha + "|" + number_text(r.distances[i]) + "|" + option_key.str(); };
  // Reused levels first (sequentially: hashing files), so that every partial manifest lists them.
  for (std::size_t i = 0; i < n; ++i) {
    const auto old = previous.by_key.find(key_of(i));
    if (old == previous.by_key.end()) continue;
    const OffsetManifestEntry& e = old->second;
    const std::string file = e.file ? r.out_dir + "/" + *e.file : std::string();
    if (!e.file || (std::filesystem::is_regular_file(file) && sha256_file(file) == *e.sha256)) {
      entries[i] = e.json;
      entries[i]["level"] = r.names[i];
      typed[i] = {e.status, e.file.value_or(std::string()), e.epsilon, e.faces, true, 0.0};
    }
  }
  Progress progress("offset levels", n);
  // One level can mesh for minutes: the line names the levels in work and keeps its pace.
  progress.start_heartbeat();
  std::vector<char> running(n, 0);
  const auto mark_running = [&](std::size_t i, bool on) {
    std::lock_guard<std::mutex> lock(manifest_mutex);
    running[i] = on;
    std::string detail;
    for (std::size_t k = 0; k < n; ++k)
      if (running[k]) detail += (detail.empty() ? "(computing " : ", ") + r.names[k];
    progress.set_detail(detail.empty() ? detail : detail + ")");
  };
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    if (typed[i].reused) {
      progress.advance();
      return;
    }
    Timer t_level;
    const double d = r.distances[i];
    const std::string key = key_of(i);
    const std::string name = file_name(i, r.names[i]);
    mark_running(i, true);
    const OffsetLevel level = compute_offset_level(sdf, mp, d, oo);
    mark_running(i, false);
    nlohmann::json e;
    e["level"] = r.names[i];
    e["key"] = key;
    e["d"] = d;
    e["fraction_of_max_penetration"] = d / mp.depth.lo;
    e["status"] = to_string(level.status);
    e["message"] = level.message;
    e["epsilon"] = level.epsilon;
    e["epsilon_over_diagonal"] = level.epsilon / diag;
    e["complete"] = level.complete;
    e["attempts"] = level.attempts;
    e["local_repairs"] = level.repairs;
    e["mesher_distance_bound"] = level.distance_bound;
    e["file"] = nullptr;
    e["sha256"] = nullptr;
    if (level.status == OffsetStatus::Certified) {
      std::ostringstream os;
      write_off(level.mesh, os);
      const std::string bytes = os.str();
      write_file_atomically(r.out_dir + "/" + name, [&](std::ostream& out) { out << bytes; });
      e["file"] = name;
      e["sha256"] = sha256_hex(bytes);
      e["vertices"] = level.mesh.vertices.size();
      e["faces"] = level.mesh.faces.size();
      e["genus"] = level.report.genus;
      e["components"] = level.report.components;
    } else {
      e["vertices"] = 0;
      e["faces"] = 0;
    }
    e["seconds"] = {{"mesh", level.seconds_mesh}, {"band", level.seconds_band},
                    {"completeness", level.seconds_completeness}};
    typed[i] = {level.status, level.status == OffsetStatus::Certified ? name : std::string(), level.epsilon,
                level.status == OffsetStatus::Certified ? level.mesh.faces.size() : 0, false, t_level.seconds()};
    {
      std::lock_guard<std::mutex> lock(manifest_mutex);
      entries[i] = e;
      const nlohmann::json partial = manifest_of(entries, false);
      write_file_atomically(manifest_path, [&](std::ostream& out) { out << std::setw(2) << partial << "\n"; });
    }
    progress.advance();
  });
  progress.finish();

  nlohmann::json timings;
  timings["max_penetration"] = r.seconds_max_penetration;
  timings["read"] = r.source.seconds_read;
  timings["validate"] = r.source.seconds_validate;
  for (std::size_t i = 0; i < n; ++i)
    timings["levels"].push_back({{"level", r.names[i]}, {"reused", typed[i].reused}, {"seconds", typed[i].seconds},
                                 {"detail", entries[i].contains("seconds") ? entries[i]["seconds"] : nlohmann::json()}});
  const nlohmann::json manifest = manifest_of(entries, true);
  timings["total"] = total.seconds() + r.seconds_max_penetration;
  write_file_atomically(manifest_path, [&](std::ostream& out) { out << std::setw(2) << manifest << "\n"; });
  write_file_atomically(r.out_dir + "/timings.json", [&](std::ostream& out) { out << std::setw(2) << timings << "\n"; });

  OffsetSetResult result;
  result.manifest = manifest;
  result.levels = std::move(typed);
  return result;
}

}  // namespace cdbench
