#pragma once
// Private to ltca_solvers: the balance of a preloaded mesh over both flanks (docs/solvers.md
// "Two flanks").
#include "ltca/solvers/load_problem.hpp"
#include "ltca/solvers/load_solver.hpp"

namespace ltca::solvers {

/// The disc's rotation psi about its held centre at which the pins of both signs of arm balance
/// `torque` (N*mm, in the problem's frame, >= 0; 0 gives the preload state):
///   M(psi) = sum_i F_i(delta_i(psi)) L_i(psi) = torque,
/// F_i the law's force of the approach (or, coupled, the coupled complementarity problem's forces
/// at psi, coupled_contact.hpp). Linearised, dM/dpsi = sum_i k_i L_i^2 >= 0 whatever the sign of
/// L_i, so M is monotone and the root is bracketed from psi = 0 by doubling steps (at most a
/// quarter tooth pitch, contact::RotationWindow) and found by Illinois' regula falsi; under exact
/// kinematics the same search on the re-evaluated geometry. Converged when
/// |M - torque| <= torque_tolerance * max(torque, M_flank) (M_flank: half of sum_i F_i |L_i|, the
/// torque each flank carries at zero torque), and within 1e-7 N*mm at zero torque (the shared
/// judge's scale there is 1 N*mm), or within what the arithmetic resolves at psi.
/// Sets status (kSuccess, kLawCannotCarry, kEdgeContact, kMaxIterations, kNumericalFailure),
/// message, rotation, force, iterations and torque_evaluations.
void SolveTwoFlanks(const LoadProblem& problem, double torque, const SolverOptions& options, Workspace& workspace,
                    LoadResult* result);

}  // namespace ltca::solvers
