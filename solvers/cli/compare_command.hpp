#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "ltca/solvers/deck.hpp"

namespace ltca::cli {

struct CompareOptions {
  std::vector<std::string> solvers;  ///< empty: every registered solver
  std::string kinematics;            ///< "" = the deck's
  std::string json_path;
};

/// `ltca compare`: several solvers on the same sweep, side by side, with their largest
/// differences from the first in TE, pin force and contact count, and their times.
void RunCompare(const solvers::Deck& deck, const CompareOptions& options, std::ostream& out);

}  // namespace ltca::cli
