// The documents built from the analyses' results (solvers/app/documents). Independent references:
// the analysis's own summary (the mean a figure marks), the positions as the analysis hands them
// out (what a decimated figure must keep), and the JSON document streamed against the same
// document built whole.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "documents/backlash.hpp"
#include "documents/stiffness.hpp"
#include "helpers.hpp"
#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/geometry/units.hpp"

using ltca::test::Case;

TEST_CASE("app: the backlash figure of a long sweep is decimated, keeps every extreme and marks the sweep's own mean") {
  // Liu Table 1 over one revolution in 5,000 positions: at most about 2,000 runs of positions,
  // each its least and largest backlash; the drawn extremes are the sweep's (peak-to-peak), and
  // the mean marked is the summary's, not the drawn points'.
  const ltca::app::Deck deck = ltca::app::LoadDeck(Case("liu2021_table1.toml"), {"sweep.positions=5000", "sweep.crank_end_deg=360"});
  const ltca::analysis::Stage stage(deck, deck.sweep.CrankAngles());
  ltca::app::documents::BacklashSeries series(stage.cranks().size());
  std::vector<double> all;
  const auto result = ltca::analysis::Backlash(stage, deck.kinematics, [&](const ltca::analysis::BacklashPosition& p) {
    series.Add(p);
    all.push_back(ltca::units::RadToArcsec(p.contact.backlash));
  });
  REQUIRE(all.size() == 5000);
  CHECK(series.backlash().stride() == 3);
  const std::vector<double>& drawn = series.backlash().y();
  CHECK(drawn.size() <= 2 * 2000);
  CHECK(drawn.size() < all.size());
  CHECK(*std::max_element(drawn.begin(), drawn.end()) == *std::max_element(all.begin(), all.end()));
  CHECK(*std::min_element(drawn.begin(), drawn.end()) == *std::min_element(all.begin(), all.end()));
  const ltca::app::plots::Figure figure = ltca::app::documents::Figure(deck, series, result);
  REQUIRE(!figure.panels.empty());
  REQUIRE(!figure.panels[0].marks.empty());
  CHECK(figure.panels[0].marks[0].value == doctest::Approx(ltca::units::RadToArcsec(result.summary.mean())).epsilon(1e-12));
  CHECK(figure.caption.find("least and largest of each 3 positions") != std::string::npos);
}

TEST_CASE("app: the backlash JSON streamed position by position is the document built whole") {
  const ltca::app::Deck deck = ltca::app::LoadDeck(Case("rv_two_discs.toml"), {"sweep.positions=7"});
  const ltca::analysis::Stage stage(deck, deck.sweep.CrankAngles());
  std::ostringstream streamed;
  std::vector<ltca::analysis::BacklashPosition> kept;
  ltca::app::documents::BacklashJsonWriter writer(streamed, deck, deck.kinematics, stage.disc_count() == 2);
  const auto result = ltca::analysis::Backlash(stage, deck.kinematics, [&](const ltca::analysis::BacklashPosition& p) {
    writer.Add(p);
    kept.push_back(p);
  });
  writer.Finish(deck, result);
  REQUIRE(kept.size() == 7);
  const nlohmann::json whole = ltca::app::documents::Json(deck, kept, result);
  CHECK(nlohmann::json::parse(streamed.str()) == whole);
  CHECK(whole.at("positions").at(0).contains("first_contact_disc"));  // two discs: the disc of each first contact
}

TEST_CASE("app: the stiffness figure's caption names the definition the loop was read with, not the deck's") {
  // The deck reads the secant at +-3 % (its defaults); the loop is read here as the tangent at
  // 100 N*m with lost motion at +-5 %, as --rigidity tangent --tangent-torque-nm 100
  // --lost-motion-fraction 0.05 ask. The caption must say what was computed.
  const ltca::app::Deck deck = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"));
  REQUIRE(deck.stiffness.rigidity == ltca::analysis::StiffnessSettings::Rigidity::kSecant);
  ltca::analysis::StiffnessSettings settings = deck.stiffness;
  settings.steps = 21;
  settings.crank = 0.0;
  settings.rigidity = ltca::analysis::StiffnessSettings::Rigidity::kTangent;
  settings.tangent_torque = ltca::units::NmToNmm(100.0);
  settings.lost_motion_fraction = 0.05;
  const ltca::solvers::SolverOptions solver = ltca::app::SolverFor(deck, "");
  const auto result = ltca::analysis::Stiffness(deck.MakeStage({0.0}), solver, settings, deck.RequireLoad().torque);
  const std::string caption = ltca::app::documents::Figure(deck, solver, result).caption;
  CHECK(caption.find("rigidity: the tangent at 100 N*m") != std::string::npos);
  CHECK(caption.find("+-5 % of T") != std::string::npos);
  CHECK(caption.find("secant") == std::string::npos);
}
