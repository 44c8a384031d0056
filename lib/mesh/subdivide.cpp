// CGAL's subdivision lives in this translation unit only.
#include "mesh/subdivide.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>

#include "util/error.h"

namespace cdbench {

TriangleMesh loop_subdivide(const TriangleMesh& mesh, int steps) {
  using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
  using SurfaceMesh = CGAL::Surface_mesh<Point>;
  if (steps < 0) throw InputError("subdivide: the number of steps must be >= 0");
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> vertex;
  vertex.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) vertex.push_back(sm.add_vertex(Point(p.x(), p.y(), p.z())));
  for (const Face& f : mesh.faces)
    if (sm.add_face(vertex[f[0]], vertex[f[1]], vertex[f[2]]) == SurfaceMesh::null_face())
      throw InputError("subdivide: the mesh is not a 2-manifold (a face could not be added)");
  if (!CGAL::is_closed(sm)) throw InputError("subdivide: the mesh is not closed");
  CGAL::Subdivision_method_3::Loop_subdivision(sm, CGAL::parameters::number_of_iterations(steps));
  TriangleMesh out;
  std::vector<std::uint32_t> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), 0);
  out.vertices.reserve(sm.number_of_vertices());
  for (auto v : sm.vertices()) {
    index[v] = static_cast<std::uint32_t>(out.vertices.size());
    const Point& p = sm.point(v);
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  out.faces.reserve(sm.number_of_faces());
  for (auto f : sm.faces()) {
    Face tri{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) tri[k++] = index[v];
    out.faces.push_back(tri);
  }
  return out;
}

}  // namespace cdbench
