#include "poseset/merge_shards.h"

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <optional>
#include <set>

#include "poseset/level_summary.h"
#include "poseset/pose_csv.h"
#include "poseset/poseset_manifest.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/json_keys.h"

namespace cdbench {
namespace {

// The run a shard belongs to: its run key without the shard.
nlohmann::json run_of(nlohmann::json key) {
  key.erase("shard");
  return key;
}

std::uint64_t shard_field(const nlohmann::json& ps, const char* key) { return ps["shard"][key].get<std::uint64_t>(); }

}  // namespace

MergeResult merge_poseset_shards(const std::vector<std::string>& inputs, const std::string& out) {
  if (inputs.empty()) throw InputError("merge: no shard directories given");
  std::vector<nlohmann::json> sets;
  for (const std::string& dir : inputs) {
    nlohmann::json ps = read_poseset_manifest(dir).json;  // checks the format and the core keys
    const nlohmann::json& shard = ps.value("shard", nlohmann::json());
    if (!ps.contains("run_key") || !shard.is_object() || !shard.value("count", nlohmann::json()).is_number_unsigned() ||
        !shard.value("index", nlohmann::json()).is_number_unsigned())
      throw InputError(dir + "/poseset.json: not a shard of cdbench poses (no run_key or shard index and count)");
    sets.push_back(std::move(ps));
  }
  // Same run, shards covering it once each, same offsets.
  const nlohmann::json run = run_of(sets[0]["run_key"]);
  const std::uint64_t count = shard_field(sets[0], "count");
  const auto offsets_of = [](const std::string& dir) {
    return parse_json_file(dir + "/offsets/manifest.json", "not a pose-set directory?")["levels"].dump();
  };
  const std::string offsets = offsets_of(inputs[0]);
  std::set<std::uint64_t> seen;
  for (std::size_t i = 0; i < sets.size(); ++i) {
    if (run_of(sets[i]["run_key"]) != run)
      throw InputError(inputs[i] + ": a shard of a different run (inputs or options differ from " + inputs[0] + ")");
    if (shard_field(sets[i], "count") != count) throw InputError(inputs[i] + ": shard count differs from " + inputs[0]);
    if (!seen.insert(shard_field(sets[i], "index")).second)
      throw InputError(inputs[i] + ": shard " + sets[i]["shard"]["index"].dump() + " given twice");
    if (offsets_of(inputs[i]) != offsets) throw InputError(inputs[i] + ": its offsets differ from those of " + inputs[0]);
  }
  if (seen.size() != count) {
    std::string missing;
    for (std::uint64_t k = 0; k < count; ++k)
      if (!seen.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
    throw InputError("missing shard(s) " + missing + " of " + std::to_string(count));
  }
  // Rows, in pose order (each line kept byte for byte).
  std::map<std::uint64_t, std::string> lines;
  std::vector<PoseRow> rows;
  for (const std::string& dir : inputs) {
    const std::string path = dir + "/poses.csv";
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot be read");
    std::string line;
    std::getline(in, line);
    if (line != kPoseCsvHeader) throw InputError(path + ": unexpected header");
    std::size_t n = 1;
    while (std::getline(in, line)) {
      ++n;
      const PoseRow r = parse_pose_row(line, path + ":" + std::to_string(n));
      if (!lines.emplace(r.pose, line + "\n").second)
        throw InputError(path + ":" + std::to_string(n) + ": pose " + std::to_string(r.pose) + " appears in two shards");
      rows.push_back(r);
    }
  }
  const std::uint64_t approaches = run["directions"].get<std::uint64_t>() * run["orientations"].get<std::uint64_t>();
  const std::size_t levels = sets[0]["levels"].size();
  if (lines.size() != approaches * levels)
    throw InputError("the shards hold " + std::to_string(lines.size()) + " poses, the run has " +
                     std::to_string(approaches * levels));

  prepare_output_directory(out + "/offsets");
  const std::filesystem::path src = std::filesystem::path(inputs[0]) / "offsets";
  if (std::filesystem::weakly_canonical(src) != std::filesystem::weakly_canonical(std::filesystem::path(out) / "offsets"))
    for (const auto& entry : std::filesystem::directory_iterator(src)) {
      write_file_atomically(out + "/offsets/" + entry.path().filename().string(), [&](std::ostream& o) {
        std::ifstream in(entry.path(), std::ios::binary);
        o << in.rdbuf();
      });
    }
  write_file_atomically(out + "/poses.csv", [&](std::ostream& o) {
    o << kPoseCsvHeader << "\n";
    for (const auto& [pose, line] : lines) o << line;
  });
  // poses.csv is in place: an interrupt before poseset.json is removes it.
  std::optional<RemovedIfInterrupted> pair(std::in_place, out + "/poses.csv");

  MergeResult result;
  nlohmann::json& ps = result.poseset = sets[0];
  const std::vector<LevelSummary> summary =
      summarize_levels(rows, levels, ps["certification"]["tolerance"].get<double>());
  for (std::size_t l = 0; l < summary.size(); ++l) set_level_counts(ps["levels"][l], summary[l]);
  ps["shard"] = {{"index", 0}, {"count", 1}, {"first_approach", 0}, {"end_approach", approaches}};
  ps["run_key"]["shard"] = "0/1";
  ps["merged_from"] = inputs;
  double poses_seconds = 0.0, computed = 0.0;
  for (const auto& s : sets) {
    poses_seconds += s["timings"]["poses"].get<double>();
    computed += s["timings"]["poses_computed"].get<double>();
  }
  ps["timings"] = {{"poses", poses_seconds},
                   {"poses_computed", computed},
                   {"poses_per_second", poses_seconds > 0 ? computed / poses_seconds : 0.0},
                   {"note", "sums over the shards"}};
  write_file_atomically(out + "/poseset.json", [&](std::ostream& o) { o << std::setw(2) << ps << "\n"; });
  pair.reset();
  result.shards = sets.size();
  result.poses = lines.size();
  result.diagonal = ps["certification"]["diagonal"].get<double>();
  return result;
}

}  // namespace cdbench
