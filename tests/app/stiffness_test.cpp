// Issue 13: the torque-twist loop (ltca stiffness). Independent references: the closed form of the
// linear law (sum over the loaded pins of k_i L_i^2), the unloaded analysis that `ltca backlash`
// runs (contact::AnalyseUnloaded, its own code path), the mirror symmetry of the perfect pair,
// and `ltca solve`'s sweep (SolveSweep) at the lost-motion torques.
#include <cmath>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "ltca/app/deck.hpp"
#include "ltca/app/stiffness.hpp"
#include "ltca/app/sweep.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"

using ltca::app::Branch;
using ltca::app::Deck;
using ltca::app::StiffnessPosition;
using ltca::app::StiffnessRunner;
using ltca::app::StiffnessSettings;
using ltca::contact::ContactKinematics;
using ltca::solvers::SolverOptions;

namespace {

std::string Case(const std::string& rel) { return std::string(LTCA_CASES_DIR) + "/" + rel; }

SolverOptions Options(const std::string& solver, ContactKinematics kinematics) {
  SolverOptions o;
  o.name = solver;
  o.kinematics = kinematics;
  return o;
}

StiffnessSettings AtCrank(double crank_deg) {
  StiffnessSettings s;
  s.crank = ltca::units::DegToRad(crank_deg);
  return s;
}

/// The twists of one branch at the non-zero levels, in level order.
std::vector<const ltca::app::CurvePoint*> Branch0(const StiffnessPosition& p, Branch branch) {
  std::vector<const ltca::app::CurvePoint*> out;
  for (const auto& c : p.curve) {
    if (c.branch == branch && c.torque != 0.0) out.push_back(&c);
  }
  return out;
}

}  // namespace

TEST_CASE("app: stiffness of the linear law without clearance is the closed form sum k_i L_i^2 over the loaded pins (1e-9)") {
  // Liu Table 1, perfect profile: every pin of the loaded half touches at zero load (c_i = 0) and
  // the other half opens, on either flank. The linear law F = k B delta with linearised
  // kinematics (delta_i = L_i psi - c_i) gives T = psi sum k B L_i^2 on the loaded half: the loop
  // is two straight lines and every secant or tangent of a flank is that sum. k = 2e4 N/mm^2,
  // B = 12 mm, a small torque of 1 N*m.
  const double k = 2e4;
  const Deck deck = ltca::app::LoadDeck(Case("liu2021_table1.toml"),
                                        {"contact.law=linear", "contact.stiffness_n_per_mm2=2e4", "load.torque_nm=1"});
  const ltca::contact::MeshModel model = deck.MakeModel();
  for (const std::string solver : {"compatibility", "bisection", "energy-groups", "energy-qp"}) {
    for (const double crank_deg : {0.0, 3.3, 7.1}) {
      CAPTURE(solver);
      CAPTURE(crank_deg);
      double drive = 0.0, coast = 0.0;  // N*mm/rad, closed form
      for (const auto& pin : model.Evaluate(ltca::units::DegToRad(crank_deg), 0.0).pins) {
        REQUIRE(std::abs(pin.clearance) < (pin.arm > 0.0 ? 1e-12 : 1.0));  // the loaded half touches
        (pin.arm > 0.0 ? drive : coast) += k * pin.length * pin.arm * pin.arm;
      }
      StiffnessSettings secant = AtCrank(crank_deg);
      secant.steps = 5;
      StiffnessRunner runner(deck, Options(solver, ContactKinematics::kLinearised), secant);
      const StiffnessPosition p = runner.Solve(*secant.crank);
      REQUIRE(p.succeeded());
      CHECK(p.rigidity_drive == doctest::Approx(drive).epsilon(1e-9));
      CHECK(p.rigidity_coast == doctest::Approx(coast).epsilon(1e-9));
      CHECK(p.rigidity == doctest::Approx(1.0 / (0.5 / drive + 0.5 / coast)).epsilon(1e-9));
      for (const double at : {0.5e3, -0.25e3}) {  // the tangent at +0.5 and -0.25 N*m
        StiffnessSettings tangent = secant;
        tangent.rigidity = StiffnessSettings::Rigidity::kTangent;
        tangent.tangent_torque = at;
        StiffnessRunner t(deck, Options(solver, ContactKinematics::kLinearised), tangent);
        // The central difference over +-1 % of the torque divides two twists, each balanced to the
        // torque tolerance 1e-10 (bisection stops there): up to 2e-10 x 50 = 1e-8 of the slope.
        CHECK(t.Solve(*tangent.crank).rigidity == doctest::Approx(at > 0.0 ? drive : coast).epsilon(2e-8));
      }
    }
  }
}

TEST_CASE("app: stiffness backlash and the zero-torque points are the unloaded analysis of ltca backlash (1e-12 rad)") {
  // Liu section 5.2 base modification (dR_rp -4 um, dR_p -17 um): about 48 arcsec of backlash.
  const Deck deck = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"));
  const ltca::contact::MeshModel model = deck.MakeModel();
  for (const ContactKinematics kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    for (const double crank_deg : {0.0, 2.5, 4.5, 8.2}) {
      CAPTURE(crank_deg);
      const StiffnessSettings settings = AtCrank(crank_deg);
      StiffnessRunner runner(deck, Options("compatibility", kinematics), settings);
      const StiffnessPosition p = runner.Solve(*settings.crank);
      REQUIRE(p.succeeded());
      const ltca::contact::UnloadedContact u = ltca::contact::AnalyseUnloaded(model, *settings.crank, kinematics);
      CHECK(p.backlash == doctest::Approx(u.backlash).epsilon(1e-12));
      CHECK(std::abs(p.backlash - u.backlash) < 1e-12);
      CHECK(ltca::units::RadToArcsec(p.backlash) > 40.0);
      // Each branch crosses the free play at zero torque: from the flank it comes from to the other.
      std::vector<const ltca::app::CurvePoint*> zero;
      for (const auto& c : p.curve) {
        if (c.torque == 0.0) zero.push_back(&c);
      }
      REQUIRE(zero.size() == 4);
      CHECK(std::abs(zero[0]->twist - u.theta_c2) < 1e-12);  // increasing: coast first contact, then drive
      CHECK(std::abs(zero[1]->twist - u.theta_c1) < 1e-12);
      CHECK(std::abs(zero[2]->twist - u.theta_c1) < 1e-12);  // decreasing: drive, then coast
      CHECK(std::abs(zero[3]->twist - u.theta_c2) < 1e-12);
    }
  }
}

TEST_CASE("app: stiffness of the Liu Table 1 perfect pair: no backlash and a curve symmetric about the origin") {
  // The perfect pair mirrors about the line of centres at crank 0 (tests/solvers/flanks_test.cpp):
  // the twist at -t is minus the twist at +t. Over one mesh period sampled symmetrically
  // (crank theta and 9 deg - theta), the mean curve is symmetric too.
  const Deck deck = ltca::app::LoadDeck(Case("liu2021_table1.toml"), {"sweep.positions=11"});
  for (const std::string solver : {"compatibility", "bisection"}) {
    CAPTURE(solver);
    const StiffnessSettings settings = AtCrank(0.0);
    StiffnessRunner runner(deck, Options(solver, ContactKinematics::kLinearised), settings);
    const StiffnessPosition p = runner.Solve(0.0);
    REQUIRE(p.succeeded());
    CHECK(std::abs(p.backlash) < 1e-12);
    const auto up = Branch0(p, Branch::kIncreasing);
    REQUIRE(up.size() == 40);
    for (std::size_t i = 0; i < up.size(); ++i) {
      const auto* mirror = up[up.size() - 1 - i];
      REQUIRE(mirror->torque == -up[i]->torque);
      CHECK(up[i]->twist == doctest::Approx(-mirror->twist).epsilon(1e-8));
    }
    CHECK(p.rigidity_drive == doctest::Approx(p.rigidity_coast).epsilon(1e-8));
    StiffnessRunner sweep(deck, Options(solver, ContactKinematics::kLinearised), StiffnessSettings{});
    for (const double crank : sweep.cranks()) REQUIRE(sweep.Solve(crank).succeeded());
    const ltca::app::StiffnessSummary s = sweep.Summary();
    CHECK(std::abs(s.backlash.max) < 1e-12);
    const std::size_t n = s.curve.size() / 2;  // the increasing branch
    for (std::size_t i = 0; i < n; ++i) {
      CHECK(s.curve[i].twist == doctest::Approx(-s.curve[n - 1 - i].twist).epsilon(1e-8));
    }
  }
}

TEST_CASE("app: stiffness of the Liu 5.2 base: lost motion is the twist between +-3 % of T solved by ltca solve, above the backlash") {
  // Without friction both branches have one twist per torque, so the midpoints of the loop at
  // +-3 % of T are the twists SolveSweep (ltca solve) finds at +-6.18 N*m: their difference is the
  // lost motion (1e-12 rad), and it exceeds the backlash (the free play) by the wind-up of both
  // flanks at 3 %.
  for (const ContactKinematics kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    for (const double crank_deg : {0.0, 4.5}) {
      CAPTURE(crank_deg);
      const Deck deck = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"));
      const StiffnessSettings settings = AtCrank(crank_deg);
      StiffnessRunner runner(deck, Options("compatibility", kinematics), settings);
      const StiffnessPosition p = runner.Solve(*settings.crank);
      REQUIRE(p.succeeded());
      double twist[2] = {0.0, 0.0};
      for (int side = 0; side < 2; ++side) {
        const Deck one = ltca::app::LoadDeck(
            Case("liu2021_sec52_base.toml"),
            {side == 0 ? "load.torque_nm=6.18" : "load.torque_nm=-6.18", "sweep.positions=1",
             "sweep.crank_start_deg=" + std::to_string(crank_deg), "sweep.crank_end_deg=" + std::to_string(crank_deg)});
        const ltca::app::SweepResult r = ltca::app::SolveSweep(one, Options("bisection", kinematics));
        REQUIRE(r.summary.all_succeeded());
        twist[side] = -r.positions.front().result.te;
      }
      CHECK(std::abs(p.lost_motion - (twist[0] - twist[1])) < 1e-12);
      CHECK(p.lost_motion > p.backlash);
      CHECK(p.lost_motion < 1.2 * p.backlash);  // the wind-up at 3 % is a few per cent of the free play
    }
  }
}

TEST_CASE("app: the [stiffness] section is read in internal units and defaults to the catalogue definitions") {
  const Deck plain = ltca::app::LoadDeck(Case("liu2021_table1.toml"));
  CHECK(plain.stiffness.steps == 41);
  CHECK(plain.stiffness.rigidity == StiffnessSettings::Rigidity::kSecant);
  CHECK(plain.stiffness.lost_motion_fraction == 0.03);
  CHECK(!plain.stiffness.crank.has_value());
  const Deck deck = ltca::app::LoadDeck(
      Case("liu2021_table1.toml"), {"stiffness.steps_per_branch=21", "stiffness.rigidity=tangent", "stiffness.tangent_torque_nm=-150",
                                    "stiffness.lost_motion_fraction=0.05", "stiffness.crank_deg=4.5"});
  CHECK(deck.stiffness.steps == 21);
  CHECK(deck.stiffness.rigidity == StiffnessSettings::Rigidity::kTangent);
  CHECK(deck.stiffness.tangent_torque == -150e3);  // N*mm
  CHECK(deck.stiffness.lost_motion_fraction == 0.05);
  CHECK(*deck.stiffness.crank == doctest::Approx(ltca::units::DegToRad(4.5)).epsilon(1e-15));
  // The levels are symmetric and hold zero and +-T / 2 when (steps - 1) / 2 is even.
  StiffnessSettings five;
  five.steps = 5;
  five.crank = 0.0;
  const StiffnessRunner runner(deck, Options("compatibility", ContactKinematics::kLinearised), five);
  CHECK(runner.Levels() == std::vector<double>{-206e3, -103e3, 0.0, 103e3, 206e3});
}
