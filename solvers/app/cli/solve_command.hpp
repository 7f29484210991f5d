#pragma once
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "ltca/app/deck.hpp"
#include "ltca/analysis/sweep.hpp"
#include "output.hpp"

namespace ltca::cli {

struct SolveOptions {
  std::string solver;      ///< "" = the deck's [solver] name
  std::string kinematics;  ///< "" = the deck's
  std::string json_path, csv_path, svg_path;
  std::string pattern_csv_path;  ///< the contact pattern: a row per position, pin and slice (issue 11)
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

/// The document `ltca solve --json` writes, of a sweep whose positions were kept (the Python
/// module, issue 30): built by the same functions, so the two agree to the last digit.
nlohmann::json SolveJson(const app::Deck& deck, const solvers::SolverOptions& solver, const app::SweepResult& sweep);
/// Its summary alone (the streamed writer's and SolveJson's).
nlohmann::json SolveSummaryJson(const app::Deck& deck, const app::SweepSummary& summary);

/// The deck with the command line's --kinematics ("" keeps the deck's [solver] kinematics).
app::Deck DeckFor(const app::Deck& deck, const std::string& kinematics);
/// The deck's [solver] with the command line's --solver ("" keeps the deck's).
solvers::SolverOptions SolverFor(const app::Deck& deck, const std::string& name);
/// The solver that ran as JSON: {name, kinematics, torque_tolerance, law, rho_convention}.
nlohmann::json SolverJson(const app::Deck& deck, const solvers::SolverOptions& solver);
/// "solver    name (kinematics, torque tolerance), law / rho convention\n".
std::string SolverLine(const app::Deck& deck, const solvers::SolverOptions& solver);
/// The deck as JSON: {title, source, deck}.
nlohmann::json CaseJson(const app::Deck& deck);

/// The "n of m positions failed" lines of the text summary ("" when none failed).
std::string FailureNote(const app::SweepSummary& summary);

}  // namespace ltca::cli
