#pragma once
#include "ltca/solvers/load_solver.hpp"

namespace ltca::solvers {

/// Liu 2021 section 3 (Fig. 4, eq. 26): rotate the cycloid about its centre from the unloaded
/// first contact in steps, doubling the step while the output torque (eq. 26) stays below the
/// load and halving it (bisection) when it overshoots, until |T_out - T| / T <= torque_tolerance.
/// Departures: the first step is Liu's 1/60 arcsec but steps grow (Liu keeps them fixed), and
/// the general default tolerance is 1e-10 (the `liu2021` preset restores his 1 %).
/// Coupled (LoadProblem::WithCoupling): the forces at each trial rotation solve the coupled
/// complementarity problem (coupled_contact.hpp) instead of following from each pin's law alone.
/// With the CHOLMOD or Woodbury kernel (pin bending) the search over psi is the same; with the
/// dense kernel (the elastic disc body) it is a safeguarded Newton iteration on psi with Liu's
/// verdicts (overshoot not accepted, the same balance check), using the coupled solve's own
/// dT/dpsi (issue 48: about 7 trials a position instead of about 74). Uncoupled problems take
/// the published path unchanged.
class BisectionSolver final : public LoadSolver {
 public:
  std::string name() const override { return "bisection"; }
  bool supports_coupling() const override { return true; }
  bool supports_reducer() const override { return true; }
  /// A preloaded mesh (LoadProblem::preloaded): the same search on psi over the pins of both
  /// flanks, bracketed from the theoretical position (two_flanks.hpp).
  bool supports_two_flanks() const override { return true; }

 private:
  /// The stage: Liu's search on the output rotation; at each trial rotation every
  /// disc's translation and rotation (and the shafts' deflections) balance by Newton's method.
  void DoSolveReducer(const LoadProblem& problem, const ReducerSystem& system, const SolverOptions& options,
                    Workspace& workspace, LoadResult* result) const override;
  void DoSolve(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
               LoadResult* result) const override;
};

}  // namespace ltca::solvers
