#include "cholmod_lazy.hpp"

#include <dlfcn.h>

#include <stdexcept>
#include <string>

#include <fmt/format.h>

#ifndef LTCA_CHOLMOD_SONAME
#define LTCA_CHOLMOD_SONAME "libcholmod.so.3"
#endif

namespace ltca::cholmod {
namespace {

/// The process's CHOLMOD, opened and checked once (a failure is thrown again at every call).
void* Library() {
  static void* const handle = CholmodLibraryCheck(LTCA_CHOLMOD_SONAME);
  return handle;
}

void* Symbol(const char* name) {
  void* address = dlsym(Library(), name);
  if (address == nullptr) {
    throw std::runtime_error(fmt::format("CHOLMOD ({}) has no function {}: reinstall libsuitesparse-dev (Debian 12)",
                                         LTCA_CHOLMOD_SONAME, name));
  }
  return address;
}

}  // namespace

const char* CholmodSoname() { return LTCA_CHOLMOD_SONAME; }

void* CholmodLibraryCheck(const std::string& file) {
  dlerror();
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = dlerror();
    throw std::runtime_error(fmt::format(
        "CHOLMOD ({}) cannot be loaded: {}; the elastic discs, the coupled pins and the beam models need it: "
        "install libsuitesparse-dev (Debian 12)",
        file, why != nullptr ? why : "unknown error"));
  }
  using VersionFn = int (*)(int*);
  const auto version = reinterpret_cast<VersionFn>(dlsym(handle, "cholmod_version"));
  if (version == nullptr) {
    dlclose(handle);
    throw std::runtime_error(fmt::format("{} is not CHOLMOD (it has no cholmod_version)", file));
  }
  int theirs[3] = {-1, -1, -1};
  version(theirs);
  if (theirs[0] != CHOLMOD_MAIN_VERSION || theirs[1] != CHOLMOD_SUB_VERSION) {
    dlclose(handle);
    throw std::runtime_error(fmt::format(
        "CHOLMOD in {} is version {}.{}.{}, ltca was built with the headers of {}.{}.{}: rebuild ltca against it or "
        "install the CHOLMOD of the build (libsuitesparse-dev, Debian 12)",
        file, theirs[0], theirs[1], theirs[2], CHOLMOD_MAIN_VERSION, CHOLMOD_SUB_VERSION, CHOLMOD_SUBSUB_VERSION));
  }
  return handle;
}

}  // namespace ltca::cholmod

// The forwarders named in cholmod_lazy.hpp: each resolves CHOLMOD's own function on its first call.
#define LTCA_CHOLMOD_FORWARD(ret, name, params, args)                                                       \
  ret ltca_lazy_cholmod_##name params {                                                                    \
    static const auto f = reinterpret_cast<ret(*) params>(ltca::cholmod::Symbol("cholmod_" #name)); \
    return f args;                                                                                          \
  }

LTCA_CHOLMOD_FORWARD(int, start, (cholmod_common * c), (c))
LTCA_CHOLMOD_FORWARD(int, finish, (cholmod_common * c), (c))
LTCA_CHOLMOD_FORWARD(int, free_factor, (cholmod_factor * *l, cholmod_common * c), (l, c))
LTCA_CHOLMOD_FORWARD(int, free_dense, (cholmod_dense * *x, cholmod_common * c), (x, c))
LTCA_CHOLMOD_FORWARD(int, free_sparse, (cholmod_sparse * *a, cholmod_common * c), (a, c))
LTCA_CHOLMOD_FORWARD(cholmod_sparse*, allocate_sparse,
                     (size_t nrow, size_t ncol, size_t nzmax, int sorted, int packed, int stype, int xtype,
                      cholmod_common* c),
                     (nrow, ncol, nzmax, sorted, packed, stype, xtype, c))
LTCA_CHOLMOD_FORWARD(cholmod_factor*, analyze, (cholmod_sparse * a, cholmod_common * c), (a, c))
LTCA_CHOLMOD_FORWARD(int, factorize, (cholmod_sparse * a, cholmod_factor * l, cholmod_common * c), (a, l, c))
LTCA_CHOLMOD_FORWARD(int, factorize_p,
                     (cholmod_sparse * a, double beta[2], int* fset, size_t fsize, cholmod_factor* l, cholmod_common* c),
                     (a, beta, fset, fsize, l, c))
LTCA_CHOLMOD_FORWARD(cholmod_dense*, solve, (int sys, cholmod_factor* l, cholmod_dense* b, cholmod_common* c),
                     (sys, l, b, c))
LTCA_CHOLMOD_FORWARD(int, solve2,
                     (int sys, cholmod_factor* l, cholmod_dense* b, cholmod_sparse* bset, cholmod_dense** x,
                      cholmod_sparse** xset, cholmod_dense** y, cholmod_dense** e, cholmod_common* c),
                     (sys, l, b, bset, x, xset, y, e, c))
LTCA_CHOLMOD_FORWARD(cholmod_sparse*, spsolve, (int sys, cholmod_factor* l, cholmod_sparse* b, cholmod_common* c),
                     (sys, l, b, c))
LTCA_CHOLMOD_FORWARD(int, rowadd, (size_t k, cholmod_sparse* r, cholmod_factor* l, cholmod_common* c), (k, r, l, c))
LTCA_CHOLMOD_FORWARD(int, rowdel, (size_t k, cholmod_sparse* r, cholmod_factor* l, cholmod_common* c), (k, r, l, c))
LTCA_CHOLMOD_FORWARD(int, updown, (int update, cholmod_sparse* u, cholmod_factor* l, cholmod_common* c),
                     (update, u, l, c))
