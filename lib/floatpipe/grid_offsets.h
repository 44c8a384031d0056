#pragma once
// The paper's float offsets: the fixed mesh's signed distance sampled on a regular grid (OpenVDB's
// narrow-band mesh-to-volume, float32 values) and iso-surfaces of it by marching cubes (OpenVDB's
// volume-to-mesh, adaptivity 0, quads split into two triangles). Nothing here is certified: the
// surfaces are within about a voxel of the true level sets, which `cdbench validate` measures
// (doc/float-pipeline.md). OpenVDB stays inside the module grid_vdb.cpp, loaded on first use
// (grid_module.h).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "core/triangle_mesh.h"

namespace cdbench {

struct GridSdfOptions {
  double voxel = 0.0;            // edge of a grid cell (absolute, > 0)
  double exterior_reach = 0.0;   // the field is sampled up to this distance outside (>= 0)
  // ... and up to this depth inside; infinity: the whole interior (then max_depth() is the
  // deepest sample). A narrow interior band costs far fewer voxels on thick solids.
  double interior_reach = std::numeric_limits<double>::infinity();
};

// The sampled field; movable, not copyable.
class GridField;
class GridSdf {
 public:
  // Throws SetupError (util/error.h) naming the paths tried when the OpenVDB module cannot be loaded.
  GridSdf(const TriangleMesh& mesh, const GridSdfOptions& options);
  ~GridSdf();
  GridSdf(GridSdf&&) noexcept;
  GridSdf& operator=(GridSdf&&) noexcept;

  double voxel() const;
  std::size_t active_voxels() const;
  // The deepest sampled value's depth (−min over the samples): the grid's estimate of the maximum
  // penetration (the radius of the largest inscribed ball), too small by up to about a voxel.
  // Only meaningful with the whole interior sampled.
  double max_depth() const;
  // World positions of the samples at most `margin` shallower than the deepest one, deepest
  // first, at most max_count of them.
  std::vector<Vec3> deepest_samples(double margin, std::size_t max_count) const;
  // The iso-surface {s = iso} by marching cubes: a triangle soup (no validity claimed); empty
  // when iso lies outside the sampled range. Thread-safe (the grid is only read).
  TriangleMesh isosurface(double iso) const;

 private:
  std::unique_ptr<GridField> field_;
};

// The deepest point of the fine lattice {i h : i integer} (the sample points of a grid of voxel h)
// found from a coarse grid of voxel k h (k = 4, or 1 on small grids) with the whole interior
// sampled. Every fine point lies within k/2 fine steps per axis of a coarse sample q, so at most
// r = sqrt(3) (k/2) h from it, and (the distance being 1-Lipschitz) at most r deeper than q. The coarse samples near the coarse maximum (by the
// grid's values, with a coarse voxel's slack for its approximate interior) are taken deepest
// first; a fine point p near q is evaluated only if depth(q) + |p - q| can beat the best so far.
// `distance_at(p)` is the unsigned distance to the surface; `inside_at(p)` its side (only asked
// when the ball of radius depth(q) around q does not already contain p).
struct LatticeDepth {
  double depth = 0.0;
  Vec3 point = Vec3::Zero();
  std::size_t evaluations = 0;
};
template <class DistanceAt, class InsideAt>
LatticeDepth deepest_lattice_point(const GridSdf& coarse, double h, const DistanceAt& distance_at,
                                   const InsideAt& inside_at) {
  LatticeDepth best;
  // The coarse spacing is `ratio` fine steps; offsets lo .. lo + ratio - 1 per axis tile the fine
  // lattice (each fine point belongs to exactly one coarse sample) and stay within ratio / 2 steps.
  const int ratio = std::max(1, static_cast<int>(std::lround(coarse.voxel() / h)));
  const int lo = -(ratio / 2), hi = lo + ratio - 1;
  const double reach = std::sqrt(3.0) * (ratio / 2) * h;
  const std::vector<Vec3> cand = coarse.deepest_samples(reach + 2.0 * coarse.voxel(), 4096);
  for (const Vec3& q : cand) {
    if (!inside_at(q)) continue;
    const double dq = distance_at(q);
    ++best.evaluations;
    const Vec3 c(std::round(q.x() / h), std::round(q.y() / h), std::round(q.z() / h));
    for (int i = lo; i <= hi; ++i)
      for (int j = lo; j <= hi; ++j)
        for (int k = lo; k <= hi; ++k) {
          const Vec3 p = (c + Vec3(i, j, k)) * h;
          const double pq = (p - q).norm();
          if (dq + pq <= best.depth) continue;
          const double d = (i | j | k) == 0 ? dq : distance_at(p);
          best.evaluations += (i | j | k) != 0;
          if (d > best.depth && (pq < dq || inside_at(p))) {
            best.depth = d;
            best.point = p;
          }
        }
  }
  return best;
}

// Voxel size for --grid N: the longest side of the mesh's bounding box over N.
double voxel_for_grid(const TriangleMesh& mesh, int cells_along_longest_side);

}  // namespace cdbench
