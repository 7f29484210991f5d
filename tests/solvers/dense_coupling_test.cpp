// A small dense coupling, as the elastic disc body gives (contact::DiscFlankCompliance::Coupling:
// every contact point coupled to every other, a new matrix at every crank position), without the
// finite-element body: a synthetic symmetric positive semidefinite matrix over the 40 pins of
// Liu's section 5.2 pair, C = s G + e I with G_ij = exp(-|x_i - x_j|^2 / (2 w^2)) over the pins'
// centres x (the Gaussian kernel is positive definite: a Gram matrix), s of the order of a contact's
// own compliance. The coupled solves take the dense kernel (ActiveSetDense) here; it is checked
// against a dense solve and against the CHOLMOD kernel, and every registered solver against the
// others on the problem.
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <doctest/doctest.h>

#include "active_set_cholmod.hpp"
#include "active_set_dense.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "ltca/solvers/registry.hpp"
#include "ltca/solvers/workspace.hpp"
#include "helpers.hpp"
#include "problems.hpp"

namespace dense_coupling_test {

using ltca::contact::ContactKinematics;
using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::SolverStatus;

/// Liu 2021 section 5.2's pair with the signed rho (as the elastic disc body's deck runs it).
const ltca::test::PaperCase& Case() {
  static const ltca::test::PaperCase c = [] {
    ltca::test::PaperCase p = ltca::test::LiuSec52Base();
    p.contact.rho_convention = ltca::contact::RhoConvention::kSigned;
    return p;
  }();
  return c;
}
std::shared_ptr<const ltca::contact::MeshModel> Model() {
  static const auto model = Case().Model();
  return model;
}

/// C = s G + e I over the problem's points (mm/N): G the Gaussian kernel of the pins' centres with
/// width w = 1.5 pin pitches; s = 3e-6 mm/N, e = 2e-7 mm/N (a hertz-line contact near 1 kN has
/// about 2.5e-6 mm/N of its own).
Eigen::MatrixXd BodyLike(const LoadProblem& problem) {
  const auto& pins = problem.base_state().pins;
  const auto n = static_cast<Eigen::Index>(pins.size());
  const double r = Model()->pair().pin_circle_radius;
  const double w = 1.5 * 2.0 * 3.141592653589793 * r / Model()->pin_count();
  Eigen::MatrixXd c(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      const double d = (pins[static_cast<std::size_t>(i)].pin_point - pins[static_cast<std::size_t>(j)].pin_point).norm();
      c(i, j) = 3e-6 * std::exp(-d * d / (2.0 * w * w)) + (i == j ? 2e-7 : 0.0);
    }
  }
  return c;
}

LoadProblem Coupled(double crank_deg, ContactKinematics kinematics) {
  const LoadProblem plain = Case().Problem(Model(), ltca::units::DegToRad(crank_deg), kinematics);
  const Eigen::MatrixXd c = BodyLike(plain);
  return plain.WithCoupling(LoadProblem::CheckCoupling(Eigen::SparseMatrix<double>(c.sparseView()), plain.point_count(),
                                                       LoadProblem::PositiveSemidefiniteByConstruction{}));
}


/// Solved with the torque balanced to 1e-13 (the default tolerance, 1e-10, would leave the
/// solvers apart by about that much of the TE).
LoadResult Tight(const std::string& name, const LoadProblem& problem, ltca::solvers::Workspace& workspace) {
  ltca::solvers::SolverOptions options;
  options.name = name;
  options.torque_tolerance = 1e-13;
  return ltca::solvers::MakeSolver(name)->Solve(problem, options, workspace);
}

}  // namespace dense_coupling_test

TEST_CASE("solvers: dense active-set kernel - refactorised after set changes, it solves as a dense LDLT and the CHOLMOD kernel do") {
  using ltca::solvers::ActiveSetCholmod;
  using ltca::solvers::ActiveSetDense;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 40;
  Eigen::MatrixXd g(n, n);
  for (int i = 0; i < n; ++i) for (int j = 0; j < n; ++j) g(i, j) = u(rng) - 0.5;
  const Eigen::MatrixXd full = 1e-6 * g * g.transpose() / n;  // positive semidefinite, dense
  const Eigen::SparseMatrix<double> c = full.sparseView();
  REQUIRE(ActiveSetDense::Suits(c));
  ActiveSetDense dense(c);
  ActiveSetCholmod sparse(c);
  CHECK(dense.Matches(c));
  Eigen::SparseMatrix<double> other = c;
  other.coeffRef(0, 0) *= 2.0;
  CHECK_FALSE(dense.Matches(other));
  // A new matrix loaded in place starts as a new kernel; the original loaded back matches again.
  dense.Load(other);
  CHECK(dense.Matches(other));
  CHECK_FALSE(dense.Matches(c));
  dense.Load(c);
  CHECK(dense.Matches(c));
  CHECK(std::none_of(dense.active_set().begin(), dense.active_set().end(), [](char a) { return a != 0; }));
  CHECK_THROWS_AS(dense.Load(Eigen::SparseMatrix<double>(3, 3)), std::invalid_argument);
  Eigen::VectorXd d(n);
  for (int i = 0; i < n; ++i) d(i) = 4e-6 * (0.5 + u(rng));
  std::vector<char> active(static_cast<std::size_t>(n), 0);
  dense.SetDiagonal(d);
  sparse.SetDiagonal(d);
  double worst = 0.0, worst_kernels = 0.0;
  for (int step = 0; step < 200; ++step) {
    CAPTURE(step);
    const int i = static_cast<int>(u(rng) * n) % n;
    if (step % 37 == 36) {
      for (int k = 0; k < n; ++k) d(k) = 4e-6 * (0.5 + u(rng));
      dense.SetDiagonal(d);
      sparse.SetDiagonal(d);
    } else if (active[static_cast<std::size_t>(i)]) {
      dense.Remove(i);
      sparse.Remove(i);
      active[static_cast<std::size_t>(i)] = 0;
    } else {
      d(i) = 4e-6 * (0.5 + u(rng));
      dense.Add(i, d(i));
      sparse.Add(i, d(i));
      active[static_cast<std::size_t>(i)] = 1;
    }
    Eigen::MatrixXd b(n, 2), x, y;
    for (int k = 0; k < n; ++k) b(k, 0) = u(rng) - 0.5, b(k, 1) = 1.0;
    if (std::none_of(active.begin(), active.end(), [](char a) { return a != 0; })) continue;
    REQUIRE(dense.Solve(b, &x));
    REQUIRE(sparse.Solve(b, &y));
    std::vector<int> a;
    for (int k = 0; k < n; ++k) if (active[static_cast<std::size_t>(k)]) a.push_back(k);
    const auto m = static_cast<Eigen::Index>(a.size());
    Eigen::MatrixXd maa(m, m);
    for (Eigen::Index r = 0; r < m; ++r) {
      for (Eigen::Index q = 0; q < m; ++q) maa(r, q) = full(a[static_cast<std::size_t>(r)], a[static_cast<std::size_t>(q)]);
      maa(r, r) += d(a[static_cast<std::size_t>(r)]);
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(maa);
    for (int col = 0; col < 2; ++col) {
      Eigen::VectorXd ba(m);
      for (Eigen::Index r = 0; r < m; ++r) ba(r) = b(a[static_cast<std::size_t>(r)], col);
      const Eigen::VectorXd xa = ldlt.solve(ba);
      const double scale = std::max(xa.cwiseAbs().maxCoeff(), 1e-300);
      for (Eigen::Index r = 0; r < m; ++r) {
        worst = std::max(worst, std::abs(x(a[static_cast<std::size_t>(r)], col) - xa(r)) / scale);
      }
      worst_kernels = std::max(worst_kernels, (x.col(col) - y.col(col)).cwiseAbs().maxCoeff() / scale);
      for (int k = 0; k < n; ++k) if (!active[static_cast<std::size_t>(k)]) CHECK(x(k, col) == 0.0);
    }
    // C f over all points, f with zeros (the kernel skips them).
    Eigen::VectorXd f = Eigen::VectorXd::Zero(n), cf, cs;
    for (const int k : a) f(k) = u(rng);
    dense.Apply(f, &cf);
    sparse.Apply(f, &cs);
    CHECK((cf - full * f).cwiseAbs().maxCoeff() <= 1e-13 * (full.cwiseAbs() * f.cwiseAbs()).maxCoeff());
    CHECK((cf - cs).cwiseAbs().maxCoeff() <= 1e-13 * cs.cwiseAbs().maxCoeff());
  }
  CHECK(worst < 1e-12);
  CHECK(worst_kernels < 1e-12);
  MESSAGE("dense kernel: worst relative error against LDLT ", worst, ", against the CHOLMOD kernel ", worst_kernels);
}

TEST_CASE("solvers: a body-like dense coupling - the caller's promise skips only the eigenvalue check") {
  using namespace dense_coupling_test;
  const LoadProblem plain = Case().Problem(Model(), 0.0, ContactKinematics::kLinearised);
  const int n = plain.point_count();
  const Eigen::SparseMatrix<double> c = BodyLike(plain).sparseView();
  const LoadProblem checked = plain.WithCoupling(c);  // the full check passes: C is positive semidefinite
  const LoadProblem promised = Coupled(0.0, ContactKinematics::kLinearised);
  REQUIRE(checked.coupling() != nullptr);
  REQUIRE(promised.coupling() != nullptr);
  const Eigen::MatrixXd a(*checked.coupling()), b(*promised.coupling());
  CHECK((a.array() == b.array()).all());  // stored the same way, bit for bit
  const LoadProblem::PositiveSemidefiniteByConstruction promise;
  // The other checks stay: the size, finiteness and symmetry.
  CHECK_THROWS_AS(LoadProblem::CheckCoupling(c, n + 1, promise), std::invalid_argument);
  Eigen::SparseMatrix<double> skew = c;
  skew.coeffRef(0, 1) *= 1.01;
  CHECK_THROWS_AS(LoadProblem::CheckCoupling(skew, n, promise), std::invalid_argument);
  Eigen::SparseMatrix<double> nan = c;
  nan.coeffRef(2, 2) = NAN;
  CHECK_THROWS_AS(LoadProblem::CheckCoupling(nan, n, promise), std::invalid_argument);
  // Without the promise an indefinite matrix is refused as before.
  Eigen::SparseMatrix<double> indefinite = c;
  indefinite.coeffRef(3, 3) = -1e-5;
  CHECK_THROWS_AS(plain.WithCoupling(indefinite), std::invalid_argument);
}

TEST_CASE("solvers: a coupling checked dense is stored as the sparse check stores it, bit for bit, and refused alike") {
  // The elastic disc body's coupling is checked dense (Stage::Problem): the sparse matrix it stores
  // must be the sparse overload's, entry for entry and in pattern, and the dense copy the kernel
  // takes must hold the same numbers. The matrix: the body-like C with a few exact zeros (pins
  // far apart) and entries nudged off symmetry by up to 1e-13 relative (within the tolerance).
  using namespace dense_coupling_test;
  const LoadProblem plain = Case().Problem(Model(), 0.0, ContactKinematics::kLinearised);
  const int n = plain.point_count();
  Eigen::MatrixXd c = BodyLike(plain);
  std::mt19937 rng(48);
  std::uniform_real_distribution<double> nudge(-1e-13, 1e-13);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (i != j) c(i, j) *= 1.0 + nudge(rng);
    }
  }
  c(0, 5) = c(5, 0) = 0.0;
  c(7, 30) = c(30, 7) = 0.0;
  const LoadProblem::PositiveSemidefiniteByConstruction promise;
  const LoadProblem::CheckedCoupling sparse = LoadProblem::CheckCoupling(Eigen::SparseMatrix<double>(c.sparseView()), n, promise);
  const LoadProblem::CheckedCoupling dense = LoadProblem::CheckCoupling(c, n, promise);
  REQUIRE(sparse.matrix != nullptr);
  REQUIRE(dense.matrix != nullptr);
  REQUIRE(dense.dense != nullptr);
  CHECK(sparse.dense == nullptr);
  const Eigen::SparseMatrix<double>& a = *sparse.matrix;
  const Eigen::SparseMatrix<double>& b = *dense.matrix;
  REQUIRE(a.nonZeros() == b.nonZeros());
  REQUIRE(b.isCompressed());
  CHECK(b.nonZeros() == n * n - 4);  // the four zeros dropped
  CHECK(std::equal(a.outerIndexPtr(), a.outerIndexPtr() + n + 1, b.outerIndexPtr()));
  CHECK(std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr()));
  CHECK(std::equal(a.valuePtr(), a.valuePtr() + a.nonZeros(), b.valuePtr()));
  CHECK((Eigen::MatrixXd(a).array() == dense.dense->array()).all());
  CHECK((dense.dense->array() == dense.dense->transpose().array()).all());
  // A problem given either solves to the same numbers: the dense kernel reads the same C.
  ltca::solvers::Workspace w1, w2;
  const LoadResult r1 = Tight("bisection", plain.WithCoupling(sparse), w1);
  const LoadResult r2 = Tight("bisection", plain.WithCoupling(dense), w2);
  REQUIRE(r1.status == SolverStatus::kSuccess);
  CHECK(r1.rotation == r2.rotation);
  CHECK(r1.force == r2.force);
  // The same refusals: size, square, finiteness, symmetry beyond 1e-12; all zero is no coupling.
  CHECK_THROWS_WITH_AS(LoadProblem::CheckCoupling(c, n + 1, promise), doctest::Contains("does not match"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(LoadProblem::CheckCoupling(Eigen::MatrixXd(c.leftCols(n - 1)), n, promise),
                       doctest::Contains("not square"), std::invalid_argument);
  Eigen::MatrixXd skew = c;
  skew(0, 1) *= 1.01;
  CHECK_THROWS_WITH_AS(LoadProblem::CheckCoupling(skew, n, promise), doctest::Contains("not symmetric"), std::invalid_argument);
  Eigen::MatrixXd nan = c;
  nan(2, 2) = NAN;
  CHECK_THROWS_WITH_AS(LoadProblem::CheckCoupling(nan, n, promise), doctest::Contains("not finite"), std::invalid_argument);
  CHECK(LoadProblem::CheckCoupling(Eigen::MatrixXd::Zero(n, n).eval(), n, promise).matrix == nullptr);
}

TEST_CASE("solvers: a body-like dense coupling - every registered solver agrees to 1e-9, linearised and exact") {
  // TE to 1e-9 relative and every force to 1e-9 of the largest, against bisection, at three cranks
  // of a mesh period; one workspace per solver over the cranks, as a sweep keeps it (the dense
  // kernel takes each crank's new matrix in place). Linearised, a workspace kept over the cranks
  // gives bisection's and compatibility's answers bit for bit as a new one does.
  using namespace dense_coupling_test;
  const std::vector<std::string> names = ltca::solvers::SolverNames();
  REQUIRE(names.size() >= 4);
  for (const auto kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    std::vector<ltca::solvers::Workspace> workspaces(names.size());
    double worst_te = 0.0, worst_force = 0.0;
    for (const double crank : {0.0, 2.7, 6.1}) {
      CAPTURE(static_cast<int>(kinematics));
      CAPTURE(crank);
      const LoadProblem problem = Coupled(crank, kinematics);
      const LoadProblem plain = Case().Problem(Model(), ltca::units::DegToRad(crank), kinematics);
      std::vector<LoadResult> r;
      for (std::size_t s = 0; s < names.size(); ++s) {
        CAPTURE(names[s]);
        r.push_back(Tight(names[s], problem, workspaces[s]));
        REQUIRE(r.back().status == SolverStatus::kSuccess);
        CHECK(r.back().residuals.Normalised() < 1e-9);
      }
      const std::size_t bisection = static_cast<std::size_t>(std::find(names.begin(), names.end(), "bisection") - names.begin());
      REQUIRE(bisection < names.size());
      const LoadResult& ref = r[bisection];
      for (std::size_t s = 0; s < names.size(); ++s) {
        CAPTURE(names[s]);
        const double te = std::abs(r[s].te - ref.te) / std::abs(ref.te);
        const double force = ltca::test::MaxDifference(r[s].force, ref.force) / ltca::test::MaxAbs(ref.force);
        CHECK(te <= 1e-9);
        CHECK(force <= 1e-9);
        worst_te = std::max(worst_te, te);
        worst_force = std::max(worst_force, force);
      }
      // The body turns the cycloid further than the rigid disc and loads more pins.
      ltca::solvers::Workspace fresh;
      const LoadResult rigid = Tight("bisection", plain, fresh);
      REQUIRE(rigid.status == SolverStatus::kSuccess);
      CHECK(std::abs(ref.te) > 1.1 * std::abs(rigid.te));
      CHECK(ref.active.size() >= rigid.active.size());
      if (kinematics == ContactKinematics::kLinearised) {
        for (const std::string name : {"bisection", "compatibility"}) {
          CAPTURE(name);
          ltca::solvers::Workspace one;
          const LoadResult alone = Tight(name, problem, one);
          const std::size_t s = static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
          CHECK(alone.te == r[s].te);
          CHECK(alone.force == r[s].force);
        }
      }
    }
    MESSAGE("kinematics ", static_cast<int>(kinematics), ": every solver within ", worst_te, " of bisection's TE, ",
            worst_force, " of the largest force");
  }
}
