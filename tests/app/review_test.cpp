// Issue 26: the defects an independent review found, each a number a user would trust and should
// not, or a crash. Every test here failed on the code before the fix. The references are
// independent of the code under test: a plane model at each face edge for the misaligned
// backlash, the symmetry of +dy and -dy, the recorded positions of the sweep itself for its mean,
// hand-made inputs for the messages.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "cli_run.hpp"
#include "ltca/app/deck.hpp"
#include "deck_runs.hpp"
#include "ltca/analysis/slice_study.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"

using ltca::app::Deck;
using ltca::contact::ContactKinematics;
namespace units = ltca::units;

namespace {

using ltca::test::Case;
using ltca::test::Outcome;
using ltca::test::RunCli;

std::filesystem::path Temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("ltca_review_test_" + name);
}

}  // namespace

TEST_CASE("app: backlash under misalignment is the face-edge value at 5, 20 and 100 slices (1e-3 arcsec), issue 26 item 1") {
  // Liu 5.3, phi = 0.02 deg about face B: the review found 37.352 arcsec at 20 slices against
  // 36.777 at the face edges (slice centres miss the edge by B / (2 n)).
  const Deck deck = ltca::app::LoadDeck(Case("liu2021_sec53_phi.toml"));
  for (const ContactKinematics kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    // The reference takes another path: two plane models (no slices) with the cycloid centre where
    // the tilted axis puts it at face B and at the far face (the gap is linear along the face).
    const double reference = ltca::analysis::FaceEdgeUnloaded(deck, deck.sweep.CrankAngles(), kinematics).mean_arcsec;
    for (const int n : {5, 20, 100}) {
      Deck d = deck;
      d.geometry.width_slices = n;
      const auto sweep = ltca::contact::AnalyseUnloadedSweep(d.MakeModel(), d.sweep.CrankAngles(), kinematics);
      CAPTURE(n);
      CHECK(sweep.closed_period);
      CHECK(std::abs(units::RadToArcsec(sweep.mean_backlash) - reference) <= 1e-3);
    }
  }
}

TEST_CASE("app: +dy and -dy of Liu 5.3 give equal mean TE and mean backlash (1e-9 relative), issue 26 item 2") {
  // The pair offset by +dy at crank theta is the pair offset by -dy at theta + 180 deg turned half
  // a revolution: over one revolution the two sweeps visit the same states. The sweep from 0 to 360
  // deg repeats its first state as its last; counted twice it made -31.784 and -32.788 arcsec.
  const auto run = [](double dy_mm) {
    const Deck deck = ltca::app::LoadDeck(Case("liu2021_sec53_dy.toml"), {fmt::format("errors.centre_dy_mm={}", dy_mm)});
    ltca::solvers::SolverOptions options = deck.solver;
    options.name = "compatibility";
    const auto sweep = ltca::test::SolveSweep(deck, options);
    REQUIRE(sweep.summary.all_succeeded());
    CHECK(sweep.summary.closed_period);
    const auto backlash =
        ltca::contact::AnalyseUnloadedSweep(deck.MakeModel(), deck.sweep.CrankAngles(), ContactKinematics::kLinearised);
    CHECK(backlash.closed_period);
    // The mean weights each state once: the recorded positions but the last.
    double sum = 0.0;
    for (std::size_t i = 0; i + 1 < sweep.positions.size(); ++i) sum += sweep.positions[i].result.te;
    CHECK(sweep.summary.mean_te == doctest::Approx(sum / static_cast<double>(sweep.positions.size() - 1)).epsilon(1e-14));
    return std::pair{sweep.summary.mean_te, backlash.mean_backlash};
  };
  const auto [te_plus, backlash_plus] = run(0.009);
  const auto [te_minus, backlash_minus] = run(-0.009);
  CHECK(std::abs(te_plus - te_minus) <= 1e-9 * std::abs(te_plus));
  CHECK(std::abs(backlash_plus - backlash_minus) <= 1e-9 * std::abs(backlash_plus));
}

TEST_CASE("app: a sweep that does not close a period weights every position in the mean, issue 26 item 2") {
  // Half a mesh period of Liu Table 1: the last state is not the first.
  const Deck deck = ltca::app::LoadDeck(Case("liu2021_table1.toml"), {"sweep.crank_end_deg=4.5", "sweep.positions=10"});
  auto options = deck.solver;
  const auto sweep = ltca::test::SolveSweep(deck, options);
  REQUIRE(sweep.summary.all_succeeded());
  CHECK_FALSE(sweep.summary.closed_period);
  double sum = 0.0;
  for (const auto& p : sweep.positions) sum += p.result.te;
  CHECK(sweep.summary.mean_te == doctest::Approx(sum / static_cast<double>(sweep.positions.size())).epsilon(1e-14));
  // One mesh period (360 / z_p = 9 deg, the deck's own sweep) of the error-free pair closes.
  const Deck period = ltca::app::LoadDeck(Case("liu2021_table1.toml"));
  CHECK(ltca::test::SolveSweep(period, options).summary.closed_period);
}

TEST_CASE("app: no tip relief is assumed: the |d| >= 2 decks keep the tips they are given at any torque and stress limit, issue 26 item 3") {
  // The earlier default changed the part with the torque (0.01 / 0.2 / 0.5 mm at 250 / 500 / 1000
  // N*m) and the stress limit. Now the geometry is the deck's, and a loaded sharp corner is an
  // edge contact: a named status that every solver gives at the same positions, never a number.
  for (const char* name : {"hard/d2_loaded.toml", "hard/d3_loaded.toml"}) {
    for (const std::vector<std::string>& set : {std::vector<std::string>{}, std::vector<std::string>{"load.torque_nm=250"},
                                                std::vector<std::string>{"load.torque_nm=1000"},
                                                std::vector<std::string>{"material.contact_stress_limit_mpa=6000"}}) {
      CAPTURE(name);
      const Deck deck = ltca::app::LoadDeck(Case(name), set);
      CHECK(deck.tip_relief_source == "none");
      CHECK(deck.modification.tip_relief.rounding_radius == 0.0);
      CHECK(deck.modification.tip_relief.truncation == 0.0);
      CHECK(deck.tip_relief_note.find("sharp tips") != std::string::npos);
    }
    const Deck deck = ltca::app::LoadDeck(Case(name));
    std::vector<std::vector<ltca::solvers::SolverStatus>> statuses;
    for (const char* solver : {"bisection", "compatibility", "energy-qp", "energy-groups"}) {
      auto options = deck.solver;
      options.name = solver;
      const auto sweep = ltca::test::SolveSweep(deck, options);
      statuses.emplace_back();
      for (const auto& p : sweep.positions) {
        statuses.back().push_back(p.result.status);
      }
    }
    const auto edge = std::count(statuses[0].begin(), statuses[0].end(), ltca::solvers::SolverStatus::kEdgeContact);
    CHECK(edge > 0);
    for (const auto& s : statuses) CHECK(s == statuses[0]);
  }
}

TEST_CASE("app: a relief the user gives that carries load is reported with a warning, issue 26 item 3") {
  // d2_loaded with a 0.2 mm rounding: the review found a 3,782 MPa contact on the arc at crank 9 deg
  // where the sharp tips had a 754 MPa flank contact.
  const Deck deck = ltca::app::LoadDeck(Case("hard/d2_loaded.toml"), {"modification.tip_rounding_radius_mm=0.2"});
  REQUIRE(deck.tip_relief_source == "deck");
  auto options = deck.solver;
  options.name = "compatibility";
  const auto sweep = ltca::test::SolveSweep(deck, options);
  REQUIRE(sweep.summary.all_succeeded());
  bool on_arc = false;
  for (const auto& p : sweep.positions) {
    for (const auto& w : p.result.warnings) on_arc = on_arc || w.find("tip-rounding") != std::string::npos;
  }
  CHECK(on_arc);
  CHECK(sweep.summary.warned > 0);
}

TEST_CASE("cli: backlash and compare name the tips the geometry has, issue 26 item 3") {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"backlash", Case("hard/d2_loaded.toml"), "--set", "sweep.positions=3"},
        std::vector<std::string>{"compare", Case("hard/d2_loaded.toml"), "--set", "sweep.positions=3", "--solvers",
                                 "bisection,compatibility"}}) {
    const auto r = RunCli(args);
    CAPTURE(args[0]);
    CHECK(r.out.find("sharp tips") != std::string::npos);
  }
  const auto json = RunCli({"backlash", Case("hard/d2_loaded.toml"), "--set", "sweep.positions=3", "--json", "-"});
  REQUIRE(json.code == 0);
  const auto doc = nlohmann::json::parse(json.out);
  CHECK(doc["model"]["tip_relief"]["source"] == "none");
  const auto given = RunCli({"backlash", Case("hard/d2_loaded.toml"), "--set", "sweep.positions=3", "--set",
                             "modification.tip_rounding_radius_mm=0.2"});
  CHECK(given.out.find("0.2 mm rounding radius (from the deck)") != std::string::npos);
}

TEST_CASE("cli: compare lists the warnings that solve lists, issue 26 item 7") {
  // 1e6 N*m on Liu 5.2's pair: every solver solves, at 79,000 MPa, far beyond the material's limit.
  const std::vector<std::string> set = {"--set", "load.torque_nm=1e6", "--set", "sweep.positions=2"};
  std::vector<std::string> solve = {"solve", Case("liu2021_sec52_base.toml"), "--json", "-"};
  solve.insert(solve.end(), set.begin(), set.end());
  const auto s = RunCli(solve);
  REQUIRE(nlohmann::json::parse(s.out)["summary"]["warned_positions"].get<int>() > 0);
  std::vector<std::string> compare = {"compare", Case("liu2021_sec52_base.toml"), "--json", "-", "--solvers", "bisection,compatibility"};
  compare.insert(compare.end(), set.begin(), set.end());
  const auto c = RunCli(compare);
  const auto doc = nlohmann::json::parse(c.out);
  for (const auto& solver : doc["solvers"]) {
    CHECK(solver["warned_positions"].get<int>() > 0);
    CHECK(solver["first_warning"].is_string());
  }
  CHECK(c.err.find("warnings") != std::string::npos);
}

TEST_CASE("cli: backlash at a degenerate eccentricity is a failed position with null figures, never inf or nan, issue 26 item 8") {
  const auto r = RunCli({"backlash", Case("liu2021_sec52_base.toml"), "--set", "pair.eccentricity_mm=1e-4", "--set",
                         "sweep.positions=3", "--json", "-"});
  CAPTURE(r.err);
  // Either the deck is refused, naming the key, or every position that has no first contact
  // fails with null figures and exit 1.
  if (r.code == 2) {
    CHECK(r.err.find("eccentricity_mm") != std::string::npos);
    return;
  }
  REQUIRE(r.code == 1);
  CHECK(r.out.find("inf") == std::string::npos);
  CHECK(r.out.find("nan") == std::string::npos);
  const auto doc = nlohmann::json::parse(r.out);
  for (const auto& p : doc["positions"]) {
    if (p["status"] == "success") continue;
    CHECK(p["backlash_arcsec"].is_null());
    CHECK(p["first_contact_pin"].is_null());
  }
  CHECK(doc["summary"]["failed_positions"].get<int>() > 0);
}

TEST_CASE("cli: backlash follows the deck's [solver] kinematics as solve and stiffness do, issue 26 item 11") {
  const auto with = [](const std::string& kinematics) {
    const auto r = RunCli({"backlash", Case("liu2021_sec52_base.toml"), "--set", "sweep.positions=2", "--set",
                           "solver.kinematics=" + kinematics, "--json", "-"});
    REQUIRE(r.code == 0);
    return nlohmann::json::parse(r.out);
  };
  CHECK(with("linearised")["kinematics"] == "linearised");
  CHECK(with("exact")["kinematics"] == "exact");
  const auto given = RunCli({"backlash", Case("liu2021_sec52_base.toml"), "--set", "sweep.positions=2", "--set",
                             "solver.kinematics=linearised", "--kinematics", "exact", "--json", "-"});
  CHECK(nlohmann::json::parse(given.out)["kinematics"] == "exact");
  // The linearised and exact first contacts differ at second order: the deck's choice shows.
  CHECK(with("linearised")["summary"]["mean_backlash_arcsec"] != with("exact")["summary"]["mean_backlash_arcsec"]);
}

TEST_CASE("cli: a 1000-character title draws (cut) instead of crashing PLplot, issue 26 item 12") {
  const std::string title(1000, 'x');
  const auto svg = Temp("long_title.svg");
  const auto r = RunCli({"geometry", Case("liu2021_table1.toml"), "--set", "case.title=\"" + title + "\"", "--svg", svg.string()});
  CHECK(r.code == 0);
  std::ifstream in(svg);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(text.find("<title>") != std::string::npos);
  CHECK(text.find(title) != std::string::npos);  // the <title> keeps the whole text
  std::filesystem::remove(svg);
}

TEST_CASE("cli: two outputs to one file are refused before the file exists, however it is spelled, issue 26 item 14") {
  const auto dir = std::filesystem::temp_directory_path() / "ltca_review_outputs";
  std::filesystem::create_directories(dir);
  const auto file = dir / "o.json";
  std::filesystem::remove(file);
  const auto cwd = std::filesystem::current_path();
  std::filesystem::current_path(dir);
  const auto a = RunCli({"solve", Case("liu2021_table1.toml"), "--set", "sweep.positions=2", "--json", "o.json", "--csv", "./o.json"});
  const auto b = RunCli({"backlash", Case("liu2021_table1.toml"), "--set", "sweep.positions=2", "--json", "o.json", "--svg",
                         file.string()});
  std::filesystem::current_path(cwd);
  CHECK(a.code == 2);
  CHECK(a.err.find("--json o.json and --csv ./o.json") != std::string::npos);
  CHECK(b.code == 2);
  CHECK_FALSE(std::filesystem::exists(file));
}

TEST_CASE("cli: messages say what happened, issue 26 item 16") {
  SUBCASE("an option of another command is named in the order given, with the command") {
    const auto r = RunCli({"backlash", Case("liu2021_table1.toml"), "--crank-deg", "0"});
    CHECK(r.code == 2);
    CHECK(r.err.find("'--crank-deg 0'") != std::string::npos);
    CHECK(r.err.find("ltca backlash --help") != std::string::npos);
  }
  SUBCASE("--help cites no issue numbers") {
    for (const char* command : {"stiffness", "tolerance", "efficiency", "backlash", "solve"}) {
      const auto r = RunCli({command, "--help"});
      CAPTURE(command);
      CHECK(r.code == 0);
      CHECK(r.out.find("issue ") == std::string::npos);
    }
  }
  SUBCASE("a title with control characters is refused, naming the key") {
    const auto r = RunCli({"geometry", Case("liu2021_table1.toml"), "--set", "case.title=\"a\\u001b[31mb\""});
    CHECK(r.code == 2);
    CHECK(r.err.find("[case] title") != std::string::npos);
    CHECK(r.err.find("U+001B") != std::string::npos);
  }
  SUBCASE("with [second_disc] the torque key's description is the stage's") {
    const auto r = RunCli({"solve", Case("rv_two_discs.toml"), "--set", "load.torque_nm=\"x\""});
    CHECK(r.code == 2);
    CHECK(r.err.find("this cycloid gear") == std::string::npos);
  }
  SUBCASE("the report's status line is every part's") {
    // The loop fails beyond the law's capacity (cases/hard/law_cannot_carry.toml fails its solve).
    const auto dir = std::filesystem::temp_directory_path() / "ltca_review_report";
    std::filesystem::remove_all(dir);
    const auto r = RunCli({"report", Case("hard/law_cannot_carry.toml"), "-o", dir.string()});
    CHECK(r.code == 1);
    CHECK(r.out.find("status success") == std::string::npos);
    CHECK(r.out.find("not every part succeeded") != std::string::npos);
    std::filesystem::remove_all(dir);
  }
  SUBCASE("two-disc pins are numbered 1 .. z_p on each disc in backlash") {
    const auto r = RunCli({"backlash", Case("rv_two_discs.toml"), "--set", "sweep.positions=3", "--json", "-"});
    REQUIRE(r.code == 0);
    const auto doc = nlohmann::json::parse(r.out);
    for (const auto& p : doc["positions"]) {
      CHECK(p["first_contact_pin"].get<int>() <= 40);
      CHECK(p["first_contact_disc"].get<int>() >= 1);
    }
  }
}
