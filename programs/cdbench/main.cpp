// cdbench: certified benchmark pose sets for static collision detection.
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include "commands.h"
#include "util/error.h"
#include "util/interrupt.h"

int main(int argc, char** argv) {
  using namespace cdbench::cli;
  CLI::App app{"cdbench " CDBENCH_VERSION
               " - certified benchmark pose sets for static collision detection.\n"
               "Exit codes: 0 success, 1 the mesh is not a valid closed solid, 2 bad input or option, 3 internal error or incomplete installation, "
               "130/143 interrupted (SIGINT/SIGTERM)."};
  cdbench::install_interrupt_handlers(
      "Run the same command with --resume to continue (poses, certify: certified work is journaled); "
      "offset and poses reuse every offset level already written; bench and score start again.");
  app.require_subcommand(1);
  app.set_version_flag("--version", CDBENCH_VERSION);
  int exit_code = kExitOk;
  register_check(app, exit_code);
  register_wrap(app, exit_code);
  register_repair(app, exit_code);
  register_offset(app, exit_code);
  std::string command_line;
  for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);
  register_poses(app, exit_code, command_line);
  register_merge(app, exit_code);
  register_certify(app, exit_code, command_line);
  register_bench(app, exit_code);
  register_score(app, exit_code);
  register_plot(app, exit_code);
  register_subdivide(app, exit_code);
  register_validate(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  } catch (const cdbench::InputError& e) {
    std::cerr << "cdbench: error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const cdbench::SetupError& e) {
    std::cerr << "cdbench: error: " << e.what() << "\n";
    return kExitInternal;
  } catch (const std::bad_alloc&) {
    std::cerr << "cdbench: error: out of memory\n";
    return kExitInternal;
  } catch (const std::exception& e) {
    std::cerr << "cdbench: internal error: " << e.what() << "\n";
    return kExitInternal;
  }
  return exit_code;
}
