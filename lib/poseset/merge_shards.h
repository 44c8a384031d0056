#pragma once
// The shards of one pose set (cdbench poses --shard I/N, all N of them) joined into one bundle
// (`cdbench merge`): its poses.csv is byte-identical to that of a single unsharded run, its
// poseset.json that of shard 0 with the per-level counts of all rows, timings summed and the
// shard set to 0/1 (doc/poses.md, "Determinism, shards, resume").
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace cdbench {

struct MergeResult {
  std::size_t shards = 0, poses = 0;
  nlohmann::json poseset;  // as written to out/poseset.json
  double diagonal = 0.0;   // the fixed mesh's (for the printed table)
};

// InputError, before anything is written, naming the directory and what is wrong: not a shard
// of `cdbench poses`, shards of different runs (inputs or options) or with different offsets, a
// shard given twice or missing, a pose in two shards, a row count that is not the run's. The
// outputs are written under temporary names and renamed; an interrupt between the renames of
// poses.csv and poseset.json removes the new poses.csv (util/atomic_file.h).
MergeResult merge_poseset_shards(const std::vector<std::string>& shard_dirs, const std::string& out);

}  // namespace cdbench
