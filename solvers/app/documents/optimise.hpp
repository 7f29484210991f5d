#pragma once
// The documents of a design optimisation (analysis::RunOptimisation, docs/optimise.md): each
// evaluation's JSON and CSV row, the JSON document (streamed: its history after the summary), the
// text, the convergence figure (with the map and the front) and the best design as a deck.
// `ltca optimise`, `ltca report` and the Python module all build theirs here.
#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "documents/common.hpp"
#include "ltca/analysis/optimise.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"

namespace ltca::app::documents {

/// The deck's [optimise] with a front-end's budget (evaluations when given). Throws
/// std::invalid_argument naming the missing section when the deck has none.
analysis::OptimiseSettings OptimiseSettingsFor(const Deck& deck, std::optional<int> evaluations);

/// How a robust design's figures are taken: "p95 bounded at confidence 0.9 (upper: the 64th
/// smallest, ...)" or "p95 (point estimate)".
std::string RobustRule(const analysis::OptimiseSettings& settings);

/// One evaluation: index, phase, variables by key (their keys' units), objective, violation,
/// feasible, status, message, every figure (null where not finite) and, robust, samples_failed.
nlohmann::json Json(const analysis::OptimiseSettings& settings, const analysis::DesignEvaluation& e);
/// The JSON document's history as columns, a row per evaluation (its numeric keys: index,
/// objective, violation, samples_failed for a robust search; NaN where the document has null; the
/// variables and figures are records, the --csv columns have them).
Table Columns(const analysis::OptimiseSettings& settings, const std::vector<analysis::DesignEvaluation>& history);
/// The JSON document's other lists of records as columns (NaN where the document has null): the
/// settings' variables (lower, upper, in the key's unit) and constraints (min, max, in the
/// figure's) and the search's phases (evaluations).
Table VariableColumns(const analysis::OptimiseSettings& settings);
Table ConstraintColumns(const analysis::OptimiseSettings& settings);
Table PhaseColumns(const analysis::OptimiseResult& search);
/// The JSON document without its arrays: case, model, solver, settings (with threads and ranks)
/// and the summary (status, counts, phases, the best evaluation, wall time s).
nlohmann::json OptimiseJsonHead(const Deck& deck, const SolverOptions& solver, const analysis::OptimiseSettings& settings,
                                const analysis::OptimiseRun& run);
/// The JSON document streamed: the head, then "history" (its items written by `history`, each
/// item preceded by its separator as HistoryItem writes them), the map and the front.
void WriteOptimiseJson(std::ostream& os, const nlohmann::json& head, const std::function<void(std::ostream&)>& history,
                       const analysis::OptimiseSettings& settings, const analysis::OptimiseRun& run);
/// An item of the streamed history: its separator and the evaluation's JSON on one line.
std::string HistoryItem(const analysis::OptimiseSettings& settings, const analysis::DesignEvaluation& e);
/// The whole document from a history kept in memory (the Python module; the command streams).
nlohmann::json Json(const Deck& deck, const SolverOptions& solver, const analysis::OptimiseSettings& settings,
                    const analysis::OptimiseRun& run, const std::vector<analysis::DesignEvaluation>& history);

/// The text before the search: case, model, solver, objective, variables, constraints, method.
std::string OptimiseTextHead(const Deck& deck, const SolverOptions& solver, const analysis::OptimiseSettings& settings, int threads,
                             int ranks);
/// The text after it: the phases, the counts, the best design (or none) and the front.
std::string Text(const analysis::OptimiseSettings& settings, const analysis::OptimiseRun& run);

/// The CSV: its header (index, phase, the variables, objective, violation, feasible, status, every
/// figure, message) and an evaluation's row (every bit: 17 significant digits, empty when not
/// finite; the message quoted, its double quotes as single ones).
std::string OptimiseCsvHead(const analysis::OptimiseSettings& settings);
std::string Csv(const analysis::DesignEvaluation& e);

/// The figure's series kept as the evaluations stream by (decimated: DecimatedSeries): the
/// feasible and infeasible objectives, the best feasible so far and, with a map, the path over the
/// first two variables.
class OptimiseSeries {
 public:
  OptimiseSeries(const analysis::OptimiseSettings& settings, bool path);
  void Add(const analysis::DesignEvaluation& e);

 private:
  friend plots::Figure Figure(const Deck& deck, const analysis::OptimiseSettings& settings, const analysis::OptimiseRun& run,
                              OptimiseSeries& series);
  bool maximise_, path_;
  DecimatedSeries feasible_, infeasible_, best_, drawn_path_;
  double best_so_far_;
};
/// The convergence (every successful evaluation's objective, the best feasible so far), with the
/// objective's map over the two variables and the Pareto front when they ran.
plots::Figure Figure(const Deck& deck, const analysis::OptimiseSettings& settings, const analysis::OptimiseRun& run,
                     OptimiseSeries& series);

/// The best design as a deck: the deck's own text with the optimum of every variable (also where
/// [second_disc] gives its own value of that key), without [optimise], under a header naming the
/// search. Throws std::invalid_argument when the deck's text does not take the edit; needs a best.
std::string BestDesignDeck(const Deck& deck, const analysis::OptimiseSettings& settings, const analysis::OptimiseRun& run);

}  // namespace ltca::app::documents
