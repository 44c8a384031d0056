// CGAL's subdivision lives in this translation unit only.
#include "mesh/subdivide.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>

#include "mesh/cgal_surface_mesh.h"
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
  return triangle_mesh_from(sm);
}

}  // namespace cdbench
