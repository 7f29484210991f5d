#pragma once
// Private to ltca_solvers: the start every rotation-searching backend shares.
#include <cmath>
#include <optional>

#include "ltca/solvers/load_problem.hpp"
#include "ltca/solvers/load_solver.hpp"

namespace ltca::solvers {

/// The unloaded first contact in the load direction (LoadProblem::FirstContactRotation), rad; or
/// nullopt, with result's status and message set, when no pin can close its gap.
inline std::optional<double> FirstContactOrFail(const LoadProblem& problem, LoadResult* result) {
  const double psi = problem.FirstContactRotation();
  if (std::isfinite(psi)) return psi;
  result->status = SolverStatus::kNumericalFailure;
  result->message = "no pin can close its gap in the load direction";
  return std::nullopt;
}

}  // namespace ltca::solvers
