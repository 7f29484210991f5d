// analysis::RunToleranceStudy, a tolerance study run whole, against the single-purpose
// computations it gathers: each sample's figures are the unloaded backlash (analysis::Backlash)
// and the loaded sweep (analysis::SolveSweep) of that sample's pair, built from its drawn inputs;
// each limit's pass fraction is the count of the samples within it; the chains are the
// extreme-value closing link and its Monte Carlo. One disc and two discs (the second indexed
// 5 um ahead). The stage is built from data (analysis::StageDesign), no deck.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <cstdint>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/analysis/tolerance.hpp"
#include "ltca/analysis/tolerance_run.hpp"
#include "ltca/geometry/units.hpp"
#include "designs.hpp"

namespace {

namespace analysis = ltca::analysis;
using analysis::ToleranceSample;

/// Liu 2021 Table 1 (40 pins, R_p 64 mm, r_rp 3 mm, e 1.3 mm, B 12 mm) with section 5.2's base
/// modification (dR_rp -4 um, dR_p -17 um), steel, 100 N*m on the output over 0 .. 9 deg crank.
analysis::ToleranceCase TolerancedLiu52(bool two_discs) {
  return ltca::test::Over9DegreesAt100Nm(two_discs ? ltca::test::SteelLiu52TwoDiscs() : ltca::test::SteelLiu52(), 4);
}

/// Pin-circle radius deviation drawn normal, eccentricity deviation uniform (mm), six samples, limits on the
/// peak-to-peak TE and the largest contact stress that some samples miss.
analysis::ToleranceSettings StudySettings() {
  analysis::ToleranceSettings s;
  analysis::ToleranceDistribution circle;
  circle.key = "pin_circle_deviation_mm";
  circle.kind = analysis::ToleranceDistribution::Kind::kNormal;
  circle.sigma = 0.003;
  analysis::ToleranceDistribution radius;
  radius.key = "eccentricity_deviation_mm";
  radius.kind = analysis::ToleranceDistribution::Kind::kUniform;
  radius.tolerance = 0.002;
  s.distributions = {circle, radius};
  s.samples = 6;
  s.seed = 11;
  s.limits = {{"mean_backlash_arcsec", -INFINITY, 0.0}, {"max_contact_stress_mpa", 0.0, 1e9}};
  s.chains = {{"B0", {{"housing bore", true, 9.0, 0.0}, {"bearing ring", false, 0.0, -6.0}}}};
  return s;
}

}  // namespace

TEST_CASE("analysis: a tolerance study's samples are the backlash and the loaded sweep of each sample's pair, its pass fractions their counts") {
  for (const bool two_discs : {false, true}) {
    CAPTURE(two_discs);
    const analysis::ToleranceStudy study(TolerancedLiu52(two_discs), analysis::SolverOptions{}, StudySettings());
    std::vector<ToleranceSample> streamed;
    analysis::ToleranceRunPlan plan;
    plan.threads = 2;
    plan.worst_case = false;
    plan.sink = [&](const ToleranceSample& s) { streamed.push_back(s); };
    const analysis::ToleranceResult result = analysis::RunToleranceStudy(study, plan);

    REQUIRE(result.table.size() == 6);
    REQUIRE(streamed.size() == 6);
    CHECK(result.summary.samples == 6);
    CHECK(result.all_succeeded());
    CHECK_FALSE(result.worst_case.has_value());
    for (std::int64_t k = 0; k < result.table.size(); ++k) {
      CAPTURE(k);
      const ToleranceSample& s = streamed[static_cast<std::size_t>(k)];
      REQUIRE(s.index == k);
      REQUIRE(result.table.succeeded(k));
      // The sample's inputs are its draw, and its pair is the nominal one with them applied.
      CHECK(s.inputs == study.Draw(k));
      const analysis::ToleranceCase pair = study.Apply(s.inputs);
      const analysis::Stage stage(pair.design, pair.sweep.CrankAngles());
      const analysis::BacklashSummary backlash = analysis::Backlash(stage, stage.kinematics()).summary;
      const analysis::SweepSummary loaded = analysis::SolveSweep(stage, study.options(), pair.torque).summary;
      const analysis::ToleranceFigures& f = result.table.figures(k);
      CHECK(f[analysis::kMeanBacklashArcsec] == doctest::Approx(ltca::units::RadToArcsec(backlash.mean())).epsilon(1e-12));
      CHECK(f[analysis::kPpBacklashArcsec] == doctest::Approx(ltca::units::RadToArcsec(backlash.pp())).epsilon(1e-12));
      CHECK(f[analysis::kMeanTeArcsec] == doctest::Approx(ltca::units::RadToArcsec(loaded.mean_te)).epsilon(1e-12));
      CHECK(f[analysis::kPpTeArcsec] == doctest::Approx(ltca::units::RadToArcsec(loaded.pp_te)).epsilon(1e-12));
      CHECK(f[analysis::kMaxContactStressMpa] == doctest::Approx(loaded.max_contact_stress).epsilon(1e-12));
      CHECK(f[analysis::kMaxPinForceN] == doctest::Approx(loaded.max_pin_force).epsilon(1e-12));
      // The pins vary from sample to sample: every sample is its own pair.
      if (k > 0) CHECK(f[analysis::kMeanTeArcsec] != result.table.figures(k - 1)[analysis::kMeanTeArcsec]);
    }
    // Each limit's pass fraction is the count of the samples with the figure within it.
    REQUIRE(result.summary.limits.size() == 2);
    std::int64_t all = 0;
    for (std::int64_t k = 0; k < 6; ++k) {
      bool every = true;
      for (const analysis::LimitResult& l : result.summary.limits) {
        const auto& names = analysis::ToleranceSettings::FigureNames();
        const std::size_t f = static_cast<std::size_t>(std::find(names.begin(), names.end(), l.limit.figure) - names.begin());
        const double v = result.table.figures(k)[f];
        every = every && v >= l.limit.min && v <= l.limit.max;
      }
      all += every ? 1 : 0;
    }
    std::int64_t within_stress = 0;
    for (std::int64_t k = 0; k < 6; ++k) within_stress += result.table.figures(k)[analysis::kMaxContactStressMpa] <= 1e9 ? 1 : 0;
    CHECK(result.summary.limits[1].passed == within_stress);
    CHECK(result.summary.limits[1].fraction == doctest::Approx(within_stress / 6.0));
    CHECK(result.summary.limits[0].passed == 0);  // no mean backlash is negative
    CHECK(result.summary.passed_all == all);
    CHECK(result.summary.pass_fraction == doctest::Approx(all / 6.0));
    // The chain: the extreme-value closing link of Jiang 2022 section 5.1 (max = ES - EI = 9 - (-6),
    // min = EI - ES = 0 - 0) and its Monte Carlo inside it.
    REQUIRE(result.chains.size() == 1);
    CHECK(result.chains[0].name == "B0");
    CHECK(result.chains[0].extreme_value.min == doctest::Approx(0.0));
    CHECK(result.chains[0].extreme_value.max == doctest::Approx(15.0));
    CHECK(result.chains[0].monte_carlo.count == 6);
    CHECK(result.chains[0].monte_carlo.min >= 0.0);
    CHECK(result.chains[0].monte_carlo.max <= 15.0);
  }
}

TEST_CASE("analysis: a tolerance study's result does not depend on its threads or its first block, the worst case runs when asked") {
  const analysis::ToleranceStudy study(TolerancedLiu52(false), analysis::SolverOptions{}, StudySettings());
  analysis::ToleranceRunPlan one;
  one.threads = 1;
  one.first = 3;
  one.worst_case = true;
  analysis::ToleranceRunPlan three = one;
  three.threads = 3;
  three.worst_case = false;
  const analysis::ToleranceResult a = analysis::RunToleranceStudy(study, one), b = analysis::RunToleranceStudy(study, three);
  REQUIRE(a.table.size() == 6);
  REQUIRE(b.table.size() == 6);
  CHECK(a.table.first() == 3);
  for (std::int64_t k = 0; k < 6; ++k) {
    for (std::size_t f = 0; f < analysis::kToleranceFigureCount; ++f) {
      const double x = a.table.figures(k)[f], y = b.table.figures(k)[f];
      CHECK(((std::isnan(x) && std::isnan(y)) || x == y));
    }
    // Sample 3 + k of this study is sample 3 + k whatever the block it runs in.
    CHECK(a.table.figures(k)[analysis::kMeanTeArcsec] == study.Run(3 + k).figures[analysis::kMeanTeArcsec]);
  }
  REQUIRE(a.worst_case.has_value());
  CHECK(a.worst_case->runs > 0);
  CHECK(std::isfinite(a.worst_case->figures[analysis::kMeanTeArcsec].nominal));
  CHECK_FALSE(b.worst_case.has_value());
  // --first beyond the last index a std::int64_t holds.
  analysis::ToleranceRunPlan overflow;
  overflow.first = INT64_MAX - 2;
  CHECK_THROWS_AS(analysis::RunToleranceStudy(study, overflow), std::invalid_argument);
}

TEST_CASE("analysis: a tolerance run's estimate counts the worst case's runs at the samples' rate, none without it") {
  // Two input columns (the pin-circle and the eccentricity deviations) and 12 figures: the worst
  // case runs at most 1 + 2 x (2 + 12) = 29 corners (tolerance_run.hpp, ToleranceProgress::Start).
  struct Recorder final : analysis::ToleranceProgress {
    int estimates = 0;
    double seconds = 0.0, worst_seconds = -1.0;
    std::int64_t worst_runs = -1, worst_total = -1;
    void Start(analysis::TolerancePhase phase, std::int64_t total) override {
      if (phase == analysis::TolerancePhase::kWorstCase) worst_total = total;
    }
    void Estimate(double s, std::int64_t, std::int64_t, double ws, std::int64_t wr) override {
      ++estimates, seconds = s, worst_seconds = ws, worst_runs = wr;
    }
  };
  const analysis::ToleranceStudy study(TolerancedLiu52(false), analysis::SolverOptions{}, StudySettings());
  REQUIRE(study.inputs().size() == 2);
  for (const bool worst_case : {true, false}) {
    CAPTURE(worst_case);
    Recorder recorder;
    analysis::ToleranceRunPlan plan;
    plan.threads = 1;  // 2 warm-up samples, then the estimate at the third of 6 (a twentieth passed)
    plan.worst_case = worst_case;
    plan.progress = &recorder;
    const analysis::ToleranceResult result = analysis::RunToleranceStudy(study, plan);
    REQUIRE(recorder.estimates == 1);
    CHECK(recorder.seconds > 0.0);
    if (worst_case) {
      CHECK(recorder.worst_runs == 29);
      CHECK(recorder.worst_total == 29);
      REQUIRE(result.worst_case.has_value());
      CHECK(result.worst_case->runs <= 29);
      CHECK(recorder.worst_seconds > 0.0);
    } else {
      CHECK(recorder.worst_runs == 0);
      CHECK(recorder.worst_seconds == 0.0);
    }
  }
}
