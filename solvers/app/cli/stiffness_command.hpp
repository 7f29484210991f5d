#pragma once
#include <optional>
#include <string>

#include "ltca/app/deck.hpp"
#include "output.hpp"

namespace ltca::cli {

/// The command line of `ltca stiffness`: each option given replaces the deck's [stiffness] key.
struct StiffnessOptions {
  std::string solver;      ///< "" = the deck's [solver] name
  std::string kinematics;  ///< "" = the deck's
  std::string json_path, csv_path, svg_path;
  std::optional<double> crank_deg;             ///< [stiffness] crank_deg
  std::optional<int> steps;                    ///< [stiffness] steps_per_branch
  std::string rigidity;                        ///< [stiffness] rigidity ("" = the deck's)
  std::optional<double> tangent_torque_nm;     ///< [stiffness] tangent_torque_nm
  std::optional<double> lost_motion_fraction;  ///< [stiffness] lost_motion_fraction
};

/// The deck's [stiffness] with the command line's options applied and validated.
analysis::StiffnessSettings StiffnessSettingsFor(const app::Deck& deck, const StiffnessOptions& options);

/// `ltca stiffness`: the torque-twist loop (docs/stiffness.md), streamed position by
/// position to JSON and CSV, an SVG of the loop. Returns kExitSuccess when every solve succeeded,
/// kExitNotSucceeded otherwise (the outputs are complete either way).
int RunStiffness(const app::Deck& deck, const StiffnessOptions& options, const Streams& streams);

}  // namespace ltca::cli
