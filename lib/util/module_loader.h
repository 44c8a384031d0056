#pragma once
// Parts of cdbench built as shared libraries (modules) and loaded on first use, so that a program
// does not pay, at every start, the dynamic linking of the heavy libraries behind them: OpenVDB for
// the float pipeline (floatpipe/grid_module.h), FCL and Bullet for the benchmark's peers
// (collide/peer_module.h). Each module exports one C function returning a struct that begins with a
// ModuleHeader and has a `make` entry; both sides are built together by the same compiler, so C++
// types cross over. CMake: cdbench_loaded_module (lib/CMakeLists.txt).
#include <string>

#include "util/error.h"

namespace cdbench {

struct ModuleHeader {
  int abi;              // the struct's layout version, bumped when it changes
  const char* version;  // the cdbench version the module was built with
};

struct ModuleSearch {
  std::string file;        // the module's file name, e.g. libcdbench_grid_vdb.so
  std::string env;         // a variable that names the module's path: if set, nothing else is tried
  std::string symbol;      // its one exported function: const <struct>* symbol()
  int abi = 0;             // the ModuleHeader::abi expected
  std::string build_path;  // its path in the build tree
  std::string needed_for;  // the error's start, e.g. "the float pipeline needs its OpenVDB module"
};

// Loads the first candidate (the variable's path; else <libdir>/cdbench/ next to the program as
// installed, the configured prefix's, the build tree) whose entry returns a header of the expected
// ABI and of this build's version, and returns that entry's result; the module stays loaded for the
// life of the process. Throws a SetupError that names every candidate and why it was not used.
const ModuleHeader* load_module(const ModuleSearch& search);

// The same, as the module's own struct M (which begins with its ModuleHeader) with a `make` entry.
template <class M>
const M* load_module_as(const ModuleSearch& search) {
  const M* m = reinterpret_cast<const M*>(load_module(search));
  if (!m->make) throw SetupError(search.file + ": a module without its entry");
  return m;
}

}  // namespace cdbench
