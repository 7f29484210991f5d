#pragma once
// The documents of the loaded sweep with one solver (app::SolveDeckSweep -> SweepResult): its JSON
// (whole, or streamed position by position), the summary's JSON, the text, the CSVs and the
// figure. `ltca solve`, the default job, `ltca report` and the Python module all build theirs here.
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "documents/common.hpp"
#include "ltca/analysis/spectrum.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"

namespace ltca::app::documents {

/// The solver that ran as JSON: {name, kinematics, torque_tolerance, law, rho_convention}.
nlohmann::json SolverJson(const Deck& deck, const SolverOptions& solver);
/// "solver    name (kinematics, torque tolerance), law / rho convention\n".
std::string SolverLine(const Deck& deck, const SolverOptions& solver);

/// The JSON document's members before its positions: case, model, solver.
nlohmann::json SolveHead(const Deck& deck, const SolverOptions& solver);
/// One position of the JSON document: crank (deg), TE (arcsec, Liu eq. 16), pin forces (N), pin
/// angles (deg), contact stresses (MPa), status; for two discs each disc's torque (N*m) and the first
/// disc's share, for a stage its solution, for the slice model the contact pattern. A failed
/// position's figures are null, its status and message kept.
nlohmann::json Json(const analysis::PositionResult& p);
/// The same position's JSON text, compact, appended to `out` without building the tree: the
/// streamed document's. The members and their order are Dump(Json(p), -1)'s; the numbers are the
/// shortest text that reads back to the same double (AppendJsonNumber), so the text is Dump's but
/// where nlohmann's Grisu2 writes more digits. A reducer stage's solution alone goes through nlohmann.
void AppendJson(std::string& out, const analysis::PositionResult& p);
/// The JSON document's summary: the sweep's figures over its successful positions, the note on
/// failed ones, and for a reducer stage its loads and bearing lives (SweepSummary::bearing_life).
nlohmann::json Json(const Deck& deck, const analysis::SweepSummary& summary);
/// The whole JSON document of a sweep whose positions were kept (the Python module; the command
/// streams): the same document as SolveJsonWriter's (its numbers in nlohmann's text, which reads
/// back to the same doubles).
nlohmann::json Json(const Deck& deck, const SolverOptions& solver, const analysis::SweepResult& sweep);

/// The JSON document streamed to `os` as the positions come (bounded memory in positions), inside
/// an envelope (`before` and `after`: the default job nests it in a larger document). Nothing is
/// written before the first Add or Finish, so a sweep refused before its first position leaves
/// no partial document.
class SolveJsonWriter {
 public:
  SolveJsonWriter(std::ostream& os, const Deck& deck, const SolverOptions& solver, std::string before = {},
                  std::string after = {});
  void Add(const analysis::PositionResult& p);
  /// The summary, then (with a load spectrum) its "spectrum" block.
  void Finish(const Deck& deck, const analysis::SweepSummary& summary, const analysis::SpectrumResult* spectrum = nullptr);

 private:
  void Start();
  std::ostream& os_;
  nlohmann::json head_;
  std::string before_, after_;
  bool started_ = false;
  std::int64_t written_ = 0;
  std::string buffer_;  ///< a position's text, its capacity kept from one to the next
};

/// The "n of m positions failed" lines of the text ("" when none failed).
std::string FailureNote(const analysis::SweepSummary& summary);
/// The text: case, model, solver, status, mean and peak-to-peak TE (arcsec), pins in contact, the
/// discs' shares, the largest pin force (N) and contact stress (MPa), a stage's loads and shortest
/// bearing L10 (h), the wall time.
std::string Text(const Deck& deck, const SolverOptions& solver, const analysis::SweepSummary& summary);

/// The load spectrum (issue 50): per bin its torque (N*m), crank speed (rpm), time share, status,
/// mean and peak-to-peak TE (arcsec), largest pin force (N) and contact stress (MPa) and each
/// bearing's lives (h) at its speed; the lives combined by Miner's rule over the shares; the static
/// figures of the worst bin, each with the bin (1-based) that sets it; the pitting safety over the
/// spectrum; and every figure's verdict against the deck's [allowables] and stress limits
/// (analysis::SpectrumRatingRows).
nlohmann::json SpectrumJson(const Deck& deck, const analysis::SpectrumResult& spectrum);
/// The same as text lines.
std::string SpectrumText(const Deck& deck, const analysis::SpectrumResult& spectrum);

/// The CSV: its header line and a row per position (figures empty where the position failed).
std::string SolveCsvHead(const Deck& deck);
std::string Csv(const analysis::PositionResult& p);
/// The contact pattern's CSV: its header and a row per pin and slice of a position (z in mm from
/// face B at the slice's centre, force N, stress MPa).
std::string PatternCsvHead();
std::string PatternCsv(const Deck& deck, const analysis::PositionResult& p);

/// What the figure needs, kept compactly as the sweep streams by: the TE line (DecimatedSeries:
/// every position up to about 2,000, beyond that the least and largest TE of each run), the pin x
/// crank maps at most about kMapColumns columns (each the largest figure of every pin over its run
/// of positions), and the position of the largest pin force, so that memory and the figure stay
/// bounded in positions.
class SolveSeries {
 public:
  static constexpr std::int64_t kMapColumns = 120;
  explicit SolveSeries(std::int64_t positions);
  void Add(const analysis::PositionResult& p);

 private:
  friend plots::Figure Figure(const Deck& deck, const SolverOptions& solver, SolveSeries& series,
                              const analysis::SweepSummary& summary);
  std::optional<analysis::PositionResult> peak_;
  double f_peak_ = -1.0;
  std::int64_t stride_ = 1, seen_ = 0;
  std::vector<double> map_crank_;  ///< deg, the middle of each column's run
  double map_first_crank_ = NAN;   ///< deg, the open column's first crank
  std::vector<std::vector<double>> map_force_, map_stress_;
  DecimatedSeries te_;
  std::int64_t positions_ = 0;
  double first_crank_ = NAN, last_crank_ = NAN;  ///< deg (the title's range)
};
/// The TE over the sweep with the summary's mean and its peak-to-peak marked, the pin forces and
/// contact stresses at the position of the largest pin force, the pin x crank maps, and for the
/// slice model the contact pattern across the face width there.
plots::Figure Figure(const Deck& deck, const SolverOptions& solver, SolveSeries& series,
                     const analysis::SweepSummary& summary);

}  // namespace ltca::app::documents
