#pragma once
#include <ostream>
#include <string>

#include "ltca/solvers/deck.hpp"
#include "ltca/solvers/sweep.hpp"

namespace ltca::cli {

struct SolveOptions {
  std::string solver;      ///< "" = the deck's [solver] name
  std::string kinematics;  ///< "" = the deck's
  std::string json_path, csv_path, svg_path;
};

/// `ltca solve`: the loaded sweep with one solver.
void RunSolve(const solvers::Deck& deck, const SolveOptions& options, std::ostream& out);

}  // namespace ltca::cli
