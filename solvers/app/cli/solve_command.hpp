#pragma once
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "ltca/app/deck.hpp"
#include "ltca/analysis/sweep.hpp"
#include "documents/solve.hpp"
#include "output.hpp"

namespace ltca::cli {

struct SolveOptions {
  std::string solver;      ///< "" = the deck's [solver] name
  std::string kinematics;  ///< "" = the deck's
  std::string json_path, csv_path, svg_path;
  std::string pattern_csv_path;  ///< the contact pattern: a row per position, pin and slice
};

/// Text written around the solve JSON document (the default job nests it in a larger one).
struct JsonEnvelope {
  std::string before, after;
};

/// `ltca solve`: the loaded sweep with one solver, streamed: every position is written to the
/// JSON and CSV outputs as it is solved and not kept. Returns kExitSuccess when every position
/// succeeded, kExitNotSucceeded otherwise (the outputs are complete either way).
int RunSolve(const app::Deck& deck, const SolveOptions& options, const Streams& streams,
             const JsonEnvelope& envelope = {});

// The commands' --kinematics and --solver over the deck's, and the solver's JSON and text line
// (the solve's documents), shared by every command that solves.
using app::DeckFor;
using app::SolverFor;
using app::documents::SolverJson;
using app::documents::SolverLine;

}  // namespace ltca::cli
