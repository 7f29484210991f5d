// A preloaded pair's unloaded backlash and torque-twist loop (docs/stiffness.md "Preload"):
// Liu 2021 Table 1 with every pin 0.5 um into the cycloid, the linear law. Independent reference:
// the tests' two-flank network (tests/solvers/two_flank_network.hpp, a breakpoint walk over the
// contact layer's clearances and arms), and the linearised closings c_i / L_i for the interference.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <doctest/doctest.h>

#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/geometry/units.hpp"
#include "designs.hpp"
#include "solvers/two_flank_network.hpp"

namespace {

constexpr double kPreloadLaw = 2e4;          ///< N/mm per mm of contact length
constexpr double kPreloadTorque = 206'000.0;  ///< N*mm

ltca::analysis::StageDesign PreloadedLiu() {
  ltca::analysis::StageDesign d = ltca::test::SteelLiuTable1();
  d.modification.pin_radius = -0.0005;  // every pin 0.5 um into the cycloid
  d.contact.law = ltca::contact::LawKind::kLinear;
  d.contact.stiffness_per_length = kPreloadLaw;
  d.kinematics = ltca::contact::ContactKinematics::kLinearised;
  return d;
}

std::vector<ltca::test::FlankSpring> PreloadSprings(const ltca::analysis::Stage& stage, double crank) {
  std::vector<ltca::test::FlankSpring> springs;
  for (const auto& pin : stage.model().Evaluate(crank, 0.0).pins) {
    springs.push_back({pin.arm, pin.clearance, kPreloadLaw * pin.length});
  }
  return springs;
}

double Phi(const std::vector<ltca::test::FlankSpring>& springs, double torque) {
  return ltca::test::SolveTwoFlankNetwork(springs, torque).phi;
}

}  // namespace

TEST_CASE("analysis: a preloaded pair's backlash is none, it reports the interference and the torques that unload a flank") {
  const double crank = ltca::units::DegToRad(0.3);
  const ltca::analysis::Stage stage(PreloadedLiu(), {crank});
  const auto springs = PreloadSprings(stage, crank);
  // The linearised closings: the drive flank's first, min over L > 0 of c / L, lies behind the coast
  // flank's, max over L < 0 of c / L; their overlap is the interference.
  double c1 = std::numeric_limits<double>::infinity(), c2 = -c1;
  for (const auto& s : springs) {
    if (s.arm > 0.0) c1 = std::min(c1, s.clearance / s.arm);
    if (s.arm < 0.0) c2 = std::max(c2, s.clearance / s.arm);
  }
  REQUIRE(c2 > c1);
  std::vector<ltca::analysis::BacklashPosition> positions;
  const auto result = ltca::analysis::Backlash(stage, ltca::contact::ContactKinematics::kLinearised,
                                               [&](const auto& p) { positions.push_back(p); });
  REQUIRE(positions.size() == 1);
  const auto& p = positions.front();
  REQUIRE(p.ok);
  CHECK(p.contact.backlash == 0.0);
  CHECK(p.contact.interference == doctest::Approx(c2 - c1).epsilon(1e-9));
  // Turning in the load direction to c2 opens the coast flank's last pin: the drive flank's moment
  // there is the torque that unloads the coast flank; the other way, to c1, the drive flank.
  CHECK(p.unload_torque_nmm == doctest::Approx(ltca::test::TwoFlankMoment(springs, c2)).epsilon(1e-9));
  CHECK(p.unload_torque_reverse_nmm == doctest::Approx(-ltca::test::TwoFlankMoment(springs, c1)).epsilon(1e-9));
  CHECK(result.summary.preloaded() == 1);
  CHECK(result.summary.mean() == 0.0);
  CHECK(result.summary.max_interference() == p.contact.interference);
}

TEST_CASE("analysis: a preloaded pair's loop runs through zero without free play, its lost motion over +-3 % T is the network's") {
  const double crank = ltca::units::DegToRad(0.3);
  const ltca::analysis::Stage stage(PreloadedLiu(), {crank});
  const auto springs = PreloadSprings(stage, crank);
  ltca::analysis::StiffnessSettings settings;
  settings.steps = 9;
  settings.crank = crank;
  settings.lost_motion_fraction = 0.03;  // the catalogue's +-3 % of the rated torque
  ltca::solvers::SolverOptions options;
  options.torque_tolerance = 1e-13;
  const auto result = ltca::analysis::Stiffness(stage, options, settings, kPreloadTorque);
  REQUIRE(result.all_succeeded());
  const auto& pos = result.positions.front();
  const double t = kPreloadTorque, f = 0.03;
  // No free play: the loop rests at the preload state from either flank.
  CHECK(std::abs(pos.backlash) <= 1e-15);  // the preload state, the same from either flank
  const double rest = Phi(springs, 0.0);
  // Every point of the curve is the network's twist at its torque: continuous through zero.
  for (const auto& point : pos.curve) {
    CAPTURE(point.torque);
    CHECK(point.twist == doctest::Approx(Phi(springs, point.torque)).epsilon(1e-6));
  }
  CHECK(pos.first_contact_drive == doctest::Approx(rest).epsilon(1e-6));
  // The catalogue's definitions on the network's twists (docs/stiffness.md).
  const double lost = Phi(springs, f * t) - Phi(springs, -f * t);
  CHECK(lost > 0.0);
  CHECK(pos.lost_motion == doctest::Approx(lost).epsilon(1e-6));
  const double drive = Phi(springs, t) - Phi(springs, 0.5 * t), coast = Phi(springs, -0.5 * t) - Phi(springs, -t);
  CHECK(pos.rigidity == doctest::Approx(t / (drive + coast)).epsilon(1e-6));
}

namespace {

/// The network's balance on a pass of the loop with Coulomb friction (sense +1 increasing, -1
/// decreasing): the disc turning about its centre slides every pressed point along its tangent,
/// whose friction mu F_i resists the turning at the arm a_i = |(P_i - O_c) . n_i|, so the normal
/// forces carry t - sense M_f: sum_i F_i(phi) (L_i + sense mu a_i) = t, F_i = k_i (L_i phi - c_i)_+.
/// Piecewise linear in phi (breakpoints c_i / L_i): the piece whose ends bracket t, solved there.
double FrictionPhi(const std::vector<ltca::test::FlankSpring>& springs, const std::vector<double>& arms, double mu,
                   double sense, double torque) {
  const auto g = [&](double phi) {
    double m = 0.0;
    for (std::size_t i = 0; i < springs.size(); ++i) {
      const auto& s = springs[i];
      m += s.k * std::max(0.0, s.arm * phi - s.clearance) * (s.arm + sense * mu * arms[i]);
    }
    return m - torque;
  };
  std::vector<double> breaks;
  for (const auto& s : springs) {
    if (s.arm != 0.0) breaks.push_back(s.clearance / s.arm);
  }
  std::sort(breaks.begin(), breaks.end());
  breaks.insert(breaks.begin(), breaks.front() - 1.0);
  breaks.push_back(breaks.back() + 1.0);
  double root = std::numeric_limits<double>::quiet_NaN();
  int roots = 0;
  for (std::size_t j = 0; j + 1 < breaks.size(); ++j) {
    const double a = breaks[j], b = breaks[j + 1], ga = g(a), gb = g(b);
    if (ga == 0.0) root = a, ++roots;
    if (ga * gb < 0.0) root = a - ga * (b - a) / (gb - ga), ++roots;  // linear on the piece
  }
  REQUIRE(roots == 1);
  return root;
}

}  // namespace

TEST_CASE("analysis: a preloaded pair's loop with friction runs through zero torque, every point the network's balance with friction (1e-6)") {
  // Issue 52: the 0.5 um preload under the linear law with Coulomb friction mu = 0.05. Both flanks
  // carry load at zero torque, so friction resists there too: each pass is the network's balance
  // with friction at every level, zero included (FrictionPhi, a breakpoint walk written here), and
  // after each reversal the output holds its twist until that pass reaches it. At 206 N*m the stick
  // ends before zero; at 1.5 times the preload's friction moment at rest (M_0, from the network) it
  // holds the output through zero; at M_0 / 2 from one end to the other: no loop, a named failure.
  const double crank = ltca::units::DegToRad(0.3);
  const ltca::analysis::Stage stage(PreloadedLiu(), {crank});
  const auto springs = PreloadSprings(stage, crank);
  std::vector<double> arms;
  for (const auto& pin : stage.model().Evaluate(crank, 0.0).pins) {
    const Eigen::Vector2d centre = stage.model().CyclePose(crank, 0.0, pin.z).centre;
    arms.push_back(std::abs((pin.cycloid_point - centre).dot(pin.normal)));
  }
  const double mu = 0.05;
  ltca::analysis::FrictionSettings friction;
  friction.coefficient = mu;
  ltca::solvers::SolverOptions options;
  options.torque_tolerance = 1e-13;
  // The preload's friction moment at rest, mu sum F_i a_i at the network's zero-torque twist.
  const double rest = Phi(springs, 0.0);
  double drag = 0.0;
  for (std::size_t i = 0; i < springs.size(); ++i) {
    drag += mu * springs[i].k * std::max(0.0, springs[i].arm * rest - springs[i].clearance) * arms[i];
  }
  REQUIRE(drag > 0.0);
  REQUIRE(drag < 0.1 * kPreloadTorque);
  for (const double t : {kPreloadTorque, 1.5 * drag}) {
    CAPTURE(t);
    ltca::analysis::StiffnessSettings settings;
    settings.steps = 9;
    settings.crank = crank;
    const auto result = ltca::analysis::Stiffness(stage, options, settings, t, friction);
    INFO(result.summary.first_failure);
    REQUIRE(result.all_succeeded());
    const auto& pos = result.positions.front();
    // The loop starts at -T on the decreasing pass; the increasing pass holds that twist, the
    // decreasing one the increasing pass's twist at +T.
    const double held_up = FrictionPhi(springs, arms, mu, -1.0, -t);
    const double held_down = FrictionPhi(springs, arms, mu, 1.0, t);
    int stuck = 0, moving = 0, ends = 0, zero_stuck = 0;
    for (const auto& point : pos.curve) {
      CAPTURE(point.torque);
      const bool up = point.branch == ltca::analysis::Branch::kIncreasing;
      const double sense = up ? 1.0 : -1.0;
      const double held = up ? held_up : held_down;
      const double free = FrictionPhi(springs, arms, mu, sense, point.torque);
      if (point.stick_end) {
        ++ends;
        CHECK(point.twist == doctest::Approx(held).epsilon(1e-6));
        CHECK(free == doctest::Approx(held).epsilon(1e-6));  // the pass reaches the held twist there
      } else if (sense * (free - held) < -1e-9 * std::abs(held)) {
        ++stuck;
        if (point.torque == 0.0) ++zero_stuck;
        CHECK(point.twist == doctest::Approx(held).epsilon(1e-6));
      } else {
        ++moving;
        CHECK(point.twist == doctest::Approx(free).epsilon(1e-6));
      }
    }
    CHECK(ends == 2);
    CHECK(stuck > 0);
    CHECK(moving > 0);
    if (t == kPreloadTorque) CHECK(zero_stuck == 0);  // the stick ends before zero
    if (t != kPreloadTorque) CHECK(zero_stuck == 2);  // it holds through zero on both passes
    CHECK(pos.hysteresis > 0.0);
  }
  ltca::analysis::StiffnessSettings settings;
  settings.steps = 9;
  settings.crank = crank;
  const auto locked = ltca::analysis::Stiffness(stage, options, settings, 0.5 * drag, friction);
  CHECK_FALSE(locked.all_succeeded());
  CHECK(locked.summary.first_failure.find("the output sticks from") != std::string::npos);
}
