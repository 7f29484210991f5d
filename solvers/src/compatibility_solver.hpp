#pragma once
// No NLopt header here: the backend is private to compatibility_solver.cpp (linked PRIVATE).
#include <limits>
#include <optional>

#include "ltca/solvers/load_solver.hpp"

namespace ltca::solvers {

/// Deformation compatibility (Jiang 2022 eq. 10-11, Li eq. 13): every loaded pin's approach is
/// delta_i = L_i psi - c_i, its force follows from the law, and the torque balance closes the
/// system. The one unknown psi is the minimiser of the convex potential
///   Pi(psi) = sum_i U_i(delta_i(psi)) - T psi,   U_i = int_0^delta F_i,   dPi/dpsi = sum F_i L_i - T,
/// found with NLopt in the bracket [first contact, a rotation that overshoots T]. The algorithm
/// is selectable by NLopt name (SolverOptions::nlopt_algorithm); gradient-based ones use the
/// exact derivative (the torque mismatch), derivative-free ones only Pi. Exact kinematics
/// minimises Pi of the linearisation about the unloaded pose, then closes the exact torque balance
/// by Newton's method from there (SolveExact; docs/solvers.md).
/// Coupled (LoadProblem::WithCoupling): compatibility w_i(F_i) + (C F)_i = delta_i(psi)
/// on the loaded points and the torque balance, solved by Newton on (psi, F) over the active set
/// (the bordered matrix [D + C_AA, -L_A; L_A^T, 0], Schur complement on psi; coupled_contact.hpp);
/// exact kinematics re-linearises about each new psi until the exact torque balances. Uncoupled
/// problems take the path above unchanged.
class CompatibilitySolver final : public LoadSolver {
 public:
  std::string name() const override { return "compatibility"; }
  bool supports_coupling() const override { return true; }
  bool supports_reducer() const override { return true; }
  bool supports_two_flanks() const override { return true; }

 private:
  /// The stage: Newton's method with an active set over the poses (the contacts that
  /// carry load at each iterate), damped to a trust region (ReducerSystem::Minimise).
  void DoSolveReducer(const LoadProblem& problem, const ReducerSystem& system, const SolverOptions& options,
                    Workspace& workspace, LoadResult* result) const override;
  void DoSolve(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
               LoadResult* result) const override;
  /// guess_rotation: a rotation near the answer to start NLopt from (NaN: the linear prediction).
  /// two_flanks: a preloaded pair, bracketed from guess_rotation (its preload state) instead of a
  /// first contact (docs/solvers.md "Two flanks").
  void SolveLinearised(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace, LoadResult* result,
                       double guess_rotation = std::numeric_limits<double>::quiet_NaN(), bool two_flanks = false) const;
  /// preload: a preloaded pair's preload rotation (LoadResult::preload), else none.
  void SolveExact(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                  LoadResult* result, std::optional<double> preload = std::nullopt) const;
  void SolveCoupled(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                    LoadResult* result) const;
};

}  // namespace ltca::solvers
