// Issue 13: the two discs of an RV stage through the application layer: the [second_disc] deck
// section, the sweep's per-crank split, the stage's torque-twist loop and its backlash.
// References: one disc at T / 2 (two identical discs), the unloaded analysis of each disc on its
// own (contact::AnalyseUnloaded), and the sweep against the loop at the same crank and torque.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "helpers.hpp"
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ltca/app/deck.hpp"
#include "deck_runs.hpp"
#include "problems.hpp"
#include "ltca/analysis/efficiency.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/analysis/tolerance.hpp"
#include "cli.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"

using ltca::app::Deck;
using ltca::analysis::StiffnessPosition;
using ltca::analysis::StiffnessRunner;
using ltca::analysis::StiffnessSettings;
using ltca::analysis::SweepRunner;
using ltca::contact::ContactKinematics;
using ltca::solvers::SolverOptions;

namespace {

using ltca::test::Case;

/// The message of the std::invalid_argument the deck text throws ("" when it reads).
std::string Rejection(const std::vector<std::string>& overrides, const std::string& deck = "liu2021_table1.toml") {
  try {
    (void)ltca::app::LoadDeck(Case(deck), overrides);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("app: two identical discs: 50/50 at every position of the sweep, and the stage is twice as stiff as one disc at T/2 (1e-9)") {
  // Liu 5.2's base modification (48 arcsec of backlash, a curved loop): the stage at T against
  // one disc at T / 2. Every twist of the stage's loop is the one disc's at half the torque, so
  // the secant rigidity doubles and lost motion and backlash are equal.
  const Deck stage = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"), {"second_disc.indexing_deviation_mm=0"});
  const Deck one = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"), {"load.torque_nm=103"});
  REQUIRE(stage.disc_count() == 2);
  CHECK(stage.Model().name == "plane+two-discs");
  CHECK(stage.Model().discs == 2);
  CHECK(one.Model().name == "plane");

  auto sweep = ltca::test::SweepOn(stage, ltca::test::Named("compatibility"), ContactKinematics::kLinearised);
  for (const double crank : stage.sweep.CrankAngles()) {
    const ltca::analysis::PositionResult p = sweep.Solve(crank);
    REQUIRE(p.succeeded());
    REQUIRE(p.disc_torque.size() == 2);
    CHECK(p.disc_torque[0] == doctest::Approx(103e3).epsilon(1e-9));
    CHECK(p.disc_torque[1] == doctest::Approx(103e3).epsilon(1e-9));
    CHECK(p.pin_force.size() == 80);  // disc 1's 40 pins, then disc 2's
  }
  const ltca::analysis::SweepSummary s = sweep.Summary();
  CHECK(s.succeeded == 91);
  CHECK(s.first_disc_share_min == doctest::Approx(0.5).epsilon(1e-9));
  CHECK(s.first_disc_share_max == doctest::Approx(0.5).epsilon(1e-9));

  for (const std::string solver : {"compatibility", "bisection"}) {
    for (const double crank_deg : {0.0, 3.3}) {
      CAPTURE(solver);
      CAPTURE(crank_deg);
      StiffnessSettings settings;
      settings.steps = 5;
      settings.crank = ltca::units::DegToRad(crank_deg);
      auto two = ltca::test::StiffnessOn(stage, ltca::test::Named(solver), settings, ContactKinematics::kLinearised);
      auto single = ltca::test::StiffnessOn(one, ltca::test::Named(solver), settings, ContactKinematics::kLinearised);
      const StiffnessPosition a = two.Solve(*settings.crank), b = single.Solve(*settings.crank);
      REQUIRE(a.succeeded());
      REQUIRE(b.succeeded());
      CHECK(a.rigidity == doctest::Approx(2.0 * b.rigidity).epsilon(1e-9));
      CHECK(a.rigidity_drive == doctest::Approx(2.0 * b.rigidity_drive).epsilon(1e-9));
      CHECK(a.lost_motion == doctest::Approx(b.lost_motion).epsilon(1e-9));
      CHECK(a.backlash == doctest::Approx(b.backlash).epsilon(1e-12));
      CHECK(a.first_disc_share_drive == doctest::Approx(0.5).epsilon(1e-9));
      CHECK(a.first_disc_share_coast == doctest::Approx(0.5).epsilon(1e-9));
      CHECK(std::isnan(b.first_disc_share_drive));  // one disc: no split
      REQUIRE(a.curve.size() == b.curve.size());
      for (std::size_t i = 0; i < a.curve.size(); ++i) {
        CHECK(a.curve[i].torque == doctest::Approx(2.0 * b.curve[i].torque).epsilon(1e-15));
        CHECK(a.curve[i].twist == doctest::Approx(b.curve[i].twist).epsilon(1e-9));
      }
    }
  }
}

TEST_CASE("app: a second disc indexed 0.5 um ahead carries more of +T and less of -T, reported per crank alike by solve and stiffness") {
  const Deck stage = ltca::app::LoadDeck(Case("rv_two_discs.toml"), {"second_disc.indexing_deviation_mm=0.0005"});
  auto sweep = ltca::test::SweepOn(stage, ltca::test::Named("compatibility"), ContactKinematics::kLinearised);
  StiffnessSettings settings;
  settings.steps = 3;
  for (const double crank_deg : {0.0, 2.5, 6.1}) {
    CAPTURE(crank_deg);
    const double crank = ltca::units::DegToRad(crank_deg);
    const ltca::analysis::PositionResult p = sweep.Solve(crank);
    REQUIRE(p.succeeded());
    const double share = p.disc_torque[0] / (p.disc_torque[0] + p.disc_torque[1]);
    CHECK(share > 0.3);  // both carry (observed 0.40 to 0.42)
    CHECK(share < 0.48);
    settings.crank = crank;
    auto loop = ltca::test::StiffnessOn(stage, ltca::test::Named("compatibility"), settings, ContactKinematics::kLinearised);
    const StiffnessPosition q = loop.Solve(crank);
    REQUIRE(q.succeeded());
    CHECK(q.first_disc_share_drive == doctest::Approx(share).epsilon(1e-8));  // the same solve at +T
    CHECK(q.first_disc_share_coast > 0.52);  // under -T the first disc is the nearer one
    CHECK(q.first_disc_share_coast < 0.7);
  }
}

TEST_CASE("app: the stage's backlash is the nearer first contact of either disc on each flank (1e-12 rad)") {
  // Reference: each disc's own unloaded analysis (contact::AnalyseUnloaded, the code of ltca
  // backlash), the second at crank + pi; the loop finds its zero-torque points by the load
  // problem's closing rotations over both discs' points (another code path).
  const Deck stage = ltca::app::LoadDeck(Case("rv_two_discs.toml"));
  const ltca::contact::MeshModel first = stage.MakeModel();
  const auto second = std::make_shared<const ltca::contact::MeshModel>(stage.MakeSecondRealPair(), stage.geometry,
                                                                       stage.SlicesForced());
  for (const ContactKinematics kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    for (const double crank_deg : {0.0, 4.5, 8.2}) {
      CAPTURE(crank_deg);
      StiffnessSettings settings;
      settings.steps = 3;
      settings.crank = ltca::units::DegToRad(crank_deg);
      auto loop = ltca::test::StiffnessOn(stage, ltca::test::Named("compatibility"), settings, kinematics);
      const StiffnessPosition p = loop.Solve(*settings.crank);
      REQUIRE(p.succeeded());
      const auto a = ltca::contact::AnalyseUnloaded(first, *settings.crank, kinematics);
      const auto b = ltca::contact::AnalyseUnloaded(*second, *settings.crank + ltca::contact::kSecondDiscCrankOffset, kinematics);
      const double drive = std::min(a.theta_c1, b.theta_c1), coast = std::min(-a.theta_c2, -b.theta_c2);
      CHECK(std::abs(p.first_contact_drive - drive) < 1e-12);
      CHECK(std::abs(p.first_contact_coast - coast) < 1e-12);
      CHECK(std::abs(p.backlash - (drive + coast)) < 1e-12);
      // 5 um ahead is 16.1 arcsec: the stage's free play is the one disc's less s / R_p.
      // Exact to round-off; linearised to first order in s / R_p (2e-4 of it observed, bound 1e-3).
      CHECK(std::abs(p.backlash - (a.backlash - 0.005 / 64.0)) <
            (kinematics == ContactKinematics::kExact ? 1e-12 : 1e-3 * 0.005 / 64.0));
    }
  }
}

TEST_CASE("app: [second_disc] copies the first disc unless told, and rejects pin-ring keys, unknown keys and [pins]") {
  // The default copy: the second disc's pair is the first's (the same modification and errors).
  const Deck copy = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"), {"second_disc.indexing_deviation_mm=0"});
  REQUIRE(copy.second_disc.has_value());
  CHECK(copy.second_disc->modification.pin_radius == copy.modification.pin_radius);
  CHECK(copy.second_disc->modification.pin_circle_radius == copy.modification.pin_circle_radius);
  CHECK(copy.second_disc->modification.rotation == copy.modification.rotation);
  // Its own modification key, over the first disc's; indexing adds s / R_p to its rotation.
  const Deck own = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"),
                                       {"second_disc.pin_radius_mm=-0.006", "second_disc.indexing_deviation_mm=0.002"});
  CHECK(own.second_disc->modification.pin_radius == doctest::Approx(-0.006));
  CHECK(own.second_disc->modification.pin_circle_radius == copy.modification.pin_circle_radius);
  CHECK(own.second_disc->modification.rotation == doctest::Approx(copy.modification.rotation + 0.002 / 64.0).epsilon(1e-15));
  CHECK(own.modification.pin_radius == copy.modification.pin_radius);  // the first disc is untouched

  const std::string ring = Rejection({"second_disc.pin_circle_deviation_mm=0.001"});
  CHECK(ring.find("pin_circle_deviation_mm") != std::string::npos);
  CHECK(ring.find("pin ring is common") != std::string::npos);
  const std::string unknown = Rejection({"second_disc.tooth_count=38"});
  CHECK(unknown.find("unknown key 'tooth_count'") != std::string::npos);
  const std::string pins = Rejection({"second_disc.indexing_deviation_mm=0", "pins.span_mm=20", "pins.face_offset_mm=4"});
  CHECK(pins.find("[second_disc] with [pins]") != std::string::npos);
  const std::string far = Rejection({"second_disc.indexing_deviation_mm=5"});
  CHECK(far.find("indexing_deviation_mm") != std::string::npos);
  CHECK(Rejection({"second_disc.indexing_deviation_mm=0.001"}).empty());

  // The studies take both discs since issue 27: efficiency sums both discs' contacts
  // (tests/app/efficiency_test.cpp), the tolerance study draws each disc's keys
  // (tests/app/tolerance_test.cpp).
  const Deck stage = ltca::app::LoadDeck(Case("rv_two_discs.toml"),
                                         {"friction.coefficient=0.05", "operation.input_speed_rpm=1500"});
  CHECK_NOTHROW(ltca::test::EfficiencyOn(stage, ltca::test::Named("compatibility"), ContactKinematics::kLinearised));
  ltca::analysis::ToleranceSettings tolerances;
  CHECK_NOTHROW(ltca::test::ToleranceOn(stage, ltca::test::Named("compatibility"), tolerances));
}

TEST_CASE("app: a bad [second_disc] value is named with its own section, key and value") {
  // A review found [second_disc] indexing_deviation_mm = nan reported as "[modification]: every
  // value must be finite", and [second_disc] pin_radius_mm = -0.5 as a [modification] key.
  const auto error = [](const std::string& set) {
    try {
      (void)ltca::app::LoadDeck(Case("rv_two_discs.toml"), {set});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  for (const auto& [set, expected] : std::vector<std::pair<std::string, std::string>>{
           {"second_disc.indexing_deviation_mm=nan", "[second_disc] indexing_deviation_mm = nan"},
           {"second_disc.indexing_deviation_mm=inf", "[second_disc] indexing_deviation_mm = inf"},
           {"second_disc.pin_radius_mm=-0.5", "[second_disc] pin_radius_mm = -0.5"},
           {"second_disc.pin_radius_mm=nan", "[second_disc] pin_radius_mm = nan"},
           {"second_disc.rotation_deg=1", "[second_disc] rotation_deg = 1"},
           {"modification.pin_circle_radius_mm=nan", "[modification] pin_circle_radius_mm = nan"}}) {
    CAPTURE(set);
    CHECK(error(set).find(expected) != std::string::npos);
  }
}

TEST_CASE("cli: two discs in the JSON and CSV of solve, stiffness and backlash: the split per position, the model named") {
  // cases/rv_two_discs.toml with the second disc 0.5 um ahead: both carry. The JSON figures are
  // checked against the library's (SweepRunner) at the same crank, and against their own sums.
  const std::vector<std::string> set = {"--set", "second_disc.indexing_deviation_mm=0.0005", "--set", "sweep.positions=3"};
  const auto run = [&](std::vector<std::string> args) {
    args.insert(args.end(), set.begin(), set.end());
    std::ostringstream out, err;
    const int code = ltca::cli::Run(args, out, err);
    REQUIRE(code == 0);
    return out.str();
  };
  const std::string deck = Case("rv_two_discs.toml");
  const auto solve = nlohmann::json::parse(run({"solve", deck, "--json", "-"}));
  CHECK(solve.at("model").at("name") == "plane+two-discs");
  CHECK(solve.at("model").at("discs") == 2);
  const Deck stage = ltca::app::LoadDeck(deck, {"second_disc.indexing_deviation_mm=0.0005", "sweep.positions=3"});
  auto sweep = ltca::test::SweepOn(stage, ltca::test::Named("bisection"), ContactKinematics::kLinearised);
  double lo = 1.0, hi = 0.0;
  for (const auto& p : solve.at("positions")) {
    const auto torques = p.at("disc_torque_nm").get<std::vector<double>>();
    REQUIRE(torques.size() == 2);
    CHECK(torques[0] + torques[1] == doctest::Approx(206.0).epsilon(1e-8));
    CHECK(p.at("pin_force_n").size() == 80);
    const double share = p.at("first_disc_share").get<double>();
    const ltca::analysis::PositionResult r = sweep.Solve(ltca::units::DegToRad(p.at("crank_deg").get<double>()));
    CHECK(share == doctest::Approx(r.disc_torque[0] / 206e3).epsilon(1e-9));
    lo = std::min(lo, share), hi = std::max(hi, share);
  }
  CHECK(solve.at("summary").at("first_disc_share_min").get<double>() == doctest::Approx(lo).epsilon(1e-15));
  CHECK(solve.at("summary").at("first_disc_share_max").get<double>() == doctest::Approx(hi).epsilon(1e-15));
  const std::string csv = run({"solve", deck, "--csv", "-"});
  CHECK(csv.rfind("crank_deg,te_arcsec,contacts,max_pin_force_n,max_contact_stress_mpa,status,disc1_torque_nm,disc2_torque_nm\n", 0) == 0);

  const auto loop = nlohmann::json::parse(run({"stiffness", deck, "--json", "-", "--crank-deg", "0"}));
  CHECK(loop.at("model").at("name") == "plane+two-discs");
  CHECK(loop.at("summary").at("first_disc_share_drive").get<double>() ==
        doctest::Approx(solve.at("positions").at(0).at("first_disc_share").get<double>()).epsilon(1e-8));
  const auto backlash = nlohmann::json::parse(run({"backlash", deck, "--json", "-", "--kinematics", "linearised"}));
  CHECK(backlash.at("positions").at(0).at("backlash_arcsec").get<double>() ==
        doctest::Approx(loop.at("summary").at("backlash_arcmin").get<double>() * 60.0).epsilon(1e-9));
  CHECK(backlash.at("positions").at(0).at("second_disc_clearance_um").size() == 40);
}
