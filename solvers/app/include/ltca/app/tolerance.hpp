#pragma once
// Tolerance analysis (issue 15, docs/tolerance.md): a seeded Monte Carlo over the manufacturing
// and assembly errors of [tolerances], and the extreme-value (worst-case) counterpart.
//
// Every sample is a pair as made: the deck's [errors] and [modification] values plus the draws of
// [tolerances] (per-pin keys drawn independently for every pin). Its random numbers come from the
// counter-based stream of geometry/counter_rng.hpp: draw (key k, pin j) of sample i is a pure
// function of (seed, k, j, i), so any split of the samples over threads or MPI ranks gives the
// same samples bit for bit. Each sample runs, on its own runners (no state shared between
// samples):
//  - the unloaded TCA over the deck's sweep: mean and peak-to-peak backlash (Liu 2021 eq. 17);
//  - the loaded TCA over the sweep (ltca solve's summary): mean and peak-to-peak TE, the largest
//    contact stress and pin force, the pins in contact;
//  - when asked ([tolerances] lost_motion = true), lost motion at +-f T (issue 13, ltca stiffness).
// MPI stays out of this header (solvers/app/cli/tolerance_mpi.cpp).
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "ltca/app/deck.hpp"

namespace ltca::app {

/// The figures of a sample, in the order of ToleranceSettings::FigureNames(), in the units their
/// names carry (arcsec, MPa, N, arcmin; contacts as counts).
inline constexpr std::size_t kToleranceFigureCount = 9;
using ToleranceFigures = std::array<double, kToleranceFigureCount>;
enum ToleranceFigure : std::size_t {
  kMeanBacklashArcsec, kPpBacklashArcsec, kMeanTeArcsec, kPpTeArcsec, kMaxContactStressMpa, kMaxPinForceN,
  kContactsMin, kContactsMax, kLostMotionArcmin
};

/// One input column of the study: a scalar key, or one pin of a per-pin key.
struct ToleranceInput {
  std::string name;          ///< "pin_circle_deviation_mm" or "pin_radius_deviations_mm[7]" (pin 7, 1-based)
  std::size_t distribution;  ///< index into ToleranceSettings::distributions
  int pin = -1;              ///< 0-based pin of a per-pin key, -1 for a scalar key
};

struct ToleranceSample {
  std::int64_t index = 0;
  /// Drawn deviation of every input column from the deck's value (the distribution's mean
  /// included), in the key's unit.
  std::vector<double> inputs;
  ToleranceFigures figures;  ///< NaN: no valid solve produced the figure
  /// "success": every solve succeeded; "failed": some position did not succeed (its figures are
  /// over the successful positions, as `ltca solve` reports them); "rejected": the pair as drawn
  /// interferes or cannot be built (no figure).
  std::string status = "success";
  std::string message;  ///< why, when not success
  ToleranceSample() { figures.fill(std::numeric_limits<double>::quiet_NaN()); }
};

/// The Monte Carlo: immutable once built, Run() may be called from any number of threads.
class ToleranceStudy {
 public:
  /// Validates the options and the settings; the deck is copied. Requires [material] and [load]
  /// (and a non-zero torque when lost motion is asked for).
  ToleranceStudy(const Deck& deck, const SolverOptions& options, const ToleranceSettings& settings);

  const Deck& deck() const { return deck_; }
  const SolverOptions& options() const { return options_; }
  const ToleranceSettings& settings() const { return settings_; }
  const std::vector<ToleranceInput>& inputs() const { return inputs_; }
  /// Notes for the user: a sweep shorter than the symmetry the errors break, etc.
  const std::vector<std::string>& notes() const { return notes_; }

  /// The input columns of sample i: a pure function of (seed, i).
  std::vector<double> Draw(std::int64_t i) const;
  /// The deck of a pair with these input deviations (from the deck's values) applied.
  Deck Apply(const std::vector<double>& inputs) const;
  /// The figures of one pair (the deterministic run of a deck), with status and message.
  ToleranceSample Evaluate(const Deck& pair) const;
  /// Sample i: Draw, Apply, Evaluate.
  ToleranceSample Run(std::int64_t i) const;
  /// Samples first .. first + count - 1 on `threads` threads (>= 1), in sample order. The
  /// callback (if any) is called from the calling thread with the number done so far.
  std::vector<ToleranceSample> RunRange(std::int64_t first, std::int64_t count, int threads,
                                        const std::function<void(std::int64_t)>& progress = {}) const;

 private:
  Deck deck_;
  SolverOptions options_;
  ToleranceSettings settings_;
  std::vector<ToleranceInput> inputs_;
  std::vector<std::string> notes_;
};

/// Percentiles by linear interpolation between order statistics (Hyndman & Fan type 7, numpy's
/// default) over the finite values.
struct FigureStats {
  std::int64_t count = 0;  ///< samples with a finite value
  double mean = std::numeric_limits<double>::quiet_NaN();
  double std = std::numeric_limits<double>::quiet_NaN();  ///< sample standard deviation (n - 1)
  double p1 = std::numeric_limits<double>::quiet_NaN(), p5 = p1, p50 = p1, p95 = p1, p99 = p1, min = p1, max = p1;
};
FigureStats ComputeStats(std::vector<double> values);

struct LimitResult {
  ToleranceLimit limit;
  std::int64_t passed = 0;  ///< samples whose figure is finite and within the limit
  double fraction = 0.0;    ///< passed / samples
};

/// Which tolerance drives a figure's spread: standardised regression coefficients (SRC) of a
/// least-squares fit of the figure on every input column, both standardised (Saltelli et al.,
/// "Global sensitivity analysis: the primer", 2008, section 1.2.5). A key's share is the sum of
/// SRC^2 over its columns (one per pin for a per-pin key): with independent inputs and a linear
/// response the shares add up to R^2, the fraction of the variance the linear fit explains.
struct KeySensitivity {
  std::string key;
  double src = std::numeric_limits<double>::quiet_NaN();    ///< scalar keys: the signed SRC
  double share = std::numeric_limits<double>::quiet_NaN();  ///< sum of SRC^2 over the key's columns
};
struct FigureSensitivity {
  std::string figure;
  double r_squared = std::numeric_limits<double>::quiet_NaN();
  std::vector<KeySensitivity> keys;  ///< largest share first
  std::string note;                  ///< why there is no ranking, when there is none
};
inline constexpr const char* kSensitivityMethod =
    "standardised regression coefficients (SRC): least squares of the standardised figure on the standardised "
    "inputs (Eigen column-pivoting QR) over the successful samples; a key's share is the sum of SRC^2 over its "
    "columns (per pin for per-pin keys); R^2 says how much of the variance the linear model explains";

struct ToleranceSummary {
  std::int64_t samples = 0, succeeded = 0, failed = 0, rejected = 0;
  std::uint64_t seed = 0;
  std::array<FigureStats, kToleranceFigureCount> figures;
  std::vector<LimitResult> limits;
  std::int64_t passed_all = 0;    ///< samples within every limit
  double pass_fraction = std::numeric_limits<double>::quiet_NaN();  ///< passed_all / samples (NaN without limits)
  std::vector<FigureSensitivity> sensitivity;
};
/// The summary of samples in sample order (it does not depend on how they were computed).
ToleranceSummary Summarise(const ToleranceStudy& study, const std::vector<ToleranceSample>& samples);

// --- The extreme-value (worst-case) counterpart ------------------------------------------------

struct ClosingLink {
  double min = 0.0, max = 0.0;  ///< limits of the closing link (the clearance), the links' unit
};
/// The extreme-value method (Jiang 2022 section 5.1, Table 3): every link at the limit that
/// widens (max) or narrows (min) the closing link: max = sum ES(increasing) - sum EI(decreasing),
/// min = sum EI(increasing) - sum ES(decreasing).
ClosingLink ExtremeValueClosingLink(const std::vector<DimensionLink>& links);
/// The closing link by Monte Carlo: every link uniform within [lower, upper], independent, sample
/// i of link k a pure function of (seed, chain, k, i); the statistics of the closing link.
FigureStats ChainMonteCarlo(const std::vector<DimensionLink>& links, std::int64_t samples, std::uint64_t seed,
                            std::uint64_t chain);

/// The extreme-value method on the figures: every input column at the end of its range
/// (uniform: +-tolerance; normal: +-3 sigma) about its centre, the effects stacked linearly
/// (the secant over the range, one pair of deterministic runs per column), and the corner that
/// the stack picks evaluated by one more run each way.
struct WorstCaseFigure {
  double nominal = std::numeric_limits<double>::quiet_NaN();  ///< every input at its centre
  double stack_low = nominal, stack_high = nominal;           ///< nominal -+ sum |effect|
  double corner_low = nominal, corner_high = nominal;         ///< the run at the corner
  /// The corner runs' status ("success", "failed", "rejected": e.g. the corner pair interferes).
  std::string corner_low_status, corner_high_status;
};
struct WorstCaseResult {
  std::array<WorstCaseFigure, kToleranceFigureCount> figures;
  std::int64_t runs = 0;
  std::int64_t failed_runs = 0;  ///< runs that were rejected or failed (their effect is taken as 0)
};
WorstCaseResult ExtremeValueWorstCase(const ToleranceStudy& study, int threads);

}  // namespace ltca::app
