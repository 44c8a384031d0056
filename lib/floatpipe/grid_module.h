#pragma once
// The OpenVDB side of GridSdf, built as a module (libcdbench_grid_vdb.so, grid_vdb.cpp) that
// GridSdf loads on first use. Why: libopenvdb costs about 40 ms of dynamic linking at every start
// of a program that links it (57,000 symbol bindings, doc/float-pipeline.md), and only the float
// pipeline uses it. Loaded by util/module_loader.h (checked by kGridModuleAbi and the version).
#include <cstddef>
#include <vector>

#include "core/triangle_mesh.h"
#include "util/module_loader.h"

namespace cdbench {

struct GridSdfOptions;

// One sampled field (see GridSdf in grid_offsets.h for the meaning of each call).
class GridField {
 public:
  virtual ~GridField() = default;
  virtual double voxel() const = 0;
  virtual std::size_t active_voxels() const = 0;
  virtual double max_depth() const = 0;
  virtual std::vector<Vec3> deepest_samples(double margin, std::size_t max_count) const = 0;
  virtual TriangleMesh isosurface(double iso) const = 0;
};

// Bumped whenever GridField, GridSdfOptions or GridModule change.
constexpr int kGridModuleAbi = 1;

struct GridModule {
  ModuleHeader header;  // kGridModuleAbi, the cdbench version it was built with
  GridField* (*make)(const TriangleMesh& mesh, const GridSdfOptions& options);  // may throw
};

// The module's file name; looked for (load_module) in $CDBENCH_GRID_MODULE if set, else next to the
// program as installed (<bindir>/../<libdir>/cdbench/), the install prefix's <libdir>/cdbench/, and
// the build tree.
constexpr const char* kGridModuleFile = "libcdbench_grid_vdb.so";

}  // namespace cdbench

// The module's one exported symbol.
extern "C" const cdbench::GridModule* cdbench_grid_module();
