#include "offset/refine_offset.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <tbb/parallel_for.h>

namespace cdbench {

RefinedMesh refine_faces(const TriangleMesh& mesh, const std::vector<char>& wide, const PlaceEdgeVertex& place) {
  const std::size_t n = mesh.faces.size();
  // Edge ids in order of first appearance (deterministic).
  std::unordered_map<std::uint64_t, std::uint32_t> edge_id;
  edge_id.reserve(2 * n);
  std::vector<std::array<std::uint32_t, 3>> face_edges(n);
  std::vector<std::array<std::uint32_t, 2>> edges;
  for (std::size_t f = 0; f < n; ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % 3];
      const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
      const auto [it, inserted] = edge_id.emplace(key, static_cast<std::uint32_t>(edges.size()));
      if (inserted) edges.push_back({a, b});
      face_edges[f][k] = it->second;
    }
  std::vector<char> split(edges.size(), 0);
  for (std::size_t f = 0; f < n; ++f)
    if (f < wide.size() && wide[f])
      for (int k = 0; k < 3; ++k) split[face_edges[f][k]] = 1;
  // Closure: a face with two split edges would need a non-conforming split; split its third too.
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t f = 0; f < n; ++f) {
      const auto& e = face_edges[f];
      if (split[e[0]] + split[e[1]] + split[e[2]] == 2) {
        for (int k = 0; k < 3; ++k) split[e[k]] = 1;
        changed = true;
      }
    }
  }
  RefinedMesh out;
  out.mesh.vertices = mesh.vertices;
  std::vector<std::uint32_t> mid(edges.size(), 0);
  std::vector<std::uint32_t> to_split;
  for (std::uint32_t e = 0; e < edges.size(); ++e)
    if (split[e]) {
      mid[e] = static_cast<std::uint32_t>(mesh.vertices.size() + to_split.size());
      to_split.push_back(e);
    }
  out.split_edges = to_split.size();
  // Each split edge's normal: the sum of its faces' unit normals (the placement's search direction).
  std::vector<Vec3> edge_normal(edges.size(), Vec3::Zero());
  for (std::size_t f = 0; f < n; ++f) {
    const auto& e = face_edges[f];
    if (!(split[e[0]] || split[e[1]] || split[e[2]])) continue;
    const Face& v = mesh.faces[f];
    const Vec3 c = (mesh.vertices[v[1]] - mesh.vertices[v[0]]).cross(mesh.vertices[v[2]] - mesh.vertices[v[0]]);
    const double len = c.norm();
    if (!(len > 0.0) || !std::isfinite(len)) continue;
    for (int k = 0; k < 3; ++k)
      if (split[e[k]]) edge_normal[e[k]] += c / len;
  }
  out.first_new_vertex = mesh.vertices.size();
  for (std::uint32_t e : to_split) {
    out.new_vertex_edge.push_back(edges[e]);
    out.new_vertex_normal.push_back(edge_normal[e]);
  }
  out.mesh.vertices.resize(mesh.vertices.size() + to_split.size());
  // Placing a vertex may cost a few dozen distance queries: in parallel, each into its own slot.
  tbb::parallel_for(std::size_t{0}, to_split.size(), [&](std::size_t k) {
    const auto& ab = out.new_vertex_edge[k];
    out.mesh.vertices[out.first_new_vertex + k] = place(mesh.vertices[ab[0]], mesh.vertices[ab[1]], out.new_vertex_normal[k]);
  });
  auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, bool fresh, std::size_t from) {
    out.mesh.faces.push_back({a, b, c});
    out.is_new.push_back(fresh ? 1 : 0);
    out.kept_from.push_back(from);
  };
  for (std::size_t f = 0; f < n; ++f) {
    const Face& v = mesh.faces[f];
    const auto& e = face_edges[f];  // e[k] joins v[k] and v[k + 1]
    const int count = split[e[0]] + split[e[1]] + split[e[2]];
    if (count == 0) {
      add(v[0], v[1], v[2], false, f);
    } else if (count == 3) {
      const std::uint32_t m0 = mid[e[0]], m1 = mid[e[1]], m2 = mid[e[2]];
      add(v[0], m0, m2, true, f);
      add(m0, v[1], m1, true, f);
      add(m2, m1, v[2], true, f);
      add(m0, m1, m2, true, f);
    } else {  // one split edge, k: (v[k], v[k+1]) with the opposite corner v[k+2]
      int k = 0;
      while (!split[e[k]]) ++k;
      const std::uint32_t m = mid[e[k]], a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
      add(a, m, c, true, f);
      add(m, b, c, true, f);
    }
  }
  return out;
}

}  // namespace cdbench
