#pragma once
// A mesh as a command read it, for the manifests and timings of what it builds (offset sets, pose
// sets): its path, the validated closed solid and what reading and validating it cost.
#include <string>

#include "core/triangle_mesh.h"

namespace cdbench {

struct MeshSource {
  std::string path;
  const TriangleMesh* mesh = nullptr;  // the validated closed solid
  double seconds_read = 0.0, seconds_validate = 0.0;
};

}  // namespace cdbench
