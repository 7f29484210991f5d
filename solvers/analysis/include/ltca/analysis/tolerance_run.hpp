#pragma once
// A tolerance study run whole (docs/tolerance.md): the samples of a run plan, distributed over
// threads and ranks, their summary, the extreme-value worst case, the assembly chains, the pass
// fractions against the limits, what failed and the wall times, in one result. `ltca tolerance`,
// `ltca report` and the Python module run it and build their documents from the result.
//
// Sample i depends on (seed, i) only (ToleranceStudy::Draw), so the plan's split over threads and
// ranks changes no number: the result and the samples handed to the sink are the same bit for
// bit. Ranks are an interface (SampleRanks): MPI stays a front-end detail.
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "ltca/analysis/sample_ranks.hpp"
#include "ltca/analysis/tolerance.hpp"

namespace ltca::analysis {

/// The threads a run uses: `requested` when it is 1 .. kMaxToleranceThreads, every hardware thread
/// for 0 (at least 1, at most kMaxToleranceThreads). The one rule of `ltca tolerance`, `ltca
/// optimise`, the report and Python. Throws std::invalid_argument naming --threads otherwise.
int ResolveThreads(int requested);

/// The phases of a run, as its progress reports them.
enum class TolerancePhase {
  kSamples,    ///< the Monte Carlo samples of this rank
  kWorstCase,  ///< the extreme-value runs (rank 0)
};

/// How far a run is, told from the calling thread. Every member does nothing by default.
class ToleranceProgress {
 public:
  virtual ~ToleranceProgress() = default;
  /// A phase begins: `total` is this rank's samples, or the most worst-case runs
  /// (1 + 2 x input columns + 2 x figures).
  virtual void Start(TolerancePhase /*phase*/, std::int64_t /*total*/) {}
  /// `done` of the phase's total so far.
  virtual void Update(TolerancePhase /*phase*/, std::int64_t /*done*/) {}
  /// The phase ended.
  virtual void Finish(TolerancePhase /*phase*/) {}
  /// Rank 0, when more samples follow: `seconds` (s), the estimate of this rank's `count` samples
  /// from the first `done` (RunTolerance: the time so far and the rate after the warm-up).
  virtual void Estimate(double /*seconds*/, std::int64_t /*done*/, std::int64_t /*count*/) {}
};

/// What to run and how: the samples settings().samples from `first`, on `threads` threads of
/// each rank, the worst case unless skipped.
struct ToleranceRunPlan {
  std::int64_t first = 0;       ///< index of the first sample (>= 0)
  int threads = 1;              ///< per rank, 1 .. kMaxToleranceThreads (ResolveThreads)
  SampleRanks* ranks = nullptr;  ///< nullptr: this process alone
  bool worst_case = true;       ///< also the extreme-value runs (rank 0)
  /// Rank 0: every sample, inputs included, in sample order as it is computed or gathered (the
  /// per-sample CSV streams from here; the result keeps figures and status only).
  std::function<void(const ToleranceSample&)> sink;
  ToleranceProgress* progress = nullptr;  ///< nullptr: nothing told
  /// Throws std::invalid_argument naming --first when the last sample index (first + samples - 1)
  /// would pass the largest std::int64_t.
  void Validate(const ToleranceSettings& settings) const;
};

/// An assembly chain's closing link (the clearance, um): by the extreme-value method and by Monte
/// Carlo over the study's sample count and seed (ChainMonteCarlo, chain number its index).
struct ChainResult {
  std::string name;
  ClosingLink extreme_value;
  FigureStats monte_carlo;
};

/// A study run whole. On a rank other than 0 only the plan's members and rank_succeeded are set
/// (rank 0 holds the samples, the summary and the rest).
struct ToleranceResult {
  std::int64_t first = 0;    ///< index of the first sample
  std::int64_t samples = 0;  ///< samples asked for (every rank's)
  int threads = 1;           ///< threads of each rank
  int ranks = 1;             ///< ranks that ran the samples
  int rank = 0;              ///< this process's rank
  SampleTable table;         ///< every sample's figures and status, in sample order (rank 0)
  ToleranceSummary summary;  ///< percentiles, limits and pass fractions, sensitivity (rank 0)
  std::optional<WorstCaseResult> worst_case;  ///< unless the plan skipped it (rank 0)
  /// Per figure: the samples beyond the worst-case corners (zero without a worst case).
  std::array<CornerExceedance, kToleranceFigureCount> beyond{};
  std::vector<ChainResult> chains;  ///< in the order of settings().chains
  double sample_seconds = std::numeric_limits<double>::quiet_NaN();      ///< wall time of the samples, s
  double worst_case_seconds = std::numeric_limits<double>::quiet_NaN();  ///< wall time of the worst case, s
  bool rank_succeeded = true;  ///< every sample of this rank succeeded

  /// Every sample succeeded (on a rank other than 0: every sample of this rank).
  bool all_succeeded() const { return rank == 0 ? summary.succeeded == summary.samples : rank_succeeded; }
};

/// Runs the study by the plan (validated first). Throws std::runtime_error when the gathered
/// samples are not all there.
ToleranceResult RunToleranceStudy(const ToleranceStudy& study, const ToleranceRunPlan& plan);

}  // namespace ltca::analysis
