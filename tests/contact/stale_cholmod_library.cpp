// A stand-in for a CHOLMOD of another version (contact/cholmod/cholmod_lazy.hpp): it reports 2.2.0
// (SuiteSparse 4's CHOLMOD) by cholmod_version and has no other function.
extern "C" __attribute__((visibility("default"))) int cholmod_version(int version[3]) {
  if (version != nullptr) version[0] = 2, version[1] = 2, version[2] = 0;
  return 2 * 1000 + 2;  // CHOLMOD_VER_CODE(2, 2)
}
