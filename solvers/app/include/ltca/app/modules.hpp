#pragma once
// The parts of ltca built as shared modules of their own, loaded the first time a command needs
// them (issue 54: a command maps only the libraries it uses; `ltca --version` maps none of MPI or
// PLplot). A module is a MODULE library of CMake named ltca_<name>.so with extern "C" entry points,
// found in, in order: the executable's own folder, <that folder>/../lib/ltca (an installation), and
// the build tree's folder of modules (tests and the Python module run from the build tree); or, when
// the environment variable LTCA_MODULE_DIR is set, in that folder only.
// docs/architecture.md, "Modules", lists them.

#include <string>

namespace ltca::app {

/// The entry point `symbol` of the module `name` ("mpi" for ltca_mpi.so), loaded once per process
/// (thread-safe). Throws std::runtime_error naming the module, the folders searched and the loader's
/// message when the module or the symbol is missing.
void* ModuleSymbol(const std::string& name, const char* symbol);

/// The module's entry point as a function pointer of type `F`.
template <typename F>
F ModuleFunction(const std::string& name, const char* symbol) {
  return reinterpret_cast<F>(ModuleSymbol(name, symbol));
}

}  // namespace ltca::app
