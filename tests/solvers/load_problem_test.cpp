// LoadProblem's evaluation of the pins at a trial rotation (issue 29): what a solver's inner loop
// may leave out, and what it must not.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/solvers/load_problem.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "problems.hpp"

using ltca::contact::ContactKinematics;
using ltca::contact::ContactLaw;
using ltca::solvers::LoadProblem;
using ltca::solvers::Workspace;

TEST_CASE("solvers: exact trials that skip the pins that cannot have closed give every force a full evaluation gives") {
  // Liu 2021 section 5.2 (clearances of microns, cases/liu2021_sec52_base.toml), exact kinematics,
  // 206 N*m. One workspace follows a bisection-like path of trial rotations (rising, overshooting,
  // halving back) with Freshness::kLoadedOnly; each trial is checked against a fresh workspace that
  // searches every pin (kAll): a pressed pin's approach to 1e-12 mm and its force to 1e-9 relative
  // (the same search from another warm start), an unpressed pin reported unpressed, and its
  // reported approach an upper bound of the true one (what kLoadedOnly promises). The path must
  // skip some pins, or the test shows nothing.
  const ltca::test::PaperCase sec52 = ltca::test::LiuSec52Base();
  const auto model = sec52.Model();
  for (const double crank : {0.0, ltca::units::DegToRad(4.3)}) {
    CAPTURE(crank);
    const LoadProblem problem = sec52.Problem(model, crank, ContactKinematics::kExact);
    const double first = problem.FirstContactRotation();
    REQUIRE(std::isfinite(first));
    std::vector<double> path;
    double psi = first, step = 2e-6;
    for (int k = 0; k < 40; ++k) {  // rising by doubling steps, then overshoot and halve back
      path.push_back(psi + step);
      if (k < 8) psi += step, step *= 2.0;
      else step *= (k % 3 == 0 ? 1.5 : 0.5);
    }
    Workspace trials;
    std::vector<ContactLaw> scratch, fresh_scratch;
    std::vector<LoadProblem::PinAt> pins, fresh;
    int skipped = 0, pressed = 0;
    for (const double at : path) {
      CAPTURE(at);
      problem.At(at, trials, &scratch, &pins, LoadProblem::Freshness::kLoadedOnly);
      Workspace full;
      problem.At(at, full, &fresh_scratch, &fresh, LoadProblem::Freshness::kAll);
      REQUIRE(pins.size() == fresh.size());
      const ltca::solvers::Loading a = ltca::solvers::LoadAt(pins, nullptr);
      const ltca::solvers::Loading b = ltca::solvers::LoadAt(fresh, nullptr);
      CHECK(a.torque == doctest::Approx(b.torque).epsilon(1e-9));
      for (std::size_t i = 0; i < pins.size(); ++i) {
        CAPTURE(i);
        if (fresh[i].approach > 0.0) {
          ++pressed;
          CHECK(std::abs(pins[i].approach - fresh[i].approach) <= 1e-12);
          CHECK(a.force[i] == doctest::Approx(b.force[i]).epsilon(1e-9));
        } else {
          CHECK(pins[i].approach <= 1e-12);
          CHECK(a.force[i] == 0.0);
          CHECK(pins[i].approach >= fresh[i].approach - 1e-12);
          if (pins[i].approach > fresh[i].approach + 1e-9) ++skipped;
        }
      }
    }
    CHECK(pressed > 0);
    CHECK(skipped > 0);
  }
}

TEST_CASE("solvers: the torque resolution from the pins' forces is the one from a law inversion per pin") {
  // Bisection's convergence check takes each pressed pin's stiffness as 1 / Compliance(F_i) from
  // the forces of its accepted trial (issue 29); Stiffness(approach) inverts the law instead. The
  // two must agree to rounding (1e-12 relative) at rotations that press few pins and many, under
  // both kinematics; a wrong closed form (e.g. the compliance without its log term) fails here.
  const ltca::test::PaperCase sec52 = ltca::test::LiuSec52Base();
  const auto model = sec52.Model();
  for (const ContactKinematics kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    const LoadProblem problem = sec52.Problem(model, 0.0, kinematics);
    const double first = problem.FirstContactRotation();
    REQUIRE(std::isfinite(first));
    for (const double turn : {1e-6, 1e-5, 1e-4, 5e-4}) {
      CAPTURE(turn);
      Workspace workspace;
      std::vector<ContactLaw> scratch;
      const std::vector<LoadProblem::PinAt> pins = problem.At(first + turn, workspace, &scratch);
      const ltca::solvers::Loading loading = ltca::solvers::LoadAt(pins, nullptr);
      const double by_inversion = problem.TorqueResolution(first + turn, pins);
      const double by_force = problem.TorqueResolution(first + turn, pins, &loading.force);
      REQUIRE(by_inversion > 0.0);
      CHECK(std::abs(by_force / by_inversion - 1.0) <= 1e-12);  // relative: the values are ulp-sized
    }
  }
}

TEST_CASE("solvers: laws scaled by w everywhere balance T as the unscaled laws balance T / w, with w times their forces (issue 27)") {
  // LoadProblem::WithLawScales (friction's balance in one solve, analysis/friction.hpp): every
  // law carries w times its force, so sum w F_i(psi) L_i = T is sum F_i(psi) L_i = T / w, the same
  // rotation (the independent side: the unscaled problem at T / w). Liu 2021 5.2 base, linearised,
  // both flanks, every solver; the rotation to 1e-9 relative, each force to 1e-8 of the largest.
  // A problem whose laws are not its own (exact kinematics) and a wrong scale are refused.
  const ltca::test::PaperCase sec52 = ltca::test::LiuSec52Base();
  const auto model = sec52.Model();
  const double w = 1.7;
  for (const double torque : {206e3, -206e3}) {
    ltca::test::PaperCase at = sec52;
    at.torque = torque;
    const LoadProblem problem = at.Problem(model, 0.0, ContactKinematics::kLinearised);
    at.torque = torque / w;
    const LoadProblem reduced = at.Problem(model, 0.0, ContactKinematics::kLinearised);
    REQUIRE(problem.scalable_laws());
    const LoadProblem scaled = problem.WithLawScales(std::vector<double>(static_cast<std::size_t>(problem.point_count()), w));
    for (const char* solver : {"bisection", "compatibility", "energy-qp", "energy-groups"}) {
      CAPTURE(torque);
      CAPTURE(solver);
      const auto got = ltca::test::SolveWith(solver, scaled);
      const auto want = ltca::test::SolveWith(solver, reduced);
      REQUIRE(got.status == ltca::solvers::SolverStatus::kSuccess);
      REQUIRE(want.status == ltca::solvers::SolverStatus::kSuccess);
      CHECK(std::abs(got.rotation - want.rotation) <= 1e-9 * std::abs(want.rotation));
      const double largest = *std::max_element(want.force.begin(), want.force.end());
      for (std::size_t i = 0; i < want.force.size(); ++i) CHECK(std::abs(got.force[i] - w * want.force[i]) <= 1e-8 * w * largest);
    }
  }
  const LoadProblem exact = sec52.Problem(model, 0.0, ContactKinematics::kExact);
  CHECK_FALSE(exact.scalable_laws());
  CHECK_THROWS_AS(exact.WithLawScales(std::vector<double>(static_cast<std::size_t>(exact.point_count()), 1.0)), std::invalid_argument);
  const LoadProblem linear = sec52.Problem(model, 0.0, ContactKinematics::kLinearised);
  CHECK_THROWS_AS(linear.WithLawScales({1.0}), std::invalid_argument);
  std::vector<double> zero(static_cast<std::size_t>(linear.point_count()), 1.0);
  zero[3] = 0.0;
  CHECK_THROWS_AS(linear.WithLawScales(zero), std::invalid_argument);
}
