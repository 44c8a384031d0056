#include "mesh/components.h"

#include "util/union_find.h"

namespace cdbench {

std::vector<std::uint32_t> component_representatives(const TriangleMesh& mesh) {
  UnionFind sets(mesh.vertices.size());
  for (const Face& f : mesh.faces)
    for (int k = 1; k < 3; ++k) sets.unite(f[0], f[k]);
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const Face& f : mesh.faces) used[f[0]] = 1;
  std::vector<std::uint32_t> reps;
  std::vector<char> seen(mesh.vertices.size(), 0);
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!used[v]) continue;
    const std::size_t r = sets.find(v);
    if (!seen[r]) {
      seen[r] = 1;
      reps.push_back(v);
    }
  }
  return reps;
}

}  // namespace cdbench
