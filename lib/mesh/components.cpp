#include "mesh/components.h"

#include "util/union_find.h"

namespace cdbench {
namespace {

constexpr std::uint32_t kNone = 0xffffffffu;

// The components' representatives (per set, the least vertex that is some face's first vertex)
// in ascending order into `reps`, and (if `faces` is given) each face's component, numbered in
// that order.
void label_components(const TriangleMesh& mesh, std::vector<std::uint32_t>& reps, std::vector<std::uint32_t>* faces) {
  UnionFind sets(mesh.vertices.size());
  for (const Face& f : mesh.faces)
    for (int k = 1; k < 3; ++k) sets.unite(f[0], f[k]);
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const Face& f : mesh.faces) used[f[0]] = 1;
  std::vector<std::uint32_t> id_of_root(mesh.vertices.size(), kNone);
  reps.clear();
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!used[v]) continue;
    const std::size_t r = sets.find(v);
    if (id_of_root[r] == kNone) {
      id_of_root[r] = static_cast<std::uint32_t>(reps.size());
      reps.push_back(v);
    }
  }
  if (!faces) return;
  faces->resize(mesh.faces.size());
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) (*faces)[i] = id_of_root[sets.find(mesh.faces[i][0])];
}

}  // namespace

std::vector<std::uint32_t> component_representatives(const TriangleMesh& mesh) {
  std::vector<std::uint32_t> reps;
  label_components(mesh, reps, nullptr);
  return reps;
}

std::vector<std::uint32_t> face_components(const TriangleMesh& mesh, std::size_t* count) {
  std::vector<std::uint32_t> reps, faces;
  label_components(mesh, reps, &faces);
  if (count) *count = reps.size();
  return faces;
}

}  // namespace cdbench
