// The documents built from the analyses' results (solvers/app/documents). Independent references:
// the analysis's own summary (the mean a figure marks), the positions as the analysis hands them
// out (what a decimated figure must keep), and the JSON document streamed against the same
// document built whole.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "cli_run.hpp"
#include "documents/backlash.hpp"
#include "documents/common.hpp"
#include "documents/mesh.hpp"
#include "documents/solve.hpp"
#include "documents/stiffness.hpp"
#include "documents/tolerance.hpp"
#include "helpers.hpp"
#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/mesh.hpp"
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

TEST_CASE("app: a JSON number is written as nlohmann::json writes it and reads back to the same double") {
  // Independent references: the C library's strtod (the text must read back to the double, bit
  // for bit) and nlohmann::json's own serializer (Grisu2: the same text, or where Grisu2 misses the
  // shortest digits, text no longer than its and reading back to the same double).
  std::vector<double> values = {0.0, -0.0, 1.0, -1.0, 0.1, 1e-5, 1e-4, 0.00012345, 1e15, 1e16, 123456789012345.0,
                                1234567890123456.0, 2.5e-300, 5e-324, std::numeric_limits<double>::max(),
                                std::numeric_limits<double>::min(), 1.0 / 3.0, -2.0 / 3.0, 100.0, 1e21, 1e22};
  std::mt19937_64 random(20261129);
  for (int i = 0; i < 200000; ++i) {
    std::uint64_t bits = random();
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof v);
    if (i % 2 == 0) v = std::ldexp(static_cast<double>(bits >> 11) / 9007199254740992.0, static_cast<int>(bits % 80) - 40);
    values.push_back(v);
  }
  int same = 0, shorter = 0, finite = 0;
  for (const double v : values) {
    std::string ours;
    ltca::app::documents::AppendJsonNumber(ours, v);
    const std::string theirs = nlohmann::json(v).dump();
    if (!std::isfinite(v)) {
      CHECK(ours == "null");
      continue;
    }
    ++finite;
    const double back = std::strtod(ours.c_str(), nullptr);
    CHECK(std::memcmp(&back, &v, sizeof v) == 0);
    if (ours == theirs) {
      ++same;
    } else {
      ++shorter;
      CHECK(ours.size() <= theirs.size());
      CHECK(std::strtod(theirs.c_str(), nullptr) == v);
    }
  }
  MESSAGE(same, " of ", finite, " finite values in the same text as nlohmann's, ", shorter, " shorter");
  CHECK(same >= 0.99 * finite);
  // Integers and strings: as nlohmann writes them.
  for (const std::int64_t k : {std::int64_t{0}, std::int64_t{-7}, std::int64_t{1234567890123}}) {
    std::string ours;
    ltca::app::documents::AppendJsonNumber(ours, k);
    CHECK(ours == nlohmann::json(k).dump());
  }
  for (const std::string& text : std::vector<std::string>{"", "success", "a \"quoted\" path\\x\n\ttab", std::string("ctl\x01\x1f"), "caf\xc3\xa9",
                                 std::string("bad \xff byte")}) {
    std::string ours;
    ltca::app::documents::AppendJsonString(ours, text);
    CHECK(ours == ltca::app::documents::Dump(nlohmann::json(text), -1));
  }
}

TEST_CASE("app: a position's JSON streamed without a tree is the document built whole") {
  // Every position of one disc, two discs, the slice model, a reducer stage and a failed solve
  // (a torque no position carries): AppendJson's text read back by nlohmann's parser is the
  // document Json(p) dumped and read back, every double bit for bit; the texts are the same bytes
  // but where nlohmann's Grisu2 writes a number in more digits than the shortest (about 1 in 1,000
  // numbers, above).
  struct Run {
    const char* deck;
    std::vector<std::string> sets;
  };
  const std::vector<Run> runs = {{"liu2021_table1.toml", {"sweep.positions=9"}},
                                 {"rv_two_discs.toml", {"sweep.positions=5"}},
                                 {"crowned.toml", {"sweep.positions=3"}},
                                 {"stage/cycloidal_drive.toml", {"sweep.positions=3"}},
                                 {"liu2021_table1.toml", {"sweep.positions=2", "load.torque_nm=1e9"}}};
  int positions = 0, failed = 0, slices = 0, stages = 0, discs = 0, same_bytes = 0;
  for (const Run& run : runs) {
    const std::string name = run.deck;
    CAPTURE(name);
    const ltca::app::Deck deck = ltca::app::LoadDeck(Case(run.deck), run.sets);
    ltca::analysis::SweepCallbacks callbacks;
    callbacks.on_position = [&](const ltca::analysis::PositionResult& p) {
      std::string streamed;
      ltca::app::documents::AppendJson(streamed, p);
      const std::string whole = ltca::app::documents::Dump(ltca::app::documents::Json(p), -1);
      CHECK(nlohmann::json::parse(streamed) == nlohmann::json::parse(whole));
      same_bytes += streamed == whole ? 1 : 0;
      ++positions;
      failed += p.succeeded() ? 0 : 1;
      slices += p.slices > 1 ? 1 : 0;
      stages += p.result.reducer ? 1 : 0;
      discs += p.disc_torque.empty() ? 0 : 1;
    };
    (void)ltca::app::SolveDeckSweep(deck, deck.solver, callbacks);
  }
  CHECK(positions == 22);
  CHECK(failed >= 2);
  CHECK(slices == 3);
  CHECK(stages == 3);
  CHECK(discs == 5);
  CHECK(same_bytes >= positions / 2);
}

TEST_CASE("app: the solve figure of a long sweep keeps each pin's largest force of every run of positions in its map") {
  // Liu Table 1 over 1,000 positions of 360 deg (compatibility): 120 map columns at most, so each
  // column stands for 9 positions. Independent reference: the positions as the sweep hands them
  // out, each column's largest force per pin taken here; the TE panel and the caption say the
  // decimation.
  const ltca::app::Deck deck =
      ltca::app::LoadDeck(Case("liu2021_table1.toml"), {"sweep.positions=1000", "sweep.crank_end_deg=360"});
  ltca::solvers::SolverOptions solver = deck.solver;
  solver.name = "compatibility";
  ltca::app::documents::SolveSeries series(deck.sweep.positions);
  std::vector<std::vector<double>> forces;
  ltca::analysis::SweepCallbacks callbacks;
  callbacks.on_position = [&](const ltca::analysis::PositionResult& p) {
    series.Add(p);
    forces.push_back(p.succeeded() ? p.pin_force : std::vector<double>(p.pin_force.size(), NAN));
  };
  const auto sweep = ltca::app::SolveDeckSweep(deck, solver, callbacks);
  REQUIRE(sweep.summary.all_succeeded());
  REQUIRE(forces.size() == 1000);
  const ltca::app::plots::Figure figure = ltca::app::documents::Figure(deck, solver, series, sweep.summary);
  REQUIRE(figure.panels.size() >= 4);
  const auto& map = figure.panels[3].map;
  REQUIRE(map.has_value());
  const std::size_t stride = 9;  // ceil(1000 / 120)
  REQUIRE(map->z.size() == (1000 + stride - 1) / stride);
  double largest_drawn = 0.0;
  for (std::size_t c = 0; c < map->z.size(); ++c) {
    for (std::size_t j = 0; j < forces[0].size(); ++j) {
      double want = 0.0;
      for (std::size_t i = c * stride; i < std::min<std::size_t>(forces.size(), (c + 1) * stride); ++i) want = std::max(want, forces[i][j]);
      CHECK(map->z[c][j] == want);
      largest_drawn = std::max(largest_drawn, map->z[c][j]);
    }
  }
  CHECK(largest_drawn == sweep.summary.max_pin_force);
  CHECK(figure.panels[3].title.find("max of every 9 positions") != std::string::npos);
  CHECK(figure.panels[0].title == "loaded transmission error");  // 1,000 positions: every one drawn
}

TEST_CASE("app: the tolerance estimate names the samples' time, the worst case's bound of runs and their sum") {
  // 2 s for 100 samples, then 185 runs at most at the samples' rate, 3 s: 5 s in all.
  const std::string both = ltca::app::documents::ToleranceEstimateText(2.0, 5, 100, 2, false, 3.0, 185);
  CHECK(both.find("about 2 s for the 100 samples, then about 3 s for the worst case's 185 runs at most, about 5 s in all") !=
        std::string::npos);
  CHECK(both.find("at the rate of samples 5 to 5 on 2 thread(s), after 4 that warm the caches") != std::string::npos);
  const std::string samples_only = ltca::app::documents::ToleranceEstimateText(2.0, 5, 100, 2, false, 0.0, 0);
  CHECK(samples_only.find("about 2 s for the 100 samples (") != std::string::npos);
  CHECK(samples_only.find("worst case's") == std::string::npos);
}

TEST_CASE("app: a deck read with --set or --unset names its overrides in the JSON case, the text, the figure's title and its caption") {
  // A deck changed on the command line is not the deck its title names (a figure titled "Liu 2021
  // Table 1" of an elastic body is a wrong label). Independent reference: the arguments as typed.
  const ltca::test::Outcome json = ltca::test::RunCli({"solve", Case("liu2021_table1.toml"), "--set", "sweep.positions=2",
                                                       "--unset", "load.torque_nm", "--set", "load.torque_nm=100", "--json", "-"});
  REQUIRE(json.code == 0);
  const auto doc = nlohmann::json::parse(json.out);
  // In the order they were applied: the removals first, then the values (cli/command.cpp).
  CHECK(doc.at("case").at("overrides") ==
        nlohmann::json({"--unset load.torque_nm", "--set sweep.positions=2", "--set load.torque_nm=100"}));
  const ltca::test::Outcome text = ltca::test::RunCli({"solve", Case("liu2021_table1.toml"), "--set", "sweep.positions=2"});
  REQUIRE(text.code == 0);
  CHECK(text.out.find("\noverrides --set sweep.positions=2\n") != std::string::npos);

  // Read as written: no overrides anywhere.
  const ltca::test::Outcome plain = ltca::test::RunCli({"mesh", Case("liu2021_table1.toml"), "--json", "-"});
  REQUIRE(plain.code == 0);
  CHECK_FALSE(nlohmann::json::parse(plain.out).at("case").contains("overrides"));
  const ltca::app::Deck as_written = ltca::app::LoadDeck(Case("liu2021_table1.toml"));
  CHECK(ltca::app::documents::CaseTitle(as_written) == as_written.info.title);
  CHECK(ltca::app::documents::CaseLines(as_written).find("overrides") == std::string::npos);

  // A short list follows the title in full, a long one is counted; the caption lists them.
  const ltca::app::Deck one = ltca::app::LoadDeck(Case("liu2021_table1.toml"), {"load.torque_nm=100"});
  const auto mesh = ltca::analysis::MeshAt(one.MakeModel(), 0.0);
  const ltca::app::plots::Figure figure = ltca::app::documents::Figure(one, mesh);
  CHECK(figure.title.starts_with(one.info.title + " (--set load.torque_nm=100): "));
  CHECK(figure.caption.find("\nwith --set load.torque_nm=100\n") != std::string::npos);
  const ltca::app::Deck many = ltca::app::LoadDeck(
      Case("liu2021_table1.toml"), {"load.torque_nm=100", "sweep.positions=3", "sweep.crank_end_deg=4", "-load.torque_nm", "load.torque_nm=50"});
  CHECK(ltca::app::documents::CaseTitle(many) == many.info.title + " (with 5 overrides)");
  CHECK(ltca::app::documents::CaseLines(many).find("overrides --set load.torque_nm=100 --set sweep.positions=3 --set "
                                                   "sweep.crank_end_deg=4 --unset load.torque_nm --set load.torque_nm=50\n") !=
        std::string::npos);
}
