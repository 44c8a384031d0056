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

std::vector<std::uint32_t> face_components(const TriangleMesh& mesh, std::size_t* count) {
  UnionFind sets(mesh.vertices.size());
  for (const Face& f : mesh.faces)
    for (int k = 1; k < 3; ++k) sets.unite(f[0], f[k]);
  // Roots are each set's least vertex, so numbering roots in ascending order follows
  // component_representatives.
  constexpr std::uint32_t kUnset = 0xffffffffu;
  std::vector<std::uint32_t> id_of_root(mesh.vertices.size(), kUnset);
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const Face& f : mesh.faces) used[f[0]] = 1;
  std::uint32_t next = 0;
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!used[v]) continue;
    const std::size_t r = sets.find(v);
    if (id_of_root[r] == kUnset) id_of_root[r] = next++;
  }
  std::vector<std::uint32_t> out(mesh.faces.size());
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) out[i] = id_of_root[sets.find(mesh.faces[i][0])];
  if (count) *count = next;
  return out;
}

}  // namespace cdbench
