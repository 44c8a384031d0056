#pragma once
// Reading and validating a mesh for a subcommand, with timings.
#include <string>

#include "core/mesh_source.h"
#include "mesh/validate_mesh.h"

namespace cdbench::cli {

struct LoadedMesh {
  std::string path;
  ValidatedMesh validated;
  double seconds_read = 0.0, seconds_validate = 0.0;
};

// The mesh as the library's offset and pose sets record it.
inline MeshSource mesh_source(const LoadedMesh& loaded) {
  return {loaded.path, &loaded.validated.mesh, loaded.seconds_read, loaded.seconds_validate};
}

// Throws InputError when the file cannot be read as a mesh (not when it is an invalid solid).
LoadedMesh load_mesh(const std::string& path, const ValidateOptions& options = {});

// For commands that need a closed solid: true if the mesh is one; otherwise lists its problems
// on stderr, says how to repair it, and returns false (the caller exits with kExitInvalidMesh).
bool report_if_not_solid(const LoadedMesh& loaded);

// The fixed mesh and, when mover_path is not empty, the mover: both must be closed solids (false
// when one is not; its problems are printed).
bool load_solids(const std::string& fixed_path, const std::string& mover_path, LoadedMesh* fixed, LoadedMesh* mover);

}  // namespace cdbench::cli
