#include "util/module_loader.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <vector>

#include "util/error.h"

namespace cdbench {
namespace {

// The directory of the program or library that holds this code (for an installed layout).
std::string own_directory() {
  Dl_info info{};
  std::string path;
  if (dladdr(reinterpret_cast<void*>(&load_module), &info) != 0 && info.dli_fname && info.dli_fname[0] == '/')
    path = info.dli_fname;
  if (path.empty()) {  // the main program: dladdr may give its name as typed
    char buf[4096];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n > 0) path.assign(buf, static_cast<std::size_t>(n));
  }
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash);
}

// One candidate: loaded and checked, or the reason it is not used.
const ModuleHeader* try_load(const ModuleSearch& s, const std::string& path, std::string& why) {
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    why = dlerror();
    return nullptr;
  }
  const auto entry = reinterpret_cast<const ModuleHeader* (*)()>(dlsym(handle, s.symbol.c_str()));
  const ModuleHeader* m = entry ? entry() : nullptr;
  if (!m || m->abi != s.abi || !m->version || std::string(CDBENCH_VERSION) != m->version) {
    why = !m ? "not a module of this kind (no " + s.symbol + ")"
             : "built for cdbench " + std::string(m->version ? m->version : "?") + " (ABI " + std::to_string(m->abi) +
                   "), this is " CDBENCH_VERSION " (ABI " + std::to_string(s.abi) + ")";
    dlclose(handle);
    return nullptr;
  }
  return m;
}

}  // namespace

const ModuleHeader* load_module(const ModuleSearch& s) {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv(s.env.c_str()); env && *env) {
    candidates.push_back(env);  // asked for: nothing else is tried
  } else {
    const std::string own = own_directory();
    if (!own.empty()) candidates.push_back(own + "/" CDBENCH_MODULE_RELDIR "/" + s.file);
    candidates.push_back(CDBENCH_MODULE_INSTALLDIR "/" + s.file);
    candidates.push_back(s.build_path);
  }
  std::string reasons;
  for (const std::string& path : candidates) {
    std::string why;
    if (const ModuleHeader* m = try_load(s, path, why)) return m;
    reasons += "\n  " + path + ": " + why;
  }
  throw SetupError(s.needed_for + " " + s.file + " (built and installed with cdbench), and none could be loaded:" +
                   reasons + "\n  (set " + s.env + " to the module's path)");
}

}  // namespace cdbench
