// Mesh intake, every format: structural pre-check, read (our OBJ/STL readers, CGAL's OFF/PLY
// behind the pre-check), then validation (welding, triangulation, manifoldness, exact
// self-intersections, orientation, coordinate range). First byte: the format.
#include "fuzz_support.h"
#include "mesh/read_mesh.h"
#include "mesh/validate_mesh.h"
#include "util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kNames[] = {"fuzz.off", "fuzz.obj", "fuzz.ply", "fuzz.stl"};
  const std::string name = kNames[data[0] % 4];
  try {
    const cdbench::PolygonSoup soup = cdbench::read_polygon_soup_from_bytes(cdbench::fuzz::payload(data, size), name);
    const cdbench::ValidatedMesh v = cdbench::validate_mesh(soup);
    // A valid result must be what validation promises: a closed mesh with indices in range.
    if (v.report.valid()) {
      for (const auto& f : v.mesh.faces)
        for (int c = 0; c < 3; ++c)
          if (static_cast<std::size_t>(f[c]) >= v.mesh.vertices.size()) std::abort();
      if (!v.report.closed) std::abort();
    }
  } catch (const cdbench::InputError&) {
  }
  return 0;
}
