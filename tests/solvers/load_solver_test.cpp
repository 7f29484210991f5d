// Load solvers judged by the shared residual, never by their own claim, and against closed forms.
#include <cmath>
#include <memory>
#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "ltca/solvers/registry.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "pairs.hpp"
#include "problems.hpp"

using ltca::contact::ContactKinematics;
using ltca::contact::ContactSettings;
using ltca::contact::LawKind;
using ltca::contact::MeshModel;
using ltca::solvers::LoadProblem;
using ltca::solvers::MakeSolver;
using ltca::solvers::SolverOptions;
using ltca::solvers::SolverStatus;

namespace {


}  // namespace

TEST_CASE("solvers: closed form 1 - linear law, no clearance, linearised: F_i = F_max sin(phi_i) / S_i") {
  // Issue closed form: F_max = T / (e z_c sum sin^2 phi_i / S_i^2) over the loaded pins. The
  // shared residual is recomputed from the problem data (1e-8); forces to 1e-8 of F_max.
  const auto pair = ltca::test::LiuPair();
  const MeshModel model(pair, {});
  const double torque = 206e3, k1 = 40 * 1.3 / 64.0;
  for (const auto& name : ltca::solvers::SolverNames()) {
    CAPTURE(name);
    for (const double crank : {0.0, 0.05}) {
      const LoadProblem problem(model, crank, ltca::test::LinearLaw(), ltca::contact::Material{}, torque, ContactKinematics::kLinearised);
      SolverOptions options;
      options.name = name;
      const auto r = MakeSolver(name)->Solve(problem, options);
      REQUIRE(r.status == SolverStatus::kSuccess);
      CHECK(ltca::solvers::ComputeResiduals(problem, r.rotation, r.force).Normalised() < 1e-8);
      double sum = 0;
      for (const auto& c : problem.base_state().pins) {
        const double s = std::sqrt(1 + k1 * k1 - 2 * k1 * std::cos(c.angle));
        if (std::sin(c.angle) > 1e-12) sum += std::pow(std::sin(c.angle) / s, 2);
      }
      const double f_max = torque / (pair.eccentricity * pair.tooth_count * sum);
      for (const auto& c : problem.base_state().pins) {
        const double s = std::sqrt(1 + k1 * k1 - 2 * k1 * std::cos(c.angle));
        const double expected = std::sin(c.angle) > 0 ? f_max * std::sin(c.angle) / s : 0.0;
        CHECK(std::abs(r.force[static_cast<std::size_t>(c.pin)] - expected) < 1e-8 * f_max);
      }
    }
  }
}

TEST_CASE("solvers: the liu2021 preset of bisection lands within 1 % in torque, the default within 1e-10") {
  const LoadProblem problem = ltca::test::LiuTable1().Problem(0.3, ContactKinematics::kLinearised);
  const auto tight = MakeSolver("bisection")->Solve(problem, SolverOptions{});
  const auto liu = MakeSolver("bisection")->Solve(problem, ltca::solvers::ApplyPreset(SolverOptions{}, "liu2021"));
  CHECK(tight.status == SolverStatus::kSuccess);
  CHECK(liu.status == SolverStatus::kSuccess);
  CHECK(tight.residuals.torque_relative <= 1e-10);
  CHECK(liu.residuals.torque_relative <= 1e-2);
  CHECK(liu.torque_evaluations < tight.torque_evaluations);
}

TEST_CASE("solvers: zero torque leaves the cycloid at its theoretical position with no forces") {
  const MeshModel model(ltca::test::LiuPair(), ltca::test::Mod(-4, -17));
  const LoadProblem problem(model, 0.1, ContactSettings{}, ltca::contact::Material{}, 0.0, ContactKinematics::kLinearised);
  const auto r = MakeSolver("bisection")->Solve(problem, SolverOptions{});
  CHECK(r.status == SolverStatus::kSuccess);
  CHECK(r.rotation == 0.0);
  CHECK(r.active.empty());
}

TEST_CASE("solvers: an unknown solver name is rejected with the valid names") {
  CHECK_THROWS_WITH_AS(MakeSolver("newton"), doctest::Contains("bisection"), std::invalid_argument);
  SolverOptions bad;
  bad.torque_tolerance = 0.0;
  CHECK_THROWS_WITH_AS(bad.Validate(), doctest::Contains("torque_tolerance"), std::invalid_argument);
}

TEST_CASE("solvers: closed form 2 - Kudryavtsev's load-increase factor (Jiang 2022 eq. 11-12)") {
  // Jiang eq. 11-12 with its typos mended (the bracket uses the pin's normalised arm L_i / L_max
  // where it prints sin(theta); "2a sin A" is 2 arcsin A): linear law, clearances
  // c_i = Delta (1 - L_i / L_max) (what an isometric modification leaves after first contact),
  // L_max = e z_c, P = Delta / w_max, A = P / (1 + P),
  //   k_z = pi / [(1 + P)(pi - 2 arcsin A - 2 A sqrt(1 - A^2))],  F_max = 4 k_z T / (z_p e z_c),
  //   F_i = F_max [(1 + P) L_i / L_max - P]  on the loaded pins.
  // The closed form integrates over a continuum of pins: within 1.5 % at 40 pins and 0.1 % at
  // 200 pins (of F_max), for P from 0 to 2 and K1 from 0.5 to 0.8125.
  const double pi = ltca::units::kPi;
  for (const int zp : {40, 200}) {
    for (const double k1 : {0.5, 0.8125}) {
      for (const double p : {0.0, 0.5, 1.0, 2.0}) {
        CAPTURE(zp);
        CAPTURE(k1);
        CAPTURE(p);
        const double rp = 64.0 * zp / 40.0, e = k1 * rp / zp;
        const ltca::geometry::PairParameters pair{zp, zp - 1, 0.2 * rp * std::sin(pi / zp), rp, e, 12.0};
        const MeshModel model(pair, {});
        const double torque = 2e5, l_max = e * (zp - 1);
        const double a = p / (1 + p);
        const double kz = pi / ((1 + p) * (pi - 2 * std::asin(a) - 2 * a * std::sqrt(1 - a * a)));
        const double f_max = 4 * kz * torque / (zp * e * (zp - 1));
        const ContactSettings law = ltca::test::LinearLaw();
        const double k = law.stiffness_per_length * pair.face_width;  // N/mm per pin
        const double delta = p * f_max / k;                            // P = Delta / w_max
        auto state = model.Evaluate(0.0);
        for (auto& c : state.pins) c.clearance = c.arm > 0 ? delta * (1 - c.arm / l_max) : 1.0;
        const LoadProblem problem(model, state, law, ltca::contact::Material{}, torque);
        for (const auto& name : ltca::solvers::SolverNames()) {
          CAPTURE(name);
          SolverOptions options;
          options.name = name;
          const auto r = MakeSolver(name)->Solve(problem, options);
          REQUIRE(r.status == SolverStatus::kSuccess);
          const double tol = (zp == 40 ? 0.015 : 0.001) * f_max;
          for (const auto& c : state.pins) {
            const double expected = c.arm > 0 ? std::max(0.0, f_max * ((1 + p) * c.arm / l_max - p)) : 0.0;
            CHECK(std::abs(r.force[static_cast<std::size_t>(c.pin)] - expected) <= tol);
          }
        }
      }
    }
  }
}

TEST_CASE("solvers: each backend fills its own details") {
  const LoadProblem problem = ltca::test::LiuSec52Base().Problem(0.0, ContactKinematics::kLinearised);
  const auto run = [&](const std::string& name) {
    SolverOptions options;
    options.name = name;
    return MakeSolver(name)->Solve(problem, options);
  };
  CHECK(run("bisection").details.at("final_step_rad") > 0.0);
  const auto qp = run("energy-qp");
  CHECK(qp.details.at("candidates") >= 6);
  CHECK(qp.details.at("ipopt_iterations") >= 1);
  const auto groups = run("energy-groups");
  CHECK(groups.details.at("groups_evaluated") > 1);
  const auto compat = run("compatibility");
  CHECK(compat.details.count("polish_steps") == 1);
}

TEST_CASE("solvers: torque_tolerance is refused above 5 % (the load would not be the given torque), naming the key and the range") {
  // Issue 26 item 16: torque_tolerance accepted up to 0.999, a "balance" at 0.1 % of the load.
  // Liu 2021 section 3 stops at 1 %; 5 % is the loosest a balance of the given torque can mean.
  for (const double bad : {0.06, 0.5, 0.999}) {
    CAPTURE(bad);
    SolverOptions o;
    o.torque_tolerance = bad;
    const std::string expected = fmt::format("torque_tolerance = {}: expected a relative tolerance from 1e-15 to 0.05", bad);
    CHECK_THROWS_WITH_AS(o.Validate(), doctest::Contains(expected.c_str()), std::invalid_argument);
  }
  SolverOptions ok;
  ok.torque_tolerance = 0.05;
  CHECK_NOTHROW(ok.Validate());
  ok.torque_tolerance = 1e-2;  // Liu's
  CHECK_NOTHROW(ok.Validate());
}

TEST_CASE("solvers: bisection stopped by max_iterations says that the iteration limit was reached, not how close it came") {
  // Issue 26 item 16: the message read "torque off by 1e-10 relative", as if it had converged.
  const LoadProblem problem = ltca::test::LiuTable1().Problem(0.3, ContactKinematics::kLinearised);
  SolverOptions options;
  options.max_iterations = 3;
  const auto r = MakeSolver("bisection")->Solve(problem, options);
  REQUIRE(r.status == SolverStatus::kMaxIterations);
  CHECK(r.message.find("iteration limit") != std::string::npos);
  CHECK(r.message.find("max_iterations = 3") != std::string::npos);
  CHECK(r.message.find("torque_tolerance") != std::string::npos);
}

TEST_CASE("solvers: at the solution no feasible perturbation of the forces lowers the complementary energy") {
  // Independent of the solvers: perturb the solution along every pair of pins (i, j) in the
  // direction that keeps the torque, dF_i = +eps / L_i, dF_j = -eps / L_j, wherever the forces stay
  // >= 0, and recompute sum_i [E_i^c(F_i) + c_i F_i] from the laws. None may be lower
  // (beyond 1e-12 relative rounding).
  const LoadProblem problem = ltca::test::LiuSec52Base().Problem(0.07, ContactKinematics::kLinearised);
  for (const auto& solver : ltca::solvers::SolverNames()) {
    CAPTURE(solver);
    SolverOptions options;
    options.name = solver;
    const auto r = MakeSolver(solver)->Solve(problem, options);
    REQUIRE(r.status == SolverStatus::kSuccess);
    const auto& pins = problem.base_state().pins;
    const auto& laws = problem.base_laws();
    const auto energy = [&](const std::vector<double>& f) {
      double e = 0;
      for (std::size_t k = 0; k < f.size(); ++k) e += laws[k].ComplementaryEnergy(f[k]) + pins[k].clearance * f[k];
      return e;
    };
    const double e0 = energy(r.force);
    double f_max = *std::max_element(r.force.begin(), r.force.end());
    int tried = 0;
    for (std::size_t i = 0; i < pins.size(); ++i) {
      for (std::size_t j = 0; j < pins.size(); ++j) {
        if (i == j || pins[i].arm <= 1e-6 || pins[j].arm <= 1e-6 || pins[i].edge || pins[j].edge) continue;
        for (const double eps : {1e-4 * f_max, 1e-2 * f_max}) {
          auto f = r.force;
          f[i] += eps / pins[i].arm;
          f[j] -= eps / pins[j].arm;
          if (f[j] < 0.0) continue;
          ++tried;
          CHECK(energy(f) >= e0 - 1e-12 * std::abs(e0));
        }
      }
    }
    CHECK(tried > 100);
  }
}
