// CGAL's corefinement with the exact kernel lives in this translation unit only.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Surface_mesh.h>

#include "mesh/cgal_surface_mesh.h"
#include "mesh/repair.h"

namespace cdbench {

bool exact_union(const std::vector<TriangleMesh>& parts, TriangleMesh& out, std::string& reason) {
  using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
  using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
  namespace PMP = CGAL::Polygon_mesh_processing;
  const auto to_exact = [](const TriangleMesh& m) {
    Mesh sm;
    std::vector<Mesh::Vertex_index> v;
    v.reserve(m.vertices.size());
    for (const Vec3& p : m.vertices) v.push_back(sm.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z())));
    for (const Face& f : m.faces) sm.add_face(v[f[0]], v[f[1]], v[f[2]]);
    return sm;
  };
  if (parts.empty()) {
    reason = "no parts";
    return false;
  }
  Mesh acc = to_exact(parts[0]);
  try {
    for (std::size_t i = 1; i < parts.size(); ++i) {
      Mesh next = to_exact(parts[i]);
      Mesh result;
      if (!PMP::corefine_and_compute_union(acc, next, result)) {
        reason = "CGAL's corefinement cannot make a 2-manifold union when part " + std::to_string(i) +
                 " is added (parts touching along an edge or at a vertex only?)";
        return false;
      }
      acc = std::move(result);
    }
  } catch (const std::exception& e) {
    reason = std::string("CGAL's corefinement failed: ") + e.what();
    return false;
  }
  out = triangle_mesh_from(acc);
  return true;
}

}  // namespace cdbench
