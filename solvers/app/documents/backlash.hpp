#pragma once
// The documents of the unloaded backlash (analysis::Backlash): its JSON, text, CSV and figure,
// built position by position from the analysis's sink and closed with its result. `ltca backlash`,
// `ltca report` and the Python module all build theirs here.
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ltca/analysis/backlash.hpp"
#include "ltca/app/deck.hpp"
#include "documents/common.hpp"
#include "ltca/app/plots.hpp"

namespace ltca::app::documents {

/// The JSON document's members before its positions: case, model, kinematics.
nlohmann::json BacklashHead(const Deck& deck, contact::ContactKinematics kinematics);
/// One position of the JSON document (angles in arcsec, clearances in um; null where it failed).
nlohmann::json Json(const analysis::BacklashPosition& p, bool two_discs);
/// The JSON document's summary.
nlohmann::json Json(const Deck& deck, const analysis::BacklashResult& result);
/// The JSON document's positions as columns (the numeric keys of Json(p, two_discs): arcsec, um;
/// a pin or disc numbered from 1; NaN where the document has null).
Table Columns(const std::vector<analysis::BacklashPosition>& positions, bool two_discs);
/// The whole JSON document from positions kept in memory (the Python module; the command streams).
nlohmann::json Json(const Deck& deck, const std::vector<analysis::BacklashPosition>& positions,
                    const analysis::BacklashResult& result);

/// The JSON document streamed to `os` as the positions come (bounded memory in positions): the
/// head when built, a position per Add, the summary and the closing brace at Finish.
class BacklashJsonWriter {
 public:
  BacklashJsonWriter(std::ostream& os, const Deck& deck, contact::ContactKinematics kinematics, bool two_discs);
  void Add(const analysis::BacklashPosition& p);
  void Finish(const Deck& deck, const analysis::BacklashResult& result);

 private:
  std::ostream& os_;
  bool two_discs_;
  std::size_t written_ = 0;
};

/// The text: the head (case, model, the table's header), a row per position, the summary.
std::string BacklashTextHead(const Deck& deck, const analysis::Stage& stage, contact::ContactKinematics kinematics);
std::string Text(const analysis::BacklashPosition& p, bool two_discs);
std::string Text(const Deck& deck, const analysis::BacklashResult& result);

/// The CSV: its header line and a row per position.
std::string BacklashCsvHead();
std::string Csv(const analysis::BacklashPosition& p);

/// The figure's series, gathered position by position and decimated (DecimatedSeries: at most
/// about 2,000 runs of positions, each its least and largest value), so that the figure and its
/// memory stay bounded in positions.
class BacklashSeries {
 public:
  explicit BacklashSeries(std::size_t positions);
  void Add(const analysis::BacklashPosition& p);
  DecimatedSeries& backlash() { return backlash_; }
  DecimatedSeries& theta_c1() { return c1_; }
  DecimatedSeries& theta_c2() { return c2_; }
  std::int64_t added() const { return added_; }

 private:
  DecimatedSeries backlash_, c1_, c2_;
  std::int64_t added_ = 0;
};
/// Backlash over crank angle with its mean and peak-to-peak (left); the rotations to first contact
/// both ways (right).
plots::Figure Figure(const Deck& deck, BacklashSeries& series, const analysis::BacklashResult& result);

}  // namespace ltca::app::documents
