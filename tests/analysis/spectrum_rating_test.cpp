// Issue 50: a load spectrum's pitting safety (analysis::SpectrumContactSafety) and its verdicts
// (analysis::SpectrumRatingRows). The safety is checked against a closed form derived here, not
// against the program: on one falling segment of ISO 6336-2's life-factor curve for steel,
// Z_NT = 1.6 (N / 1e5)^-b with b = ln 1.6 / ln 500 (1.6 at 1e5 cycles, 1.0 at 5e7), the cycles to
// pitting at a stress sigma are N = 1e5 (sigma / (1.6 sigma_Hlim))^(-1/b), and Miner's damage
// sum_i n_i / N(S sigma_i) = 1 solves to S = 1.6 sigma_Hlim / (sum_i n_i sigma_i^(1/b) / 1e5)^b
// (the equivalent stress of a Basquin curve). One load: S = sigma_Hlim Z_NT(n) / sigma, the single
// run's S_H (ISO 6336-2 S_H = sigma_HG / sigma_H with the other factors 1), on every part of the
// curve, its flat ends included.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/analysis/allowables.hpp"
#include "ltca/analysis/spectrum.hpp"
#include "ltca/contact/bearing.hpp"
#include "ltca/contact/contact_fatigue.hpp"

namespace {

const ltca::analysis::AllowableRow& Row(const std::vector<ltca::analysis::AllowableRow>& rows, const std::string& figure) {
  for (const auto& r : rows) {
    if (r.figure == figure) return r;
  }
  FAIL("no row " << figure);
  return rows.front();
}

}  // namespace

TEST_CASE("analysis: a spectrum's pitting safety is the single run's S_H for one load and the closed form for two") {
  using ltca::analysis::SpectrumContactSafety;
  using ltca::contact::LifeCurve;
  const double hlim = 1500.0;
  // One load, on each part of the steel curve: static (1e4 cycles), falling (1e6, 1e9) and the floor (1e11).
  for (const double n : {1e4, 1e6, 1e9, 1e11}) {
    CAPTURE(n);
    const double sigma = 1400.0;
    const double s_h = hlim * ltca::contact::LifeFactor(LifeCurve::kSteel, n) / sigma;
    CHECK(SpectrumContactSafety({{n, sigma}}, LifeCurve::kSteel, hlim) == doctest::Approx(s_h).epsilon(1e-12));
  }
  // Two loads on the segment 1e5 to 5e7: the closed form above (the scaled loads land at 1.1e6 and
  // 2.1e7 cycles to pitting, inside the segment).
  const double b = std::log(1.6) / std::log(500.0);
  const double n1 = 1e6, s1 = 1500.0, n2 = 2e6, s2 = 1200.0;
  const double expected = 1.6 * hlim / std::pow((n1 * std::pow(s1, 1.0 / b) + n2 * std::pow(s2, 1.0 / b)) / 1e5, b);
  CHECK(expected == doctest::Approx(1.33420576).epsilon(1e-8));  // /usr/bin/python3, the same closed form
  CHECK(SpectrumContactSafety({{n1, s1}, {n2, s2}}, LifeCurve::kSteel, hlim) == doctest::Approx(expected).epsilon(1e-12));
  // An unloaded bin adds nothing; no loaded bin: no damage at any factor; a bin not rated: unknown.
  CHECK(SpectrumContactSafety({{n1, s1}, {n2, s2}, {0.0, 0.0}}, LifeCurve::kSteel, hlim) == doctest::Approx(expected).epsilon(1e-12));
  CHECK(std::isinf(SpectrumContactSafety({{0.0, 0.0}}, LifeCurve::kSteel, hlim)));
  CHECK(std::isnan(SpectrumContactSafety({{n1, s1}, {NAN, NAN}}, LifeCurve::kSteel, hlim)));
}

TEST_CASE("analysis: each verdict of a spectrum flips where its figure crosses its target") {
  using namespace ltca::analysis;
  SpectrumResult r;
  r.l10_hours = {9000.0, 12000.0};
  r.load_zone_hours = {6000.0, 8000.0};
  r.contact_life_hours = {30000.0, 50000.0};
  r.contact_safety = {1.2, 1.4};
  r.required_contact_hours = 20000.0;
  r.static_safety = {3.0, 2.5};
  r.static_safety_bin = {0, 1};
  r.max_roller_stress = {2100.0, 2400.0};
  r.max_roller_stress_bin = {1, 1};
  r.max_contact_stress = 1800.0;
  r.max_contact_stress_bin = 1;
  // Each figure with its target a hair above and a hair below it.
  const auto judge = [&](double life, double s0, double contact_life, double s_h, double stress_limit) {
    AllowablesSettings t;
    t.bearing_life_hours = life;
    t.min_static_safety = s0;
    t.contact_life_hours = contact_life;
    t.min_contact_safety = s_h;
    return SpectrumRatingRows(r, t, stress_limit, true);
  };
  const double up = 1.0 + 1e-9, down = 1.0 - 1e-9;
  const auto below = judge(6000.0 * down, 2.5 * down, 30000.0 * down, 1.2 * down, 1800.0 * up);
  const auto above = judge(6000.0 * up, 2.5 * up, 30000.0 * up, 1.2 * up, 1800.0 * down);
  for (const char* figure : {"spectrum.shortest_load_zone_life_hours", "spectrum.smallest_static_safety",
                             "spectrum.shortest_pitting_life_hours", "spectrum.smallest_pitting_safety", "spectrum.max_contact_stress_mpa"}) {
    CAPTURE(figure);
    CHECK(Row(below, figure).verdict == AllowableVerdict::kPass);
    CHECK(Row(above, figure).verdict == AllowableVerdict::kFail);
  }
  // The basic L10 (9000 h) passes both; the roller stress against ISO 76's 4,000 MPa passes.
  CHECK(Row(above, "spectrum.shortest_l10_hours").verdict == AllowableVerdict::kPass);
  CHECK(Row(above, "spectrum.largest_roller_contact_stress_mpa").value == 2400.0);
  CHECK(Row(above, "spectrum.largest_roller_contact_stress_mpa").range.max == ltca::contact::kStaticStressLimitRoller);
  r.max_roller_stress = {2100.0, ltca::contact::kStaticStressLimitRoller * up};
  CHECK(Row(judge(1.0, 1.0, 1.0, 1.0, 1e4), "spectrum.largest_roller_contact_stress_mpa").verdict == AllowableVerdict::kFail);
  // The static rows name the bin that sets them (1-based).
  CHECK(Row(above, "spectrum.smallest_static_safety").basis.find("set by bin 2") != std::string::npos);
  CHECK(Row(above, "spectrum.max_contact_stress_mpa").basis.find("set by bin 2") != std::string::npos);
  // Without targets: computed, no allowable (the stresses keep their limits).
  const auto none = SpectrumRatingRows(r, AllowablesSettings{}, std::numeric_limits<double>::infinity(), true);
  CHECK(Row(none, "spectrum.smallest_static_safety").verdict == AllowableVerdict::kNoAllowable);
  CHECK(Row(none, "spectrum.max_contact_stress_mpa").verdict == AllowableVerdict::kNoAllowable);
}
