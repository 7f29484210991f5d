#pragma once
// The parts of ltca built as shared modules of their own, loaded the first time a run needs them,
// so that a command maps only the libraries it uses (`ltca --version` and a compatibility solve map
// none of MPI, PLplot, Ipopt or MUMPS). A module is a MODULE library of CMake named ltca_<name>.so with extern "C" entry points,
// found in, in order: the executable's own folder, <that folder>/../lib/ltca (an installation), and
// the build tree's folder of modules (tests and the Python module run from the build tree); or, when
// the environment variable LTCA_MODULE_DIR is set, in that folder only.
// docs/architecture.md, "Modules", lists them.

#include <stdexcept>
#include <string>

namespace ltca::solvers {

/// A module that is missing, cannot be loaded or was built from another version of ltca: a part of
/// the installation, not a bug (the command line exits 1 naming it, having written nothing).
class ModuleError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The entry point `symbol` of the module `name` ("mpi" for ltca_mpi.so), loaded once per process
/// (thread-safe). Throws ModuleError naming the module, the folders searched and the loader's
/// message when the module or the symbol is missing.
void* ModuleSymbol(const std::string& name, const char* symbol);

/// The module's entry point as a function pointer of type `F`.
template <typename F>
F ModuleFunction(const std::string& name, const char* symbol) {
  return reinterpret_cast<F>(ModuleSymbol(name, symbol));
}

}  // namespace ltca::solvers
