// analysis::RunOptimisation, a design optimisation run whole, against the single-purpose
// computations it gathers: the evaluations the sink sees are the search's, in index order, and
// its best is the least objective among the feasible ones; the best design's and the map's
// figures are the loaded sweep (analysis::SolveSweep) and the unloaded backlash
// (analysis::Backlash) of the pair with the design's values applied. One disc and two discs
// (the second indexed 5 um ahead). The stage is built from data (analysis::StageDesign), no deck.
#include <cmath>
#include <cstdint>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/optimise.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/geometry/units.hpp"
#include "designs.hpp"

namespace {

namespace analysis = ltca::analysis;
using analysis::DesignEvaluation;

/// Liu 2021 Table 1 (40 pins, R_p 64 mm, r_rp 3 mm, e 1.3 mm, B 12 mm), steel, 100 N*m on the
/// output over 0 .. 9 deg crank in 3 positions.
analysis::ToleranceCase LiuTable1(bool two_discs) {
  return ltca::test::Over9DegreesAt100Nm(
      two_discs ? ltca::test::WithSecondDisc(ltca::test::SteelLiuTable1()) : ltca::test::SteelLiuTable1(), 3);
}

/// The peak-to-peak TE over the pin radius and pin-circle radius modifications (mm), the mean
/// backlash within a window (arcsec), 14 evaluations.
analysis::OptimiseSettings SearchSettings() {
  analysis::OptimiseSettings s;
  s.variables = {{"modification.pin_radius_mm", nullptr, -0.03, 0.0}, {"modification.pin_circle_radius_mm", nullptr, -0.03, 0.0}};
  s.objective = "pp_te_arcsec";
  s.constraints = {{"mean_backlash_arcsec", 60.0, 200.0}};
  s.evaluations = 14;
  return s;
}

/// The figures of a design by the single-purpose computations: its pair's loaded sweep (TE in
/// arcsec) and unloaded backlash (mean, arcsec).
/// A design that cannot be assembled is a preload beyond the material (the pins overlap the
/// cycloid so far that the stress at zero torque exceeds the limit): every loaded position says so.
void CheckDesignFigures(const analysis::Optimiser& optimiser, const DesignEvaluation& e) {
  CAPTURE(e.x[0]);
  CAPTURE(e.x[1]);
  const analysis::ToleranceCase pair = optimiser.Apply(e.x);
  if (e.status == analysis::RunStatus::kCannotAssemble) {
    const analysis::Stage stage(pair.design, pair.sweep.CrankAngles());
    CHECK(analysis::SolveSweep(stage, optimiser.options(), pair.torque).summary.cannot_assemble > 0);
    CHECK(std::isnan(e.objective));
    return;
  }
  REQUIRE(e.status == analysis::RunStatus::kSuccess);
  const analysis::Stage stage(pair.design, pair.sweep.CrankAngles());
  const analysis::SweepSummary loaded = analysis::SolveSweep(stage, optimiser.options(), pair.torque).summary;
  const analysis::BacklashSummary backlash = analysis::Backlash(stage, stage.kinematics()).summary;
  CHECK(e.figures[analysis::kPpTeArcsec] == doctest::Approx(ltca::units::RadToArcsec(loaded.pp_te)).epsilon(1e-12));
  CHECK(e.figures[analysis::kMeanTeArcsec] == doctest::Approx(ltca::units::RadToArcsec(loaded.mean_te)).epsilon(1e-12));
  CHECK(e.figures[analysis::kMeanBacklashArcsec] == doctest::Approx(ltca::units::RadToArcsec(backlash.mean())).epsilon(1e-12));
  CHECK(e.objective == e.figures[analysis::kPpTeArcsec]);
}

}  // namespace

TEST_CASE("analysis: an optimisation's best is the least feasible objective the sink saw, its figures the sweep and backlash of its pair") {
  for (const bool two_discs : {false, true}) {
    CAPTURE(two_discs);
    const analysis::Optimiser optimiser(LiuTable1(two_discs), analysis::SolverOptions{}, SearchSettings(), 2);
    std::vector<DesignEvaluation> streamed;
    analysis::OptimiseRunPlan plan;
    plan.map = 3;
    plan.sink = [&](const DesignEvaluation& e) { streamed.push_back(e); };
    const analysis::OptimiseRun run = analysis::RunOptimisation(optimiser, plan);

    CHECK(run.threads == 2);
    CHECK(run.ranks == 1);
    REQUIRE(run.search.evaluations > 0);
    REQUIRE(static_cast<std::int64_t>(streamed.size()) == run.search.evaluations);
    const DesignEvaluation* least = nullptr;
    for (std::size_t i = 0; i < streamed.size(); ++i) {
      CHECK(streamed[i].index == static_cast<std::int64_t>(i));
      if (streamed[i].feasible && (least == nullptr || streamed[i].objective < least->objective)) least = &streamed[i];
    }
    REQUIRE(least != nullptr);
    REQUIRE(run.best() != nullptr);
    CHECK(run.best()->index == least->index);
    CHECK(run.best()->objective == least->objective);
    CHECK(run.best()->x == least->x);
    CheckDesignFigures(optimiser, *run.best());
    // The map: 3 x 3 designs over the box, the first variable fastest, each judged as the search judges.
    REQUIRE(run.map == 3);
    REQUIRE(run.grid.size() == 9);
    CHECK(run.grid[0].x == std::vector<double>{-0.03, -0.03});
    CHECK(run.grid[1].x[0] == doctest::Approx(-0.015));
    CHECK(run.grid[1].x[1] == doctest::Approx(-0.03));
    CHECK(run.grid[3].x[1] == doctest::Approx(-0.015));
    CHECK(run.grid[8].x == std::vector<double>{0.0, 0.0});
    int rejected = 0;
    for (const DesignEvaluation& e : run.grid) {
      CheckDesignFigures(optimiser, e);
      rejected += e.status == analysis::RunStatus::kCannotAssemble ? 1 : 0;
    }
    CHECK(rejected > 0);  // a corner of the box overlaps by 30 um: beyond the material, it cannot be assembled
    CHECK(run.front.empty());
    CHECK(run.pareto.empty());
  }
}
