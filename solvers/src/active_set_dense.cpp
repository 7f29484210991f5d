#include "active_set_dense.hpp"
#include "sparse_identical.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace ltca::solvers {

bool ActiveSetDense::Suits(const Eigen::SparseMatrix<double>& coupling) {
  return coupling.rows() == coupling.cols() && coupling.rows() <= kDenseLimit;
}

ActiveSetDense::ActiveSetDense(const Eigen::SparseMatrix<double>& coupling, const Eigen::MatrixXd* dense) {
  if (coupling.rows() != coupling.cols()) {
    throw std::invalid_argument(fmt::format("active-set dense factor: {} x {} is not square", coupling.rows(), coupling.cols()));
  }
  dense_.resize(coupling.rows(), coupling.cols());
  Load(coupling, dense);
}

void ActiveSetDense::Load(const Eigen::SparseMatrix<double>& coupling, const Eigen::MatrixXd* dense) {
  if (coupling.rows() != dense_.rows() || coupling.cols() != dense_.cols()) {
    throw std::invalid_argument(fmt::format("active-set dense factor: {} x {} where {} x {} was held", coupling.rows(),
                                            coupling.cols(), dense_.rows(), dense_.cols()));
  }
  c_ = coupling;
  c_.makeCompressed();
  if (dense != nullptr && dense->rows() == dense_.rows() && dense->cols() == dense_.cols()) {
    dense_ = *dense;  // the same numbers, zeros where the sparse matrix has no entry
  } else {
    dense_.setZero();
    for (int j = 0; j < c_.outerSize(); ++j) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(c_, j); it; ++it) dense_(it.row(), it.col()) = it.value();
    }
  }
  Reset(static_cast<int>(dense_.rows()));
  index_.clear();
}

bool ActiveSetDense::Matches(const Eigen::SparseMatrix<double>& coupling) const {
  return IdenticalSparse(c_, coupling);
}

bool ActiveSetDense::Factorise() {
  const int n = size();
  index_.clear();
  for (int i = 0; i < n; ++i) {
    if (state_.active[static_cast<std::size_t>(i)]) index_.push_back(i);
  }
  const auto m = static_cast<Eigen::Index>(index_.size());
  m_.resize(m, m);
  for (Eigen::Index b = 0; b < m; ++b) {
    const int j = index_[static_cast<std::size_t>(b)];
    for (Eigen::Index a = b; a < m; ++a) m_(a, b) = dense_(index_[static_cast<std::size_t>(a)], j);  // lower triangle
    m_(b, b) += state_.d(j);
  }
  ++state_.stats.factorisations;
  llt_.compute(m_);  // reads the lower triangle
  state_.stale = llt_.info() != Eigen::Success;
  return !state_.stale;
}

bool ActiveSetDense::Solve(const Eigen::MatrixXd& b, Eigen::MatrixXd* x) {
  if (state_.stale && !Factorise()) return false;
  const auto m = static_cast<Eigen::Index>(index_.size());
  ++state_.stats.solves;
  x->setZero(b.rows(), b.cols());
  bool finite = true;
  for (Eigen::Index k = 0; k < b.cols(); ++k) {  // column by column: the triangular solves of a vector
    column_.resize(m);
    for (Eigen::Index a = 0; a < m; ++a) column_(a) = b(index_[static_cast<std::size_t>(a)], k);
    llt_.solveInPlace(column_);
    for (Eigen::Index a = 0; a < m; ++a) (*x)(index_[static_cast<std::size_t>(a)], k) = column_(a);
    finite = finite && column_.allFinite();
  }
  return finite;
}

void ActiveSetDense::Apply(const Eigen::VectorXd& f, Eigen::VectorXd* cf) const {
  cf->setZero(dense_.rows());
  for (Eigen::Index j = 0; j < dense_.cols(); ++j) {
    const double fj = f(j);
    if (fj == 0.0) continue;
    cf->noalias() += dense_.col(j) * fj;
  }
}

}  // namespace ltca::solvers
