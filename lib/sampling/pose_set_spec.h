#pragma once
// What a pose set asks for, whichever pipeline places its poses (the certified one,
// poseset/build_poseset.h; the paper's float one, floatpipe/float_poseset.h): the meshes, the
// levels, the approaches' sampling (sampling.h) and the output directory. Each pipeline's request
// adds its own options to it.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/mesh_source.h"

namespace cdbench {

struct PoseSetSpec {
  MeshSource fixed;  // a valid closed solid
  MeshSource mover;  // empty path: the fixed mesh is the mover
  std::string levels, out;
  std::size_t directions = 100, orientations = 10;
  std::string direction_sampling = "fibonacci", orientation_sampling = "super-fibonacci";
  std::uint64_t seed = 1;
  std::string command_line;  // recorded in poseset.json
};

}  // namespace cdbench
