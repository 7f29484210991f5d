#include "beam_woodbury.hpp"
#include "sparse_identical.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <Eigen/SparseCholesky>
#include "cholmod_lazy.hpp"  // CHOLMOD, loaded on its first call

namespace ltca::solvers {

struct BeamWoodbury::Impl {
  std::shared_ptr<const LoadProblem::CouplingFactors> factors;
  Eigen::SparseMatrix<double> b;   // B, points x dofs
  Eigen::SparseMatrix<double> bt;  // B^T, dofs x points: column i is b_i
  // K, for C F: natural order (banded per pin, no fill).
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> k_factor;
  mutable Eigen::VectorXd load_dofs, w_dofs;  // Apply's work vectors
  cholmod_common common{};
  cholmod_sparse* a = nullptr;  // upper triangle of S, pattern of triu(K + B^T B) (stype 1)
  std::vector<int> k_at;        // per stored upper entry of K (column-major order): its position in a
  std::vector<double> k_value;
  std::vector<int> b_begin;     // per point: its pairs' range in b_at / b_pair
  std::vector<int> b_at;        // position in a of the pair (r <= c) of b_i's entries
  std::vector<double> b_pair;   // b_ir b_ic
  cholmod_factor* l = nullptr;
  cholmod_sparse* column = nullptr;  // updown's column, dofs x 1
  cholmod_dense* x = nullptr;
  cholmod_dense* y = nullptr;
  cholmod_dense* e = nullptr;
  // The kernel's shared bookkeeping (ActiveSetKernel::State): d per point, the laws' compliances.
  std::vector<char>& active;
  Eigen::VectorXd& d;
  bool& stale;
  Stats& stats;
  Eigen::VectorXd held;  // per active point, the D_i the factor holds
  Eigen::MatrixXd y_points, z_dofs, b_u;

  explicit Impl(State& s) : active(s.active), d(s.d), stale(s.stale), stats(s.stats) {}

  ~Impl() {
    cholmod_free_dense(&x, &common);
    cholmod_free_dense(&y, &common);
    cholmod_free_dense(&e, &common);
    cholmod_free_sparse(&column, &common);
    cholmod_free_factor(&l, &common);
    cholmod_free_sparse(&a, &common);
    cholmod_finish(&common);
  }

  int Position(int row, int col) const {
    const auto* ap = static_cast<const int*>(a->p);
    const auto* ai = static_cast<const int*>(a->i);
    const int* at = std::lower_bound(ai + ap[col], ai + ap[col + 1], row);
    if (at == ai + ap[col + 1] || *at != row) throw std::logic_error("beam Woodbury: entry outside the pattern of S");
    return static_cast<int>(at - ai);
  }

  double Weight(int i, double di) const { return 1.0 / (di + factors->local(i)); }

  bool Factorise() {
    auto* ax = static_cast<double*>(a->x);
    std::fill(ax, ax + static_cast<std::ptrdiff_t>(static_cast<const int*>(a->p)[a->ncol]), 0.0);
    for (std::size_t k = 0; k < k_at.size(); ++k) ax[k_at[k]] += k_value[k];
    const int n = static_cast<int>(active.size());
    for (int i = 0; i < n; ++i) {
      if (!active[static_cast<std::size_t>(i)]) continue;
      const double w = Weight(i, d(i));
      held(i) = d(i);
      for (int p = b_begin[static_cast<std::size_t>(i)]; p < b_begin[static_cast<std::size_t>(i) + 1]; ++p) {
        ax[b_at[static_cast<std::size_t>(p)]] += w * b_pair[static_cast<std::size_t>(p)];
      }
    }
    ++stats.factorisations;
    const int ok = cholmod_factorize(a, l, &common);
    stale = !(ok && common.status == CHOLMOD_OK);
    return !stale;
  }

  // S +- b_i b_i^T / (D_i + E_i).
  bool UpDown(int i, double di, bool update) {
    auto* cp = static_cast<int*>(column->p);
    auto* ci = static_cast<int*>(column->i);
    auto* cx = static_cast<double*>(column->x);
    const double s = std::sqrt(Weight(i, di));
    int p = 0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(bt, i); it; ++it) {
      ci[p] = static_cast<int>(it.row());
      cx[p++] = s * it.value();
    }
    cp[0] = 0;
    cp[1] = p;
    if (p == 0) return true;
    const int ok = cholmod_updown(update ? 1 : 0, column, l, &common);
    return ok && common.status == CHOLMOD_OK;
  }
};

BeamWoodbury::BeamWoodbury(std::shared_ptr<const LoadProblem::CouplingFactors> factors)
    : impl_(std::make_unique<Impl>(state_)) {
  Impl& m = *impl_;
  if (factors == nullptr) throw std::invalid_argument("beam Woodbury: no factors");
  m.factors = std::move(factors);
  const LoadProblem::CouplingFactors& f = *m.factors;
  m.b = f.loads;
  m.b.makeCompressed();
  m.bt = f.loads.transpose();
  m.bt.makeCompressed();
  m.k_factor.compute(f.stiffness);
  if (m.k_factor.info() != Eigen::Success) throw std::invalid_argument("beam Woodbury: K is not positive definite");
  const int n = static_cast<int>(m.b.rows());
  const int dofs = static_cast<int>(f.stiffness.rows());
  cholmod_start(&m.common);
  m.common.print = 0;
  m.common.supernodal = CHOLMOD_SIMPLICIAL;  // updown modifies a simplicial LDL^T
  m.common.final_ll = 0;
  m.common.final_asis = 1;
  // Natural order: K is banded per pin (pin-major dofs), B^T B adds entries within an element
  // only, so there is no fill beyond the band, and updown's columns need no permutation.
  m.common.nmethods = 1;
  m.common.method[0].ordering = CHOLMOD_NATURAL;
  m.common.postorder = 0;
  // Pattern of S: K + B^T B (every point active), upper triangle, every diagonal entry.
  Eigen::SparseMatrix<double> ones = f.stiffness;
  for (int k = 0; k < ones.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(ones, k); it; ++it) it.valueRef() = 1.0;
  }
  Eigen::SparseMatrix<double> bones = m.bt;
  for (int k = 0; k < bones.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(bones, k); it; ++it) it.valueRef() = 1.0;
  }
  Eigen::SparseMatrix<double> eye(dofs, dofs);
  eye.setIdentity();
  Eigen::SparseMatrix<double> pattern = Eigen::SparseMatrix<double>(ones + bones * bones.transpose() + eye).triangularView<Eigen::Upper>();
  pattern.makeCompressed();
  const auto nnz = static_cast<std::size_t>(pattern.nonZeros());
  m.a = cholmod_allocate_sparse(static_cast<std::size_t>(dofs), static_cast<std::size_t>(dofs), nnz, 1, 1, 1,
                                CHOLMOD_REAL, &m.common);
  if (m.a == nullptr) throw std::runtime_error("beam Woodbury: CHOLMOD could not allocate S");
  std::memcpy(m.a->p, pattern.outerIndexPtr(), sizeof(int) * static_cast<std::size_t>(dofs + 1));
  std::memcpy(m.a->i, pattern.innerIndexPtr(), sizeof(int) * nnz);
  std::fill(static_cast<double*>(m.a->x), static_cast<double*>(m.a->x) + nnz, 1.0);
  for (int c = 0; c < f.stiffness.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(f.stiffness, c); it; ++it) {
      if (it.row() > c) continue;
      m.k_at.push_back(m.Position(static_cast<int>(it.row()), c));
      m.k_value.push_back(it.value());
    }
  }
  m.b_begin.assign(static_cast<std::size_t>(n) + 1, 0);
  int longest = 1;
  for (int i = 0; i < n; ++i) {
    m.b_begin[static_cast<std::size_t>(i)] = static_cast<int>(m.b_at.size());
    const int begin = m.bt.outerIndexPtr()[i], end = m.bt.outerIndexPtr()[i + 1];
    longest = std::max(longest, end - begin);
    for (int p = begin; p < end; ++p) {
      for (int q = begin; q < end; ++q) {
        const int r = m.bt.innerIndexPtr()[p], c = m.bt.innerIndexPtr()[q];
        if (r > c) continue;
        m.b_at.push_back(m.Position(r, c));
        m.b_pair.push_back(m.bt.valuePtr()[p] * m.bt.valuePtr()[q]);
      }
    }
  }
  m.b_begin[static_cast<std::size_t>(n)] = static_cast<int>(m.b_at.size());
  m.l = cholmod_analyze(m.a, &m.common);
  if (m.l == nullptr) throw std::runtime_error("beam Woodbury: cholmod_analyze failed");
  m.column = cholmod_allocate_sparse(static_cast<std::size_t>(dofs), 1, static_cast<std::size_t>(longest), 1, 1, 0,
                                     CHOLMOD_REAL, &m.common);
  if (m.column == nullptr) throw std::runtime_error("beam Woodbury: CHOLMOD could not allocate a column");
  Reset(n);
  m.held = Eigen::VectorXd::Ones(n);
}

BeamWoodbury::~BeamWoodbury() = default;

bool BeamWoodbury::Matches(const std::shared_ptr<const LoadProblem::CouplingFactors>& factors) const {
  if (factors == impl_->factors) return true;
  if (factors == nullptr) return false;
  const LoadProblem::CouplingFactors& mine = *impl_->factors;
  return mine.local.size() == factors->local.size() && mine.local == factors->local &&
         IdenticalSparse(mine.stiffness, factors->stiffness) && IdenticalSparse(mine.loads, factors->loads);
}

bool BeamWoodbury::UpdateAdd(int i, double d_i) {
  Impl& m = *impl_;
  ++m.stats.rowadds;
  m.held(i) = d_i;
  return m.UpDown(i, d_i, true);
}

bool BeamWoodbury::UpdateRemove(int i) {
  Impl& m = *impl_;
  ++m.stats.rowdels;
  return m.UpDown(i, m.held(i), false);
}

bool BeamWoodbury::Solve(const Eigen::MatrixXd& rhs, Eigen::MatrixXd* out) {
  Impl& m = *impl_;
  const int n = size();
  if (m.stale && !m.Factorise()) return false;
  const Eigen::Index k = rhs.cols();
  // y = D'^-1 r on the active points (D' = D + E, the D the factor holds).
  m.y_points.setZero(n, k);
  for (int i = 0; i < n; ++i) {
    if (m.active[static_cast<std::size_t>(i)]) m.y_points.row(i) = rhs.row(i) * m.Weight(i, m.held(i));
  }
  m.z_dofs = m.bt * m.y_points;  // B_A^T D'^-1 r
  cholmod_dense view{};
  view.nrow = static_cast<std::size_t>(m.z_dofs.rows());
  view.ncol = static_cast<std::size_t>(k);
  view.nzmax = view.nrow * view.ncol;
  view.d = view.nrow;
  view.x = m.z_dofs.data();
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  ++m.stats.solves;
  if (!cholmod_solve2(CHOLMOD_A, m.l, &view, nullptr, &m.x, nullptr, &m.y, &m.e, &m.common)) return false;
  const Eigen::Map<const Eigen::MatrixXd> u(static_cast<const double*>(m.x->x), m.z_dofs.rows(), k);
  m.b_u = m.b * u;
  out->resize(n, k);
  for (int i = 0; i < n; ++i) {
    if (m.active[static_cast<std::size_t>(i)]) {
      out->row(i) = m.y_points.row(i) - m.b_u.row(i) * m.Weight(i, m.held(i));
    } else {
      out->row(i).setZero();
    }
  }
  return out->allFinite();
}

void BeamWoodbury::Apply(const Eigen::VectorXd& f, Eigen::VectorXd* cf) const {
  const Impl& m = *impl_;
  m.load_dofs.noalias() = m.bt * f;
  m.w_dofs = m.k_factor.solve(m.load_dofs);
  cf->noalias() = m.b * m.w_dofs;
  *cf += m.factors->local.cwiseProduct(f);
}


}  // namespace ltca::solvers
