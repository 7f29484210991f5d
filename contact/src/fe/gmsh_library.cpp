#include "fe/gmsh_library.hpp"

#include <dlfcn.h>

#include <stdexcept>

// gmsh 4.8 keeps caches for the life of the process (its basis and field factories, the project
// ClearProject makes) and frees them only in gmshFinalize, which ltca does not call (meshes may
// be asked for until exit). LeakSanitizer would report them at exit in the sanitizer builds: its
// suppressions hook (compiler-rt's lsan_interface.h), linked into whatever binary meshes a disc,
// suppresses leaks whose allocation stack is inside libgmsh, and only those. Unused without
// LeakSanitizer. The process has one such hook: it also names OpenCASCADE's libraries (libTK*), whose
// allocator (Standard_MMgrRaw) and static handles live until exit in the binaries that load them
// (the STEP module, its read-back test tests/app/step_test.cpp).
extern "C" __attribute__((visibility("default"), used)) const char* __lsan_default_suppressions() {
  return "leak:libgmsh.so\nleak:libTK\n";
}

namespace ltca::contact::fe {
namespace {

// The soname of Debian 12's gmsh 4.8 (libgmsh4.8, pulled in by libgmsh-dev).
constexpr const char* kSoname = "libgmsh.so.4.8";
constexpr const char* kInstall =
    "the elastic disc needs gmsh 4.8's library (libgmsh.so.4.8): apt-get install libgmsh-dev "
    "(Debian 12)";

template <typename F>
void Resolve(void* handle, const char* name, F& slot) {
  void* symbol = dlsym(handle, name);
  if (symbol == nullptr) {
    throw std::runtime_error(std::string(kSoname) + " has no " + name + ": " + kInstall);
  }
  slot = reinterpret_cast<F>(symbol);
}

}  // namespace

GmshLibrary& GmshLibrary::Get() {
  // A function-local static: constructed once, thread-safe; a failed construction throws and is
  // tried again by the next call. Never unloaded (gmsh registers exit handlers).
  static GmshLibrary library;
  return library;
}

void* OpenGmsh(const char* soname) {
  void* handle = dlopen(soname, RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* reason = dlerror();
    throw std::runtime_error(std::string(kInstall) + " (dlopen: " + (reason ? reason : "?") + ")");
  }
  return handle;
}

GmshLibrary::GmshLibrary() {
  void* handle = OpenGmsh(kSoname);
  Resolve(handle, "gmshFree", free);
  Resolve(handle, "gmshInitialize", initialize);
  Resolve(handle, "gmshClear", clear);
  Resolve(handle, "gmshOptionSetNumber", option_set_number);
  Resolve(handle, "gmshModelAdd", model_add);
  Resolve(handle, "gmshModelGeoAddPoint", geo_add_point);
  Resolve(handle, "gmshModelGeoAddLine", geo_add_line);
  Resolve(handle, "gmshModelGeoAddCircleArc", geo_add_circle_arc);
  Resolve(handle, "gmshModelGeoAddSpline", geo_add_spline);
  Resolve(handle, "gmshModelGeoAddCurveLoop", geo_add_curve_loop);
  Resolve(handle, "gmshModelGeoAddPlaneSurface", geo_add_plane_surface);
  Resolve(handle, "gmshModelGeoSynchronize", geo_synchronize);
  Resolve(handle, "gmshModelMeshFieldAdd", field_add);
  Resolve(handle, "gmshModelMeshFieldSetNumber", field_set_number);
  Resolve(handle, "gmshModelMeshFieldSetNumbers", field_set_numbers);
  Resolve(handle, "gmshModelMeshFieldSetAsBackgroundMesh", field_set_as_background_mesh);
  Resolve(handle, "gmshModelGeoMeshSetTransfiniteCurve", geo_mesh_set_transfinite_curve);
  Resolve(handle, "gmshModelMeshGenerate", mesh_generate);
  Resolve(handle, "gmshModelMeshSetOrder", mesh_set_order);
  Resolve(handle, "gmshModelMeshGetNodes", mesh_get_nodes);
  Resolve(handle, "gmshModelMeshGetElementsByType", mesh_get_elements_by_type);
  Resolve(handle, "gmshLoggerGetLastError", logger_get_last_error);
  int ierr = 0;
  // No argv, no configuration files (~/.gmshrc would change the mesh).
  initialize(0, nullptr, 0, &ierr);
  Check(ierr, "gmshInitialize");
  option_set_number("General.Terminal", 0.0, &ierr);  // silent: ltca owns stdout
  Check(ierr, "General.Terminal");
}

void GmshLibrary::Check(int ierr, const char* what) const {
  if (ierr == 0) return;
  std::string message = std::string("gmsh: ") + what + " failed";
  if (logger_get_last_error != nullptr) {
    char* error = nullptr;
    int ignored = 0;
    logger_get_last_error(&error, &ignored);
    if (error != nullptr) {
      if (error[0] != '\0') message += std::string(": ") + error;
      free(error);
    }
  }
  throw std::runtime_error(message);
}

}  // namespace ltca::contact::fe
