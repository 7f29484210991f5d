#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ltca/app/deck.hpp"
#include "output.hpp"

namespace ltca::cli {

struct ReportOptions {
  std::string out_dir;     ///< the folder of index.html (created when missing)
  std::string solver;      ///< "" = the deck's [solver] name
  std::string kinematics;  ///< "" = the deck's [solver] kinematics; else every analysis of the page runs with it
  /// The tolerance study's: [tolerances] samples unless given, threads (0: every
  /// hardware thread), and whether to skip the extreme-value runs.
  std::optional<std::int64_t> samples;
  int threads = 0;
  bool no_worst_case = false;
  /// Replace DIR even when it holds files that no `ltca report` wrote (no marker file).
  bool force = false;
};

/// The file in a folder that `ltca report` built; a folder with it may be replaced by the next report.
inline constexpr const char* kReportMarker = ".ltca-report";

/// `ltca report DECK -o DIR`: one static HTML page, DIR/index.html, that a browser
/// opens from disk with nothing fetched: the case, the model and solver that ran, the geometry
/// table, the summary tables of the loaded sweep, the unloaded backlash and the torque-twist loop
/// at crank 0, and the figures (geometry drawing, TE, load distribution and maps, backlash, mesh
/// clearances, the loop) inlined as SVG. The documents the page is built from (geometry.json,
/// solve.json, backlash.json, mesh.json, stiffness.json) are left beside it. Returns
/// kExitNotSucceeded when a solve failed, else kExitSuccess.
int RunReport(const app::Deck& deck, const ReportOptions& options, const Streams& streams);

/// The page's sections in order, (anchor, title) each: the fixed ones, then one for every generic
/// analysis of the table (documents::Analyses()).
std::vector<std::pair<std::string, std::string>> ReportSectionTitles();

}  // namespace ltca::cli
