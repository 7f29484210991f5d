#pragma once
// The documents of the mesh state at one crank (analysis::MeshAt): its JSON, text and figure.
// `ltca mesh`, `ltca report` and the Python module all build theirs here.
#include <string>

#include <nlohmann/json.hpp>

#include "ltca/analysis/mesh.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"

namespace ltca::app::documents {

/// The JSON document: case, crank_deg, model, and a row per pin (and slice) with its angle (deg),
/// clearance (um), arm, radii, points (mm) and normal; a non-finite radius of curvature is null.
nlohmann::json Json(const Deck& deck, const analysis::MeshResult& mesh);
/// The JSON document's pins as columns, a row per pin (the numeric keys of its records: deg, um,
/// mm; the points and the normal as x, y rows; slice and z_mm for a sliced model; NaN where the
/// document has null).
Table Columns(const analysis::MeshResult& mesh);

/// The text: case, crank, model, and the table of a row per pin (and slice).
std::string Text(const Deck& deck, const analysis::MeshResult& mesh);

/// The clearance of every pin around the ring (the least over its slices; on a log scale when it
/// spans more than two decades) and its moment arm: the first disc's mesh.
plots::Figure Figure(const Deck& deck, const analysis::MeshResult& mesh);

}  // namespace ltca::app::documents
