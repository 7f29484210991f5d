// The stage's torque-twist loop with friction (docs/stiffness.md, "The stage's loop with friction"):
// the mesh's friction and the bearings' on each disc, apart from the output torque. Independent
// references: the friction loads written again here from their derivation (the disc's motion along
// the branch from two frictionless solves, mu F against its tangential part at each loaded pin; the
// bearing's mu_b |F| d / 2 against its relative rotation, the crankshaft's through the first stage
// by virtual work) and their fixed point found by plain substitution, each step a stage solve with
// those loads (LoadProblem::WithStageLoads, checked against the hand network in
// tests/solvers/rv_stage_test.cpp); and every coefficient zero is the frictionless loop.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "deck_runs.hpp"
#include "helpers.hpp"
#include "ltca/analysis/friction.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/solvers/registry.hpp"

using ltca::app::Deck;
using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::SolverStatus;
using ltca::test::Case;

namespace stage_loop_test {

Deck StageDeck(const std::string& name, std::vector<std::string> options) {
  options.push_back("sweep.positions=4");
  return ltca::app::LoadDeck(Case("stage/" + name), options);
}

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }
double Sign(double v) { return v > 0.0 ? 1.0 : v < 0.0 ? -1.0 : 0.0; }

/// The friction loads on the stage at `r`'s forces, the stage moving as from `from` to `to`:
/// per disc its force (N) and moment (N*mm, the problem's frame), then the output's moment.
ltca::solvers::StageLoads Loads(const ltca::analysis::Stage& stage, const LoadProblem& problem,
                                const ltca::contact::MeshState& state, const LoadResult& r, const LoadResult& from,
                                const LoadResult& to, double mu, double mu_b, double d_b) {
  ltca::solvers::StageLoads loads;
  loads.discs.resize(static_cast<std::size_t>(stage.disc_count()));
  const double frame = stage.model().load_direction() * problem.direction();  // problem frame = frame x counterclockwise
  for (std::size_t i = 0; i < state.pins.size(); ++i) {
    const auto& pin = state.pins[i];
    if (!(r.force[i] > 0.0)) continue;
    const auto d = static_cast<std::size_t>(pin.disc);
    const double crank = state.crank + (d == 1 ? ltca::contact::kSecondDiscCrankOffset : 0.0);
    const Eigen::Vector2d o = stage.model(pin.disc).CyclePose(crank, 0.0, pin.z).centre;
    const auto& a = from.reducer->discs[d];
    const auto& b = to.reducer->discs[d];
    // The tangential slide along t = perp(n): (dt + frame dphi perp(P - O)) . t, and perp(x) . perp(n) = x . n.
    const Eigen::Vector2d t = Perp(pin.normal);
    const double slide = (b.translation - a.translation).dot(t) + frame * (b.rotation - a.rotation) * (pin.cycloid_point - o).dot(pin.normal);
    const double f = -Sign(slide) * mu * r.force[i];  // along t, on the disc
    loads.discs[d].force += f * t;
    loads.discs[d].moment += frame * f * (pin.cycloid_point - o).dot(pin.normal);  // (P - O) x t = (P - O) . n
  }
  const auto& settings = *problem.reducer();
  const bool cranks = settings.kind == ltca::solvers::OutputKind::kCranks;
  const double k = cranks ? settings.cranks.turns_per_output_turn : 0.0;
  for (std::size_t d = 0; d < loads.discs.size(); ++d) {
    // The eccentric's (or crankshaft's) turn against the disc's, in the problem's frame.
    const double relative = (k * (to.rotation - from.rotation)) - (to.reducer->discs[d].rotation - from.reducer->discs[d].rotation);
    for (const Eigen::Vector2d& force : r.reducer->discs[d].bearing_force) {
      const double m = mu_b * force.norm() * d_b / 2.0;
      // Virtual work -M sign(relative) (k dpsi - dphi): +M sign on phi, -M sign k on psi.
      loads.discs[d].moment += Sign(relative) * m;
      loads.output_moment -= Sign(relative) * m * k;
    }
  }
  return loads;
}

void CheckAgainstSubstitution(const Deck& deck, double crank, double mu, double mu_b, double d_b) {
  const ltca::analysis::Stage stage = deck.MakeStage({crank});
  const ltca::contact::MeshState state = stage.State(crank);
  const auto solver = ltca::solvers::MakeSolver(deck.solver.name);
  const auto problem = [&](double t) { return stage.Problem(state, t); };
  const auto solve = [&](const LoadProblem& p) { return solver->Solve(p, deck.solver); };
  const double rated = std::abs(deck.RequireLoad().torque);
  for (const double torque : {rated, 0.4 * rated, -0.7 * rated}) {
    for (const double sense : {1.0, -1.0}) {
      CAPTURE(torque);
      CAPTURE(sense);
      ltca::analysis::StageLoopFriction friction{mu, mu_b, d_b};
      int solves = 0;
      const LoadResult got = ltca::analysis::SolveStageWithLoopFriction(stage.model(), state, torque, sense, friction, problem, solve,
                                                                       &solves, stage.disc_count() == 2 ? &stage.model(1) : nullptr);
      INFO(got.message);
      REQUIRE(got.status == SolverStatus::kSuccess);
      // Plain substitution from the frictionless stage: the motion between a step behind on the
      // branch and T, then the loads of each answer until they repeat.
      const LoadProblem at = problem(torque);
      const LoadResult to = solve(at);
      const LoadResult from = solve(problem(torque - sense * 1e-4 * std::abs(torque)));
      REQUIRE(to.status == SolverStatus::kSuccess);
      REQUIRE(from.status == SolverStatus::kSuccess);
      LoadResult r = to;
      for (int it = 0; it < 60; ++it) {
        r = solve(at.WithStageLoads(Loads(stage, at, state, r, from, to, mu, mu_b, d_b)));
        REQUIRE(r.status == SolverStatus::kSuccess);
      }
      CHECK(got.rotation == doctest::Approx(r.rotation).epsilon(1e-9));
      CHECK(std::abs(got.rotation - to.rotation) > 1e-4 * std::abs(to.rotation));  // friction moved it
      double f_max = 0.0;
      for (const double f : r.force) f_max = std::max(f_max, f);
      for (std::size_t i = 0; i < r.force.size(); ++i) CHECK(std::abs(got.force[i] - r.force[i]) <= 1e-8 * f_max);
      CHECK(solves < 30);
    }
  }
}

// The tests sit in the namespace: a unity build puts other files' helpers of the same names beside them.

TEST_CASE("app: the stage's loop with friction is the fixed point of its own friction loads: the cycloidal drive, mesh and bearing (1e-9)") {
  const Deck deck = StageDeck("cycloidal_drive.toml", {});
  CheckAgainstSubstitution(deck, 0.0, 0.05, 0.002, 40.0);
  CheckAgainstSubstitution(deck, 0.3, 0.1, 0.0, 40.0);
}

TEST_CASE("app: the stage's loop with friction is the fixed point of its own friction loads: two discs on crankshafts through the first stage (1e-9)") {
  const Deck deck = StageDeck("rv_catalogue.toml", {});
  CheckAgainstSubstitution(deck, 0.0, 0.05, 0.002, 30.0);
  CheckAgainstSubstitution(deck, 0.0, 0.0, 0.01, 30.0);  // the bearings alone: the output's moment through the first stage
}

TEST_CASE("app: the stage's loop: every coefficient zero is the frictionless loop bit for bit, and friction opens a loop that grows with it") {
  ltca::analysis::StiffnessSettings settings;
  settings.crank = 0.0;
  settings.steps = 11;
  const auto loop = [&](const std::string& name, std::vector<std::string> options) {
    const Deck deck = StageDeck(name, std::move(options));
    return ltca::test::StiffnessOn(deck, deck.solver, settings, deck.kinematics).Run();
  };
  for (const std::string name : {"cycloidal_drive.toml", "rv_catalogue.toml"}) {
    CAPTURE(name);
    const auto none = loop(name, {});
    const auto zero = loop(name, {"friction.coefficient=0", "friction.bearing_coefficient=0"});
    REQUIRE(none.all_succeeded());
    REQUIRE(zero.all_succeeded());
    REQUIRE(zero.summary.curve.size() == none.summary.curve.size());
    for (std::size_t i = 0; i < none.summary.curve.size(); ++i) CHECK(zero.summary.curve[i].twist == none.summary.curve[i].twist);
    CHECK(zero.summary.hysteresis.mean == none.summary.hysteresis.mean);
    double last = 0.0;
    for (const double mu : {0.02, 0.05, 0.1}) {
      CAPTURE(mu);
      const auto with = loop(name, {fmt::format("friction.coefficient={}", mu), "friction.bearing_coefficient=0.002"});
      INFO(with.summary.first_failure);
      REQUIRE(with.all_succeeded());
      CHECK(with.bearing_friction_coefficient == 0.002);
      CHECK(with.summary.hysteresis.mean > last);
      // The loading pass is the stiffer one (docs/stiffness.md): friction helps carry the torque.
      CHECK(with.summary.rigidity.mean > none.summary.rigidity.mean);
      last = with.summary.hysteresis.mean;
    }
  }
}

TEST_CASE("app: the stage's loop: friction acting with the torque on the way back is no lock, a preloaded pair's loop with friction is a named failure") {
  ltca::analysis::StiffnessSettings settings;
  settings.crank = 0.0;
  settings.steps = 11;
  // The crank bearings' moment at d = 600 mm reaches the torque in sum (6 bearings), but on the way
  // back it acts with the torque, and on the way up the output supplies only (k - 1) of it.
  const Deck big = StageDeck("rv_catalogue.toml", {"friction.coefficient=0", "friction.bearing_coefficient=0.05",
                                                   "friction.bearing_diameter_mm=600"});
  const auto loop = ltca::test::StiffnessOn(big, big.solver, settings, big.kinematics).Run();
  INFO(loop.summary.first_failure);
  CHECK(loop.all_succeeded());
  CHECK(loop.summary.hysteresis.mean > 0.0);
  const Deck preloaded = StageDeck("rv_catalogue.toml", {"modification.pin_circle_radius_mm=-0.002", "friction.coefficient=0.01"});
  const auto failed = ltca::test::StiffnessOn(preloaded, preloaded.solver, settings, preloaded.kinematics).Run();
  CHECK_FALSE(failed.all_succeeded());
  CHECK(failed.summary.first_failure.find("the loop with friction of a preloaded pair") != std::string::npos);
}

TEST_CASE("solvers: a stage's preload state carries no loads besides T") {
  const Deck deck = StageDeck("cycloidal_drive.toml", {});
  const ltca::analysis::Stage stage = deck.MakeStage({0.0});
  ltca::solvers::StageLoads loads;
  loads.discs = {{Eigen::Vector2d(10.0, 0.0), 1e3}};
  const LoadProblem p = stage.Problem(0.0, 1e5).WithStageLoads(loads);
  REQUIRE(p.stage_loads() != nullptr);
  CHECK(p.Unloaded(1e-7).stage_loads() == nullptr);
}

}  // namespace stage_loop_test
