#include "ltca/solvers/modules.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <vector>

#include <fmt/format.h>

namespace ltca::solvers {
namespace {

/// The folders a module is looked for in, in order (modules.hpp).
std::vector<std::filesystem::path> ModuleFolders() {
  std::vector<std::filesystem::path> folders;
  if (const char* only = std::getenv("LTCA_MODULE_DIR"); only != nullptr && *only != '\0') {
    folders.emplace_back(only);  // the user's (or a test's) folder, and no other
    return folders;
  }
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec && self.has_parent_path()) {
    folders.push_back(self.parent_path());
    folders.push_back(self.parent_path().parent_path() / "lib" / "ltca");
  }
#ifdef LTCA_MODULE_DIR
  folders.emplace_back(LTCA_MODULE_DIR);
#endif
  return folders;
}

struct LoadedModules {
  std::mutex mutex;
  std::map<std::string, void*> handles;  // never closed: a module's code may run until exit
};

LoadedModules& Modules() {
  static LoadedModules loaded;
  return loaded;
}

}  // namespace

void* ModuleSymbol(const std::string& name, const char* symbol) {
  LoadedModules& loaded = Modules();
  const std::lock_guard lock(loaded.mutex);
  auto it = loaded.handles.find(name);
  if (it == loaded.handles.end()) {
    const std::string file = "ltca_" + name + ".so";
    std::string searched, why;
    void* handle = nullptr;
    for (const std::filesystem::path& folder : ModuleFolders()) {
      const std::filesystem::path path = folder / file;
      searched += (searched.empty() ? "" : ", ") + folder.string();
      std::error_code ec;
      if (!std::filesystem::is_regular_file(path, ec)) continue;
      // RTLD_LOCAL: the module's libraries (MPI's, PLplot's, Ipopt's) do not join the global symbol search.
      handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (handle != nullptr) break;
      const char* error = dlerror();
      why = error != nullptr ? error : "unknown error";
    }
    if (handle == nullptr) {
      throw ModuleError(fmt::format("the {} part of ltca ({}) cannot be loaded: {}; looked in {}", name, file,
                                           why.empty() ? "not found" : why, searched));
    }
    it = loaded.handles.emplace(name, handle).first;
  }
  dlerror();
  void* address = dlsym(it->second, symbol);
  if (address == nullptr) {
    const char* error = dlerror();
    throw ModuleError(fmt::format("the {} part of ltca (ltca_{}.so) has no entry point {}: {}", name, name, symbol,
                                         error != nullptr ? error : "null symbol"));
  }
  return address;
}

}  // namespace ltca::solvers
