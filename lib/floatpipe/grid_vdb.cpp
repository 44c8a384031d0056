// The module libcdbench_grid_vdb.so: GridSdf's field on OpenVDB (grid_module.h says why apart).
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "floatpipe/grid_module.h"
#include "floatpipe/grid_offsets.h"

namespace cdbench {
namespace {

class VdbField final : public GridField {
 public:
  VdbField(const TriangleMesh& mesh, const GridSdfOptions& options) {
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
    grid_ = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(*xform, points, triangles, quads, ex_band,
                                                                          in_band);
    voxel_ = h;
    float lo = std::numeric_limits<float>::infinity();
    for (auto it = grid_->cbeginValueOn(); it; ++it) lo = std::min(lo, *it);
    depth_ = std::isfinite(lo) ? std::max(0.0, -static_cast<double>(lo)) : 0.0;
  }

  double voxel() const override { return voxel_; }
  std::size_t active_voxels() const override { return static_cast<std::size_t>(grid_->activeVoxelCount()); }
  double max_depth() const override { return depth_; }

  TriangleMesh isosurface(double iso) const override {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*grid_, points, triangles, quads, iso, 0.0);
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

  std::vector<Vec3> deepest_samples(double margin, std::size_t max_count) const override {
    const float cut = static_cast<float>(-(depth_ - margin));
    std::vector<std::pair<float, openvdb::Coord>> hits;
    for (auto it = grid_->cbeginValueOn(); it; ++it)
      if (*it <= cut) hits.emplace_back(*it, it.getCoord());
    // Deepest first; ties by coordinate so that the order never depends on the tree's iteration.
    std::sort(hits.begin(), hits.end(), [](const auto& a, const auto& b) {
      return a.first < b.first || (a.first == b.first && a.second < b.second);
    });
    if (hits.size() > max_count) hits.resize(max_count);
    std::vector<Vec3> out;
    out.reserve(hits.size());
    for (const auto& [v, c] : hits) {
      const openvdb::Vec3d w = grid_->indexToWorld(c);
      out.emplace_back(w.x(), w.y(), w.z());
    }
    return out;
  }

 private:
  openvdb::FloatGrid::Ptr grid_;
  double voxel_ = 0.0, depth_ = 0.0;
};

GridField* make_vdb_field(const TriangleMesh& mesh, const GridSdfOptions& options) {
  return new VdbField(mesh, options);
}

}  // namespace
}  // namespace cdbench

extern "C" __attribute__((visibility("default"))) const cdbench::GridModule* cdbench_grid_module() {
  static const cdbench::GridModule module{{cdbench::kGridModuleAbi, CDBENCH_VERSION}, &cdbench::make_vdb_field};
  return &module;
}
