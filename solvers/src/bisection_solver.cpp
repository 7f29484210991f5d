#include "bisection_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::solvers {
namespace {

struct Evaluation {
  double torque = 0.0;
  bool edge = false;       // a pin on a tip corner is pressed
  bool saturated = false;  // a pin is beyond its law's largest force
};

Evaluation Evaluate(const LoadProblem& problem, double psi, Workspace& workspace, std::vector<double>* forces,
                    std::vector<double>* hints) {
  std::vector<contact::ContactLaw> scratch;
  Loading l = LoadAt(problem.At(psi, workspace, &scratch), hints);
  *forces = std::move(l.force);
  return {l.torque, l.edge, l.saturated};
}

}  // namespace

void BisectionSolver::DoSolve(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                              LoadResult* result) const {
  // Start at the unloaded first contact in the load direction (Liu: theta_c1).
  double psi = problem.FirstContactRotation();
  if (!std::isfinite(psi)) {
    result->status = SolverStatus::kNumericalFailure;
    result->message = "no pin can close its gap in the load direction";
    return;
  }
  const double target = problem.torque();
  double step = units::ArcsecToRad(1.0 / 60.0);  // Liu section 4: 1/60 arcsec
  const auto converged = [&](double psi_now, double torque_now) {
    return problem.Balanced(psi_now, torque_now, options.torque_tolerance, workspace);
  };
  std::vector<double> forces, trial_forces, hints;
  bool edge_blocked = false;
  Evaluation at = Evaluate(problem, psi, workspace, &forces, &hints);
  int evaluations = 1;
  for (; evaluations < options.max_iterations; ++evaluations) {
    if (converged(psi, at.torque)) break;
    const Evaluation trial = Evaluate(problem, psi + step, workspace, &trial_forces, &hints);
    if (trial.edge) {
      // A tip corner would be pressed at this trial: treat it as an overshoot. If the load cannot
      // be reached before a corner engages, the answer is edge contact (below).
      edge_blocked = true;
      step *= 0.5;
      if (step < 1e-17 * std::max(std::abs(psi), 1e-12)) break;
      continue;
    }
    if (trial.torque <= target * (1.0 + options.torque_tolerance)) {
      psi += step;
      at = trial;
      forces.swap(trial_forces);
      if (at.saturated && at.torque < target * (1.0 - options.torque_tolerance)) {
        result->status = SolverStatus::kLawCannotCarry;
        result->message = fmt::format("a pin reached the largest force its contact law can carry at {:.6g} N*m of {:.6g}",
                                      at.torque / 1000.0, target / 1000.0);
        result->rotation = psi;
        result->force = forces;
        result->torque_evaluations = evaluations + 1;
        return;
      }
      step *= 2.0;  // increasing steps while below the load
    } else {
      step *= 0.5;  // overshoot: bisect the step
    }
    if (step < 1e-17 * std::max(std::abs(psi), 1e-12)) break;  // cannot refine further in double
  }
  result->rotation = psi;
  result->force = forces;
  result->details = {{"final_step_rad", step}};
  result->torque_evaluations = evaluations;
  result->iterations = evaluations;
  result->native_code = 0;
  if (converged(psi, at.torque)) {
    result->status = SolverStatus::kSuccess;
    const double miss = std::abs(at.torque - target) / target;
    result->message = fmt::format("torque balanced to {:.3g} after {} evaluations{}", miss, evaluations,
                                  miss > options.torque_tolerance ? " (limited by the resolution of the rotation in double precision)" : "");
  } else if (edge_blocked) {
    result->status = SolverStatus::kEdgeContact;
    result->message = fmt::format("the load cannot be reached before a tip corner is pressed (edge contact; line-contact "
                                  "laws do not apply): torque off by {:.3g}", std::abs(at.torque - target) / target);
  } else {
    result->status = SolverStatus::kMaxIterations;
    result->message = fmt::format("torque off by {:.3g} relative after {} evaluations",
                                  std::abs(at.torque - target) / target, evaluations);
  }
}

}  // namespace ltca::solvers
