#include "ltca/solvers/registry.hpp"

#include <functional>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "bisection_solver.hpp"
#include "compatibility_solver.hpp"
#include "energy_groups_solver.hpp"
#include "energy_qp_solver.hpp"

namespace ltca::solvers {
namespace {

struct Entry {
  const char* name;
  std::function<std::unique_ptr<LoadSolver>()> make;
};

const std::vector<Entry>& Registry() {
  static const std::vector<Entry> kRegistry = {
      {"bisection", [] { return std::make_unique<BisectionSolver>(); }},
      {"energy-qp", [] { return std::make_unique<EnergyQpSolver>(); }},
      {"energy-groups", [] { return std::make_unique<EnergyGroupsSolver>(); }},
      {"compatibility", [] { return std::make_unique<CompatibilitySolver>(); }},
  };
  return kRegistry;
}

}  // namespace

std::vector<std::string> SolverNames() {
  std::vector<std::string> names;
  for (const Entry& e : Registry()) names.emplace_back(e.name);
  return names;
}

std::vector<std::string> ReducerSolverNames() {
  std::vector<std::string> names;
  for (const Entry& e : Registry()) {
    if (e.make()->supports_reducer()) names.emplace_back(e.name);
  }
  return names;
}

std::unique_ptr<LoadSolver> MakeSolver(const std::string& name) {
  for (const Entry& e : Registry()) {
    if (name == e.name) return e.make();
  }
  throw std::invalid_argument(
      fmt::format("[solver] name = \"{}\": unknown solver; expected one of: {}", name, fmt::join(SolverNames(), ", ")));
}

}  // namespace ltca::solvers
