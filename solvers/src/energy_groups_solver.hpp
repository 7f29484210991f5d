#pragma once
#include "ltca/solvers/load_solver.hpp"

namespace ltca::solvers {

/// Li's minimum-energy method as published (Li section 3.3-3.5, Fig. 4-7, eq. 13-14):
///  1. first contact and the clearances after it (Li Fig. 4, contact/unloaded.hpp);
///  2. the maximum deformation: the rotation if the first pin carried the whole torque; every pin
///     whose remaining gap it closes is a candidate (Li Fig. 5, an upper bound of the active set);
///  3. tooth groups: the contiguous runs of candidates (in pin order) that contain the first pin,
///     Li's reading of Fig. 4 ("No. 30~38 below line 1");
///  4. each group solved with every member in contact (compatibility eq. 13 + torque balance);
///     a group is feasible when every member is compressed and every other pin stays open;
///  5. the feasible group of minimum total energy NE = sum F_i delta_i (eq. 14).
/// Departure (docs/solvers.md): a pin already pressed at the linearisation point with an arm <= 0
/// (exact kinematics, the far end of the line of centres) is in every group at the force of its
/// approach, zero once it opens; Li's groups have no place for a pin the rotation does not close.
/// More than kMaxGroups groups: status too-many-groups instead of a guess. A true active set that
/// is not contiguous (e.g. under pitch errors) has no feasible contiguous group: the groups in
/// closing order are tried next (a departure, docs/solvers.md). A tooth is a pin with its slices.
class EnergyGroupsSolver final : public LoadSolver {
 public:
  static constexpr int kMaxGroups = 5000;
  std::string name() const override { return "energy-groups"; }
  /// Coupled (pin bending): each group's coupled problem is solved by the
  /// compatibility backend's kernel (docs/solvers.md).
  bool supports_coupling() const override { return true; }
  /// A preloaded pair: linearised about its preload state (docs/solvers.md "Two flanks").
  bool supports_two_flanks() const override { return true; }

 private:
  void DoSolve(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
               LoadResult* result) const override;
};

}  // namespace ltca::solvers
