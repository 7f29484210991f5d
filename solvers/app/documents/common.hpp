#pragma once
// What every document of ltca shares (JSON, text and figures built from the analyses' results):
// null for a figure no valid solve produced, the model line, a figure's caption.
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"

namespace ltca::app::documents {

/// JSON text of a document: invalid UTF-8 (a deck path with other bytes) is replaced, never an error.
std::string Dump(const nlohmann::json& doc, int indent = 2);
/// NaN or infinite: JSON null.
nlohmann::json FiniteOrNull(double v);
/// A figure in text, or "n/a" when it is not finite (no valid solve produced it).
std::string FormatOrNa(double v, int decimals);

/// {title, source, deck}: the case a document is of.
nlohmann::json CaseJson(const Deck& deck);
/// The model that ran: {name, slices, surface}, with a note when a given slice count was not used,
/// the discs, the stage, the pin seat and the tip relief where the deck has them.
nlohmann::json ModelJson(const Deck::ModelInfo& model);
/// "model     slices (20 slices of 1.5 mm over the 30 mm face width, analytic surface)\n", with
/// the note on a line of its own.
std::string ModelLine(const Deck& deck);

/// A figure's caption: the deck and its source on one line, then `ran` (the model and solver),
/// then the version of ltca.
std::string FigureCaption(const Deck& deck, const std::string& ran);
/// Marks the mean, the largest and the smallest of the finite values on a panel (horizontal lines
/// labelled with the figure and the unit, the peak-to-peak named on the largest) and sets the y range
/// to leave room for the labels. Does nothing when no value is finite. `mean`, when finite, is the
/// mean to mark (the whole sweep's, where the values are its drawn extremes).
void MarkMeanAndPeakToPeak(plots::Panel& panel, const std::vector<double>& values, const std::string& unit,
                           double mean = NAN);

}  // namespace ltca::app::documents
