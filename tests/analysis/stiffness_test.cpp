// analysis::StiffnessResult, the torque-twist loop of a stage, against the single-purpose
// computations it gathers: the loaded solve at one torque (analysis::SweepRunner; twist = -TE,
// docs/conventions.md) for every read-off point, the catalogue's definitions applied to those
// twists (secant rigidity T / (a_drive + a_coast) with a = twist(T) - twist(T / 2) on each flank,
// lost motion twist(f T) - twist(-f T)), and the unloaded first contacts (analysis::Backlash, Liu
// 2021 eq. 17, the two-disc rule) for the backlash. One disc and two discs; the stage is built
// from data (analysis::StageDesign), no deck.
#include <algorithm>
#include <cmath>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/geometry/units.hpp"
#include "designs.hpp"

namespace {

using ltca::analysis::Stage;
using ltca::analysis::StageDesign;
using ltca::analysis::StiffnessPosition;
using ltca::analysis::StiffnessResult;
using ltca::analysis::StiffnessSettings;
using ltca::solvers::SolverOptions;

constexpr double kTorque = 206'000.0;  ///< N*mm: Liu 2021 section 5.2's 206 N*m

using ltca::test::SteelLiu52;
using ltca::test::SteelLiu52TwoDiscs;

/// The twist (rad, -TE) of the stage at `crank` under `torque` (N*mm) by one loaded solve of its own.
double LoadedTwist(const Stage& stage, double crank, double torque, double* first_disc_share = nullptr) {
  ltca::analysis::SweepRunner runner(stage, SolverOptions{}, torque);
  const ltca::analysis::PositionResult p = runner.Solve(crank);
  REQUIRE(p.succeeded());
  if (first_disc_share != nullptr) *first_disc_share = p.disc_torque.empty() ? NAN : p.disc_torque[0] / torque;
  return -p.result.te;
}

/// The loop's position at the stage's one crank checked against the independent solves: the
/// read-off twists, the rigidities and the lost motion by their definitions, the backlash of the
/// unloaded analysis; returns the first disc's share at +T by the independent solve.
double CheckAgainstSingleSolves(const Stage& stage, const StiffnessSettings& settings, const StiffnessResult& result) {
  REQUIRE(result.positions.size() == 1);
  const StiffnessPosition& p = result.positions.front();
  const double crank = stage.cranks().front();
  REQUIRE(p.crank == crank);
  REQUIRE(p.succeeded());
  REQUIRE(p.readoffs.size() == 6);  // secant: +T, +T/2, -T/2, -T, then +f T, -f T
  const double t = kTorque, f = settings.lost_motion_fraction;
  const double torques[6] = {t, 0.5 * t, -0.5 * t, -t, f * t, -f * t};
  double share = NAN;
  std::vector<double> twist;
  for (int k = 0; k < 6; ++k) {
    CAPTURE(k);
    CHECK(p.readoffs[k].torque == doctest::Approx(torques[k]).epsilon(1e-15));
    twist.push_back(LoadedTwist(stage, crank, torques[k], k == 0 ? &share : nullptr));
    // The loop warm-starts every step from the last; the single solve starts cold: equal to the
    // solver's tolerance.
    CHECK(p.readoffs[k].twist == doctest::Approx(twist.back()).epsilon(1e-7));
  }
  const double drive = twist[0] - twist[1], coast = twist[2] - twist[3];
  CHECK(p.rigidity_drive == doctest::Approx(0.5 * t / drive).epsilon(1e-6));
  CHECK(p.rigidity_coast == doctest::Approx(0.5 * t / coast).epsilon(1e-6));
  CHECK(p.rigidity == doctest::Approx(t / (drive + coast)).epsilon(1e-6));
  CHECK(p.lost_motion == doctest::Approx(twist[4] - twist[5]).epsilon(1e-6));
  // The loop's width at zero torque is the unloaded backlash (the two-disc rule included).
  std::vector<ltca::analysis::BacklashPosition> unloaded;
  ltca::analysis::Backlash(stage, stage.kinematics(), [&](const auto& u) { unloaded.push_back(u); });
  REQUIRE(unloaded.size() == 1);
  CHECK(p.backlash == doctest::Approx(unloaded.front().contact.backlash).epsilon(1e-9));
  // One position: the summary's figures are the position's.
  CHECK(result.summary.rigidity.mean == p.rigidity);
  CHECK(result.summary.lost_motion.mean == p.lost_motion);
  CHECK(result.summary.backlash.mean == p.backlash);
  CHECK(result.summary.positions() == 1);
  return share;
}

}  // namespace

TEST_CASE("analysis: one disc's loop reads its rigidity and lost motion off the loaded solves, its backlash off the unloaded analysis") {
  const double crank = ltca::units::DegToRad(0.3);
  const Stage stage(SteelLiu52(), {crank});
  StiffnessSettings settings;
  settings.steps = 9;
  settings.crank = crank;
  const StiffnessResult result = ltca::analysis::Stiffness(stage, SolverOptions{}, settings, -kTorque);
  // What ran: the settings, T = |torque|, no friction, the one crank.
  CHECK(result.rated_torque == kTorque);
  CHECK(result.friction_coefficient == 0.0);
  CHECK_FALSE(result.sweep());
  CHECK(result.settings.steps == 9);
  CHECK(result.cranks == std::vector<double>{crank});
  CHECK(result.all_succeeded());
  const double share = CheckAgainstSingleSolves(stage, settings, result);
  CHECK(std::isnan(share));
  CHECK(std::isnan(result.positions.front().first_disc_share_drive));
  CHECK(result.summary.first_disc_share_drive.count == 0);
}

TEST_CASE("analysis: two discs' loop reads its rigidity, lost motion and first disc's share off the stage's loaded solves") {
  const double crank = ltca::units::DegToRad(0.3);
  const Stage stage(SteelLiu52TwoDiscs(), {crank});
  REQUIRE(stage.disc_count() == 2);
  StiffnessSettings settings;
  settings.steps = 9;
  settings.crank = crank;
  const StiffnessResult result = ltca::analysis::Stiffness(stage, SolverOptions{}, settings, kTorque);
  CHECK(result.all_succeeded());
  const double share = CheckAgainstSingleSolves(stage, settings, result);
  const StiffnessPosition& p = result.positions.front();
  REQUIRE(std::isfinite(share));
  CHECK(share > 0.0);
  CHECK(share < 1.0);
  CHECK(p.first_disc_share_drive == doctest::Approx(share).epsilon(1e-6));
  CHECK(result.summary.first_disc_share_drive.mean == p.first_disc_share_drive);
}

TEST_CASE("analysis: a swept loop's summary spreads its positions, and a sink sees the positions the result would keep") {
  const std::vector<double> cranks = {0.0, ltca::units::DegToRad(1.5), ltca::units::DegToRad(3.0)};
  const Stage stage(SteelLiu52(), cranks);
  REQUIRE_FALSE(stage.closed_period());  // every position weighs once in the means
  StiffnessSettings settings;
  settings.steps = 5;
  const StiffnessResult kept = ltca::analysis::Stiffness(stage, SolverOptions{}, settings, kTorque);
  REQUIRE(kept.positions.size() == 3);
  CHECK(kept.sweep());
  CHECK(kept.cranks == cranks);
  double sum = 0.0, lo = INFINITY, hi = -INFINITY;
  for (const StiffnessPosition& p : kept.positions) {
    sum += p.rigidity;
    lo = std::min(lo, p.rigidity), hi = std::max(hi, p.rigidity);
  }
  CHECK(kept.summary.rigidity.mean == doctest::Approx(sum / 3.0).epsilon(1e-14));
  CHECK(kept.summary.rigidity.min == lo);
  CHECK(kept.summary.rigidity.max == hi);
  CHECK(lo < hi);  // the rigidity varies with the crank: the spread is not the one position's
  CHECK(kept.summary.positions() == 3);

  std::vector<StiffnessPosition> seen;
  ltca::analysis::StiffnessRunner runner(stage, SolverOptions{}, settings, kTorque);
  const StiffnessResult streamed = runner.Run([&](const StiffnessPosition& p) { seen.push_back(p); });
  CHECK(streamed.positions.empty());
  REQUIRE(seen.size() == 3);
  for (std::size_t i = 0; i < seen.size(); ++i) {
    CHECK(seen[i].crank == kept.positions[i].crank);
    CHECK(seen[i].rigidity == kept.positions[i].rigidity);
    CHECK(seen[i].lost_motion == kept.positions[i].lost_motion);
  }
  CHECK(streamed.summary.rigidity.mean == kept.summary.rigidity.mean);
}
