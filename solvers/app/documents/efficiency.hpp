#pragma once
// The documents of friction, power loss and efficiency over the deck's sweep
// (analysis::EfficiencyRunner, docs/efficiency.md): its JSON (whole, or streamed position by
// position), the text, the CSV and the figure. `ltca efficiency`, `ltca report` and the Python
// module all build theirs here.
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "documents/common.hpp"
#include "ltca/analysis/efficiency.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"

namespace ltca::app::documents {

/// The JSON document's members before its positions: case, model, solver, friction (the deck's
/// [friction], bore radius mm), operation (input speed rpm, oil viscosity Pa*s, pressure-viscosity
/// 1/GPa, roughness Ra um) and sweep (cranks deg, positions). Needs the deck's [friction] and
/// [operation].
nlohmann::json EfficiencyHead(const Deck& deck, const SolverOptions& solver);
/// One position of the JSON document: crank (deg), powers (W), efficiencies and coefficients (-),
/// every loaded contact (force N, speeds m/s, film um, pressure MPa; its disc, 1 or 2, when
/// `two_discs`); null for a figure that is not finite, the message of a failed position.
nlohmann::json Json(const analysis::EfficiencyPosition& p, bool two_discs);
/// The JSON document's positions as columns (the numeric keys of Json(p, ...), the same units;
/// pin_coefficient a list per position; NaN where the document has null; the contacts are records,
/// not columns).
Table Columns(const std::vector<analysis::EfficiencyPosition>& positions);
/// A position's loaded contacts as columns, a row per contact (the numeric keys of its records:
/// pin and slice numbered as the document numbers them, N, m/s, W, um, MPa; disc, from 1, for
/// two discs; NaN where the document has null; the shape is text, not a column).
Table ContactColumns(const analysis::EfficiencyPosition& p, bool two_discs);
/// The JSON document's summary: each figure's mean over the successful positions with its least
/// and largest (_min, _max), the sweep's efficiencies, the energy lost per crank revolution (J),
/// the counts, the wall times (s), the warnings and the status.
nlohmann::json Json(const analysis::EfficiencySummary& summary);
/// The whole JSON document from positions kept in memory (the Python module; the command
/// streams): the same members as EfficiencyJsonWriter's.
nlohmann::json Json(const Deck& deck, const SolverOptions& solver, const std::vector<analysis::EfficiencyPosition>& positions,
                    const analysis::EfficiencySummary& summary);

/// The JSON document streamed to `os` as the positions come (bounded memory in positions): the
/// head when built, a position per Add, the summary and the closing brace at Finish.
class EfficiencyJsonWriter {
 public:
  EfficiencyJsonWriter(std::ostream& os, const Deck& deck, const SolverOptions& solver, bool two_discs);
  void Add(const analysis::EfficiencyPosition& p);
  /// spectrum: the efficiency over the deck's [[load_spectrum]] as a "spectrum" block; nullptr: none.
  void Finish(const analysis::EfficiencySummary& summary, const analysis::EfficiencySpectrum* spectrum = nullptr);

 private:
  std::ostream& os_;
  bool two_discs_;
  std::size_t written_ = 0;
};

/// The text: the head (case, model, solver, friction, operation, the table's header), a row of a
/// position (crank deg, loss W, efficiencies, mean coefficient, status), the summary (powers W,
/// efficiencies, friction moment ratio, warnings, wall time s).
std::string EfficiencyTextHead(const Deck& deck, const SolverOptions& solver);
std::string Text(const analysis::EfficiencyPosition& p);
std::string Text(const analysis::EfficiencySummary& summary);
/// The efficiency over a load spectrum: its JSON block (a row per bin, the energy-weighted figures)
/// and its text lines.
nlohmann::json Json(const analysis::EfficiencySpectrum& spectrum);
std::string Text(const analysis::EfficiencySpectrum& spectrum);

/// The CSV: its header line and a row per loaded contact of a position (crank deg, pin from 1,
/// force N, speeds m/s, loss W, film um, pressure MPa; the disc, 1 or 2, as a last column when
/// `two_discs`).
/// stage: the position's losses by source on each row (a reducer stage's deck).
std::string EfficiencyCsvHead(bool two_discs, bool stage = false);
std::string Csv(const analysis::EfficiencyPosition& p, bool two_discs, bool stage = false);

/// Efficiency (with the first-order figure dashed), power loss and the friction coefficient per
/// pin over crank angle, one panel each; failed positions are gaps. The positions' contacts are
/// not used (they may be cleared to keep the positions small).
plots::Figure Figure(const Deck& deck, const SolverOptions& solver, const std::vector<analysis::EfficiencyPosition>& positions,
                     const analysis::EfficiencySummary& summary);

}  // namespace ltca::app::documents
