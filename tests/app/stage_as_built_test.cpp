// The RV stage as it is built (issue 49), read from decks: the first stage with the input locked,
// and the carrier in series. Independent references: the first stage's turns by hand, and the
// series combination of two torsional springs, 1/k = 1/k_stage + 1/k_carrier, on a stage that is
// linear (linear laws, no clearance).
#include <cmath>
#include <stdexcept>
#include <string>

#include <doctest/doctest.h>

#include "cli_run.hpp"
#include "deck_runs.hpp"
#include "helpers.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/reducer.hpp"
#include "problems.hpp"

namespace stage_as_built_test {

std::string ErrorOf(const std::string& text) {
  try {
    (void)ltca::app::ParseDeck(text, "t.toml");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Liu Table 1's perfect pair with linear laws (every pin of the loaded half touches at zero load),
/// one disc on three crankshafts in linear needle bearings without play, shafts of 1e5 N/mm: a
/// linear stage.
std::string LinearCranks() {
  return ltca::test::ReadText(ltca::test::Case("liu2021_table1.toml")) + R"(
[output]
kind = "cranks"
count = 3
circle_radius_mm = 35.0
phase_deg = 90.0
shaft_stiffness_n_per_mm = 1e5

[bearing]
kind = "linear"
radial_stiffness_n_per_mm = 3e5
)";
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// The tests sit in the namespace: a unity build puts other files' helpers of the same names beside them.

TEST_CASE("app: [output] first_stage_teeth turns the eccentrics 1 + z_sun / z_spur per output turn, one of it or crank_turns_per_output_turn") {
  const std::string cranks = LinearCranks();
  const std::string key = "shaft_stiffness_n_per_mm = 1e5";
  const auto with = [&](const std::string& line) { return Replace(cranks, key, key + "\n" + line); };
  // Without either key the eccentrics keep their direction: the model before issue 49, exactly.
  CHECK(ltca::app::ParseDeck(cranks, "t.toml").reducer->cranks.turns_per_output_turn == 0.0);
  // RV-40E's ratio 121 = 1 + 3 x 40: a 15-tooth sun, 45-tooth spur gears; by hand 4/3 turns (the
  // spur gear rolls once round the held sun: 15/45 of a turn on the carrier, plus the carrier's).
  const auto rv = ltca::app::ParseDeck(with("first_stage_teeth = [15, 45]"), "t.toml");
  CHECK(rv.reducer->cranks.turns_per_output_turn == doctest::Approx(4.0 / 3.0).epsilon(1e-15));
  CHECK(rv.reducer->cranks.sun_teeth == 15);
  CHECK(rv.reducer->cranks.spur_teeth == 45);
  // The same turns given as a number are the same model, bit for bit.
  CHECK(ltca::app::ParseDeck(with("crank_turns_per_output_turn = 1.3333333333333333"), "t.toml").reducer->cranks.turns_per_output_turn ==
        rv.reducer->cranks.turns_per_output_turn);
  CHECK(Contains(ErrorOf(with("first_stage_teeth = [15, 45]\ncrank_turns_per_output_turn = 0")),
                 "[output] first_stage_teeth and crank_turns_per_output_turn: both set"));
  CHECK(Contains(ErrorOf(with("first_stage_teeth = [0, 45]")), "[output] first_stage_teeth = [0, 45]: expected [z_sun, z_spur]"));
  CHECK(Contains(ErrorOf(with("first_stage_teeth = [15.5, 45]")), "[output] first_stage_teeth = [15.5, 45]"));
  CHECK(Contains(ErrorOf(with("first_stage_teeth = [15]")), "[output] first_stage_teeth = [15]"));
  const std::string pins = ltca::test::ReadText(ltca::test::Case("stage/cycloidal_drive.toml"));
  CHECK(Contains(ErrorOf(Replace(pins, "[output]", "[output]\nfirst_stage_teeth = [15, 45]")),
                 "[output] first_stage_teeth: not a key of kind = \"pins\""));
}

TEST_CASE("app: the carrier in series: a linear stage's rigidity is 1 / (1/k_stage + 1/k_carrier), its lost motion and budget alike (1e-9)") {
  // A linear stage (linear laws, no clearance): the twist is T / k_stage at every load, and a
  // torsional spring k_c in series adds T / k_c. Secant rigidity per flank, the lost motion over
  // +-3 % T (2 x 0.03 T / k per flank's k) and the carrier's share of the strain energy at +T,
  // k_stage / (k_stage + k_c) on the drive flank; two solvers, two cranks.
  const double kc_nm_per_arcmin = 200.0;
  const double kc = ltca::units::NmToNmm(kc_nm_per_arcmin) / ltca::units::ArcminToRad(1.0);  // N*mm/rad
  const std::string key = "shaft_stiffness_n_per_mm = 1e5";
  const std::string text = Replace(LinearCranks(), "[load]", "[contact]\nlaw = \"linear\"\nstiffness_n_per_mm2 = 2e4\n\n[load]");
  const ltca::app::Deck rigid = ltca::app::ParseDeck(text, "t.toml");
  const ltca::app::Deck series =
      ltca::app::ParseDeck(Replace(text, key, key + "\ncarrier_torsional_stiffness_nm_per_arcmin = 200"), "t.toml");
  REQUIRE(series.reducer->carrier_stiffness == doctest::Approx(kc).epsilon(1e-15));
  for (const std::string solver : {"compatibility", "bisection"}) {
    for (const double crank_deg : {0.0, 4.1}) {
      CAPTURE(solver);
      CAPTURE(crank_deg);
      ltca::analysis::StiffnessSettings s;
      s.crank = ltca::units::DegToRad(crank_deg);
      s.steps = 5;
      auto a = ltca::test::StiffnessOn(rigid, ltca::test::Named(solver), s, ltca::contact::ContactKinematics::kLinearised);
      auto b = ltca::test::StiffnessOn(series, ltca::test::Named(solver), s, ltca::contact::ContactKinematics::kLinearised);
      const ltca::analysis::StiffnessPosition p = a.Solve(*s.crank), q = b.Solve(*s.crank);
      REQUIRE(p.succeeded());
      REQUIRE(q.succeeded());
      const double torque = rigid.RequireLoad().torque;
      CHECK(q.rigidity_drive == doctest::Approx(1.0 / (1.0 / p.rigidity_drive + 1.0 / kc)).epsilon(1e-9));
      CHECK(q.rigidity_coast == doctest::Approx(1.0 / (1.0 / p.rigidity_coast + 1.0 / kc)).epsilon(1e-9));
      CHECK(q.lost_motion == doctest::Approx(p.lost_motion + 2.0 * 0.03 * torque / kc).epsilon(1e-9));
      const auto carrier = static_cast<std::size_t>(ltca::solvers::StageGroup::kCarrier);
      REQUIRE(q.compliance_share.size() == ltca::solvers::kStageGroups);
      CHECK(p.compliance_share[carrier] == 0.0);
      CHECK(q.compliance_share[carrier] == doctest::Approx(p.rigidity_drive / (p.rigidity_drive + kc)).epsilon(1e-9));
    }
  }
  CHECK(Contains(ErrorOf(Replace(text, key, key + "\ncarrier_torsional_stiffness_nm_per_arcmin = -1")),
                 "[output] carrier_torsional_stiffness_nm_per_arcmin = -1: expected a torsional stiffness > 0 in N*m/arcmin"));
  CHECK(Contains(ErrorOf(Replace(text, key, key + "\ncarrier_torsional_stiffness_nm_per_arcmin = inf")),
                 "[output] carrier_torsional_stiffness_nm_per_arcmin: expected a finite stiffness"));
}


TEST_CASE("app: [output] crankshafts as beams: the diameter, span and both eccentrics together, two discs, never with the spring") {
  const std::string two = ltca::test::ReadText(ltca::test::Case("stage/rv_catalogue.toml"));
  const auto deck = ltca::app::ParseDeck(two, "t.toml");
  const auto& beam = deck.reducer->cranks.beam;
  CHECK(beam.diameter == 20.0);
  CHECK(beam.span == 40.0);
  CHECK(beam.eccentric[0] == 14.0);
  CHECK(beam.eccentric[1] == 26.0);
  CHECK(beam.support_stiffness == 5e5);
  CHECK(Contains(deck.Model().scope, "crankshafts as Timoshenko beams (20 mm, 40 mm span) on elastic support bearings"));
  CHECK(Contains(deck.Model().scope, "first stage 15/45"));
  CHECK(Contains(ErrorOf(Replace(two, "[second_disc]                 # identical to the first\n", "")),
                 "[output] shaft_diameter_mm: a crankshaft as a beam carries both discs' eccentrics"));
  CHECK(Contains(ErrorOf(Replace(two, "shaft_span_mm = 40.0", "shaft_stiffness_n_per_mm = 5e5\nshaft_span_mm = 40.0")),
                 "[output] shaft_stiffness_n_per_mm and shaft_diameter_mm"));
  CHECK(Contains(ErrorOf(Replace(two, "eccentric_positions_mm = [14.0, 26.0]", "eccentric_positions_mm = [14.0]")),
                 "[output] eccentric_positions_mm = [14]: expected [a_1, a_2]"));
  CHECK(Contains(ErrorOf(Replace(two, "eccentric_positions_mm = [14.0, 26.0]", "eccentric_positions_mm = [14.0, 44.0]")),
                 "[output] eccentric_positions_mm = 44: expected each eccentric between the supports"));
  CHECK(Contains(ErrorOf(Replace(two, "shaft_span_mm = 40.0", "")), "[output] missing required key 'shaft_span_mm'"));
}

}  // namespace stage_as_built_test

TEST_CASE("app: [second_disc] gives the second disc its own holes and bearing play, the tolerance study draws the play per disc") {
  using namespace stage_as_built_test;
  const std::string rv = ltca::test::ReadText(ltca::test::Case("stage/rv_two_discs_cranks.toml"));
  const auto with = [&](const std::string& keys) {
    return Replace(rv, "[second_disc]                 # identical to the first\n", "[second_disc]\n" + keys);
  };
  const ltca::app::Deck own = ltca::app::ParseDeck(
      with("hole_radial_deviations_mm = [0.004, 0.0, -0.002]\nhole_tangential_deviations_mm = [0.0, 0.003, 0.0]\n"
           "bearing_radial_clearance_mm = 0.006\n"),
      "t.toml");
  REQUIRE(own.reducer);
  REQUIRE(own.reducer->second_disc_holes);
  CHECK(own.reducer->second_disc_holes->at(0) == Eigen::Vector2d(0.004, 0.0));
  CHECK(own.reducer->second_disc_holes->at(1) == Eigen::Vector2d(0.0, 0.003));
  CHECK(own.reducer->cranks.hole_deviation.empty());  // the first disc's holes as designed
  CHECK(own.reducer->second_disc_bearing_clearance == 0.006);
  CHECK(own.reducer->BearingOf(0).radial_clearance == 0.003);
  CHECK(own.reducer->BearingOf(1).radial_clearance == 0.006);
  // Refusals name the second disc's key.
  CHECK(Contains(ErrorOf(with("hole_radial_deviations_mm = [0.004, 0.0]\n")),
                 "[second_disc] hole_radial_deviations_mm: 2 values; expected one per hole ([output] count = 3)"));
  // A negative play is a preloaded bearing (issue 52); a non-finite one is refused naming the key.
  CHECK(ltca::app::ParseDeck(with("bearing_radial_clearance_mm = -0.001\n"), "t.toml").reducer->BearingOf(1).radial_clearance == -0.001);
  CHECK(Contains(ErrorOf(with("bearing_radial_clearance_mm = nan\n")), "[second_disc] bearing_radial_clearance_mm = nan"));
  CHECK(Contains(ErrorOf(ltca::test::ReadText(ltca::test::Case("liu2021_sec52_base.toml")) +
                         "\n[second_disc]\nbearing_radial_clearance_mm = 0.002\n"),
                 "expected an [output] section"));
  // The second disc's own play equal to the common one is the deck without it, bit for bit; a
  // larger play on disc 2 shifts the torque to disc 1.
  const auto share = [&](const std::string& text) {
    ltca::app::Deck deck = ltca::app::ParseDeck(text, "t.toml");
    deck.sweep.positions = 3;
    deck.sweep.crank_end = 0.2;
    const auto sweep = ltca::test::SolveSweep(deck, deck.solver);
    REQUIRE(sweep.summary.all_succeeded());
    return sweep.summary;
  };
  const auto plain = share(rv), same = share(with("bearing_radial_clearance_mm = 0.003\n")),
             looser = share(with("bearing_radial_clearance_mm = 0.012\n"));
  CHECK(same.mean_te == plain.mean_te);
  CHECK(same.first_disc_share_mean == plain.first_disc_share_mean);
  CHECK(looser.first_disc_share_mean > plain.first_disc_share_mean + 1e-3);
  // [tolerances] on the bearing play: one draw per disc, the second's named "(disc 2)", each going
  // to its own disc's bearing.
  const ltca::app::Deck toleranced = ltca::app::ParseDeck(
      rv + "\n[tolerances]\nsamples = 4\nbearing_radial_clearance_mm = { distribution = \"uniform\", tolerance = 0.002 }\n",
      "t.toml");
  const auto study = ltca::test::ToleranceOn(toleranced, toleranced.solver, *toleranced.tolerances);
  REQUIRE(study.inputs().size() == 2);
  CHECK(study.inputs()[0].name == "bearing_radial_clearance_mm");
  CHECK(study.inputs()[1].name == "bearing_radial_clearance_mm (disc 2)");
  const auto applied = study.Apply({0.001, -0.0015});
  CHECK(applied.design.reducer->BearingOf(0).radial_clearance == doctest::Approx(0.004).epsilon(1e-15));
  CHECK(applied.design.reducer->BearingOf(1).radial_clearance == doctest::Approx(0.0015).epsilon(1e-15));
}

TEST_CASE("app: [operation] motor_speed_rpm turns the cranks through the first stage, as the planetary kinematics by hand") {
  using namespace stage_as_built_test;
  // By hand, RV-40E-like (z_sun 15, z_spur 45, z_c 39, z_p 40): in the carrier's frame the spur gear
  // turns -z_sun / z_spur of the sun's relative turn, and the carrier (the output) turns -1/39 of a
  // crank's turn in the fixed frame (d = 1). Sun at w_m, cranks at w: w + w/39 = -(1/3)(w_m + w/39),
  // so w = -(1/3) w_m / (1 + (4/3)/39); the output w / 39 is then w_m / 121, the catalogue's ratio.
  const double hand = (1.0 / 3.0) / (1.0 + (4.0 / 3.0) / 39.0);
  CHECK(hand / 39.0 == doctest::Approx(1.0 / 121.0).epsilon(1e-15));
  const std::string deck = ltca::test::Case("stage/rv_catalogue.toml");
  const ltca::app::Deck motor = ltca::app::LoadDeck(deck, {"-operation.input_speed_rpm", "operation.motor_speed_rpm=2000"});
  REQUIRE(motor.operation);
  CHECK(motor.operation->input_speed == doctest::Approx(ltca::units::RpmToRadPerS(2000.0) * hand).epsilon(1e-14));
  // One of the two; a motor speed needs a first stage.
  const auto refused = [&](const std::string& base, const std::vector<std::string>& sets) {
    try {
      (void)ltca::app::LoadDeck(base, sets);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(Contains(refused(deck, {"operation.motor_speed_rpm=2000"}), "input_speed_rpm and motor_speed_rpm: expected one of the two"));
  CHECK(Contains(refused(ltca::test::Case("stage/cycloidal_drive.toml"), {"-operation.input_speed_rpm", "operation.motor_speed_rpm=2000"}),
                 "[operation] motor_speed_rpm = 2000: the crank speed follows from the motor's only through an RV's first stage"));
  CHECK(Contains(refused(deck, {"-operation.input_speed_rpm"}), "[operation] missing required key 'input_speed_rpm'"));
}

TEST_CASE("app: a load spectrum beside [operation] motor_speed_rpm is refused: a bin's speed is the crank's") {
  using namespace stage_as_built_test;
  const std::string deck = ltca::test::ReadText(ltca::test::Case("stage/rv_catalogue.toml")) +
                           "\n[[load_spectrum]]\ntorque_nm = 412\nspeed_rpm = 1500\ntime_share = 1\n";
  const std::string refused = [&] {
    try {
      (void)ltca::app::ParseDeck(deck, "t.toml", {"-operation.input_speed_rpm", "operation.motor_speed_rpm=4654"});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  }();
  CHECK(Contains(refused, "[[load_spectrum]] with [operation] motor_speed_rpm: a bin's speed_rpm is the crank speed"));
}
