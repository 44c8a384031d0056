#pragma once
// Our TriangleMesh from a CGAL::Surface_mesh (vertices in iteration order, triangular faces), for
// the few translation units that run CGAL's mesh algorithms (alpha wrapping, subdivision, the
// offset mesher). Include it only there: CGAL is heavy to compile.
#include <CGAL/boost/graph/iterator.h>

#include <cstdint>
#include <vector>

#include "core/triangle_mesh.h"

namespace cdbench {

template <class SurfaceMesh>
TriangleMesh triangle_mesh_from(const SurfaceMesh& sm) {
  TriangleMesh out;
  std::vector<std::uint32_t> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), 0);
  out.vertices.reserve(sm.number_of_vertices());
  for (auto v : sm.vertices()) {
    index[v] = static_cast<std::uint32_t>(out.vertices.size());
    const auto& p = sm.point(v);
    out.vertices.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  }
  out.faces.reserve(sm.number_of_faces());
  for (auto f : sm.faces()) {
    Face tri{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      if (k < 3) tri[k] = index[v];
      ++k;
    }
    if (k == 3) out.faces.push_back(tri);  // the algorithms above output triangles only
  }
  return out;
}

}  // namespace cdbench
