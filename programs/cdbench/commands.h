#pragma once
#include <CLI/CLI.hpp>

namespace cdbench::cli {

// Exit codes shared by all subcommands.
constexpr int kExitOk = 0;
constexpr int kExitInvalidMesh = 1;  // the input was read but is not a usable closed solid
constexpr int kExitBadInput = 2;     // unreadable or malformed file, bad option
constexpr int kExitInternal = 3;

// Each registers its subcommand; the callback stores the exit code in `exit_code`.
void register_check(CLI::App& app, int& exit_code);
void register_wrap(CLI::App& app, int& exit_code);
void register_repair(CLI::App& app, int& exit_code);
void register_offset(CLI::App& app, int& exit_code);
void register_poses(CLI::App& app, int& exit_code, const std::string& command_line);
void register_merge(CLI::App& app, int& exit_code);
void register_bench(CLI::App& app, int& exit_code);
void register_certify(CLI::App& app, int& exit_code, const std::string& command_line);
void register_score(CLI::App& app, int& exit_code);
void register_plot(CLI::App& app, int& exit_code);
void register_subdivide(CLI::App& app, int& exit_code);
void register_validate(CLI::App& app, int& exit_code);

}  // namespace cdbench::cli
