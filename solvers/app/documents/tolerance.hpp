#pragma once
// The documents of a tolerance study (analysis::RunToleranceStudy, docs/tolerance.md): its JSON,
// the text, the per-sample CSV and the histograms. `ltca tolerance`, `ltca report` and the Python
// module all build theirs here.
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "documents/common.hpp"
#include "ltca/analysis/tolerance.hpp"
#include "ltca/analysis/tolerance_run.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"

namespace ltca::app::documents {

/// The deck's [tolerances] with a front-end's overrides (samples, seed, lost motion when true).
/// Throws std::invalid_argument naming the missing section when the deck has none.
analysis::ToleranceSettings ToleranceSettingsFor(const Deck& deck, std::optional<std::int64_t> samples,
                                                 std::optional<std::uint64_t> seed, bool lost_motion);

/// The text before the samples run: case, model, solver, the samples (count, first index, seed,
/// threads, ranks), what a sample runs (sweep in deg crank, lost motion's fraction of T in %),
/// every distribution, the per-sample profile deviation (zone um) and the study's notes.
std::string ToleranceTextHead(const Deck& deck, const SolverOptions& solver, const analysis::ToleranceStudy& study,
                              std::int64_t first, int threads, int ranks);
/// The estimate of the whole run from its first samples: `seconds` (s) estimated for this rank's
/// `count` samples on `threads` threads, from the first `done` (the rate of those after the
/// warm-up, two a thread).
std::string ToleranceEstimateText(double seconds, std::int64_t done, std::int64_t count, int threads, bool several_ranks,
                                  bool worst_case_follows);
/// The text after the run: each figure's mean, std and percentiles (with the worst-case corners),
/// the worst case's runs, the chains (um), the limits' pass counts and fractions (%), the
/// sensitivity ranking, what did not succeed and the wall times (s).
std::string Text(const analysis::ToleranceStudy& study, const analysis::ToleranceResult& result);

/// The CSV: its header (sample, status, every input column, every figure the study runs,
/// message) and a sample's row (inputs in their key's unit, figures in theirs, every bit: 17
/// significant digits, empty when not finite).
std::string ToleranceCsvHead(const analysis::ToleranceStudy& study);
std::string Csv(const analysis::ToleranceStudy& study, const analysis::ToleranceSample& sample);

/// The JSON document: case, model, solver, tolerances (the plan and the distributions), notes and
/// the summary (statistics per figure, limits with their pass fractions, sensitivity, chains in
/// um, the worst case, wall times in s); null for a figure no valid solve produced.
nlohmann::json Json(const Deck& deck, const SolverOptions& solver, const analysis::ToleranceStudy& study,
                    const analysis::ToleranceResult& result);
/// The JSON document's lists of records as columns (NaN where the document has null): its
/// [tolerances] distributions (mean, std, worst_case_half_width in the key's unit; sigma and
/// truncated_at when a distribution is normal, tolerance when one gives it) and its summary's
/// limits (min, max, passed, fraction).
Table DistributionColumns(const analysis::ToleranceSettings& settings);
Table LimitColumns(const analysis::ToleranceSummary& summary);
/// A figure's sensitivity ranking as columns, a row per key (src, share, columns, noise_floor).
Table RankingColumns(const analysis::FigureSensitivity& sensitivity);

/// Histograms of the figures, one panel each, with p5 / p50 / p95, the limits and the worst-case
/// corners.
plots::Figure Figure(const Deck& deck, const analysis::ToleranceStudy& study, const analysis::ToleranceResult& result);

}  // namespace ltca::app::documents
