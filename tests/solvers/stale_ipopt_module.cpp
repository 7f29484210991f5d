// A stand-in for ltca_ipopt.so built from another version of ltca (solvers/src/ipopt_bridge.hpp):
// its ABI text is another version's. ltca must refuse it by that text before it calls any other
// entry point, which therefore abort if called.
#include <cstdlib>

#define ENTRY extern "C" __attribute__((visibility("default")))

ENTRY const char* ltca_ipopt_abi() { return "ltca 0.0.1, Ipopt bridge 0, sizes 4/8/8"; }
ENTRY void* ltca_ipopt_create() { std::abort(); }
ENTRY void ltca_ipopt_destroy(void*) { std::abort(); }
ENTRY bool ltca_ipopt_set_integer(void*, const char*, int) { std::abort(); }
ENTRY bool ltca_ipopt_set_numeric(void*, const char*, double) { std::abort(); }
ENTRY bool ltca_ipopt_set_string(void*, const char*, const char*) { std::abort(); }
ENTRY int ltca_ipopt_initialize(void*) { std::abort(); }
ENTRY int ltca_ipopt_optimize(void*, void*, bool, int*) { std::abort(); }
