// The stage's friction (ltca efficiency of a deck with [output]): the losses at the output pins
// and the bearings beside the mesh's, by source. Independent references, derived in
// docs/efficiency.md ("The stage's friction"): with every coefficient zero nothing is lost; the
// W mechanism's sliding loss mu_w e omega_c (z_p / z_c) sum_j F_j |cos beta_j| (the disc's material
// moves over the output member's at e omega_c z_p / z_c, perpendicular to the eccentric: a
// translation, the rotations being equal), and the bearings' M omega_rel = mu_b |F| (d / 2) omega_c
// z_p / z_c, each with the forces of a frictionless solve of the same stage done here.
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "deck_runs.hpp"
#include "helpers.hpp"
#include "ltca/analysis/efficiency.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/solvers/registry.hpp"
#include "ltca/geometry/units.hpp"

using ltca::analysis::EfficiencyPosition;
using ltca::app::Deck;
using ltca::test::Case;

namespace {

Deck StageDeck(const std::string& name, std::vector<std::string> options) {
  options.push_back("sweep.positions=4");
  return ltca::app::LoadDeck(Case("stage/" + name), options);
}

/// The frictionless stage solve at one crank, apart from the efficiency runner.
ltca::solvers::LoadResult StageSolve(const Deck& deck, double crank) {
  const ltca::analysis::Stage stage = deck.MakeStage({crank});
  return ltca::solvers::MakeSolver(deck.solver.name)->Solve(stage.Problem(crank, deck.RequireLoad().torque), deck.solver);
}

/// Each crank of the deck's sweep: the efficiency runner's position (succeeded) and the
/// frictionless stage solve at that crank, apart from it.
template <class Check>
void ForEachPosition(const Deck& deck, Check check) {
  auto runner = ltca::test::EfficiencyOn(deck, deck.solver, deck.kinematics);
  for (const double crank : runner.cranks()) {
    CAPTURE(crank);
    const EfficiencyPosition p = runner.Solve(crank);
    REQUIRE(p.succeeded());
    const auto r = StageSolve(deck, crank);
    REQUIRE(r.reducer.has_value());
    check(crank, p, r);
  }
}

/// |omega_c| (1 - phi'): the eccentric's speed relative to the disc, phi' = -(z_p - z_c) / z_c.
double RelativeSpeed(const Deck& deck) {
  return deck.RequireOperation().input_speed * static_cast<double>(deck.pair.pin_count) / deck.pair.tooth_count;
}

}  // namespace

TEST_CASE("app: a stage with every friction coefficient zero loses nothing: efficiency 1 exactly, every source 0") {
  for (const std::string name : {"cycloidal_drive.toml", "rv_catalogue.toml"}) {
    CAPTURE(name);
    const Deck deck = StageDeck(name, {"friction.coefficient=0", "friction.bearing_coefficient=0"});
    auto runner = ltca::test::EfficiencyOn(deck, deck.solver, deck.kinematics);
    for (const double crank : runner.cranks()) {
      const EfficiencyPosition p = runner.Solve(crank);
      REQUIRE(p.succeeded());
      CHECK(p.efficiency == 1.0);
      CHECK(p.efficiency_first_order == 1.0);
      CHECK(p.power_loss == 0.0);
      CHECK(p.power_loss_by_source.mesh == 0.0);
      CHECK(p.power_loss_by_source.output == 0.0);
      CHECK(p.power_loss_by_source.bearings == 0.0);
      CHECK(p.power_loss_by_source.seats == 0.0);
      CHECK(p.stage_friction_moment_ratio == 0.0);
    }
    CHECK(runner.Summary().efficiency == 1.0);
  }
}

TEST_CASE("app: the stage's losses by source add up to its loss, per position and in the summary") {
  // Every source at once, with a pin sleeve (the pin ring's sliding moves to the seats, eq. 34).
  for (const bool sleeve : {false, true}) {
    CAPTURE(sleeve);
    std::vector<std::string> o = {"friction.coefficient=0.05", "friction.output_pin_coefficient=0.05",
                                  "friction.bearing_coefficient=0.0015"};
    if (sleeve) o.push_back("friction.sleeve_bore_radius_mm=2");
    const Deck deck = StageDeck("cycloidal_drive.toml", o);
    auto runner = ltca::test::EfficiencyOn(deck, deck.solver, deck.kinematics);
    for (const double crank : runner.cranks()) {
      const EfficiencyPosition p = runner.Solve(crank);
      REQUIRE(p.succeeded());
      const auto& s = p.power_loss_by_source;
      CHECK(s.output > 0.0);
      CHECK(s.bearings > 0.0);
      CHECK((sleeve ? s.seats : s.mesh) > 0.0);
      CHECK((sleeve ? s.mesh : s.seats) == 0.0);
      CHECK(p.power_loss == doctest::Approx(s.mesh + s.output + s.bearings + s.seats).epsilon(1e-14));
      double pins = 0.0;
      for (const auto& c : p.contacts) pins += c.loss;
      CHECK((sleeve ? s.seats : s.mesh) == doctest::Approx(pins).epsilon(1e-12));
      CHECK(p.efficiency == doctest::Approx(p.output_power / (p.output_power + p.power_loss)).epsilon(1e-14));
      CHECK(p.stage_friction_moment_ratio > 0.0);
      CHECK(p.stage_friction_moment_ratio < 0.1);
    }
    const auto summary = runner.Summary();
    CHECK(summary.power_loss.mean ==
          doctest::Approx(summary.power_loss_mesh.mean + summary.power_loss_output.mean + summary.power_loss_bearings.mean +
                          summary.power_loss_seats.mean)
              .epsilon(1e-12));
  }
}

TEST_CASE("app: friction only at the output pins is the W mechanism's sliding loss in closed form (1e-9)") {
  // The disc's centre O = e u(theta) moves at e omega_c perp(u) and the disc and the output member
  // turn together at phi' omega_c, phi' = -(z_p - z_c) / z_c: the disc's material moves over the
  // output member's at v = e omega_c (1 - phi') perp(u) = e omega_c (z_p / z_c) perp(u) everywhere.
  // Pin j slides at |t_j . v|, t_j = perp(n_j): loss mu_w F_j |t_j . v| (forces from the solve
  // here). Nominally n_j is along u, and the loss mu_w e omega_c (z_p / z_c) sum F_j: to 1e-4
  // (the disc's displacement under load turns n_j by micro-radians).
  const double mu = 0.05;
  const Deck deck = StageDeck("cycloidal_drive.toml", {"friction.coefficient=0", "friction.output_pin_coefficient=0.05"});
  const double speed = deck.pair.eccentricity * RelativeSpeed(deck);  // mm/s
  ForEachPosition(deck, [&](double crank, const EfficiencyPosition& p, const ltca::solvers::LoadResult& r) {
    const Eigen::Vector2d v = speed * Eigen::Vector2d(-std::sin(crank), std::cos(crank));
    double loss = 0.0, nominal = 0.0;
    const auto& disc = r.reducer->discs.front();
    for (std::size_t j = 0; j < disc.output_force.size(); ++j) {
      const Eigen::Vector2d& n = disc.output_direction[j];
      loss += mu * disc.output_force[j] * std::abs(-n.y() * v.x() + n.x() * v.y());
      nominal += mu * disc.output_force[j] * speed;
    }
    CHECK(p.power_loss_by_source.output == doctest::Approx(ltca::units::NmmPerSToW(loss)).epsilon(1e-9));
    CHECK(p.power_loss_by_source.output == doctest::Approx(ltca::units::NmmPerSToW(nominal)).epsilon(1e-4));
    CHECK(p.power_loss_by_source.mesh == 0.0);
    CHECK(p.power_loss_by_source.bearings == 0.0);
    CHECK(p.power_loss == p.power_loss_by_source.output);
  });
}

TEST_CASE("app: friction only at the bearings is their moment times the eccentric's speed relative to the disc (1e-9)") {
  // M = mu_b |F| d / 2 (SKF's simplified friction moment) at omega_c - omega_d = omega_c z_p / z_c:
  // the eccentric bearing of the cycloidal drive (d its pitch diameter, 40 mm) and the needle
  // bearings of the RV stage's three crankshafts in both discs (d given: 10 mm).
  const double mu = 0.002;
  for (const auto& [name, diameter] : {std::pair<std::string, double>{"cycloidal_drive.toml", 40.0}, {"rv_catalogue.toml", 10.0}}) {
    CAPTURE(name);
    std::vector<std::string> o = {"friction.coefficient=0", "friction.bearing_coefficient=0.002"};
    if (name == "rv_catalogue.toml") o.push_back("friction.bearing_diameter_mm=10");
    const Deck deck = StageDeck(name, o);
    ForEachPosition(deck, [&](double, const EfficiencyPosition& p, const ltca::solvers::LoadResult& r) {
      double force = 0.0;
      int bearings = 0;
      for (const auto& disc : r.reducer->discs) {
        for (const Eigen::Vector2d& f : disc.bearing_force) {
          force += f.norm();
          ++bearings;
        }
      }
      CHECK(bearings == (name == "rv_catalogue.toml" ? 6 : 1));
      const double loss = mu * force * diameter / 2.0 * RelativeSpeed(deck);
      CHECK(p.power_loss_by_source.bearings == doctest::Approx(ltca::units::NmmPerSToW(loss)).epsilon(1e-9));
      CHECK(p.power_loss_by_source.output == 0.0);
      CHECK(p.power_loss == p.power_loss_by_source.bearings);
      CHECK(p.efficiency < 1.0);
    });
  }
}

TEST_CASE("app: the bearings' viscous moment is Palmgren's 1e-7 f_0 (nu n)^(2/3) d^3, or 160e-7 f_0 d^3 below nu n = 2000, times their relative speed (1e-9)") {
  // Harris and Kotzalas (Essential Concepts of Bearing Technology, 5th ed., sec. 10.3), by hand
  // here: n the eccentric's speed relative to the disc in rpm (omega_c z_p / z_c), nu in mm^2/s, d
  // in mm, M_0 in N*mm per bearing, beside a load term mu_b |F| d / 2 that this case leaves at 0.
  for (const auto& [name, nu, rpm] : {std::tuple<std::string, double, double>{"cycloidal_drive.toml", 68.0, 1000.0},
                                      {"cycloidal_drive.toml", 1.0, 30.0}, {"rv_catalogue.toml", 100.0, 500.0}}) {
    CAPTURE(name);
    CAPTURE(nu);
    const double f0 = 4.0;
    const Deck deck = StageDeck(name, {"friction.coefficient=0", "friction.bearing_viscous_factor=4",
                                       fmt::format("operation.oil_kinematic_viscosity_mm2_per_s={}", nu),
                                       fmt::format("operation.input_speed_rpm={}", rpm)});
    const double relative = RelativeSpeed(deck);  // rad/s
    const double n = relative * 60.0 / (2.0 * 3.14159265358979323846);
    const double d = 40.0;  // both decks' [bearing] pitch_diameter_mm
    const double m0 = (nu * n >= 2000.0 ? 1e-7 * f0 * std::pow(nu * n, 2.0 / 3.0) : 160e-7 * f0) * d * d * d;
    ForEachPosition(deck, [&](double, const EfficiencyPosition& p, const ltca::solvers::LoadResult& r) {
      std::size_t bearings = 0;
      for (const auto& disc : r.reducer->discs) bearings += disc.bearing_force.size();
      CHECK(p.power_loss_by_source.bearings ==
            doctest::Approx(ltca::units::NmmPerSToW(static_cast<double>(bearings) * m0 * relative)).epsilon(1e-9));
      CHECK(p.power_loss == p.power_loss_by_source.bearings);
    });
  }
  CHECK(ltca::test::InvalidArgumentMessage([&] {
          const Deck d = StageDeck("cycloidal_drive.toml", {"friction.coefficient=0", "friction.bearing_viscous_factor=4"});
          (void)ltca::test::EfficiencyOn(d, d.solver, d.kinematics);
        }).find("expected [operation] oil_kinematic_viscosity_mm2_per_s") != std::string::npos);
  CHECK(ltca::test::InvalidArgumentMessage([&] {
          (void)StageDeck("cycloidal_drive.toml", {"friction.coefficient=0", "friction.bearing_viscous_factor=-1"});
        }).find("bearing_viscous_factor = -1") != std::string::npos);
}

TEST_CASE("app: the stage's friction keys: refused without a stage or on the wrong output, and a bearing's coefficient without its diameter") {
  const auto message = [](const std::string& deck, std::vector<std::string> o) {
    return ltca::test::InvalidArgumentMessage([&] { (void)ltca::app::LoadDeck(Case(deck), o); });
  };
  CHECK(message("liu2021_table1.toml", {"friction.coefficient=0.05", "friction.output_pin_coefficient=0.05"})
            .find("expected an [output] section") != std::string::npos);
  CHECK(message("stage/rv_catalogue.toml", {"friction.coefficient=0.05", "friction.output_pin_coefficient=0.05"})
            .find("output_pin_coefficient = 0.05: expected [output] kind = \"pins\"") != std::string::npos);
  CHECK(message("stage/cycloidal_drive.toml", {"friction.coefficient=0.05", "friction.bearing_coefficient=2"})
            .find("bearing_coefficient = 2") != std::string::npos);
  // A stage whose bearing has no pitch diameter needs d.
  const Deck linear = StageDeck("cycloidal_drive.toml", {"friction.coefficient=0", "friction.bearing_coefficient=0.002",
                                                         "bearing.pitch_diameter_mm=0"});
  const std::string no_d = ltca::test::InvalidArgumentMessage(
      [&] { (void)ltca::test::EfficiencyOn(linear, linear.solver, linear.kinematics); });
  CHECK(no_d.find("expected bearing_diameter_mm") != std::string::npos);
  ltca::analysis::StiffnessSettings settings;  // the stage's loop with friction needs d too
  settings.crank = 0.0;
  const std::string loop_no_d = ltca::test::InvalidArgumentMessage(
      [&] { (void)ltca::test::StiffnessOn(linear, linear.solver, settings, linear.kinematics); });
  CHECK(loop_no_d.find("expected bearing_diameter_mm") != std::string::npos);
}

TEST_CASE("cli: ltca efficiency of a stage writes the loss by source per position and in the summary (JSON, CSV, text, figure)") {
  const auto dir = std::filesystem::temp_directory_path() / "ltca_stage_efficiency_test";
  std::filesystem::create_directories(dir);
  const auto csv = dir / "contacts.csv", svg = dir / "efficiency.svg";
  const auto r = ltca::test::RunCli({"efficiency", Case("stage/cycloidal_drive.toml"), "--json", "-", "--csv", csv.string(), "--svg",
                                     svg.string(), "--set", "friction.coefficient=0.05", "--set",
                                     "friction.output_pin_coefficient=0.05", "--set", "friction.bearing_coefficient=0.0015",
                                     "--set", "sweep.positions=3"});
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  for (const auto& p : j.at("positions")) {
    const auto& s = p.at("power_loss_by_source_w");
    const double sum = s.at("mesh").get<double>() + s.at("output").get<double>() + s.at("bearings").get<double>() +
                       s.at("seats").get<double>();
    CHECK(p.at("power_loss_w").get<double>() == doctest::Approx(sum).epsilon(1e-14));
    CHECK(s.at("output").get<double>() > 0.0);
  }
  const auto& summary = j.at("summary");
  CHECK(summary.at("power_loss_by_source_w").at("bearings").get<double>() > 0.0);
  CHECK(summary.at("stage_friction_moment_ratio_max").get<double>() > 0.0);
  CHECK(j.at("friction").at("output_pin_coefficient") == 0.05);
  CHECK(r.err.find("power loss by source   mesh") != std::string::npos);
  const std::string head = ltca::test::ReadText(csv).substr(0, ltca::test::ReadText(csv).find('\n'));
  CHECK(head.find(",position_loss_mesh_w,position_loss_output_w,position_loss_bearings_w,position_loss_seats_w") != std::string::npos);
  const std::string drawing = ltca::test::ReadText(svg);
  CHECK(drawing.find("<ltca:series label=\"output pins\"") != std::string::npos);
  CHECK(drawing.find("<ltca:series label=\"bearings\"") != std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST_CASE("app: jiang-mixed with a mineral gear oil on the stage decks: outside its range uncapped, finite with a limiting shear stress") {
  // 0.05 Pa*s, 18 1/GPa at the stage decks' 1.4 to 1.5 GPa: without the cap the position fails as
  // the model outside its range (naming pressure_viscosity_per_gpa); with tau_L = 0.06 p (Bair and
  // Winer 1979) every pin contact's coefficient lies below max(gamma, f_b) (the bound of
  // docs/efficiency.md) and the stage's efficiency, with its bearings, is finite and below 1.
  for (const std::string name : {"cycloidal_drive.toml", "rv_catalogue.toml"}) {
    CAPTURE(name);
    std::vector<std::string> o = {"friction.model=\"jiang-mixed\"", "operation.oil_viscosity_pa_s=0.05",
                                  "operation.pressure_viscosity_per_gpa=18", "friction.bearing_coefficient=0.0015"};
    const Deck uncapped = StageDeck(name, o);
    auto bad = ltca::test::EfficiencyOn(uncapped, uncapped.solver, uncapped.kinematics);
    const EfficiencyPosition failed = bad.Solve(bad.cranks().front());
    CHECK(!failed.succeeded());
    CHECK(failed.message.find("jiang.full_film_outside_range") != std::string::npos);
    CHECK(failed.message.find("pressure_viscosity_per_gpa = 18") != std::string::npos);
    o.push_back("friction.limiting_shear_stress_coefficient=0.06");
    const Deck capped = StageDeck(name, o);
    auto runner = ltca::test::EfficiencyOn(capped, capped.solver, capped.kinematics);
    for (const double crank : runner.cranks()) {
      const EfficiencyPosition p = runner.Solve(crank);
      REQUIRE(p.succeeded());
      for (const auto& c : p.contacts) CHECK(c.coefficient <= std::max(0.06, capped.friction->boundary_coefficient) + 1e-15);
      CHECK(p.power_loss_by_source.bearings > 0.0);
      CHECK(std::isfinite(p.efficiency));
      CHECK(p.efficiency > 0.7);
      CHECK(p.efficiency < 1.0);
    }
  }
}
