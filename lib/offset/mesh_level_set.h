#pragma once
// Meshing an implicit surface {x : f(x) = 0} with CGAL's Surface_mesher (Delaunay refinement,
// manifold output). The only CGAL mesher translation unit of the project.
#include <cstdint>
#include <functional>
#include <vector>

#include "core/triangle_mesh.h"

namespace cdbench {

struct LevelSetMeshOptions {
  double angle_bound = 30.0;     // degrees, minimum facet angle
  double radius_bound = 0.0;     // maximum radius of a facet's surface Delaunay ball (absolute)
  double distance_bound = 0.0;   // maximum distance from a facet's circumcentre to its ball centre (absolute)
  double bisection_relative_error = 1e-9;  // relative to the bounding sphere radius
  // A Lipschitz constant of f (0: unknown). The mesher uses only the sign of f; with L known, a
  // point within |f(q)| / L of a recently evaluated point q has q's sign and is not evaluated.
  double lipschitz = 0.0;
};

struct LevelSetMeshStats {
  std::uint64_t calls = 0;        // values the mesher asked for
  std::uint64_t evaluations = 0;  // of f itself (the rest: repeated points, or signs known by Lipschitz)
  std::uint64_t lipschitz = 0;    // signs known from a nearby point's value
};

// Points on {f = 0}: along `count` fixed, well-spread directions from `center` (where f < 0) to
// the sphere of `radius` (where f > 0), the sign change of f is bisected to the last double.
// Deterministic. Directions along which f does not change sign give no point.
std::vector<Vec3> level_set_seeds(const std::function<double(const Vec3&)>& f, const Vec3& center, double radius,
                                  int count);

// f must be negative at `center` and positive on the sphere of `radius` around it. `seeds` are
// points on (or within the bisection error of) the surface; every component of the surface that
// should be meshed must hold at least one seed, and together they must span 3D (at least 4 points
// not coplanar). Deterministic: no random initial points are drawn. With `options.lipschitz` set,
// the output is the same as without it wherever f is truly L-Lipschitz (only signs are skipped).
TriangleMesh mesh_level_set(const std::function<double(const Vec3&)>& f, const Vec3& center, double radius,
                            const std::vector<Vec3>& seeds, const LevelSetMeshOptions& options,
                            LevelSetMeshStats* stats = nullptr);

// The same surface with CGAL's Mesh_3 in parallel mode (TBB, all threads of the calling arena):
// the boundary facets of the restricted Delaunay triangulation of {f < 0}, refined to the same
// facet criteria, manifold, seeded with `seeds` only. NOT reproducible: the output depends on the
// threads' timing (a candidate; certification does not care how it was made).
TriangleMesh mesh_level_set_parallel(const std::function<double(const Vec3&)>& f, const Vec3& center, double radius,
                                     const std::vector<Vec3>& seeds, const LevelSetMeshOptions& options,
                                     LevelSetMeshStats* stats = nullptr);

}  // namespace cdbench
