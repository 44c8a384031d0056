// `--impl plugin:PATH.so`: a collision implementation in a shared library behind the C ABI of
// include/cdbench/plugin.h.
#include <dlfcn.h>

#include <cmath>
#include <limits>
#include <vector>

#include "cdbench/plugin.h"
#include "collide/collision_impl.h"
#include "util/error.h"

namespace cdbench {
namespace {

class PluginImpl final : public CollisionImpl {
 public:
  explicit PluginImpl(const std::string& path) : path_(path) {
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle_) throw InputError("plugin " + path + ": cannot be loaded (" + std::string(dlerror()) + ")");
    const auto entry = reinterpret_cast<cdbench_plugin_entry_fn>(dlsym(handle_, "cdbench_plugin_entry"));
    if (!entry) throw InputError("plugin " + path + ": no symbol cdbench_plugin_entry (see include/cdbench/plugin.h)");
    plugin_ = entry();
    if (!plugin_) throw InputError("plugin " + path + ": cdbench_plugin_entry returned NULL");
    if (plugin_->abi_version != CDBENCH_PLUGIN_ABI_VERSION)
      throw InputError("plugin " + path + ": built for plugin ABI version " + std::to_string(plugin_->abi_version) +
                       ", this cdbench has version " + std::to_string(CDBENCH_PLUGIN_ABI_VERSION) + " (rebuild it)");
    if (!plugin_->create || !plugin_->query || !plugin_->destroy)
      throw InputError("plugin " + path + ": create, query or destroy is NULL");
  }
  ~PluginImpl() override {
    if (state_) plugin_->destroy(state_);
    // The library stays loaded: a plugin may leave thread-local or static state behind.
  }
  std::string name() const override { return plugin_->name ? plugin_->name : "plugin:" + path_; }
  bool detects_containment() const override { return plugin_->flags & CDBENCH_PLUGIN_DETECTS_CONTAINMENT; }
  bool counts_tests() const override { return plugin_->flags & CDBENCH_PLUGIN_COUNTS_TESTS; }

  void build(const TriangleMesh& fixed, const TriangleMesh& mover) override {
    if (state_) plugin_->destroy(state_), state_ = nullptr;
    std::vector<double> fv, mv;
    std::vector<std::uint32_t> ft, mt;
    const cdbench_mesh f = view(fixed, fv, ft), m = view(mover, mv, mt);
    char error[512] = {0};
    state_ = plugin_->create(&f, &m, error, sizeof error);
    error[sizeof error - 1] = '\0';
    if (!state_) throw InputError("plugin " + path_ + ": create failed: " + std::string(error[0] ? error : "(no message)"));
  }

  QueryAnswer query(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) override {
    double r[9], tt[3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) r[3 * i + j] = R(i, j);
      tt[i] = t[i];
    }
    cdbench_answer a{0, std::numeric_limits<double>::quiet_NaN(), 0, 0};
    if (plugin_->query(state_, r, tt, &a) != 0) throw InputError("plugin " + path_ + ": query failed");
    QueryAnswer q;
    q.collides = a.collides != 0;
    if (plugin_->flags & CDBENCH_PLUGIN_COMPUTES_DISTANCE) q.distance = a.distance;
    q.bv_tests = a.bv_tests;
    q.triangle_tests = a.triangle_tests;
    return q;
  }

 private:
  static cdbench_mesh view(const TriangleMesh& m, std::vector<double>& v, std::vector<std::uint32_t>& t) {
    for (const Vec3& p : m.vertices) v.insert(v.end(), {p.x(), p.y(), p.z()});
    for (const Face& f : m.faces) t.insert(t.end(), {f[0], f[1], f[2]});
    return {v.data(), m.vertices.size(), t.data(), m.faces.size()};
  }

  std::string path_;
  void* handle_ = nullptr;
  const cdbench_plugin* plugin_ = nullptr;
  void* state_ = nullptr;
};

}  // namespace

std::unique_ptr<CollisionImpl> make_plugin_impl(const std::string& path) { return std::make_unique<PluginImpl>(path); }

}  // namespace cdbench
