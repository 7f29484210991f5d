#pragma once
// CHOLMOD (T. A. Davis, SuiteSparse; Debian 12's libcholmod3, CHOLMOD 3.0) loaded the first time a
// run factorises, so that a command that never does (`ltca --version`, a compatibility solve)
// maps neither CHOLMOD nor its BLAS, LAPACK, METIS, OpenMP and Fortran runtime
// (docs/architecture.md, "Modules"). Include this header instead of <cholmod.h>, and before
// <Eigen/CholmodSupport>: it renames the CHOLMOD functions that ltca calls to forwarders
// (cholmod_lazy.cpp), which resolve the library's own on their first call. A function not listed
// here is not renamed and fails to link (the executable does not link CHOLMOD): add it here and in
// cholmod_lazy.cpp. The first call throws std::runtime_error when the library is missing or is not
// the CHOLMOD version of the headers ltca was built with (CholmodLibraryCheck).

#define cholmod_start ltca_lazy_cholmod_start
#define cholmod_finish ltca_lazy_cholmod_finish
#define cholmod_free_factor ltca_lazy_cholmod_free_factor
#define cholmod_free_dense ltca_lazy_cholmod_free_dense
#define cholmod_free_sparse ltca_lazy_cholmod_free_sparse
#define cholmod_allocate_sparse ltca_lazy_cholmod_allocate_sparse
#define cholmod_analyze ltca_lazy_cholmod_analyze
#define cholmod_factorize ltca_lazy_cholmod_factorize
#define cholmod_factorize_p ltca_lazy_cholmod_factorize_p
#define cholmod_solve ltca_lazy_cholmod_solve
#define cholmod_solve2 ltca_lazy_cholmod_solve2
#define cholmod_spsolve ltca_lazy_cholmod_spsolve
#define cholmod_rowadd ltca_lazy_cholmod_rowadd
#define cholmod_rowdel ltca_lazy_cholmod_rowdel
#define cholmod_updown ltca_lazy_cholmod_updown

#include <cholmod.h>

#include <string>

namespace ltca::cholmod {

/// Opens the shared library `file` (dlopen, RTLD_LOCAL) and checks that it is CHOLMOD of the main
/// and sub version of the headers ltca was built with (cholmod_version against CHOLMOD_MAIN_VERSION
/// and CHOLMOD_SUB_VERSION: the layouts of cholmod_common and the factor change between them). Returns
/// the handle; throws std::runtime_error naming the file and the reason (not found, no
/// cholmod_version, another version: both named).
void* CholmodLibraryCheck(const std::string& file);

/// The soname the forwarders load (LTCA_CHOLMOD_SONAME, from the library found at build time).
const char* CholmodSoname();

}  // namespace ltca::cholmod
