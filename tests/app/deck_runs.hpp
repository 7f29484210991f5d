#pragma once
// The analyses on a deck, as the commands run them (issue 24): the deck's stage under given
// kinematics, its torque, and the analysis's settings. Shared by the tests of tests/app.
#include <optional>
#include <vector>

#include "ltca/app/deck.hpp"

namespace ltca::test {

/// The deck under other kinematics.
inline app::Deck WithKinematics(app::Deck deck, contact::ContactKinematics kinematics) {
  deck.kinematics = kinematics;
  return deck;
}

inline analysis::SweepRunner SweepOn(const app::Deck& deck, const solvers::SolverOptions& options,
                                     contact::ContactKinematics kinematics) {
  const app::Deck d = WithKinematics(deck, kinematics);
  return {d.MakeStage(), options, d.RequireLoad().torque};
}

inline analysis::SweepResult SolveSweep(const app::Deck& deck, const solvers::SolverOptions& options,
                                        const analysis::SweepCallbacks& callbacks = {}) {
  return app::SolveDeckSweep(deck, options, callbacks);
}

/// The loop at settings.crank, or over the deck's sweep, with the deck's [friction].
inline analysis::StiffnessRunner StiffnessOn(const app::Deck& deck, const solvers::SolverOptions& options,
                                             const analysis::StiffnessSettings& settings,
                                             contact::ContactKinematics kinematics) {
  const app::Deck d = WithKinematics(deck, kinematics);
  d.RequireMaterial();
  const double torque = d.RequireLoad().torque;
  return {d.MakeStage(settings.crank ? std::vector<double>{*settings.crank} : d.sweep.CrankAngles()), options, settings,
          torque, d.friction};
}

inline analysis::EfficiencyRunner EfficiencyOn(const app::Deck& deck, const solvers::SolverOptions& options,
                                               contact::ContactKinematics kinematics) {
  const app::Deck d = WithKinematics(deck, kinematics);
  d.RequireMaterial();
  const auto& friction = d.RequireFriction();
  const auto& operation = d.RequireOperation();
  return {d.MakeStage(), options, d.RequireLoad().torque, friction, operation};
}

inline analysis::ToleranceStudy ToleranceOn(const app::Deck& deck, const solvers::SolverOptions& options,
                                            const analysis::ToleranceSettings& settings) {
  return {deck.MakeToleranceCase(), options, settings};
}

}  // namespace ltca::test
