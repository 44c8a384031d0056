// cdbench merge DIR... -o DIR: join the shards of one pose set (cdbench poses --shard I/N).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "commands.h"
#include "util/json_keys.h"
#include "poseset/pose_csv.h"
#include "poseset/poseset_manifest.h"
#include "poseset_summary.h"
#include "util/atomic_file.h"
#include "util/error.h"

namespace cdbench::cli {
namespace {

struct MergeCliOptions {
  std::vector<std::string> inputs;
  std::string out;
};

nlohmann::json read_json(const std::string& path) { return parse_json_file(path, "not a pose-set directory?"); }

int run_merge(const MergeCliOptions& opt) {
  std::vector<nlohmann::json> sets;
  for (const std::string& dir : opt.inputs) {
    nlohmann::json ps = read_poseset_manifest(dir).json;  // checks the format and the core keys
    const nlohmann::json& shard = ps.value("shard", nlohmann::json());
    if (!ps.contains("run_key") || !shard.is_object() || !shard.value("count", nlohmann::json()).is_number_unsigned() ||
        !shard.value("index", nlohmann::json()).is_number_unsigned())
      throw InputError(dir + "/poseset.json: not a shard of cdbench poses (no run_key or shard index and count)");
    sets.push_back(std::move(ps));
  }
  // Same run, shards covering it once each.
  const auto run_of = [](nlohmann::json key) {
    key.erase("shard");
    return key;
  };
  const nlohmann::json run = run_of(sets[0]["run_key"]);
  const std::uint64_t count = sets[0]["shard"]["count"].get<std::uint64_t>();
  std::set<std::uint64_t> seen;
  for (std::size_t i = 0; i < sets.size(); ++i) {
    if (run_of(sets[i]["run_key"]) != run)
      throw InputError(opt.inputs[i] + ": a shard of a different run (inputs or options differ from " + opt.inputs[0] + ")");
    if (sets[i]["shard"]["count"].get<std::uint64_t>() != count)
      throw InputError(opt.inputs[i] + ": shard count differs from " + opt.inputs[0]);
    if (!seen.insert(sets[i]["shard"]["index"].get<std::uint64_t>()).second)
      throw InputError(opt.inputs[i] + ": shard " + sets[i]["shard"]["index"].dump() + " given twice");
    const std::string offsets_a = read_json(opt.inputs[0] + "/offsets/manifest.json")["levels"].dump();
    const std::string offsets_b = read_json(opt.inputs[i] + "/offsets/manifest.json")["levels"].dump();
    if (offsets_a != offsets_b) throw InputError(opt.inputs[i] + ": its offsets differ from those of " + opt.inputs[0]);
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
  for (const std::string& dir : opt.inputs) {
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
  const std::uint64_t expected = run["directions"].get<std::uint64_t>() * run["orientations"].get<std::uint64_t>() *
                                 sets[0]["levels"].size();
  if (lines.size() != expected)
    throw InputError("the shards hold " + std::to_string(lines.size()) + " poses, the run has " + std::to_string(expected));

  std::error_code ec;
  std::filesystem::create_directories(opt.out + "/offsets", ec);
  if (!std::filesystem::is_directory(opt.out + "/offsets")) throw InputError(opt.out + ": cannot create the output directory");
  const std::filesystem::path src = std::filesystem::path(opt.inputs[0]) / "offsets";
  if (std::filesystem::weakly_canonical(src) != std::filesystem::weakly_canonical(std::filesystem::path(opt.out) / "offsets"))
    for (const auto& entry : std::filesystem::directory_iterator(src)) {
      const std::string target = opt.out + "/offsets/" + entry.path().filename().string();
      write_file_atomically(target, [&](std::ostream& out) {
        std::ifstream in(entry.path(), std::ios::binary);
        out << in.rdbuf();
      });
    }
  write_file_atomically(opt.out + "/poses.csv", [&](std::ostream& out) {
    out << kPoseCsvHeader << "\n";
    for (const auto& [pose, line] : lines) out << line;
  });

  nlohmann::json ps = sets[0];
  const double tol = ps["certification"]["tolerance"].get<double>();
  const std::vector<LevelSummary> summary = summarize_levels(rows, ps["levels"].size(), tol);
  for (std::size_t l = 0; l < summary.size(); ++l) {
    const LevelSummary& x = summary[l];
    auto& e = ps["levels"][l];
    e["poses"] = x.poses;
    e["certified"] = x.certified;
    e["on_target"] = x.on_target;
    e["no_contact"] = x.no_contact;
    e["raw_placement_error"] = {{"max", x.raw_error_max}, {"mean", x.placed() ? x.raw_error_sum / x.placed() : 0.0}};
    e["mean_polish_steps"] = x.placed() ? x.steps_sum / x.placed() : 0.0;
  }
  const std::uint64_t approaches = run["directions"].get<std::uint64_t>() * run["orientations"].get<std::uint64_t>();
  ps["shard"] = {{"index", 0}, {"count", 1}, {"first_approach", 0}, {"end_approach", approaches}};
  ps["run_key"]["shard"] = "0/1";
  ps["merged_from"] = opt.inputs;
  double poses_seconds = 0.0, computed = 0.0;
  for (const auto& s : sets) {
    poses_seconds += s["timings"]["poses"].get<double>();
    computed += s["timings"]["poses_computed"].get<double>();
  }
  ps["timings"] = {{"poses", poses_seconds},
                   {"poses_computed", computed},
                   {"poses_per_second", poses_seconds > 0 ? computed / poses_seconds : 0.0},
                   {"note", "sums over the shards"}};
  write_file_atomically(opt.out + "/poseset.json", [&](std::ostream& out) { out << std::setw(2) << ps << "\n"; });
  std::cout << "merged " << sets.size() << " shard(s), " << lines.size() << " poses, into " << opt.out << "\n";
  print_level_table(std::cout, ps, ps["certification"]["diagonal"].get<double>());
  return kExitOk;
}

}  // namespace

void register_merge(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<MergeCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "merge",
      "Join the shards of one pose set (cdbench poses --shard I/N, all N of them) into one bundle; its poses.csv "
      "is byte-identical to that of a single unsharded run.");
  cmd->add_option("shards", opt->inputs, "the shard directories")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("-o,--output", opt->out, "output directory")->required();
  cmd->callback([opt, &exit_code]() { exit_code = run_merge(*opt); });
}

}  // namespace cdbench::cli
