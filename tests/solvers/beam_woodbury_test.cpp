// The Woodbury kernel of the coupled solves for a coupling given in factored form (issue 11,
// solvers/src/beam_woodbury.hpp): C = B K^-1 B^T + E of pin bending (contact::PinBendingFactors).
// Its solves after random set changes (cholmod_updown) and refactorisations equal a dense solve of
// (D + C)_AA with the explicit C (PinBendingCoupling); its C F equals the matrix product; and the
// coupled backends (bisection, compatibility) give the same answers with the factored coupling as
// with the matrix alone, over a mesh period, linearised and exact.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <doctest/doctest.h>

#include "beam_woodbury.hpp"
#include "ltca/contact/pin_bending.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "ltca/solvers/registry.hpp"
#include "problems.hpp"

using ltca::contact::ContactKinematics;
using ltca::contact::MeshModel;
using ltca::contact::MeshState;
using ltca::solvers::BeamWoodbury;
using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::MakeSolver;
using ltca::solvers::SolverOptions;
using ltca::solvers::SolverStatus;

namespace {

const ltca::test::PaperCase& Liu() {
  static const ltca::test::PaperCase liu = ltca::test::LiuTable1();
  return liu;
}
std::shared_ptr<const MeshModel> LiuModel() {
  static const auto model = Liu().Model();
  return model;
}

ltca::contact::PinBeam Pin(ltca::contact::PinSupportKind kind, double span = 16.0, double offset = 2.0) {
  ltca::contact::PinSupport support;
  support.span = span;
  support.support = kind;
  support.face_offset = offset;
  return ltca::contact::PinBeam(support, Liu().material, LiuModel()->pair().pin_radius);
}

// The plane model's state with every pin split into n slices of B / n (pin-major).
LoadProblem SlicedProblem(double crank_deg, int n) {
  return LoadProblem(LiuModel(), ltca::test::Sliced(*LiuModel(), crank_deg, n), Liu().contact, Liu().material, Liu().torque);
}

LoadProblem::CheckedCoupling Factored(const LoadProblem& p, const ltca::contact::PinBeam& beam) {
  return ltca::test::FactoredBending(p.base_state().pins, beam, LiuModel()->pair().face_width, p.point_count());
}

double MaxDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}
double MaxAbs(const std::vector<double>& a) {
  double m = 0.0;
  for (double x : a) m = std::max(m, std::abs(x));
  return m;
}

}  // namespace

TEST_CASE("solvers: beam Woodbury kernel - updown and refactorisations match a dense solve of D + C") {
  for (const auto kind : {ltca::contact::PinSupportKind::kClamped, ltca::contact::PinSupportKind::kSimplySupported}) {
    CAPTURE(std::string(ltca::contact::ToString(kind)));
    const LoadProblem p = SlicedProblem(1.0, 7);
    const LoadProblem::CheckedCoupling coupling = Factored(p, Pin(kind));
    const Eigen::MatrixXd c(*coupling.matrix);
    const int n = static_cast<int>(c.rows());
    BeamWoodbury kernel(coupling.factors);
    CHECK(kernel.Matches(coupling.factors));
    CHECK(kernel.Matches(Factored(p, Pin(kind)).factors));  // equal values
    CHECK_FALSE(kernel.Matches(Factored(p, Pin(kind, 17.0)).factors));
    std::mt19937 rng(kind == ltca::contact::PinSupportKind::kClamped ? 3 : 5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    // C F against the matrix.
    Eigen::VectorXd f(n), cf;
    for (int i = 0; i < n; ++i) f(i) = u(rng) < 0.3 ? 100.0 * u(rng) : 0.0;
    kernel.Apply(f, &cf);
    const Eigen::VectorXd want_cf = c * f;
    CHECK((cf - want_cf).cwiseAbs().maxCoeff() <= 1e-12 * want_cf.cwiseAbs().maxCoeff());
    const double scale = c.diagonal().maxCoeff();
    Eigen::VectorXd d(n);
    for (int i = 0; i < n; ++i) d(i) = scale * (0.5 + u(rng));
    std::vector<char> active(static_cast<std::size_t>(n), 0);
    kernel.SetDiagonal(d);
    for (int i = 0; i < n; i += 3) {
      kernel.Add(i, d(i));
      active[static_cast<std::size_t>(i)] = 1;
    }
    double worst = 0.0;
    for (int step = 0; step < 300; ++step) {
      CAPTURE(step);
      const int i = static_cast<int>(u(rng) * n) % n;
      if (step % 47 == 46) {
        for (int k = 0; k < n; ++k) d(k) = scale * (0.5 + u(rng));
        kernel.SetDiagonal(d);
      } else if (active[static_cast<std::size_t>(i)]) {
        kernel.Remove(i);
        active[static_cast<std::size_t>(i)] = 0;
      } else {
        d(i) = scale * (0.5 + u(rng));
        kernel.Add(i, d(i));
        active[static_cast<std::size_t>(i)] = 1;
      }
      if (step % 10 != 0) continue;
      std::vector<int> a;
      for (int k = 0; k < n; ++k) if (active[static_cast<std::size_t>(k)]) a.push_back(k);
      const auto m = static_cast<Eigen::Index>(a.size());
      Eigen::MatrixXd b(n, 2), x;
      for (int k = 0; k < n; ++k) b(k, 0) = u(rng) - 0.5, b(k, 1) = 1.0;
      REQUIRE(kernel.Solve(b, &x));
      Eigen::MatrixXd maa(m, m), ba(m, 2);
      for (Eigen::Index r = 0; r < m; ++r) {
        for (Eigen::Index q = 0; q < m; ++q) maa(r, q) = c(a[static_cast<std::size_t>(r)], a[static_cast<std::size_t>(q)]);
        maa(r, r) += d(a[static_cast<std::size_t>(r)]);
        ba.row(r) = b.row(a[static_cast<std::size_t>(r)]);
      }
      const Eigen::MatrixXd xa = maa.ldlt().solve(ba);
      for (int col = 0; col < 2; ++col) {
        const double error =
            [&] {
              double e = 0.0;
              for (Eigen::Index r = 0; r < m; ++r) e = std::max(e, std::abs(x(a[static_cast<std::size_t>(r)], col) - xa(r, col)));
              return e;
            }() /
            std::max(xa.col(col).cwiseAbs().maxCoeff(), 1e-300);
        worst = std::max(worst, error);
        CHECK(error < 1e-10);
      }
      for (int k = 0; k < n; ++k) if (!active[static_cast<std::size_t>(k)]) CHECK(x(k, 0) == 0.0);
    }
    const auto& s = kernel.stats();
    CHECK(s.factorisations <= 8);
    CHECK(s.rowadds + s.rowdels >= 200);
    MESSAGE("beam Woodbury: worst relative error ", worst, ", factorisations ", s.factorisations, ", updates ",
            s.rowadds, ", downdates ", s.rowdels);
  }
}

TEST_CASE("solvers: beam Woodbury - bisection and compatibility give the same answers with the factored coupling") {
  // Hand-sliced Liu Table 1 (linearised), n = 5 and 20; the slice model of cases/pin_bending.toml
  // (20 slices, tests/problems.hpp) with its factored coupling, linearised and exact (n = 0).
  static const ltca::test::PaperCase bending = ltca::test::PinBendingCase();
  static const auto model = bending.Model();
  for (const int n : {5, 20, 0}) {
    for (const auto kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
      if (n > 0 && kinematics == ContactKinematics::kExact) continue;  // a hand-made state is linearised only
      ltca::solvers::Workspace matrix_ws[2], factored_ws[2];
      const char* names[2] = {"bisection", "compatibility"};
      double worst_te = 0.0, worst_force = 0.0;
      double seconds[2] = {0.0, 0.0};
      for (int k = 0; k < 5; ++k) {
        const double crank = 9.0 * k / 5;
        CAPTURE(n);
        CAPTURE(crank);
        const LoadProblem plain = n > 0 ? SlicedProblem(crank, n)
                                        : LoadProblem(model, ltca::units::DegToRad(crank), bending.contact,
                                                      bending.material, bending.torque, kinematics);
        const LoadProblem::CheckedCoupling factored =
            n > 0 ? Factored(plain, Pin(ltca::contact::PinSupportKind::kClamped))
                  : ltca::test::FactoredBending(plain.base_state().pins, bending.Beam(), bending.pair.face_width,
                                                plain.point_count());
        LoadProblem::CheckedCoupling matrix_only = factored;
        matrix_only.factors = nullptr;
        const LoadProblem with_matrix = plain.WithCoupling(matrix_only);
        const LoadProblem with_factors = plain.WithCoupling(factored);
        REQUIRE(with_matrix.coupling_factors() == nullptr);
        REQUIRE(with_factors.coupling_factors() != nullptr);
        for (int s = 0; s < 2; ++s) {
          CAPTURE(std::string(names[s]));
          SolverOptions options;
          options.name = names[s];
          auto start = std::chrono::steady_clock::now();
          const LoadResult a = MakeSolver(names[s])->Solve(with_matrix, options, matrix_ws[s]);
          const double t0 = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          start = std::chrono::steady_clock::now();
          const LoadResult b = MakeSolver(names[s])->Solve(with_factors, options, factored_ws[s]);
          const double t1 = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          seconds[0] += t0, seconds[1] += t1;
          REQUIRE(a.status == SolverStatus::kSuccess);
          REQUIRE(b.status == SolverStatus::kSuccess);
          CHECK(b.residuals.Normalised() < 1e-8);
          const double te = std::abs(a.te - b.te) / std::abs(a.te);
          const double force = MaxDifference(a.force, b.force) / MaxAbs(a.force);
          CHECK(te < 1e-9);
          CHECK(force < 1e-9);
          worst_te = std::max(worst_te, te);
          worst_force = std::max(worst_force, force);
        }
      }
      MESSAGE(n, " slices, ", std::string(kinematics == ContactKinematics::kExact ? "exact" : "linearised"),
              ": factored vs matrix coupling, TE to ", worst_te, ", forces to ", worst_force, "; time ",
              1e3 * seconds[1] / 10, " ms vs ", 1e3 * seconds[0] / 10, " ms per solve");
    }
  }
}
