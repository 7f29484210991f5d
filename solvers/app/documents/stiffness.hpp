#pragma once
// The documents of the torque-twist loop (analysis::StiffnessResult, docs/stiffness.md): its JSON
// (whole, or streamed position by position), the text, the CSV and the figure. `ltca stiffness`,
// `ltca report` and the Python module all build theirs here. Units: torque N*m, twist arcmin,
// rigidity N*m/arcmin, hysteresis J per cycle, crank deg.
#include <cstddef>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "documents/common.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"

namespace ltca::app::documents {

/// A rigidity in the documents' unit: N*mm/rad to N*m/arcmin.
double RigidityNmPerArcmin(double nmm_per_rad);

/// What the figures cover: the mesh alone or the reducer stage ([output]), and the pins' seats
/// when the deck seats them.
std::string StiffnessScope(const Deck& deck);
/// The rigidity's definition in words: the secant between 50 % and 100 % of T, or the tangent at
/// settings.tangent_torque.
std::string RigidityDefinition(const analysis::StiffnessSettings& settings);

/// The JSON document's members before its positions: case, model, solver and stiffness (scope,
/// rated torque N*m, steps, definition, lost-motion fraction, the tangent torque N*m, the sweep or
/// the one crank deg). `rated`: T, N*mm.
nlohmann::json StiffnessHead(const Deck& deck, const SolverOptions& solver, const analysis::StiffnessSettings& settings,
                             double rated);
/// One position of the JSON document: crank (deg), rigidities, lost motion, backlash, branch
/// difference, hysteresis, status, solve counts, the curve; the stick ends with friction, the
/// first disc's shares for two discs, the compliance budget for a stage; null for a figure that is
/// not finite, the message of a failed position.
nlohmann::json Json(const analysis::StiffnessPosition& p);
/// The JSON document's positions as columns (the numeric keys of Json(p): N*m/arcmin, arcmin, J,
/// N*m; a friction's stick ends and two discs' shares when some position has them; NaN where the
/// document has null; the curve and the compliance budget are records, not columns).
Table Columns(const std::vector<analysis::StiffnessPosition>& positions);
/// A loop's curve as columns, a row per point (torque_nm, twist_arcmin; with `lo` and `hi`, the
/// sweep's least and largest twist at each point, twist_arcmin_min and _max; NaN where the
/// document has null; the branch is text, not a column).
Table Columns(const std::vector<analysis::CurvePoint>& curve, const std::vector<double>* lo = nullptr,
              const std::vector<double>* hi = nullptr);
/// The summary's curve as columns (the mean loop, with its least and largest twist for a sweep).
Table SummaryCurveColumns(const analysis::StiffnessResult& result);
/// The JSON document's summary: each figure's mean (with _min, _max over a sweep), the mean loop
/// (with its range over a sweep), the hysteresis and the friction note, the run record and the
/// solve count.
nlohmann::json Json(const analysis::StiffnessResult& result);
/// The whole JSON document from a result that kept its positions (the Python module; the command
/// streams): the same members as StiffnessJsonWriter's.
nlohmann::json Json(const Deck& deck, const SolverOptions& solver, const analysis::StiffnessResult& result);

/// The JSON document streamed to `os` as the positions come (bounded memory in positions): the
/// head when built, a position per Add, the summary and the closing brace at Finish.
class StiffnessJsonWriter {
 public:
  StiffnessJsonWriter(std::ostream& os, const Deck& deck, const SolverOptions& solver,
                      const analysis::StiffnessSettings& settings, double rated);
  void Add(const analysis::StiffnessPosition& p);
  void Finish(const analysis::StiffnessResult& result);

 private:
  std::ostream& os_;
  std::size_t written_ = 0;
};

/// The text: the head (case, model, solver, the loop over `positions` cranks, the definition, the
/// scope, the table's header), a row of a position (crank deg, rigidity, lost motion, backlash,
/// status), the summary (the spreads, the shares, the budget, the hysteresis, the wall time s).
std::string StiffnessTextHead(const Deck& deck, const SolverOptions& solver, const analysis::StiffnessSettings& settings,
                              double rated, std::size_t positions);
std::string Text(const analysis::StiffnessPosition& p);
std::string Text(const analysis::StiffnessResult& result);

/// The CSV: its header line and a row per curve point of a position (crank deg, branch, torque
/// N*m, twist arcmin, the solve's status; an unsolved twist empty).
std::string StiffnessCsvHead();
std::string Csv(const analysis::StiffnessPosition& p);

/// The loop as a catalogue draws it: twist (arcmin) across, torque (N*m) up, the mean loop (and
/// over a sweep its range) with the backlash, rigidity and lost motion drawn on it. The caption
/// names the deck's [stiffness] definition and lost-motion fraction.
plots::Figure Figure(const Deck& deck, const SolverOptions& solver, const analysis::StiffnessResult& result);

}  // namespace ltca::app::documents
