#pragma once
// No Ipopt header here: the backend is private to energy_qp_solver.cpp (linked PRIVATE).
#include <memory>

#include "ltca/solvers/load_solver.hpp"

namespace ltca::solvers {

/// Li's minimum-energy principle (Li eq. 14), solved as one convex program over all pins
/// instead of by enumerating tooth groups: minimise the complementary elastic energy plus the
/// work of the initial clearances, sum_i [int_0^F_i w_i + c_i F_i], over F_i >= 0 subject to the
/// torque balance sum_i L_i F_i = T (Liu eq. 26 / Li eq. 2), in Ipopt through its TNLP interface
/// with exact gradient and (diagonal) Hessian. Its KKT conditions are the compatibility
/// equations (Li eq. 13): w_i(F_i) = L_i psi - c_i on loaded pins and c_i - L_i psi >= 0 on the
/// others, with the torque multiplier as the rotation psi. Exact kinematics: re-linearised about
/// the current rotation until psi changes by less than the tolerance.
/// Coupled compliance (LoadProblem::WithCoupling): the objective adds 1/2 F^T C F, its gradient
/// C F and its Hessian C (sparse, no longer diagonal: C's lower off-diagonal entries), so the KKT
/// conditions are the coupled compatibility w_i(F_i) + (C F)_i = L_i psi - c_i on loaded pins.
class EnergyQpSolver final : public LoadSolver {
 public:
  std::string name() const override { return "energy-qp"; }
  bool supports_coupling() const override { return true; }
  bool supports_reducer() const override { return true; }
  bool supports_two_flanks() const override { return true; }

 private:
  /// The stage: Li's minimum-energy principle extended to the stage, the total
  /// potential energy over the poses and the output rotation, one convex program in Ipopt.
  void DoSolveReducer(const LoadProblem& problem, const ReducerSystem& system, const SolverOptions& options,
                    Workspace& workspace, LoadResult* result) const override;
  // The Ipopt application and the warm start live in the workspace (Workspace::BackendState,
  // defined in the .cpp: Ipopt stays private), created on the first solve of each workspace.
  void DoSolve(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
               LoadResult* result) const override;
};

}  // namespace ltca::solvers
