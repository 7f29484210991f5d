#include "ipopt_bridge.hpp"

#include "ltca/solvers/modules.hpp"

#include <stdexcept>
#include <string>

#ifndef LTCA_VERSION
#define LTCA_VERSION "unknown"
#endif

namespace ltca::solvers::ipopt {
namespace {

/// The entry points of ltca_ipopt.so (ipopt_module.cpp), once the module is known to be built from
/// this header (IpoptBridgeAbi): one of another version would call an NlpProblem of another layout.
struct Entries {
  void* (*create)() = nullptr;
  void (*destroy)(void*) = nullptr;
  bool (*set_integer)(void*, const char*, int) = nullptr;
  bool (*set_numeric)(void*, const char*, double) = nullptr;
  bool (*set_string)(void*, const char*, const char*) = nullptr;
  int (*initialize)(void*) = nullptr;
  int (*optimize)(void*, NlpProblem*, bool, int*) = nullptr;
};

const Entries& Module() {
  static const Entries entries = [] {  // a throw leaves it unset: the next call tries again
    const std::string mine = IpoptBridgeAbi(LTCA_VERSION);
    const char* (*abi)() = nullptr;
    try {
      abi = ModuleFunction<const char* (*)()>("ipopt", "ltca_ipopt_abi");
    } catch (const ModuleError& e) {
      throw ModuleError(std::string(e.what()) + " (the Ipopt solver energy-qp needs it; this ltca: " + mine + ")");
    }
    const std::string theirs = abi();
    if (theirs != mine) {
      throw ModuleError("the ipopt part of ltca (ltca_ipopt.so) was built from another version of ltca (" + theirs +
                               "; this one: " + mine + "); rebuild or reinstall it with this ltca");
    }
    Entries e;
    e.create = ModuleFunction<decltype(e.create)>("ipopt", "ltca_ipopt_create");
    e.destroy = ModuleFunction<decltype(e.destroy)>("ipopt", "ltca_ipopt_destroy");
    e.set_integer = ModuleFunction<decltype(e.set_integer)>("ipopt", "ltca_ipopt_set_integer");
    e.set_numeric = ModuleFunction<decltype(e.set_numeric)>("ipopt", "ltca_ipopt_set_numeric");
    e.set_string = ModuleFunction<decltype(e.set_string)>("ipopt", "ltca_ipopt_set_string");
    e.initialize = ModuleFunction<decltype(e.initialize)>("ipopt", "ltca_ipopt_initialize");
    e.optimize = ModuleFunction<decltype(e.optimize)>("ipopt", "ltca_ipopt_optimize");
    return e;
  }();
  return entries;
}

}  // namespace

Application::Application() : handle_(Module().create()) {}
Application::~Application() { Module().destroy(handle_); }

bool Application::SetInteger(const char* name, int value) { return Module().set_integer(handle_, name, value); }
bool Application::SetNumeric(const char* name, double value) { return Module().set_numeric(handle_, name, value); }
bool Application::SetString(const char* name, const char* value) { return Module().set_string(handle_, name, value); }
Status Application::Initialize() { return static_cast<Status>(Module().initialize(handle_)); }
Status Application::Optimize(NlpProblem& problem, bool reoptimize, int* iterations) {
  return static_cast<Status>(Module().optimize(handle_, &problem, reoptimize, iterations));
}

}  // namespace ltca::solvers::ipopt
