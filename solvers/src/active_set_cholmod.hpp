#pragma once
// Private to ltca_solvers (no CHOLMOD header here: CHOLMOD is linked PRIVATE). The linear algebra
// of the coupled solves: M = D + C over all contact points, D diagonal (the laws'
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
  int size() const { return static_cast<int>(state_.active.size()); }
  bool active(int i) const { return state_.active[static_cast<std::size_t>(i)] != 0; }
  /// Per point: 1 when active.
  const std::vector<char>& active_set() const { return state_.active; }
  /// The diagonal D_i the factor holds for an active point (mm/N).
  double diagonal(int i) const { return state_.d(i); }
  /// A new diagonal for every point (only the active ones enter M): refactorised at the next Solve.
  void SetDiagonal(const Eigen::VectorXd& d);
  /// Point i enters the active set with diagonal d_i. No effect when already active. When the
  /// factor is current it is updated (UpdateAdd), otherwise the next Solve refactorises.
  void Add(int i, double d_i);
  /// Point i leaves the active set. No effect when inactive. As Add, by UpdateRemove.
  void Remove(int i);
  /// x = M_AA^{-1} b on the active rows, 0 on the others (b, x: n x k). False when it fails.
  [[nodiscard]] virtual bool Solve(const Eigen::MatrixXd& b, Eigen::MatrixXd* x) = 0;
  /// cf = C f (all points).
  virtual void Apply(const Eigen::VectorXd& f, Eigen::VectorXd* cf) const = 0;
  /// True when a factorisation costs about as little as a solve (the dense kernel on a few
  /// active points): CoupledContact then refactorises with the current tangents at every Newton
  /// step (Newton's quadratic convergence) instead of taking chord steps.
  virtual bool refactorisation_is_cheap() const { return false; }
  const Stats& stats() const { return state_.stats; }

 protected:
  /// The bookkeeping both kernels share: the active set, the diagonal, whether the
  /// factor is stale (it does not hold the current D and active set), the counts.
  struct State {
    std::vector<char> active;
    Eigen::VectorXd d;
    bool stale = true;
    Stats stats;
  };
  /// n points, none active, D = 1, the factor stale.
  void Reset(int n);
  State state_;

 private:
  /// The factor is current and point i has just entered with d_i (left): update the factor;
  /// false when the update failed (the next Solve refactorises).
  virtual bool UpdateAdd(int i, double d_i) = 0;
  virtual bool UpdateRemove(int i) = 0;
};

class ActiveSetCholmod final : public ActiveSetKernel {
 public:
  /// Analyses the pattern of C (square, symmetric; both triangles stored). No point is active.
  explicit ActiveSetCholmod(const Eigen::SparseMatrix<double>& coupling);
  ~ActiveSetCholmod();
  ActiveSetCholmod(const ActiveSetCholmod&) = delete;
  ActiveSetCholmod& operator=(const ActiveSetCholmod&) = delete;

  /// The coupling C it was built for (compressed, both triangles).
  const Eigen::SparseMatrix<double>& coupling() const;
  /// True when this kernel was built for exactly this matrix (size, pattern and values).
  bool Matches(const Eigen::SparseMatrix<double>& coupling) const;


  /// x = M_AA^{-1} b on the active rows, 0 on the others; b and x are n x k (k right-hand sides,
  /// solved together). Refactorises first if needed. Returns false when CHOLMOD fails (M_AA not
  /// positive definite to rounding, or out of memory); x is then unusable.
  [[nodiscard]] bool Solve(const Eigen::MatrixXd& b, Eigen::MatrixXd* x) override;
  /// cf = C f over the non-zero entries of f.
  void Apply(const Eigen::VectorXd& f, Eigen::VectorXd* cf) const override;

 private:
  /// Point i entered: cholmod_rowadd. Left: cholmod_rowdel.
  bool UpdateAdd(int i, double d_i) override;
  bool UpdateRemove(int i) override;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ltca::solvers
