#pragma once
#include <string>

#include "ltca/app/deck.hpp"
#include "output.hpp"

namespace ltca::cli {

/// The command line of `ltca efficiency` (docs/efficiency.md).
struct EfficiencyOptions {
  std::string solver;      ///< "" = the deck's [solver] name
  std::string kinematics;  ///< "" = the deck's
  std::string json_path, csv_path, svg_path;
};

/// `ltca efficiency`: friction, power loss and efficiency over the deck's sweep, streamed position
/// by position to JSON and CSV (one row per loaded contact), an SVG of efficiency and power loss
/// over crank angle and the friction coefficient per pin. Returns kExitSuccess when every
/// position succeeded, kExitNotSucceeded otherwise.
int RunEfficiency(const app::Deck& deck, const EfficiencyOptions& options, const Streams& streams);

}  // namespace ltca::cli
