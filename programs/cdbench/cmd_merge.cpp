// cdbench merge DIR... -o DIR: join the shards of one pose set (cdbench poses --shard I/N).
#include <iostream>
#include <memory>

#include "commands.h"
#include "poseset/merge_shards.h"
#include "poseset_summary.h"
#include "util/interrupt.h"

namespace cdbench::cli {
namespace {

struct MergeCliOptions {
  std::vector<std::string> inputs;
  std::string out;
};

int run_merge(const MergeCliOptions& opt) {
  const MergeResult r = merge_poseset_shards(opt.inputs, opt.out);
  mark_outputs_complete();  // both files in place: a later interrupt must not report a failure
  std::cout << "merged " << r.shards << " shard(s), " << r.poses << " poses, into " << opt.out << "\n";
  print_level_table(std::cout, r.poseset, r.diagonal);
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
