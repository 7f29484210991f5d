// analysis::Judge and AllowableRange: the verdict, margin and "within" rule of the allowables
// check, against values worked by hand (a figure of 5 against [2, 4], <= 6, >= 5.5, and none).
// analysis::CheckAllowables: each row's value against the single-purpose analysis that computes
// that figure (the loaded sweep, the unloaded backlash, the torque-twist loop), in arcsec, arcmin,
// MPa as the keys say, on Liu 2021 Table 1 with section 5.2's base modification.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/analysis/allowables.hpp"
#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/geometry/units.hpp"
#include "designs.hpp"

namespace {
using ltca::analysis::AllowableRange;
using ltca::analysis::AllowableVerdict;
using ltca::analysis::Judge;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
}  // namespace

TEST_CASE("analysis: an allowable's margin is the distance to the nearer bound, positive inside") {
  const auto between = Judge("f", 3.5, "by hand", AllowableRange{2.0, 4.0});
  CHECK(between.verdict == AllowableVerdict::kPass);
  CHECK(between.margin == doctest::Approx(0.5));  // 4 - 3.5 < 3.5 - 2
  const auto above = Judge("f", 5.0, "by hand", AllowableRange{2.0, 4.0});
  CHECK(above.verdict == AllowableVerdict::kFail);
  CHECK(above.margin == doctest::Approx(-1.0));
  const auto at_max = Judge("f", 6.0, "by hand", AllowableRange{-kInf, 6.0});
  CHECK(at_max.verdict == AllowableVerdict::kPass);  // on the bound is within
  CHECK(at_max.margin == 0.0);
  const auto below_min = Judge("f", 5.0, "by hand", AllowableRange{5.5, kInf});
  CHECK(below_min.verdict == AllowableVerdict::kFail);
  CHECK(below_min.margin == doctest::Approx(-0.5));
}

TEST_CASE("analysis: a figure without a value is not computed, one without an allowable is listed") {
  const auto missing = Judge("f", kNan, "not computed", AllowableRange{0.0, 1.0});
  CHECK(missing.verdict == AllowableVerdict::kNotComputed);
  CHECK(std::isnan(missing.margin));
  CHECK(Judge("f", kInf, "diverged", AllowableRange{0.0, kInf}).verdict == AllowableVerdict::kNotComputed);
  const auto free = Judge("f", 2.0, "by hand");
  CHECK(free.verdict == AllowableVerdict::kNoAllowable);
  CHECK(std::isnan(free.margin));
  CHECK(std::string(ltca::analysis::ToString(free.verdict)) == "no allowable");
}

TEST_CASE("analysis: within an allowable is closed at its bounds and excludes what is not a finite number") {
  const AllowableRange r{2.0, 4.0};
  CHECK(r.Holds(2.0));
  CHECK(r.Holds(4.0));
  CHECK_FALSE(r.Holds(1.9));
  CHECK_FALSE(r.Holds(4.1));
  CHECK_FALSE(r.Holds(kNan));
  CHECK_FALSE(AllowableRange{-kInf, kInf}.Holds(kInf));
  CHECK_FALSE(AllowableRange{}.Given());
  CHECK(AllowableRange{-kInf, 1.0}.Given());
}

namespace {

using ltca::test::SteelLiu52;

const ltca::analysis::AllowableRow& Row(const std::vector<ltca::analysis::AllowableRow>& rows, const std::string& figure) {
  const auto it = std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r.figure == figure; });
  REQUIRE(it != rows.end());
  return *it;
}

}  // namespace

TEST_CASE("analysis: the allowables check takes each figure from the analysis that computes it and judges it by its limit") {
  using ltca::units::RadToArcmin;
  using ltca::units::RadToArcsec;
  const double torque = 206'000.0;  // N*mm, Liu 2021 section 5.2
  const std::vector<double> cranks = {0.0, ltca::units::DegToRad(3.0), ltca::units::DegToRad(6.0)};
  const ltca::analysis::Stage stage(SteelLiu52(), cranks);
  ltca::analysis::SweepRunner runner(stage, ltca::solvers::SolverOptions{}, torque);
  for (const double c : cranks) runner.Solve(c);
  const ltca::analysis::SweepSummary solve = runner.Summary();
  REQUIRE(solve.all_succeeded());
  const ltca::analysis::BacklashResult backlash = ltca::analysis::Backlash(stage, stage.kinematics(), {});
  ltca::analysis::StiffnessSettings loop;
  loop.steps = 9;
  loop.crank = 0.0;
  const ltca::analysis::Stage at_zero(SteelLiu52(), {0.0});
  const ltca::analysis::StiffnessResult stiffness = ltca::analysis::Stiffness(at_zero, ltca::solvers::SolverOptions{}, loop, torque);

  ltca::analysis::NominalResults nominal;
  nominal.solve = &solve;
  nominal.backlash = &backlash;
  nominal.stiffness = &stiffness;
  ltca::analysis::Allowables allowables;
  allowables.contact_stress_limit = 2000.0;  // MPa
  const double pp_te = RadToArcsec(solve.pp_te);
  allowables.limits = {{"pp_te_arcsec", -kInf, pp_te - 1.0}, {"contacts_min", 1.0, kInf}};
  const auto rows = ltca::analysis::CheckAllowables(nominal, allowables);

  const auto& stress = rows.front();  // first: the largest contact stress against its limit
  CHECK(stress.figure == "max_contact_stress_mpa");
  CHECK(stress.value == solve.max_contact_stress);
  CHECK(stress.verdict == AllowableVerdict::kPass);
  CHECK(stress.margin == doctest::Approx(2000.0 - solve.max_contact_stress));
  const auto& te = Row(rows, "pp_te_arcsec");  // a limit 1 arcsec under the sweep's pp TE
  CHECK(te.value == pp_te);
  CHECK(te.basis == "ltca solve");
  CHECK(te.verdict == AllowableVerdict::kFail);
  CHECK(te.margin == doctest::Approx(-1.0));
  CHECK(Row(rows, "contacts_min").value == solve.contacts_min);
  CHECK(Row(rows, "contacts_min").verdict == AllowableVerdict::kPass);
  // Not limited: listed with their values from their own analyses, pp TE once (as a limit).
  CHECK(std::count_if(rows.begin(), rows.end(), [](const auto& r) { return r.figure == "pp_te_arcsec"; }) == 1);
  const auto& mean_backlash = Row(rows, "mean_backlash_arcsec");
  CHECK(mean_backlash.value == RadToArcsec(backlash.summary.mean()));
  CHECK(mean_backlash.verdict == AllowableVerdict::kNoAllowable);
  CHECK(Row(rows, "lost_motion_arcmin").value == RadToArcmin(stiffness.summary.lost_motion.mean));
  CHECK(Row(rows, "torsional_rigidity_nm_per_arcmin").value ==
        doctest::Approx(stiffness.summary.rigidity.mean / 1000.0 / RadToArcmin(1.0)));

  // A reducer stage's backlash is its free play, the loop's width at zero torque, not the pin
  // ring's unloaded analysis.
  nominal.reducer = true;
  const auto stage_rows = ltca::analysis::CheckAllowables(nominal, allowables);
  const auto& free_play = Row(stage_rows, "mean_backlash_arcsec");
  CHECK(free_play.value == doctest::Approx(RadToArcsec(stiffness.summary.backlash.mean)));
  CHECK(free_play.basis == "ltca stiffness, crank 0: the stage's free play");
}
