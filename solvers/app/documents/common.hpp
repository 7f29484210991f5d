#pragma once
// What every document of ltca shares (JSON, text and figures built from the analyses' results):
// null for a figure no valid solve produced, the model line, a figure's caption.
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"
#include "ltca/analysis/run.hpp"

namespace ltca::app::documents {

/// JSON text of a document: invalid UTF-8 (a deck path with other bytes) is replaced, never an error.
std::string Dump(const nlohmann::json& doc, int indent = 2);
/// NaN or infinite: JSON null.
nlohmann::json FiniteOrNull(double v);
/// A figure in text, or "n/a" when it is not finite (no valid solve produced it).
std::string FormatOrNa(double v, int decimals);

/// A list of records of a document as columns, for a front-end's arrays (Python's Result.tables):
/// a column per numeric key of the JSON records, under the key's name (its unit in it), in name
/// order; a value per record, or a list of values per record (rows x values). Not finite: NaN (the
/// document's null). Built from the result, never from the document.
struct Table {
  struct Column {
    bool lists = false;                      ///< a list of values per record
    std::vector<double> values;              ///< !lists: a value per record
    std::vector<std::vector<double>> rows;   ///< lists: a list per record
  };
  std::map<std::string, Column> columns;
  /// Appends the record's value to the column `name`.
  void Add(const std::string& name, double value);
  /// Appends the record's list of values to the column `name`.
  void Add(const std::string& name, const std::vector<double>& values);
};

/// Appends the JSON text of `v` exactly as `Dump` writes a double (null when not finite): the
/// shortest digits that read back to the same double (std::to_chars, C++17 [charconv]: round trip
/// by the standard), laid out as nlohmann::json's serializer does (a point and a digit always,
/// decimal notation for decimal exponents -4 < n <= 15, else d.ddde+XX with two exponent digits
/// at least). Where nlohmann's Grisu2 does not find the shortest digits (rare), the text differs
/// and both read back to the same double.
void AppendJsonNumber(std::string& out, double v);
/// Appends the JSON text of an integer.
void AppendJsonNumber(std::string& out, std::int64_t v);
/// Appends the JSON string of `s` exactly as `Dump` writes it (escapes; invalid UTF-8 replaced).
void AppendJsonString(std::string& out, std::string_view s);
/// The shortest text that reads back to the same double (std::to_chars), "" when not finite:
/// a CSV field.
std::string ShortestOrEmpty(double v);

/// Indents every line but the first by two spaces (a document nested one level).
std::string Nested(const std::string& text);
/// The text of a JSON object (Dump, indent 2) without its closing brace, so that a streamed
/// document can go on with more members (positions, then the summary).
std::string OpenObject(const nlohmann::json& header);

/// A run's record in a summary: positions, succeeded_positions, failed_positions, wall_seconds,
/// status and, when something failed, first_failure.
void AddRunRecord(nlohmann::json& summary, const analysis::RunRecord& record);

/// {title, source, deck}: the case a document is of, and `overrides` (OverrideArguments) when the
/// deck was read with any.
nlohmann::json CaseJson(const Deck& deck);
/// The overrides the deck was read with, as the command line takes them: "--set section.key=value",
/// "--unset section[.key]"; empty for a deck read as written.
std::vector<std::string> OverrideArguments(const Deck& deck);
/// The case's title for a figure or a text: a deck changed by --set or --unset is not the deck its
/// title names, so the overrides follow the title, in full when they fit in `room` characters, else
/// counted ("with 3 overrides"; the caption and the text list them).
std::string CaseTitle(const Deck& deck, std::size_t room = 60);
/// The text's "case" line(s): "case      <title>\n", then "overrides --set ... --unset ...\n" when
/// the deck was read with any.
std::string CaseLines(const Deck& deck, int width = 10);
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

/// A figure's series of a run too long to keep whole, kept as it streams by: the points,
/// numbered 0, 1, ... in the order they come, fall into runs of `stride` consecutive numbers, at
/// most `buckets` runs for the points expected (stride 1, every point kept, when there are no more
/// points than buckets); a run keeps its point of least value, its point of largest value and its
/// first point without a value (NaN: a failed position, a gap in a line), in their order. So the
/// figure and its memory stay bounded whatever the run; a monotone series (a best so far) keeps
/// the first and last point of each run. Used by `solve --svg` (the TE line),
/// `optimise --svg` (the convergence, the path of the evaluations) and the backlash figure.
class DecimatedSeries {
 public:
  static constexpr std::int64_t kBuckets = 2000;
  /// `expected`: how many points will come (more only make more runs of the same stride).
  explicit DecimatedSeries(std::int64_t expected, std::int64_t buckets = kBuckets);
  /// Point number `at` (increasing from call to call; numbers may be skipped) at (x, y), judged by
  /// `value` (not finite: a point without a value).
  void Add(std::int64_t at, double x, double y, double value);
  void Add(std::int64_t at, double x, double y) { Add(at, x, y, y); }
  /// The points kept, in their order (the run still open included).
  const std::vector<double>& x();
  const std::vector<double>& y();
  std::int64_t stride() const { return stride_; }

 private:
  struct Point {
    std::int64_t at = -1;
    double x = NAN, y = NAN, value = NAN;
  };
  void Close();
  std::int64_t stride_ = 1, run_ = -1;
  Point least_, largest_, gap_;
  std::vector<double> x_, y_;
};

}  // namespace ltca::app::documents
