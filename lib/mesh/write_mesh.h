#pragma once
#include <ostream>
#include <string>

#include "core/triangle_mesh.h"

namespace cdbench {

// OFF with 17 significant digits: reading it back gives the same doubles.
void write_off(const TriangleMesh& mesh, std::ostream& out);
// Written to a temporary name and renamed, so `path` is never half-written.
void write_off(const TriangleMesh& mesh, const std::string& path);

}  // namespace cdbench
