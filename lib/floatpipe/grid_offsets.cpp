#include "floatpipe/grid_offsets.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "floatpipe/grid_module.h"
#include "util/error.h"

namespace cdbench {
namespace {

const GridModule& grid_module() {
  // Once, thread-safe; a failure throws (SetupError, exit 3) and is tried again at the next call.
  static const GridModule* const module = load_module_as<GridModule>(
      {kGridModuleFile, "CDBENCH_GRID_MODULE", "cdbench_grid_module", kGridModuleAbi, CDBENCH_GRID_MODULE_BUILD,
       "the float pipeline needs its OpenVDB module"});
  return *module;
}

}  // namespace

GridSdf::GridSdf(const TriangleMesh& mesh, const GridSdfOptions& options) {
  if (!(options.voxel > 0.0) || !std::isfinite(options.voxel)) throw std::invalid_argument("GridSdf: voxel must be > 0");
  field_.reset(grid_module().make(mesh, options));
}

GridSdf::~GridSdf() = default;
GridSdf::GridSdf(GridSdf&&) noexcept = default;
GridSdf& GridSdf::operator=(GridSdf&&) noexcept = default;

double GridSdf::voxel() const { return field_->voxel(); }
std::size_t GridSdf::active_voxels() const { return field_->active_voxels(); }
double GridSdf::max_depth() const { return field_->max_depth(); }
TriangleMesh GridSdf::isosurface(double iso) const { return field_->isosurface(iso); }
std::vector<Vec3> GridSdf::deepest_samples(double margin, std::size_t max_count) const {
  return field_->deepest_samples(margin, max_count);
}

double voxel_for_grid(const TriangleMesh& mesh, int cells) {
  if (cells < 1) throw std::invalid_argument("voxel_for_grid: cells must be >= 1");
  const Vec3 ext = mesh.bbox().hi - mesh.bbox().lo;
  return ext.maxCoeff() / cells;
}

}  // namespace cdbench
