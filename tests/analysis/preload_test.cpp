// A preloaded pair's unloaded backlash and torque-twist loop (docs/stiffness.md "Preload"):
// Liu 2021 Table 1 with every pin 0.5 um into the cycloid, the linear law. Independent reference:
// the tests' two-flank network (tests/solvers/two_flank_network.hpp, a breakpoint walk over the
// contact layer's clearances and arms), and the linearised closings c_i / L_i for the interference.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

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
