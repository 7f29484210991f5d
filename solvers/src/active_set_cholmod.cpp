#include "active_set_cholmod.hpp"
#include "sparse_identical.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "cholmod_lazy.hpp"  // CHOLMOD, loaded on its first call
#include <fmt/format.h>

namespace ltca::solvers {

struct ActiveSetCholmod::Impl {
  cholmod_common common{};
  Eigen::SparseMatrix<double> c;  // compressed, both triangles: columns give rowadd's R
  cholmod_sparse* a = nullptr;    // upper triangle of the masked M (stype 1), pattern of triu(C) + diagonal
  std::vector<double> c_values;   // C at a's entries (0 where only the diagonal was added)
  cholmod_factor* l = nullptr;
  std::vector<int> iperm;         // point -> row of L
  cholmod_sparse* r = nullptr;    // rowadd's column, n x 1
  cholmod_dense* x = nullptr;     // cholmod_solve2's solution and workspaces, reused
  cholmod_dense* y = nullptr;
  cholmod_dense* e = nullptr;
  // The kernel's shared bookkeeping (ActiveSetKernel::State).
  std::vector<char>& active;
  Eigen::VectorXd& d;
  bool& stale;
  Stats& stats;
  Eigen::MatrixXd rhs;  // Solve's right-hand sides, masked (reused)

  explicit Impl(State& s) : active(s.active), d(s.d), stale(s.stale), stats(s.stats) {}

  ~Impl() {
    cholmod_free_dense(&x, &common);
    cholmod_free_dense(&y, &common);
    cholmod_free_dense(&e, &common);
    cholmod_free_sparse(&r, &common);
    cholmod_free_factor(&l, &common);
    cholmod_free_sparse(&a, &common);
    cholmod_finish(&common);
  }

  bool Factorise() {
    const int n = static_cast<int>(c.rows());
    const auto* ap = static_cast<const int*>(a->p);
    const auto* ai = static_cast<const int*>(a->i);
    auto* ax = static_cast<double*>(a->x);
    for (int j = 0; j < n; ++j) {
      for (int p = ap[j]; p < ap[j + 1]; ++p) {
        const int i = ai[p];
        if (i == j) {
          ax[p] = active[static_cast<std::size_t>(j)] ? d(j) + c_values[static_cast<std::size_t>(p)] : 1.0;
        } else {
          ax[p] = active[static_cast<std::size_t>(i)] && active[static_cast<std::size_t>(j)] ? c_values[static_cast<std::size_t>(p)] : 0.0;
        }
      }
    }
    ++stats.factorisations;
    const int ok = cholmod_factorize(a, l, &common);
    stale = !(ok && common.status == CHOLMOD_OK);
    return !stale;
  }
};

ActiveSetCholmod::ActiveSetCholmod(const Eigen::SparseMatrix<double>& coupling) : impl_(std::make_unique<Impl>(state_)) {
  Impl& m = *impl_;
  if (coupling.rows() != coupling.cols()) {
    throw std::invalid_argument(fmt::format("active-set factor: {} x {} is not square", coupling.rows(), coupling.cols()));
  }
  cholmod_start(&m.common);
  m.common.print = 0;                          // failures are reported by status, not printed
  m.common.supernodal = CHOLMOD_SIMPLICIAL;    // rowadd / rowdel modify a simplicial LDL^T
  m.common.final_ll = 0;
  m.common.final_asis = 1;
  // Natural order first: pin-major points with a block-diagonal C have no fill in it, and L's
  // rows are then the points (no permuted copy of M per factorisation); AMD for other patterns.
  m.common.nmethods = 2;
  m.common.method[0].ordering = CHOLMOD_NATURAL;
  m.common.method[1].ordering = CHOLMOD_AMD;
  m.common.postorder = 0;
  m.c = coupling;
  m.c.makeCompressed();
  const int n = static_cast<int>(m.c.rows());
  // Upper triangle with every diagonal entry.
  std::size_t nnz = 0;
  for (int j = 0; j < n; ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(m.c, j); it; ++it) nnz += it.row() < j ? 1 : 0;
    ++nnz;  // the diagonal
  }
  m.a = cholmod_allocate_sparse(static_cast<std::size_t>(n), static_cast<std::size_t>(n), nnz, 1, 1, 1, CHOLMOD_REAL,
                                &m.common);
  if (m.a == nullptr) throw std::runtime_error("active-set factor: CHOLMOD could not allocate the matrix");
  auto* ap = static_cast<int*>(m.a->p);
  auto* ai = static_cast<int*>(m.a->i);
  auto* ax = static_cast<double*>(m.a->x);
  m.c_values.assign(nnz, 0.0);
  int p = 0;
  for (int j = 0; j < n; ++j) {
    ap[j] = p;
    double diagonal = 0.0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(m.c, j); it; ++it) {  // rows ascending
      if (it.row() < j) {
        ai[p] = static_cast<int>(it.row());
        m.c_values[static_cast<std::size_t>(p)] = it.value();
        ++p;
      } else if (it.row() == j) {
        diagonal = it.value();
      }
    }
    ai[p] = j;
    m.c_values[static_cast<std::size_t>(p)] = diagonal;
    ++p;
  }
  ap[n] = p;
  std::fill(ax, ax + nnz, 1.0);
  m.l = cholmod_analyze(m.a, &m.common);
  if (m.l == nullptr) throw std::runtime_error("active-set factor: cholmod_analyze failed");
  m.iperm.assign(static_cast<std::size_t>(n), 0);
  const auto* perm = static_cast<const int*>(m.l->Perm);
  for (int k = 0; k < n; ++k) m.iperm[static_cast<std::size_t>(perm[k])] = k;
  int longest = 1;
  for (int j = 0; j < n; ++j) longest = std::max(longest, static_cast<int>(m.c.outerIndexPtr()[j + 1] - m.c.outerIndexPtr()[j]) + 1);
  m.r = cholmod_allocate_sparse(static_cast<std::size_t>(n), 1, static_cast<std::size_t>(longest), 0, 1, 0, CHOLMOD_REAL,
                                &m.common);
  if (m.r == nullptr) throw std::runtime_error("active-set factor: CHOLMOD could not allocate a column");
  Reset(n);
}

ActiveSetCholmod::~ActiveSetCholmod() = default;

const Eigen::SparseMatrix<double>& ActiveSetCholmod::coupling() const { return impl_->c; }

bool ActiveSetCholmod::Matches(const Eigen::SparseMatrix<double>& coupling) const {
  return IdenticalSparse(impl_->c, coupling);  // c is kept compressed
}

void ActiveSetKernel::Reset(int n) {
  state_.active.assign(static_cast<std::size_t>(n), 0);
  state_.d = Eigen::VectorXd::Ones(n);
  state_.stale = true;
}

void ActiveSetKernel::SetDiagonal(const Eigen::VectorXd& d) {
  state_.d = d;
  state_.stale = true;
}

void ActiveSetKernel::Add(int i, double d_i) {
  const auto k = static_cast<std::size_t>(i);
  if (state_.active[k]) return;
  state_.active[k] = 1;
  state_.d(i) = d_i;
  if (state_.stale) return;
  if (!UpdateAdd(i, d_i)) state_.stale = true;
}

void ActiveSetKernel::Remove(int i) {
  const auto k = static_cast<std::size_t>(i);
  if (!state_.active[k]) return;
  state_.active[k] = 0;
  if (state_.stale) return;
  if (!UpdateRemove(i)) state_.stale = true;
}

bool ActiveSetCholmod::UpdateAdd(int i, double d_i) {
  Impl& m = *impl_;
  const auto k = static_cast<std::size_t>(i);
  // Column i of the masked M in L's row order: C_ji over the active points j, D_i + C_ii on the diagonal.
  auto* rp = static_cast<int*>(m.r->p);
  auto* ri = static_cast<int*>(m.r->i);
  auto* rx = static_cast<double*>(m.r->x);
  int p = 0;
  bool diagonal = false;
  for (Eigen::SparseMatrix<double>::InnerIterator it(m.c, i); it; ++it) {
    const auto j = static_cast<int>(it.row());
    if (j == i) {
      ri[p] = m.iperm[k];
      rx[p++] = d_i + it.value();
      diagonal = true;
    } else if (m.active[static_cast<std::size_t>(j)]) {
      ri[p] = m.iperm[static_cast<std::size_t>(j)];
      rx[p++] = it.value();
    }
  }
  if (!diagonal) {
    ri[p] = m.iperm[k];
    rx[p++] = d_i;
  }
  rp[0] = 0;
  rp[1] = p;
  m.r->sorted = 0;
  ++m.stats.rowadds;
  const int ok = cholmod_rowadd(static_cast<std::size_t>(m.iperm[k]), m.r, m.l, &m.common);
  // The new pivot must be positive (M_AA is positive definite); otherwise refactorise from scratch.
  const auto* lp = static_cast<const int*>(m.l->p);
  const auto* lx = static_cast<const double*>(m.l->x);
  return ok && m.common.status == CHOLMOD_OK && lx[lp[m.iperm[k]]] > 0.0;
}

bool ActiveSetCholmod::UpdateRemove(int i) {
  Impl& m = *impl_;
  ++m.stats.rowdels;
  const int ok = cholmod_rowdel(static_cast<std::size_t>(m.iperm[static_cast<std::size_t>(i)]), nullptr, m.l, &m.common);
  return ok && m.common.status == CHOLMOD_OK;
}

bool ActiveSetCholmod::Solve(const Eigen::MatrixXd& b, Eigen::MatrixXd* x) {
  Impl& m = *impl_;
  const int n = size();
  if (m.stale && !m.Factorise()) return false;
  Eigen::MatrixXd& rhs = m.rhs;
  rhs = b;
  for (int i = 0; i < n; ++i) {
    if (!m.active[static_cast<std::size_t>(i)]) rhs.row(i).setZero();
  }
  cholmod_dense view{};
  view.nrow = static_cast<std::size_t>(n);
  view.ncol = static_cast<std::size_t>(rhs.cols());
  view.nzmax = view.nrow * view.ncol;
  view.d = view.nrow;
  view.x = rhs.data();
  view.z = nullptr;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  ++m.stats.solves;
  if (!cholmod_solve2(CHOLMOD_A, m.l, &view, nullptr, &m.x, nullptr, &m.y, &m.e, &m.common)) return false;
  x->resize(n, rhs.cols());
  std::memcpy(x->data(), m.x->x, sizeof(double) * static_cast<std::size_t>(n) * static_cast<std::size_t>(rhs.cols()));
  for (int i = 0; i < n; ++i) {
    if (!m.active[static_cast<std::size_t>(i)]) x->row(i).setZero();
  }
  return x->allFinite();
}

void ActiveSetCholmod::Apply(const Eigen::VectorXd& f, Eigen::VectorXd* cf) const {
  const Eigen::SparseMatrix<double>& c = impl_->c;
  cf->setZero(c.rows());
  for (int j = 0; j < c.outerSize(); ++j) {
    const double fj = f(j);
    if (fj == 0.0) continue;
    for (Eigen::SparseMatrix<double>::InnerIterator e(c, j); e; ++e) (*cf)(e.row()) += e.value() * fj;
  }
}

}  // namespace ltca::solvers
