#pragma once
// Local repair of an offset candidate whose certified band is too wide on a few faces: those faces
// are split 1-to-4 and their neighbours 1-to-2 so that the mesh stays conforming (red-green
// refinement), and each new vertex is placed by the caller (on the level set, by the fast
// distance). A heuristic that only proposes a candidate: the result is validated and its band
// certified again like any mesher output. Cheaper than re-meshing the whole level with a finer
// distance bound when the wide faces are few (a re-mesh refines everywhere).
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/triangle_mesh.h"

namespace cdbench {

struct RefinedMesh {
  TriangleMesh mesh;
  std::vector<char> is_new;  // per face of `mesh`: 1 if it replaced a split face (its band is unknown)
  std::vector<std::size_t> kept_from;  // per face of `mesh` with is_new == 0: its index in the input
  std::size_t split_edges = 0;
  // New vertex k is mesh.vertices[first_new_vertex + k], on edge new_vertex_edge[k] (vertex
  // indices) whose faces' unit normals sum to new_vertex_normal[k]: where it was placed from.
  std::size_t first_new_vertex = 0;
  std::vector<std::array<std::uint32_t, 2>> new_vertex_edge;
  std::vector<Vec3> new_vertex_normal;
};

// Splits every edge of every face with wide[f] != 0, then, until no face has exactly two split
// edges, the third edge of such faces (closure). Faces with three split edges become four, faces
// with one become two; the others are kept. The new vertex of edge (a, b) is place(a, b, n), where
// n is the sum of the unit normals of the faces on the edge (outward for an outward mesh; zero
// for degenerate faces). Orientation is preserved; deterministic (faces and new vertices in input
// order). `place` is called from several threads at once.
using PlaceEdgeVertex = std::function<Vec3(const Vec3& a, const Vec3& b, const Vec3& normal)>;
RefinedMesh refine_faces(const TriangleMesh& mesh, const std::vector<char>& wide, const PlaceEdgeVertex& place);

}  // namespace cdbench
