#pragma once
// The paper's float offsets: the fixed mesh's signed distance sampled on a regular grid (OpenVDB's
// narrow-band mesh-to-volume, float32 values) and iso-surfaces of it by marching cubes (OpenVDB's
// volume-to-mesh, adaptivity 0, quads split into two triangles). Nothing here is certified: the
// surfaces are within about a voxel of the true level sets, which `cdbench validate` measures
// (doc/float-pipeline.md). OpenVDB stays inside grid_offsets.cpp.
#include <memory>

#include "mesh/triangle_mesh.h"

namespace cdbench {

struct GridSdfOptions {
  double voxel = 0.0;            // edge of a grid cell (absolute, > 0)
  double exterior_reach = 0.0;   // the field is sampled up to this distance outside (>= 0)
};

// The sampled field; movable, not copyable.
class GridSdf {
 public:
  GridSdf(const TriangleMesh& mesh, const GridSdfOptions& options);
  ~GridSdf();
  GridSdf(GridSdf&&) noexcept;
  GridSdf& operator=(GridSdf&&) noexcept;

  double voxel() const;
  std::size_t active_voxels() const;
  // The deepest sampled value's depth (−min over the samples): the grid's estimate of the maximum
  // penetration (the radius of the largest inscribed ball), too small by up to about a voxel.
  double max_depth() const;
  // The iso-surface {s = iso} by marching cubes: a triangle soup (no validity claimed); empty
  // when iso lies outside the sampled range. Thread-safe (the grid is only read).
  TriangleMesh isosurface(double iso) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Voxel size for --grid N: the longest side of the mesh's bounding box over N.
double voxel_for_grid(const TriangleMesh& mesh, int cells_along_longest_side);

}  // namespace cdbench
