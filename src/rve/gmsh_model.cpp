#include "rve/gmsh_model.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>

namespace dualcell::rve::gmsh_model {

namespace {

// The module's entry, loaded once per process from the executable's own directory (where the
// build puts every executable and the module) and kept loaded.
Entry entry() {
  static const Entry loaded = [] {
    const std::filesystem::path file = std::filesystem::read_symlink("/proc/self/exe").parent_path() / module_file;
    void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) throw std::runtime_error("cannot load the RVE mesher's module " + file.string() + ": " + dlerror());
    void* symbol = dlsym(handle, entry_name);
    if (!symbol) throw std::runtime_error(file.string() + " has no entry " + entry_name + ": " + dlerror());
    return reinterpret_cast<Entry>(symbol);
  }();
  return loaded;
}

}  // namespace

Result mesh(const Request& request) {
  Result result;
  entry()(request, result);
  return result;
}

}  // namespace dualcell::rve::gmsh_model
