#pragma once
// Welding: vertices at the same position become one vertex, so that files which repeat a corner
// per face (textured OBJ/PLY exports split vertices along seams; OFF/PLY soups) describe the
// surface they mean. By default only exactly equal coordinates are merged, which moves nothing.
#include <cstddef>

#include "core/triangle_mesh.h"

namespace cdbench {

struct WeldResult {
  std::size_t vertices_before = 0, vertices_after = 0;
  std::size_t polygons_dropped = 0;  // tolerance welding only: polygons left with fewer than 3 corners
  double max_displacement = 0.0;     // tolerance welding only: farthest a vertex moved (doubles, not certified)
  std::size_t merged() const { return vertices_before - vertices_after; }
};

// tolerance == 0: merges vertices whose coordinates are exactly equal (as doubles; -0 == +0); a
// polygon whose corners thereby repeat is kept as it is (it was degenerate in the file already).
// tolerance > 0: also merges vertices closer than `tolerance` (transitively, so clusters may be
// wider); each cluster moves onto its first vertex; repeated corners are removed from polygons and
// polygons with fewer than 3 corners left are dropped.
// Vertices keep the order of their first occurrence, so a file without duplicates is unchanged.
// Throws InputError if tolerance is negative, not finite, or too small for the coordinates' range.
WeldResult weld_vertices(PolygonSoup& soup, double tolerance = 0.0);

}  // namespace cdbench
