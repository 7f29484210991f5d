#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "ltca/app/deck.hpp"
#include "output.hpp"

namespace ltca::cli {

struct CompareOptions {
  std::vector<std::string> solvers;  ///< empty: every registered solver
  std::string kinematics;            ///< "" = the deck's
  std::string json_path;
  std::string svg_path;  ///< every solver's TE overlaid, and the differences from the first
};

/// `ltca compare`: several solvers on the same sweep, side by side, with their largest
/// differences from the first in TE, pin force and contact count, and their times. The solvers
/// run in lockstep, a position at a time, so memory does not grow with the sweep. Differences
/// are taken at the positions where both succeeded. Returns kExitSuccess when every position of
/// every solver succeeded, kExitNotSucceeded otherwise.
int RunCompare(const app::Deck& deck, const CompareOptions& options, const Streams& streams);

}  // namespace ltca::cli
