#pragma once
// Reading and validating a mesh for a subcommand, with timings.
#include <string>

#include "mesh/validate_mesh.h"
#include "offset/offset_set.h"

namespace cdbench::cli {

struct LoadedMesh {
  std::string path;
  ValidatedMesh validated;
  double seconds_read = 0.0, seconds_validate = 0.0;
};

// The mesh as the library's offset sets record it.
inline MeshSource mesh_source(const LoadedMesh& loaded) {
  return {loaded.path, &loaded.validated.mesh, loaded.seconds_read, loaded.seconds_validate};
}

// Throws InputError when the file cannot be read as a mesh (not when it is an invalid solid).
LoadedMesh load_mesh(const std::string& path, const ValidateOptions& options = {});

// For commands that need a closed solid: true if the mesh is one; otherwise lists its problems
// on stderr, says how to repair it, and returns false (the caller exits with kExitInvalidMesh).
bool report_if_not_solid(const LoadedMesh& loaded);

}  // namespace cdbench::cli
