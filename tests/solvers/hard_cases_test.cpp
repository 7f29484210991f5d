// Every solver on every hard case (cases/hard/): solved and in agreement with bisection, or an
// honest status. Expectations are keyed by case name (and kinematics), never by list index.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include <doctest/doctest.h>

#include "ltca/solvers/registry.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/solvers/load_solver.hpp"

using ltca::contact::ContactKinematics;
using ltca::solvers::LoadProblem;
using ltca::solvers::MakeSolver;
using ltca::solvers::SolverOptions;
using ltca::solvers::SolverStatus;

namespace {

// Cases that must show an honest non-success status at some position (at every position for
// law_cannot_carry): the |d| >= 2 pairs keep their sharp tips (no relief is assumed, issue 26),
// whose loaded corners are edge contacts.
const std::map<std::string, SolverStatus> kExpectedStatus = {
    {"law_cannot_carry", SolverStatus::kLawCannotCarry},
    {"d2_loaded", SolverStatus::kEdgeContact},
    {"d3_loaded", SolverStatus::kEdgeContact},
};

}  // namespace

TEST_CASE("solvers: every solver answers every hard case, solved and agreeing or with an honest status") {
  int decks = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(LTCA_CASES_DIR) + "/hard")) {
    const std::string name = entry.path().stem().string();
    const auto deck = ltca::app::LoadDeck(entry.path());
    const ltca::contact::MeshModel model = deck.MakeModel();
    ++decks;
    int expected_seen = 0;
    for (const auto kin : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
      const auto cranks = deck.sweep.CrankAngles();
      for (std::size_t i = 0; i < cranks.size(); ++i) {
        const LoadProblem problem(model, cranks[i], deck.contact, *deck.material, deck.load->torque, kin);
        SolverOptions options;
        const auto ref = MakeSolver("bisection")->Solve(problem, options);
        for (const auto& solver : ltca::solvers::SolverNames()) {
          CAPTURE(name);
          CAPTURE(solver);
          CAPTURE(static_cast<int>(kin));
          CAPTURE(i);
          options.name = solver;
          const auto r = MakeSolver(solver)->Solve(problem, options);
          CAPTURE(r.message);
          const auto expected = kExpectedStatus.find(name);
          if (expected != kExpectedStatus.end() && r.status == expected->second) ++expected_seen;
          if (r.status == SolverStatus::kLawCannotCarry) CHECK(std::isnan(r.te));  // never a silent number
          if (name == "tiny_torque" && kin == ContactKinematics::kExact) {
            // 1e-3 N*mm: deformations of 1e-10 mm against the ~1e-13 mm rounding of an exact gap
            // (coordinates of 64 mm). Every solver succeeds (issue 10: the convergence rule allows
            // the gap's rounding) and finds the linearised model's rotation to 1e-6; the forces
            // are resolved to about 1e-3 of the largest only (1e-13 / 1e-10), so they are held to 1e-2.
            REQUIRE(r.status == SolverStatus::kSuccess);
            CHECK(r.te == doctest::Approx(ref.te).epsilon(1e-6));
            double f_ref = 0;
            for (const double f : ref.force) f_ref = std::max(f_ref, f);
            for (std::size_t k = 0; k < r.force.size(); ++k) CHECK(std::abs(r.force[k] - ref.force[k]) <= 1e-2 * f_ref);
            continue;
          }
          if (ref.status != SolverStatus::kSuccess) {  // an honest status: every solver says the same
            CHECK(r.status == ref.status);
            continue;
          }
          REQUIRE(r.status == SolverStatus::kSuccess);
          CHECK(ltca::solvers::ComputeResiduals(problem, r.rotation, r.force).Normalised() < 1e-8);
          CHECK(r.te == doctest::Approx(ref.te).epsilon(1e-6));
          double f_max = 0;
          for (const double f : ref.force) f_max = std::max(f_max, f);
          for (std::size_t k = 0; k < r.force.size(); ++k) CHECK(std::abs(r.force[k] - ref.force[k]) <= 1e-6 * f_max + 1e-300);
          if (name == "zero_torque") {
            CHECK(r.rotation == 0.0);
            CHECK(r.active.empty());
          }
          if (name == "single_pitch_error") {  // pin 6 (index 5) carries most of the load
            CHECK(r.force[5] >= 0.5 * f_max);
            CHECK(std::max_element(r.force.begin(), r.force.end()) - r.force.begin() == 5);
          }
        }
      }
    }
    if (kExpectedStatus.count(name) != 0) {
      CAPTURE(name);
      CHECK(expected_seen > 0);
    }
  }
  CHECK(decks >= 11);
}

TEST_CASE("solvers: at the solution no feasible perturbation of the forces lowers the complementary energy") {
  // Independent of the solvers: perturb the solution along every pair of pins (i, j) in the
  // direction that keeps the torque, dF_i = +eps / L_i, dF_j = -eps / L_j, wherever the forces stay
  // >= 0, and recompute sum_i [E_i^c(F_i) + c_i F_i] from the laws. None may be lower
  // (beyond 1e-12 relative rounding).
  const auto deck = ltca::app::LoadDeck(std::string(LTCA_CASES_DIR) + "/liu2021_sec52_base.toml");
  const ltca::contact::MeshModel model = deck.MakeModel();
  const LoadProblem problem(model, 0.07, deck.contact, *deck.material, deck.load->torque, ContactKinematics::kLinearised);
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

TEST_CASE("solvers: compatibility with exact kinematics at the inflection-pin crank where its quarter-tolerance step could not refine") {
  // Issue 10, found by a 2,000-position exact sweep of cases/hard/inflection_pin.toml over
  // 1.356-43.644 deg: at crank 23.166345849916095 deg compatibility's first re-linearisation
  // stopped 2.5e-11 off its inner (quarter) tolerance of 2.5e-11 and the solve ended
  // numerical-failure. Independent reference: bisection on the same exact problem; they must
  // agree to 1e-8 relative in the TE (both balance the torque to 1e-10).
  const auto deck = ltca::app::LoadDeck(std::string(LTCA_CASES_DIR) + "/hard/inflection_pin.toml");
  const auto model = deck.MakeModel();
  const LoadProblem problem(model, 23.166345849916095 * M_PI / 180.0, deck.contact, *deck.material, deck.load->torque,
                            ContactKinematics::kExact);
  SolverOptions options;
  options.name = "compatibility";
  const auto compat = MakeSolver("compatibility")->Solve(problem, options);
  options.name = "bisection";
  const auto bisection = MakeSolver("bisection")->Solve(problem, options);
  REQUIRE(bisection.status == SolverStatus::kSuccess);
  CHECK(compat.status == SolverStatus::kSuccess);
  CHECK(compat.te == doctest::Approx(bisection.te).epsilon(1e-8));
}
