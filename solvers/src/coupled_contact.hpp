#pragma once
// Private to ltca_solvers: the coupled contact problem of one crank position, shared by
// the coupled paths of `bisection` and `compatibility`. With the coupling C (LoadProblem::coupling)
// the deformed gap of point i is g_i = w_i(F_i) + (C F)_i - delta_i, and
//   at a given rotation (one bisection trial, Liu 2021):  F >= 0, g >= 0, F g = 0;
//   for a given torque (compatibility, Jiang 2022):       the same with delta_i = a_i + L_i psi and
//                                                         sum F_i L_i = T, psi free.
// Both are the optimality conditions of a convex energy, sum_i W_i(F_i) + F^T C F / 2 - delta^T F
// (W_i the complementary energy of the law, W_i' = w_i), over F >= 0 (and sum F L = T, psi its
// multiplier), which has one solution for strictly increasing laws.
//
// Method: an active-set Newton iteration. On the free set A (points allowed to carry force) the
// Newton step of w_A(F_A) + C_AA F_A = delta_A uses M = D + C_AA, D_i = w_i'(F_i) the tangent
// compliance (ContactLaw::Compliance; at F_i = 0, where the hertz-line compliance is infinite,
// the secant w_i(f) / f at the force scale f); for a given torque the step solves the bordered
// system [M, -L_A; L_A^T, 0] by the Schur complement on psi (two right-hand sides M^-1 [g, L_A]).
// After a full step every point whose force fell to <= 0 leaves A and every point held at zero
// whose gap is negative (beyond the rounding of the gap) enters it: a semismooth Newton
// (primal-dual active set) iteration, which needs one to three steps from a warm start. Should
// it not settle in 40 steps it continues as a monotone primal active-set method (a ratio test
// that stops at the first force reaching zero, one point entering at a time, an Armijo line
// search on the energy), which cannot cycle. The linear systems are those of ActiveSetCholmod:
// points entering and leaving by rowadd / rowdel, a numeric refactorisation only when a tangent
// compliance has moved by more than 10 % from the factorised one (otherwise the step is a chord
// step, which converges linearly at that rate). Converged: the set is settled and the last step
// changed no force by more than 1e-12 of the largest. A small coupling given as a matrix (at most
// ActiveSetDense::kDenseLimit points, e.g. the elastic disc body's) takes the dense kernel
// (ActiveSetDense) instead, which factorises M_AA anew where ActiveSetCholmod updates it; its
// factorisation costs about what a solve does, so every step is a Newton step with the current
// tangents (no chord steps): the same fixed point, reached in fewer steps.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "active_set_cholmod.hpp"
#include "ltca/solvers/load_problem.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "ltca/solvers/workspace.hpp"

namespace ltca::solvers {

class ActiveSetDense;
class BeamWoodbury;

/// One contact point of a coupled solve.
struct CoupledPoint {
  const contact::ContactLaw* law = nullptr;  ///< nullptr: an edge contact, which carries no force
  double approach = 0.0;  ///< delta_i at the reference rotation, mm
  double arm = 0.0;       ///< L_i = d delta_i / d psi, mm
};
/// The points of LoadProblem::At (approach, arm, law; an edge point gets no law).
std::vector<CoupledPoint> CoupledPoints(const std::vector<LoadProblem::PinAt>& pins);
/// The same into *points (its storage reused).
void CoupledPoints(const std::vector<LoadProblem::PinAt>& pins, std::vector<CoupledPoint>* points);

struct CoupledOutcome {
  bool converged = false;
  bool saturated = false;  ///< a loaded point reached its law's largest force
  bool edge = false;       ///< an edge point (no law) has its coupled gap closed
  double rotation = 0.0;   ///< for a given torque: psi beyond the reference rotation, rad
  double torque = 0.0;     ///< sum F_i L_i, N*mm
  int iterations = 0;
  std::string failure;     ///< why it did not converge
};

class CoupledContact {
 public:
  /// With the problem's coupling: the Woodbury kernel (BeamWoodbury) when the coupling comes
  /// factored (LoadProblem::coupling_factors), otherwise the dense kernel (ActiveSetDense) for at
  /// most ActiveSetDense::kDenseLimit points, the sparse matrix kernel (ActiveSetCholmod) beyond.
  /// `dense`: the same coupling dense when the problem has it (LoadProblem::coupling_dense), for
  /// the dense kernel.
  explicit CoupledContact(const Eigen::SparseMatrix<double>& coupling,
                          std::shared_ptr<const LoadProblem::CouplingFactors> factors = nullptr,
                          const Eigen::MatrixXd* dense = nullptr);
  ~CoupledContact();
  bool Matches(const Eigen::SparseMatrix<double>& coupling,
               const std::shared_ptr<const LoadProblem::CouplingFactors>& factors) const;
  /// Takes another coupling in place when the kernel allows it (the dense kernel and a matrix of
  /// the same size without factors: no allocation), starting as a new solver would (no point
  /// active). False, nothing changed, otherwise.
  bool Reload(const Eigen::SparseMatrix<double>& coupling,
              const std::shared_ptr<const LoadProblem::CouplingFactors>& factors, const Eigen::MatrixXd* dense = nullptr);

  /// At the given approaches (psi fixed). force: in, the start (a warm start: any F >= 0); out,
  /// the solution, N. force_scale: a typical point force (the secant of entering points), N.
  CoupledOutcome AtRotation(const std::vector<CoupledPoint>& points, double force_scale, std::vector<double>* force);
  /// For a given torque T (N*mm): delta_i = approach_i + arm_i psi, sum F_i L_i = T; returns psi.
  /// force: in, a start (scaled to carry T; none: the first point to close carries it), out, the solution.
  CoupledOutcome ForTorque(const std::vector<CoupledPoint>& points, double torque, std::vector<double>* force);
  /// After AtRotation has converged at psi: dT/dpsi = L_A^T M_AA^-1 L_A, the torque's derivative
  /// along the solution with the active set A held (at fixed psi, w_A(F_A) + C_AA F_A = a_A +
  /// L_A psi, so dF_A/dpsi = M_AA^-1 L_A with M_AA = D_A + C_AA), from the factor the solve left
  /// (its tangents those of the last Newton step or chord: a derivative for a safeguarded search,
  /// not an exact one). 0 when no point is active or the solve fails. One solve, no factorisation
  /// on the dense kernel after a converged solve.
  double TorqueSlope(const std::vector<CoupledPoint>& points);

  const ActiveSetCholmod::Stats& stats() const { return kernel_->stats(); }
  /// True when the coupling took the dense kernel (ActiveSetDense: a small coupling given as a matrix).
  bool dense() const { return dense_kernel_ != nullptr; }

 private:
  CoupledOutcome Solve(const std::vector<CoupledPoint>& points, bool for_torque, double torque, double force_scale,
                       std::vector<double>* force);
  /// Solve's work arrays, kept from call to call (a bisection asks about 70 trial rotations a
  /// position): sized at each call, never read before they are written.
  struct Buffers {
    std::vector<char> free;
    Eigen::VectorXd f, cf, d, df;
    Eigen::MatrixXd rhs, sol;
  };
  Buffers buffers_;
  std::unique_ptr<ActiveSetKernel> kernel_;
  ActiveSetCholmod* matrix_kernel_ = nullptr;  // kernel_ when C came as a large matrix only
  ActiveSetDense* dense_kernel_ = nullptr;     // kernel_ when C came as a small matrix only
  BeamWoodbury* beam_kernel_ = nullptr;  // kernel_ when C came factored
};

/// The solver of this problem's coupling kept in the workspace (its CHOLMOD analysis is reused
/// while the coupling is the same, e.g. over a sweep); rebuilt when the coupling differs, or,
/// for the dense kernel and a coupling of the same size (the elastic disc body's, new at every
/// crank position), given the new matrix in place (CoupledContact::Reload).
CoupledContact& CoupledContactFor(const LoadProblem& problem, Workspace& workspace);

/// The kernel's work between two snapshots of its statistics, as backend details:
/// `factorisations`, `rowadds`, `rowdels`, `solves`.
void AddKernelDetails(const ActiveSetCholmod::Stats& before, const ActiveSetCholmod::Stats& now, BackendDetails* details);

/// A typical force of one point, N: T over the sum of the positive arms.
double CoupledForceScale(const LoadProblem& problem);

}  // namespace ltca::solvers
