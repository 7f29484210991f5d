// [tolerances] on a reducer stage's hole positions (output_hole_radial_deviations_mm,
// output_hole_tangential_deviations_mm): drawn for every hole of every disc, since discs are
// machined one by one (docs/stage.md, "Per-disc errors"). Independent references: the same holes
// written into a deck by hand ([output] and [second_disc] hole_*_deviations_mm), and the moments of
// the uniform and of the normal truncated at 3 sigma (Johnson, Kotz & Balakrishnan 1994, vol. 1,
// ch. 13 sec. 10.1) computed here.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "deck_runs.hpp"
#include "helpers.hpp"
#include "ltca/analysis/tolerance.hpp"
#include "ltca/app/deck.hpp"

namespace hole_tolerance_test {

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

/// rv_two_discs_cranks.toml (two discs on three crankshafts) over `positions` crank angles from 0 to
/// 6 deg, with these [tolerances] lines.
std::string RvWith(const std::string& tolerances, int positions = 2) {
  std::string rv = ltca::test::ReadText(ltca::test::Case("stage/rv_two_discs_cranks.toml"));
  rv += "\n[tolerances]\n" + tolerances;
  rv = Replace(rv, "positions = 120", fmt::format("positions = {}", positions));
  return Replace(rv, "crank_end_deg = 357.0", "crank_end_deg = 6.0");
}

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string List(const std::vector<double>& v) {
  std::string out = "[";
  for (std::size_t j = 0; j < v.size(); ++j) out += fmt::format("{}{:.17g}", j > 0 ? ", " : "", v[j]);
  return out + "]";
}

}  // namespace hole_tolerance_test

TEST_CASE("app: [tolerances] draws each disc's hole positions on its own, a sample is the deck with those holes written by hand") {
  using namespace hole_tolerance_test;
  const std::string tol =
      "samples = 3\n"
      "output_hole_radial_deviations_mm = { distribution = \"uniform\", tolerance = 0.004 }\n"
      "output_hole_tangential_deviations_mm = { distribution = \"normal\", tolerance = 0.003 }\n";
  const ltca::app::Deck deck = ltca::app::ParseDeck(RvWith(tol), "t.toml");
  REQUIRE(deck.reducer);
  REQUIRE(deck.tolerances);
  const auto study = ltca::test::ToleranceOn(deck, deck.solver, *deck.tolerances);
  // Three crank holes on each of two discs, for each of the two keys.
  const std::vector<std::string> names = {
      "output_hole_radial_deviations_mm[1]",               "output_hole_radial_deviations_mm[2]",
      "output_hole_radial_deviations_mm[3]",               "output_hole_radial_deviations_mm[1] (disc 2)",
      "output_hole_radial_deviations_mm[2] (disc 2)",      "output_hole_radial_deviations_mm[3] (disc 2)",
      "output_hole_tangential_deviations_mm[1]",           "output_hole_tangential_deviations_mm[2]",
      "output_hole_tangential_deviations_mm[3]",           "output_hole_tangential_deviations_mm[1] (disc 2)",
      "output_hole_tangential_deviations_mm[2] (disc 2)",  "output_hole_tangential_deviations_mm[3] (disc 2)"};
  REQUIRE(study.inputs().size() == names.size());
  for (std::size_t c = 0; c < names.size(); ++c) CHECK(study.inputs()[c].name == names[c]);
  CHECK(Contains(ltca::analysis::Describe(deck.tolerances->distributions[0]), "per hole of each disc"));

  const std::vector<double> x = study.Draw(1);
  // Each draw lands on its own disc's hole: disc 1's on the common list, disc 2's on its own.
  const auto applied = study.Apply(x);
  const auto& r = *applied.design.reducer;
  REQUIRE(r.second_disc_holes);
  for (int j = 0; j < 3; ++j) {
    const auto k = static_cast<std::size_t>(j);
    CHECK(r.Holes(0).at(k) == Eigen::Vector2d(x[k], x[6 + k]));
    CHECK(r.Holes(1).at(k) == Eigen::Vector2d(x[3 + k], x[9 + k]));
    CHECK(r.Holes(0).at(k) != r.Holes(1).at(k));  // the two discs' holes differ
    CHECK(std::abs(x[k]) <= 0.004);
    CHECK(std::abs(x[6 + k]) <= 0.003);  // the normal truncated at +-3 sigma
  }
  // The sample is the deck with those holes given by hand, figure for figure, bit for bit.
  const std::vector<double> r1(x.begin(), x.begin() + 3), r2(x.begin() + 3, x.begin() + 6), t1(x.begin() + 6, x.begin() + 9),
      t2(x.begin() + 9, x.end());
  std::string by_hand = RvWith("samples = 1\n");
  by_hand = Replace(by_hand, "[second_disc]                 # identical to the first\n",
                    fmt::format("[second_disc]\nhole_radial_deviations_mm = {}\nhole_tangential_deviations_mm = {}\n", List(r2), List(t2)));
  by_hand = Replace(by_hand, "kind = \"cranks\"\n",
                    fmt::format("kind = \"cranks\"\nhole_radial_deviations_mm = {}\nhole_tangential_deviations_mm = {}\n", List(r1), List(t1)));
  const ltca::app::Deck hand = ltca::app::ParseDeck(by_hand, "t.toml");
  const auto hand_study = ltca::test::ToleranceOn(hand, hand.solver, *hand.tolerances);
  const auto sample = study.Run(1);
  const auto reference = hand_study.Evaluate(hand_study.nominal());
  REQUIRE(sample.status == ltca::analysis::RunStatus::kSuccess);
  REQUIRE(reference.status == ltca::analysis::RunStatus::kSuccess);
  for (std::size_t f = 0; f < ltca::analysis::kToleranceFigureCount; ++f) {
    CAPTURE(f);
    if (std::isnan(reference.figures[f])) CHECK(std::isnan(sample.figures[f]));
    else CHECK(sample.figures[f] == reference.figures[f]);
  }
  // The holes matter: the sample's largest bearing load is not the nominal pair's.
  const auto nominal = study.Evaluate(study.nominal());
  CHECK(std::abs(sample.figures[ltca::analysis::kMaxBearingLoadN] - nominal.figures[ltca::analysis::kMaxBearingLoadN]) > 1.0);
}

TEST_CASE("app: hole position tolerances of zero give the nominal stage bit for bit, one disc draws once, no stage, no holes") {
  using namespace hole_tolerance_test;
  const ltca::app::Deck deck = ltca::app::ParseDeck(
      RvWith("samples = 2\noutput_hole_radial_deviations_mm = { distribution = \"uniform\", tolerance = 0.0 }\n"), "t.toml");
  const auto study = ltca::test::ToleranceOn(deck, deck.solver, *deck.tolerances);
  REQUIRE(study.inputs().size() == 6);
  for (const double v : study.Draw(0)) CHECK(v == 0.0);
  const auto applied = study.Apply(study.Draw(0));
  CHECK(applied.design.reducer->cranks.hole_deviation.empty());
  CHECK(!applied.design.reducer->second_disc_holes);
  const auto sample = study.Run(0), nominal = study.Evaluate(study.nominal());
  REQUIRE(sample.status == ltca::analysis::RunStatus::kSuccess);
  for (std::size_t f = 0; f < ltca::analysis::kToleranceFigureCount; ++f) {
    CAPTURE(f);
    if (std::isnan(nominal.figures[f])) CHECK(std::isnan(sample.figures[f]));
    else CHECK(sample.figures[f] == nominal.figures[f]);
  }
  // One disc (the cycloidal drive's eight output pins): one column per hole, no "(disc 2)".
  std::string one = ltca::test::ReadText(ltca::test::Case("stage/cycloidal_drive.toml"));
  one += "\n[tolerances]\nsamples = 2\noutput_hole_tangential_deviations_mm = { distribution = \"normal\", sigma = 0.001 }\n";
  const ltca::app::Deck drive = ltca::app::ParseDeck(one, "t.toml");
  const auto one_study = ltca::test::ToleranceOn(drive, drive.solver, *drive.tolerances);
  REQUIRE(one_study.inputs().size() == 8);
  CHECK(one_study.inputs()[7].name == "output_hole_tangential_deviations_mm[8]");
  const std::vector<double> x = one_study.Draw(0);
  const auto holes = one_study.Apply(x).design.reducer->pins.hole_deviation;
  REQUIRE(holes.size() == 8);
  for (std::size_t j = 0; j < 8; ++j) CHECK(holes[j] == Eigen::Vector2d(0.0, x[j]));
  // A pair without a stage has no holes to vary; a tolerance beyond the small-deviation rule is refused.
  std::string pair = ltca::test::ReadText(ltca::test::Case("liu2021_sec52_base.toml"));
  const auto error = [&](const std::string& text) {
    try {
      const ltca::app::Deck d = ltca::app::ParseDeck(text, "t.toml");
      (void)ltca::test::ToleranceOn(d, d.solver, *d.tolerances);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(Contains(error(pair + "\n[tolerances]\noutput_hole_radial_deviations_mm = { distribution = \"uniform\", tolerance = 0.002 }\n"),
                 "[tolerances] output_hole_radial_deviations_mm: the deck has no reducer stage, so no holes"));
  CHECK(Contains(error(RvWith("output_hole_radial_deviations_mm = { distribution = \"uniform\", tolerance = 2.5 }\n")),
                 "looks like an absolute value"));
}

TEST_CASE("app: the hole position draws have their distribution's mean and standard deviation, each disc's independent of the other's") {
  using namespace hole_tolerance_test;
  // 20,000 draws of every column (no solve: Draw is the sampling alone). Uniform +-t about a centre
  // offset m: mean m, sd t / sqrt 3. Normal given as +-t (3 sigma) truncated there: sd
  // sigma sqrt(1 - 2 a phi(a) / (2 Phi(a) - 1)) at a = 3. Tolerances: 5 standard errors of the
  // mean (sd / sqrt n) and of the sd (sd sqrt((kurtosis - 1) / (4 n)): kurtosis 1.8 uniform, at
  // most 3 for the truncated normal), and 5 / sqrt n for the correlation of the two discs' draws
  // of the same hole (zero for independent streams).
  const double t = 0.004, m = 0.001, tn = 0.003;
  const ltca::app::Deck deck = ltca::app::ParseDeck(
      RvWith(fmt::format("samples = 2\noutput_hole_radial_deviations_mm = {{ distribution = \"uniform\", tolerance = {}, mean = {} }}\n"
                         "output_hole_tangential_deviations_mm = {{ distribution = \"normal\", tolerance = {} }}\n",
                         t, m, tn)),
      "t.toml");
  const auto study = ltca::test::ToleranceOn(deck, deck.solver, *deck.tolerances);
  REQUIRE(study.inputs().size() == 12);
  const int n = 20000;
  std::vector<double> sum(12, 0.0), sum2(12, 0.0), cross(6, 0.0);
  for (int i = 0; i < n; ++i) {
    const std::vector<double> x = study.Draw(i);
    for (std::size_t c = 0; c < 12; ++c) sum[c] += x[c], sum2[c] += x[c] * x[c];
    for (std::size_t h = 0; h < 3; ++h) {
      cross[h] += (x[h] - m) * (x[3 + h] - m);   // radial: disc 1 against disc 2, hole h
      cross[3 + h] += x[6 + h] * x[9 + h];        // tangential
    }
  }
  const double a = 3.0, pi = std::acos(-1.0);
  const double phi = std::exp(-0.5 * a * a) / std::sqrt(2.0 * pi), mass = std::erf(a / std::sqrt(2.0));
  const double sd_uniform = t / std::sqrt(3.0), sd_normal = (tn / 3.0) * std::sqrt(1.0 - 2.0 * a * phi / mass);
  for (std::size_t c = 0; c < 12; ++c) {
    CAPTURE(study.inputs()[c].name);
    const bool radial = c < 6;
    const double mean = sum[c] / n, sd = std::sqrt((sum2[c] - n * mean * mean) / (n - 1));
    const double want_mean = radial ? m : 0.0, want_sd = radial ? sd_uniform : sd_normal;
    CHECK(std::abs(mean - want_mean) < 5.0 * want_sd / std::sqrt(n));
    CHECK(std::abs(sd - want_sd) < 5.0 * want_sd * std::sqrt((radial ? 0.8 : 2.0) / (4.0 * n)));
  }
  for (std::size_t h = 0; h < 6; ++h) {
    const double sd = h < 3 ? sd_uniform : sd_normal;
    CHECK(std::abs(cross[h] / n / (sd * sd)) < 5.0 / std::sqrt(n));
  }
}

TEST_CASE("app: the sensitivity names the hole position keys, each with its holes on both discs as its columns") {
  using namespace hole_tolerance_test;
  // Figures made from the draws (no solve): the mean TE is 1000 x the second disc's radial deviation
  // of hole 2 plus a small part of the first disc's tangential one of hole 1; the key of the radial
  // deviations then holds nearly all the variance, both keys show their 6 columns.
  const ltca::app::Deck deck = ltca::app::ParseDeck(
      RvWith("samples = 400\noutput_hole_radial_deviations_mm = { distribution = \"uniform\", tolerance = 0.004 }\n"
             "output_hole_tangential_deviations_mm = { distribution = \"uniform\", tolerance = 0.004 }\n"),
      "t.toml");
  const auto study = ltca::test::ToleranceOn(deck, deck.solver, *deck.tolerances);
  std::vector<ltca::analysis::ToleranceSample> samples;
  for (int i = 0; i < 400; ++i) {
    ltca::analysis::ToleranceSample s;
    s.index = i;
    const std::vector<double> x = study.Draw(i);
    for (auto& f : s.figures) f = 1.0;
    s.figures[ltca::analysis::kMeanTeArcsec] = 1000.0 * x[4] + 100.0 * x[6];
    samples.push_back(s);
  }
  const auto summary = ltca::analysis::Summarise(study, samples);
  const auto& te = summary.sensitivity[ltca::analysis::kMeanTeArcsec];
  REQUIRE(te.keys.size() == 2);
  CHECK(te.keys[0].key == "output_hole_radial_deviations_mm");
  CHECK(te.keys[0].columns == 6);
  CHECK(te.keys[0].distinguishable);
  CHECK(std::isnan(te.keys[0].src));  // a per-hole key has no single coefficient
  // About 1000^2 / (1000^2 + 100^2) = 0.990 (equal variances), up to the sample's own covariances.
  CHECK(te.keys[0].share > 0.97);
  CHECK(te.keys[1].key == "output_hole_tangential_deviations_mm");
  CHECK(te.keys[1].columns == 6);
  CHECK(te.keys[1].share < 0.03);
  // A linear figure of the inputs: R^2 = 1, and Pratt's shares add up to it.
  CHECK(te.r_squared == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(te.keys[0].share + te.keys[1].share == doctest::Approx(1.0).epsilon(1e-12));
}
