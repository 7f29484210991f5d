// The private CHOLMOD kernel of the coupled solves (solvers/src/active_set_cholmod.hpp): after any
// sequence of points entering and leaving the active set (cholmod_rowadd / rowdel) and new
// diagonals (numeric refactorisation), its solve equals a dense solve of M_AA = D_A + C_AA (Eigen's
// LDLT, an independent factorisation) to 1e-12 relative, with zeros on the inactive rows.
#include <algorithm>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <doctest/doctest.h>

#include "active_set_cholmod.hpp"

using ltca::solvers::ActiveSetCholmod;

namespace {

// Block diagonal (dense positive definite blocks) plus, optionally, a ring coupling the blocks
// (so that the fill-reducing ordering and the permutation of rowadd's column matter).
Eigen::SparseMatrix<double> Coupling(int blocks, int size, bool ring, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = blocks * size;
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  for (int b = 0; b < blocks; ++b) {
    Eigen::MatrixXd g(size, size);
    for (int i = 0; i < size; ++i) for (int j = 0; j < size; ++j) g(i, j) = u(rng);
    dense.block(b * size, b * size, size, size) = 1e-6 * g * g.transpose() / size;
  }
  if (ring) {
    for (int i = 0; i < n; ++i) {  // diagonally dominant additions keep it positive semidefinite
      const int j = (i + size) % n;
      dense(i, j) += 2e-7;
      dense(j, i) += 2e-7;
      dense(i, i) += 2e-7;
      dense(j, j) += 2e-7;
    }
  }
  return dense.sparseView();
}

Eigen::VectorXd Reference(const Eigen::SparseMatrix<double>& c, const Eigen::VectorXd& d, const std::vector<char>& active,
                          const Eigen::VectorXd& b) {
  const auto n = static_cast<int>(c.rows());
  std::vector<int> a;
  for (int i = 0; i < n; ++i) if (active[static_cast<std::size_t>(i)]) a.push_back(i);
  const auto m = static_cast<Eigen::Index>(a.size());
  const Eigen::MatrixXd full(c);
  Eigen::MatrixXd maa(m, m);
  Eigen::VectorXd ba(m);
  for (Eigen::Index r = 0; r < m; ++r) {
    for (Eigen::Index q = 0; q < m; ++q) maa(r, q) = full(a[static_cast<std::size_t>(r)], a[static_cast<std::size_t>(q)]);
    maa(r, r) += d(a[static_cast<std::size_t>(r)]);
    ba(r) = b(a[static_cast<std::size_t>(r)]);
  }
  const Eigen::VectorXd xa = maa.ldlt().solve(ba);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  for (Eigen::Index r = 0; r < m; ++r) x(a[static_cast<std::size_t>(r)]) = xa(r);
  return x;
}

}  // namespace

TEST_CASE("solvers: active-set CHOLMOD kernel - rowadd / rowdel and refactorisations match a dense solve") {
  for (const bool ring : {false, true}) {
    CAPTURE(ring);
    std::mt19937 rng(ring ? 11 : 7);
    const Eigen::SparseMatrix<double> c = Coupling(6, 5, ring, rng);
    const int n = static_cast<int>(c.rows());
    ActiveSetCholmod kernel(c);
    CHECK(kernel.Matches(c));
    Eigen::SparseMatrix<double> other = c;
    other.coeffRef(0, 0) *= 2.0;
    CHECK_FALSE(kernel.Matches(other));
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Eigen::VectorXd d(n);
    for (int i = 0; i < n; ++i) d(i) = 4e-6 * (0.5 + u(rng));
    std::vector<char> active(static_cast<std::size_t>(n), 0);
    kernel.SetDiagonal(d);
    for (int i = 0; i < n; i += 2) {
      kernel.Add(i, d(i));
      active[static_cast<std::size_t>(i)] = 1;
    }
    double worst = 0.0;
    for (int step = 0; step < 200; ++step) {
      CAPTURE(step);
      const int i = static_cast<int>(u(rng) * n) % n;
      if (step % 37 == 36) {  // a new diagonal: numeric refactorisation
        for (int k = 0; k < n; ++k) d(k) = 4e-6 * (0.5 + u(rng));
        kernel.SetDiagonal(d);
      } else if (active[static_cast<std::size_t>(i)]) {
        kernel.Remove(i);
        active[static_cast<std::size_t>(i)] = 0;
      } else {
        d(i) = 4e-6 * (0.5 + u(rng));
        kernel.Add(i, d(i));
        active[static_cast<std::size_t>(i)] = 1;
      }
      Eigen::MatrixXd b(n, 2), x;
      for (int k = 0; k < n; ++k) b(k, 0) = u(rng) - 0.5, b(k, 1) = 1.0;
      REQUIRE(kernel.Solve(b, &x));
      for (int col = 0; col < 2; ++col) {
        const Eigen::VectorXd want = Reference(c, d, active, b.col(col));
        const double scale = std::max(want.cwiseAbs().maxCoeff(), 1e-300);
        const double error = (x.col(col) - want).cwiseAbs().maxCoeff() / scale;
        worst = std::max(worst, error);
        CHECK(error < 1e-12);
        for (int k = 0; k < n; ++k) if (!active[static_cast<std::size_t>(k)]) CHECK(x(k, col) == 0.0);
      }
      for (int k = 0; k < n; ++k) CHECK(kernel.active(k) == (active[static_cast<std::size_t>(k)] != 0));
    }
    // The set changes went through rowadd / rowdel, not through new factorisations.
    const auto& s = kernel.stats();
    CHECK(s.factorisations <= 7);
    CHECK(s.rowadds + s.rowdels >= 150);
    MESSAGE("ring ", ring, ": worst relative error ", worst, ", factorisations ", s.factorisations, ", rowadds ",
            s.rowadds, ", rowdels ", s.rowdels);
  }
}
