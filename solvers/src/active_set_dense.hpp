#pragma once
// Private to ltca_solvers. The coupled solves' linear algebra for a small coupling given as a
// matrix (the elastic disc body's: every contact point of a slice coupled to every other, a dense
// 40 x 40 block per slice on a 40-pin pair): C held dense, M_AA = D_A + C_AA gathered on the m
// active points and factorised by a dense Cholesky (Eigen's LLT, m^3 / 3 flops: a few hundred
// for the 6-8 loaded pins of a pose) whenever the active set or D changes, where ActiveSetCholmod
// analyses the pattern once per matrix and updates a sparse LDL^T over all n points (its
// analysis, allocations and rank-2 updates cost far more than the dense factor at this size).
// C F costs n per loaded point. A new matrix of the same size is loaded in place (Load): no
// allocation, the active set emptied, as a new kernel starts. CoupledContact takes it for a
// coupling of at most kDenseLimit points (ActiveSetDense::Suits).
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "active_set_cholmod.hpp"

namespace ltca::solvers {

class ActiveSetDense final : public ActiveSetKernel {
 public:
  /// The largest coupling (points) the dense kernel takes: its matrix n^2 doubles (320 kB), its
  /// factor m^3 / 3 flops for m active points.
  static constexpr int kDenseLimit = 200;
  /// True when a coupling of this size is given to the dense kernel (square, at most kDenseLimit).
  static bool Suits(const Eigen::SparseMatrix<double>& coupling);

  /// C square and symmetric (both triangles stored, as LoadProblem::coupling()); no point active.
  /// `dense`: the same C dense (LoadProblem::coupling_dense), taken as it is; nullptr: made from
  /// the sparse matrix.
  explicit ActiveSetDense(const Eigen::SparseMatrix<double>& coupling, const Eigen::MatrixXd* dense = nullptr);
  /// Another C of the same size in place of the one held: the active set emptied, D = 1, the
  /// factor stale (as a new kernel). Throws std::invalid_argument for another size.
  void Load(const Eigen::SparseMatrix<double>& coupling, const Eigen::MatrixXd* dense = nullptr);
  /// True when this kernel holds exactly this matrix (size, pattern and values).
  bool Matches(const Eigen::SparseMatrix<double>& coupling) const;

  /// x = M_AA^{-1} b on the active rows, 0 on the others; refactorises first if needed. False
  /// when M_AA is not positive definite to rounding (Eigen's LLT fails) or x is not finite.
  [[nodiscard]] bool Solve(const Eigen::MatrixXd& b, Eigen::MatrixXd* x) override;
  /// cf = C f over the non-zero entries of f.
  void Apply(const Eigen::VectorXd& f, Eigen::VectorXd* cf) const override;
  /// M_AA of m points costs m^3 / 3 flops: every Newton step refactorises.
  bool refactorisation_is_cheap() const override { return true; }

 private:
  /// A point entering or leaving makes the factor stale: the next Solve factorises M_AA again
  /// (cheaper at this size than an update of the factor in place).
  bool UpdateAdd(int, double) override { return false; }
  bool UpdateRemove(int) override { return false; }
  bool Factorise();

  Eigen::SparseMatrix<double> c_;  // as given (compressed): Matches compares it
  Eigen::MatrixXd dense_;          // C, n x n
  std::vector<int> index_;         // the active points the factor holds, ascending
  Eigen::MatrixXd m_;              // M_AA, m x m
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::VectorXd column_;         // Solve's right-hand side on the active rows (reused)
};

}  // namespace ltca::solvers
