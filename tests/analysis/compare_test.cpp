// analysis::CompareResult, several solvers on one sweep in lockstep, against the single-purpose
// computation it gathers: each solver's sweep run alone (analysis::SweepRunner), its summary and
// its largest differences from the first solver's positions by their definitions (largest |TE -
// TE_ref|, |F_i - F_i,ref| and loaded pin count difference over the positions where both
// succeeded). One disc and two discs; the stage is built from data (analysis::StageDesign).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/analysis/compare.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/geometry/units.hpp"
#include "designs.hpp"

namespace {

using ltca::analysis::CompareResult;
using ltca::analysis::PositionResult;
using ltca::analysis::Stage;
using ltca::analysis::StageDesign;
using ltca::solvers::SolverOptions;

constexpr double kCompareTorque = 206'000.0;  ///< N*mm: Liu 2021 section 5.2's 206 N*m

/// Liu 2021 Table 1 with section 5.2's base modification, steel; two discs: a second disc half a
/// crank turn on, 5 um ahead along the pin circle.
StageDesign ComparedLiu52(bool two_discs) { return two_discs ? ltca::test::SteelLiu52TwoDiscs() : ltca::test::SteelLiu52(); }

/// Each solver's positions over the stage's cranks, run alone.
std::vector<PositionResult> RunAlone(const Stage& stage, const std::string& name, ltca::analysis::SweepSummary* summary) {
  SolverOptions o;
  o.name = name;
  ltca::analysis::SweepRunner runner(stage, o, kCompareTorque);
  std::vector<PositionResult> positions;
  for (const double crank : stage.cranks()) positions.push_back(runner.Solve(crank));
  *summary = runner.Summary();
  return positions;
}

void CheckAgainstRunsAlone(const Stage& stage, const std::vector<std::string>& names) {
  std::vector<std::vector<PositionResult>> seen(names.size());
  const CompareResult result = ltca::analysis::Compare(stage, SolverOptions{}, names, kCompareTorque, {},
                                                       [&](double crank, const std::vector<PositionResult>& at) {
                                                         REQUIRE(at.size() == names.size());
                                                         for (std::size_t r = 0; r < at.size(); ++r) {
                                                           CHECK(at[r].crank == crank);
                                                           seen[r].push_back(at[r]);
                                                         }
                                                       });
  REQUIRE(result.solvers.size() == names.size());
  CHECK(result.cranks == stage.cranks());
  CHECK(result.skipped.empty());
  CHECK(result.all_succeeded());
  CHECK_FALSE(result.any_failed());
  std::vector<std::vector<PositionResult>> alone;
  for (std::size_t r = 0; r < names.size(); ++r) {
    CAPTURE(names[r]);
    ltca::analysis::SweepSummary own;
    alone.push_back(RunAlone(stage, names[r], &own));
    const auto& s = result.solvers[r].summary;
    CHECK(result.solvers[r].options.name == names[r]);
    // The same solver with its own workspace over the same cranks: the same figures to the bit.
    CHECK(s.mean_te == own.mean_te);
    CHECK(s.pp_te == own.pp_te);
    CHECK(s.max_pin_force == own.max_pin_force);
    CHECK(s.contacts_min == own.contacts_min);
    CHECK(s.contacts_max == own.contacts_max);
    CHECK(s.succeeded == own.succeeded);
    REQUIRE(seen[r].size() == alone[r].size());
    for (std::size_t i = 0; i < seen[r].size(); ++i) CHECK(seen[r][i].result.te == alone[r][i].result.te);
  }
  for (std::size_t r = 0; r < names.size(); ++r) {
    CAPTURE(names[r]);
    double te = 0.0, force = 0.0;
    int pins = 0;
    for (std::size_t i = 0; i < alone[r].size(); ++i) {
      const PositionResult& a = alone[r][i];
      const PositionResult& ref = alone[0][i];
      te = std::max(te, std::abs(a.result.te - ref.result.te));
      for (std::size_t k = 0; k < a.result.force.size(); ++k) force = std::max(force, std::abs(a.result.force[k] - ref.result.force[k]));
      pins = std::max(pins, std::abs(a.contacts - ref.contacts));
    }
    const auto& d = result.solvers[r].differences;
    CHECK(d.te == te);
    CHECK(d.force == force);
    CHECK(d.pins == pins);
    CHECK(result.solvers[r].compared(r == 0) == static_cast<std::int64_t>(stage.cranks().size()));
    if (r == 0) CHECK(d.compared == 0);  // the reference is not compared with itself
  }
  // Two different solvers agree to their tolerances, not to the bit.
  CHECK(result.solvers[1].differences.te > 0.0);
  CHECK(ltca::units::RadToArcsec(result.solvers[1].differences.te) < 1e-3);
}

}  // namespace

TEST_CASE("analysis: one disc's comparison is each solver's sweep run alone, its differences from the first by definition") {
  const Stage stage(ComparedLiu52(false), {0.0, ltca::units::DegToRad(1.5), ltca::units::DegToRad(3.0)});
  CheckAgainstRunsAlone(stage, {"bisection", "energy-qp"});
}

TEST_CASE("analysis: two discs' comparison is each solver's sweep run alone, its differences from the first by definition") {
  const Stage stage(ComparedLiu52(true), {0.0, ltca::units::DegToRad(1.5), ltca::units::DegToRad(3.0)});
  REQUIRE(stage.disc_count() == 2);
  CheckAgainstRunsAlone(stage, {"energy-qp", "bisection"});
}

TEST_CASE("analysis: a reducer stage skips the solvers that do not solve it, and none left is an error naming the deck") {
  const auto all = ltca::analysis::SelectSolvers({"bisection", "energy-groups"}, false, "deck.toml");
  CHECK(all.run == std::vector<std::string>{"bisection", "energy-groups"});
  CHECK(all.skipped.empty());
  const auto stage = ltca::analysis::SelectSolvers({"bisection", "energy-groups"}, true, "deck.toml");
  CHECK(stage.run == std::vector<std::string>{"bisection"});
  REQUIRE(stage.skipped.size() == 1);
  CHECK(stage.skipped[0].name == "energy-groups");
  CHECK_THROWS_WITH_AS(ltca::analysis::SelectSolvers({"energy-groups"}, true, "deck.toml"),
                       doctest::Contains("deck 'deck.toml'"), std::invalid_argument);
  CHECK_THROWS_AS(ltca::analysis::SelectSolvers({"no-such-solver"}, false, "deck.toml"), std::invalid_argument);
}
