#pragma once
// The validation programs' main: a bad path or file ends with a message and exit code 2, never an
// uncaught exception.
#include <cstdio>
#include <exception>

template <class Run>
int guarded_main(const char* name, Run run, int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", name, e.what());
    return 2;
  }
}
