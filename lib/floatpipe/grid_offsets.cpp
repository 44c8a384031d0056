#include "floatpipe/grid_offsets.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cdbench {

struct GridSdf::Impl {
  openvdb::FloatGrid::Ptr grid;
  double voxel = 0.0, depth = 0.0;
};

GridSdf::GridSdf(const TriangleMesh& mesh, const GridSdfOptions& options) : impl_(std::make_unique<Impl>()) {
  if (!(options.voxel > 0.0) || !std::isfinite(options.voxel)) throw std::invalid_argument("GridSdf: voxel must be > 0");
  openvdb::initialize();
  std::vector<openvdb::Vec3s> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices)
    points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(mesh.faces.size());
  for (const Face& f : mesh.faces) triangles.emplace_back(f[0], f[1], f[2]);
  const std::vector<openvdb::Vec4I> quads;
  // Inside, the band reaches as deep as asked (the whole interior: no interior point is farther
  // than half the bounding box's smallest side from the surface). Outside, as far as asked. Both
  // plus 2 voxels so that marching cubes sees the sign change of the outermost levels.
  const Vec3 ext = mesh.bbox().hi - mesh.bbox().lo;
  const double h = options.voxel;
  const double in_reach = std::min(options.interior_reach, 0.5 * ext.minCoeff());
  const float in_band = static_cast<float>(std::ceil(std::max(0.0, in_reach) / h) + 2.0);
  const float ex_band = static_cast<float>(std::ceil(options.exterior_reach / h) + 2.0);
  const openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(h);
  impl_->grid = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(*xform, points, triangles, quads,
                                                                                  ex_band, in_band);
  impl_->voxel = h;
  float lo = std::numeric_limits<float>::infinity();
  for (auto it = impl_->grid->cbeginValueOn(); it; ++it) lo = std::min(lo, *it);
  impl_->depth = std::isfinite(lo) ? std::max(0.0, -static_cast<double>(lo)) : 0.0;
}

GridSdf::~GridSdf() = default;
GridSdf::GridSdf(GridSdf&&) noexcept = default;
GridSdf& GridSdf::operator=(GridSdf&&) noexcept = default;

double GridSdf::voxel() const { return impl_->voxel; }
std::size_t GridSdf::active_voxels() const { return static_cast<std::size_t>(impl_->grid->activeVoxelCount()); }
double GridSdf::max_depth() const { return impl_->depth; }

TriangleMesh GridSdf::isosurface(double iso) const {
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*impl_->grid, points, triangles, quads, iso, 0.0);
  TriangleMesh m;
  m.vertices.reserve(points.size());
  for (const auto& p : points) m.vertices.emplace_back(p.x(), p.y(), p.z());
  m.faces.reserve(triangles.size() + 2 * quads.size());
  // OpenVDB's polygons wind the other way round from our outward convention; the sweeps do not
  // care, but files written for inspection should look right.
  for (const auto& t : triangles) m.faces.push_back({t[0], t[2], t[1]});
  for (const auto& q : quads) {
    m.faces.push_back({q[0], q[2], q[1]});
    m.faces.push_back({q[0], q[3], q[2]});
  }
  return m;
}

std::vector<Vec3> GridSdf::deepest_samples(double margin, std::size_t max_count) const {
  const float cut = static_cast<float>(-(impl_->depth - margin));
  std::vector<std::pair<float, openvdb::Coord>> hits;
  for (auto it = impl_->grid->cbeginValueOn(); it; ++it)
    if (*it <= cut) hits.emplace_back(*it, it.getCoord());
  // Deepest first; ties by coordinate so that the order never depends on the tree's iteration.
  std::sort(hits.begin(), hits.end(), [](const auto& a, const auto& b) {
    return a.first < b.first || (a.first == b.first && a.second < b.second);
  });
  if (hits.size() > max_count) hits.resize(max_count);
  std::vector<Vec3> out;
  out.reserve(hits.size());
  for (const auto& [v, c] : hits) {
    const openvdb::Vec3d w = impl_->grid->indexToWorld(c);
    out.emplace_back(w.x(), w.y(), w.z());
  }
  return out;
}

double voxel_for_grid(const TriangleMesh& mesh, int cells) {
  if (cells < 1) throw std::invalid_argument("voxel_for_grid: cells must be >= 1");
  const Vec3 ext = mesh.bbox().hi - mesh.bbox().lo;
  return ext.maxCoeff() / cells;
}

}  // namespace cdbench
