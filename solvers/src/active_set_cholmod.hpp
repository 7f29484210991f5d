#pragma once
// Private to ltca_solvers (no CHOLMOD header here: CHOLMOD is linked PRIVATE). The linear algebra
// of the coupled solves (issue 11): M = D + C over all contact points, D diagonal (the laws'
// tangent compliances, mm/N), C the coupling (LoadProblem::coupling()), factorised with CHOLMOD
// (simplicial LDL^T) restricted to an active set: the rows and columns of inactive points are
// replaced by the identity. A point entering or leaving the active set changes the factor by
// cholmod_rowadd / cholmod_rowdel (a rank-2 update / downdate of the trailing part of L) instead of
// a new factorisation; a new D is factorised numerically, keeping the symbolic analysis
// (cholmod_analyze once, on the pattern of C plus the diagonal). One cholmod_common per instance:
// an instance belongs to one solve or one workspace, never to two threads at once.
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace ltca::solvers {

/// The linear algebra a coupled solve needs (CoupledContact): M = D + C restricted to an active
/// set, D diagonal, with points entering and leaving, and the product C F. Two kernels:
/// ActiveSetCholmod (C given as a matrix) and BeamWoodbury (C = B K^-1 B^T + E given factored,
/// beam_woodbury.hpp).
class ActiveSetKernel {
 public:
  struct Stats {
    int factorisations = 0;  ///< numeric factorisations (cholmod_factorize)
    int rowadds = 0;         ///< cholmod_rowadd calls (BeamWoodbury: rank-1 updates, cholmod_updown)
    int rowdels = 0;         ///< cholmod_rowdel calls (BeamWoodbury: rank-1 downdates)
    int solves = 0;          ///< cholmod_solve2 calls
  };
  virtual ~ActiveSetKernel() = default;
  virtual int size() const = 0;
  virtual bool active(int i) const = 0;
  /// Per point: 1 when active.
  virtual const std::vector<char>& active_set() const = 0;
  /// The diagonal D_i the factor holds for an active point (mm/N).
  virtual double diagonal(int i) const = 0;
  /// A new diagonal for every point (only the active ones enter M): refactorised at the next Solve.
  virtual void SetDiagonal(const Eigen::VectorXd& d) = 0;
  /// Point i enters the active set with diagonal d_i. No effect when already active.
  virtual void Add(int i, double d_i) = 0;
  /// Point i leaves the active set. No effect when inactive.
  virtual void Remove(int i) = 0;
  /// x = M_AA^{-1} b on the active rows, 0 on the others (b, x: n x k). False when it fails.
  [[nodiscard]] virtual bool Solve(const Eigen::MatrixXd& b, Eigen::MatrixXd* x) = 0;
  /// cf = C f (all points).
  virtual void Apply(const Eigen::VectorXd& f, Eigen::VectorXd* cf) const = 0;
  virtual const Stats& stats() const = 0;
};

class ActiveSetCholmod final : public ActiveSetKernel {
 public:
  /// Analyses the pattern of C (square, symmetric; both triangles stored). No point is active.
  explicit ActiveSetCholmod(const Eigen::SparseMatrix<double>& coupling);
  ~ActiveSetCholmod();
  ActiveSetCholmod(const ActiveSetCholmod&) = delete;
  ActiveSetCholmod& operator=(const ActiveSetCholmod&) = delete;

  int size() const override;
  /// The coupling C it was built for (compressed, both triangles).
  const Eigen::SparseMatrix<double>& coupling() const;
  /// True when this kernel was built for exactly this matrix (size, pattern and values).
  bool Matches(const Eigen::SparseMatrix<double>& coupling) const;

  bool active(int i) const override;
  /// Per point: 1 when active.
  const std::vector<char>& active_set() const override;
  /// The diagonal D_i the factor holds for an active point (mm/N).
  double diagonal(int i) const override;
  /// A new diagonal for every point (only the active ones enter M): the factor is refactorised
  /// numerically at the next Solve.
  void SetDiagonal(const Eigen::VectorXd& d) override;
  /// Point i enters the active set with diagonal d_i: cholmod_rowadd when the factor is current,
  /// otherwise only recorded (the next Solve refactorises). No effect when already active.
  void Add(int i, double d_i) override;
  /// Point i leaves the active set: cholmod_rowdel when the factor is current. No effect when inactive.
  void Remove(int i) override;

  /// x = M_AA^{-1} b on the active rows, 0 on the others; b and x are n x k (k right-hand sides,
  /// solved together). Refactorises first if needed. Returns false when CHOLMOD fails (M_AA not
  /// positive definite to rounding, or out of memory); x is then unusable.
  [[nodiscard]] bool Solve(const Eigen::MatrixXd& b, Eigen::MatrixXd* x) override;
  /// cf = C f over the non-zero entries of f.
  void Apply(const Eigen::VectorXd& f, Eigen::VectorXd* cf) const override;

  const Stats& stats() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ltca::solvers
