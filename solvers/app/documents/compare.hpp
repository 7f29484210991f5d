#pragma once
// The documents of a comparison of solvers on one deck (analysis::CompareResult): its JSON, the
// text and the figure. `ltca compare` and the Python module build theirs here. Units: TE arcsec,
// force N, stress MPa, time s, crank deg.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "documents/common.hpp"
#include "ltca/analysis/compare.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"

namespace ltca::app::documents {

/// The JSON document: case, model, the reference solver, a member per solver (status, counts,
/// TE, pins, force, stress, wall time, the largest differences from the reference, null where
/// nothing was compared, warnings) and the skipped solvers with their reasons.
nlohmann::json Json(const Deck& deck, const analysis::CompareResult& result);
/// The JSON document's solvers as columns, a row per solver (the numeric keys of its records: the
/// counts, arcsec, N, MPa, s; NaN where the document has null, first_warning only while no
/// solver warned, as a column of NaN, as the document's nulls were).
Table Columns(const analysis::CompareResult& result);
/// The text: the case, the model, what ran, the skipped solvers, a row per solver, its warnings
/// and a note when a position failed.
std::string Text(const Deck& deck, const analysis::CompareResult& result);

/// Every solver's TE (arcsec) over crank angle (deg) and, for several, its difference from the
/// reference: te[r][i] is solver r's at crank_deg[i], NaN where it failed (a gap).
plots::Figure Figure(const Deck& deck, const analysis::CompareResult& result, const std::vector<double>& crank_deg,
                     const std::vector<std::vector<double>>& te);

}  // namespace ltca::app::documents
