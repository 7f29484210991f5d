#pragma once
// Private to ltca_solvers (no CHOLMOD header here: CHOLMOD is linked PRIVATE). The coupled solves'
// linear algebra for a coupling given in factored form (pin bending):
//   C = B K^-1 B^T + E,  K the beams' banded stiffness (dofs x dofs), B (points x dofs), E diagonal.
// The Newton matrix on the active set A, M_AA = D_A + C_AA = D'_A + B_A K^-1 B_A^T with the
// diagonal D' = D + E, is solved by Woodbury:
//   M_AA^-1 = D'^-1 - D'^-1 B_A S^-1 B_A^T D'^-1,  S = K + B_A^T D'^-1 B_A,
// S sparse, symmetric positive definite and banded per pin (the pattern of K, B^T B adds nothing
// outside an element). S is factorised by CHOLMOD (simplicial LDL^T, natural order: no fill
// beyond the band); a point entering or leaving A is the rank-1 update / downdate
// cholmod_updown of S by b_i / sqrt(D'_i); a new D is a numeric refactorisation. Every operation
// costs O(points + dofs) for a bounded band: linear in the slice count. C F is B K^-1 B^T F + E F
// with K factorised once.
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "active_set_cholmod.hpp"
#include "ltca/solvers/load_problem.hpp"

namespace ltca::solvers {

class BeamWoodbury final : public ActiveSetKernel {
 public:
  explicit BeamWoodbury(std::shared_ptr<const LoadProblem::CouplingFactors> factors);
  ~BeamWoodbury() override;
  BeamWoodbury(const BeamWoodbury&) = delete;
  BeamWoodbury& operator=(const BeamWoodbury&) = delete;

  /// True when built for these factors (the same shared object, or equal sizes, patterns and values).
  bool Matches(const std::shared_ptr<const LoadProblem::CouplingFactors>& factors) const;

  [[nodiscard]] bool Solve(const Eigen::MatrixXd& b, Eigen::MatrixXd* x) override;
  void Apply(const Eigen::VectorXd& f, Eigen::VectorXd* cf) const override;

 private:
  /// Point i entered: the rank-1 update of S by b_i / sqrt(D'_i). Left: the downdate.
  bool UpdateAdd(int i, double d_i) override;
  bool UpdateRemove(int i) override;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ltca::solvers
