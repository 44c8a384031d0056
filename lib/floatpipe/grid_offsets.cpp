#include "floatpipe/grid_offsets.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "floatpipe/grid_module.h"
#include "util/error.h"

namespace cdbench {
namespace {

// The directory of the program or library that holds this code (for an installed layout).
std::string own_directory() {
  Dl_info info{};
  std::string path;
  if (dladdr(reinterpret_cast<void*>(&voxel_for_grid), &info) != 0 && info.dli_fname && info.dli_fname[0] == '/')
    path = info.dli_fname;
  if (path.empty()) {  // the main program: dladdr may give its name as typed
    char buf[4096];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n > 0) path.assign(buf, static_cast<std::size_t>(n));
  }
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash);
}

struct LoadedModule {
  const GridModule* module = nullptr;
  std::string error;  // why no candidate could be used
};

// One candidate: loaded and checked, or the reason it is not used.
const GridModule* try_load(const std::string& path, std::string& why) {
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    why = dlerror();
    return nullptr;
  }
  const auto entry = reinterpret_cast<const GridModule* (*)()>(dlsym(handle, "cdbench_grid_module"));
  const GridModule* m = entry ? entry() : nullptr;
  if (!m || m->abi != kGridModuleAbi || std::string(m->version) != CDBENCH_VERSION || !m->make) {
    why = !m ? std::string("not a cdbench grid module")
             : "built for cdbench " + std::string(m->version) + " (grid ABI " + std::to_string(m->abi) + "), this is " +
                   CDBENCH_VERSION + " (ABI " + std::to_string(kGridModuleAbi) + ")";
    dlclose(handle);
    return nullptr;
  }
  return m;  // stays loaded for the life of the process
}

LoadedModule load_module() {
  LoadedModule out;
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("CDBENCH_GRID_MODULE"); env && *env) {
    candidates.push_back(env);  // asked for: nothing else is tried
  } else {
    const std::string own = own_directory();
    if (!own.empty()) candidates.push_back(own + "/" CDBENCH_GRID_MODULE_RELDIR "/" + kGridModuleFile);
    candidates.push_back(CDBENCH_GRID_MODULE_INSTALLDIR "/" + std::string(kGridModuleFile));
    candidates.push_back(CDBENCH_GRID_MODULE_BUILD);
  }
  for (const std::string& path : candidates) {
    std::string why;
    if ((out.module = try_load(path, why))) return out;
    out.error += "\n  " + path + ": " + why;
  }
  out.error = "the float pipeline needs its OpenVDB module " + std::string(kGridModuleFile) +
              " (built and installed with cdbench), and none could be loaded:" + out.error +
              "\n  (set CDBENCH_GRID_MODULE to the module's path)";
  return out;
}

const GridModule& grid_module() {
  static const LoadedModule loaded = load_module();  // once, thread-safe
  if (!loaded.module) throw SetupError(loaded.error);
  return *loaded.module;
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
