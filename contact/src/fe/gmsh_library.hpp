#pragma once
// gmsh's C API (gmshc.h, gmsh 4.8 in Debian 12: libgmsh-dev), loaded at run time with dlopen so
// that no command that does not mesh a disc links gmsh or its OpenCASCADE. Only the functions the
// disc mesher calls; their signatures are gmshc.h's. gmsh is one global state: every use holds
// Lock().
#include <cstddef>
#include <mutex>
#include <string>

namespace ltca::contact::fe {

/// dlopen(soname): the handle, or std::runtime_error saying to install libgmsh-dev (Debian 12) and
/// why the loader refused.
void* OpenGmsh(const char* soname);

class GmshLibrary {
 public:
  /// The library, loaded and initialised once (thread-safe). Throws std::runtime_error saying what
  /// to install when libgmsh.so.4.8 cannot be loaded or lacks a function.
  static GmshLibrary& Get();

  /// gmsh's global state is not thread-safe: hold this while calling any function below.
  std::unique_lock<std::mutex> Lock() { return std::unique_lock<std::mutex>(mutex_); }

  /// Throws std::runtime_error with gmsh's last error and `what` when ierr != 0.
  void Check(int ierr, const char* what) const;

  // gmshc.h, gmsh 4.8.4.
  void (*free)(void* p) = nullptr;
  void (*initialize)(int argc, char** argv, int readConfigFiles, int* ierr) = nullptr;
  void (*clear)(int* ierr) = nullptr;
  void (*option_set_number)(const char* name, double value, int* ierr) = nullptr;
  void (*model_add)(const char* name, int* ierr) = nullptr;
  int (*geo_add_point)(double x, double y, double z, double mesh_size, int tag, int* ierr) = nullptr;
  int (*geo_add_line)(int start_tag, int end_tag, int tag, int* ierr) = nullptr;
  int (*geo_add_circle_arc)(int start_tag, int centre_tag, int end_tag, int tag, double nx, double ny,
                            double nz, int* ierr) = nullptr;
  int (*geo_add_spline)(int* point_tags, std::size_t point_tags_n, int tag, int* ierr) = nullptr;
  int (*geo_add_curve_loop)(int* curve_tags, std::size_t curve_tags_n, int tag, int reorient,
                            int* ierr) = nullptr;
  int (*geo_add_plane_surface)(int* wire_tags, std::size_t wire_tags_n, int tag, int* ierr) = nullptr;
  void (*geo_synchronize)(int* ierr) = nullptr;
  int (*field_add)(const char* field_type, int tag, int* ierr) = nullptr;
  void (*field_set_number)(int tag, const char* option, double value, int* ierr) = nullptr;
  void (*field_set_numbers)(int tag, const char* option, double* value, std::size_t value_n,
                            int* ierr) = nullptr;
  void (*field_set_as_background_mesh)(int tag, int* ierr) = nullptr;
  void (*geo_mesh_set_transfinite_curve)(int tag, int n_points, const char* mesh_type, double coef, int* ierr) = nullptr;
  void (*mesh_generate)(int dim, int* ierr) = nullptr;
  void (*mesh_set_order)(int order, int* ierr) = nullptr;
  void (*mesh_get_nodes)(std::size_t** node_tags, std::size_t* node_tags_n, double** coord,
                         std::size_t* coord_n, double** parametric_coord,
                         std::size_t* parametric_coord_n, int dim, int tag, int include_boundary,
                         int return_parametric_coord, int* ierr) = nullptr;
  void (*mesh_get_elements_by_type)(int element_type, std::size_t** element_tags,
                                    std::size_t* element_tags_n, std::size_t** node_tags,
                                    std::size_t* node_tags_n, int tag, std::size_t task,
                                    std::size_t num_tasks, int* ierr) = nullptr;
  void (*logger_get_last_error)(char** error, int* ierr) = nullptr;

 private:
  GmshLibrary();
  std::mutex mutex_;
};

}  // namespace ltca::contact::fe
