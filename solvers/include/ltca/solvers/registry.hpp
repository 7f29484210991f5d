#pragma once
// The one table of known solvers (pattern: Drake's choose_best_solver). Adding a backend means
// one line in solvers/src/registry.cpp; no public header changes.
#include <memory>
#include <string>
#include <vector>

#include "ltca/solvers/load_solver.hpp"

namespace ltca::solvers {

/// Names of every registered solver, in registry order.
std::vector<std::string> SolverNames();
/// Names of the solvers that solve the reducer stage (LoadSolver::supports_reducer()), in registry order.
std::vector<std::string> ReducerSolverNames();
/// Throws std::invalid_argument listing the valid names for an unknown one.
std::unique_ptr<LoadSolver> MakeSolver(const std::string& name);

}  // namespace ltca::solvers
