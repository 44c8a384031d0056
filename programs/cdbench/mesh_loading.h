#pragma once
// Reading and validating a mesh for a subcommand, with timings.
#include <string>

#include "mesh/validate_mesh.h"

namespace cdbench::cli {

struct LoadedMesh {
  std::string path;
  ValidatedMesh validated;
  double seconds_read = 0.0, seconds_validate = 0.0;
};

// Throws InputError when the file cannot be read as a mesh (not when it is an invalid solid).
LoadedMesh load_mesh(const std::string& path, const ValidateOptions& options = {});

}  // namespace cdbench::cli
