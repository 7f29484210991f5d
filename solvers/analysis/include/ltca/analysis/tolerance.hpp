#pragma once
// Tolerance analysis (docs/tolerance.md): a seeded Monte Carlo over the manufacturing
// and assembly errors of [tolerances], and the extreme-value (worst-case) counterpart.
//
// Every sample is a pair as made: the deck's [errors] and [modification] values plus the draws of
// [tolerances] (per-pin keys drawn independently for every pin; a reducer stage's hole positions
// for every hole of every disc, since discs are machined one by one). Its random numbers come from the
// counter-based stream of geometry/counter_rng.hpp: draw (key k, pin j) of sample i is a pure
// function of (seed, k, j, i), so any split of the samples over threads or MPI ranks gives the
// same samples bit for bit. Each sample runs, on its own runners (no state shared between
// samples):
//  - the unloaded TCA over the deck's sweep: mean and peak-to-peak backlash (Liu 2021 eq. 17);
//  - the loaded TCA over the sweep (ltca solve's summary): mean and peak-to-peak TE, the largest
//    contact stress and pin force, the pins in contact;
//  - when asked ([tolerances] lost_motion = true), lost motion at +-f T (ltca stiffness).
// MPI stays out of this header (solvers/app/cli/tolerance_mpi.cpp).
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <optional>

#include "ltca/analysis/friction.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/sweep.hpp"

namespace ltca::analysis {

/// One key of [tolerances]: how the value of an [errors] or [modification] key scatters about the
/// deck's own value (its nominal). Values are in the key's unit (mm, um or deg, as its name says).
struct ToleranceDistribution {
  enum class Kind {
    kNormal,   ///< mean + sigma z, z standard normal (deck: sigma, or tolerance read as 3 sigma)
    kUniform,  ///< uniform on mean +- tolerance (deck: tolerance)
  };
  std::string key;      ///< the [tolerances] key, e.g. "pin_circle_deviation_mm"
  Kind kind = Kind::kNormal;
  double sigma = 0.0;       ///< normal: standard deviation, key unit (>= 0)
  double tolerance = 0.0;   ///< uniform: half-width, key unit (>= 0); normal: 3 sigma when given so
  double mean = 0.0;        ///< offset of the distribution's centre from the deck's value, key unit
  bool per_pin = false;     ///< drawn independently for every pin (a list key of [errors])
  /// The half-width of the range the extreme-value (worst-case) method uses: uniform: tolerance;
  /// normal: 3 sigma.
  double WorstCaseHalfWidth() const { return kind == Kind::kUniform ? tolerance : 3.0 * sigma; }
  /// Standard deviation of a draw, key unit.
  double StandardDeviation() const;
  /// Nothing scatters and nothing is offset: the key leaves every sample at the deck's value.
  bool IsZero() const { return sigma == 0.0 && tolerance == 0.0 && mean == 0.0; }
};

/// A user-given acceptance limit on a figure of `ltca tolerance` (deck: [tolerances] limits).
struct ToleranceLimit {
  std::string figure;  ///< a figure name, e.g. "lost_motion_arcmin"
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
};

/// One link of an assembly dimensional chain: a dimension with its upper and lower deviation
/// (deck: [tolerances] chains, e.g. Jiang 2022 Table 3).
struct DimensionLink {
  std::string name;
  bool increasing = true;  ///< an increasing link widens the closing link; a decreasing one narrows it
  double upper = 0.0;      ///< upper deviation (es / ES), um in a deck
  double lower = 0.0;      ///< lower deviation (ei / EI), um in a deck
};
/// A dimensional chain whose closing link (a clearance) is solved for (deck: [tolerances] chains).
struct DimensionChain {
  std::string name;  ///< e.g. "B0"
  std::vector<DimensionLink> links;
};

/// [tolerances]: the Monte Carlo of `ltca tolerance`.
struct ToleranceSettings {
  static constexpr std::int64_t kMaxSamples = 10'000'000;
  std::vector<ToleranceDistribution> distributions;  ///< in the order of ToleranceKeys()
  std::int64_t samples = 1000;   ///< 1 .. kMaxSamples
  std::uint64_t seed = 1;        ///< of the counter-based stream: sample i depends on (seed, i) only
  bool lost_motion = false;      ///< also run lost motion per sample
  /// A reducer stage only: solve its free play per sample (the backlash figures; two
  /// stage solves a crank). `ltca tolerance` always does; `ltca optimise` only when the objective
  /// or a constraint names a backlash figure, else they are null (NaN).
  bool stage_free_play = true;
  /// [errors] profile_random_*: every sample its own random profile deviation (the zone and the
  /// law of the deck, the seed drawn from (seed, i)) instead of the deck's one profile.
  bool profile_random_per_sample = false;
  std::vector<ToleranceLimit> limits;
  /// Assembly dimensional chains (deck: chains = { B0 = [ { link = "...", kind = "increasing",
  /// upper_um = 9, lower_um = 0 }, ... ] }): their closing links by the extreme-value method and
  /// by Monte Carlo (every link uniform within its limits), reported beside the pair's figures.
  std::vector<DimensionChain> chains;
  /// The keys [tolerances] knows: every numeric key of [errors] and, prefixed "modification_", the
  /// modifications. The second member says whether the key is per pin.
  static const std::vector<std::pair<std::string, bool>>& ToleranceKeys();
  /// The figure names a limit may name (the summary keys of solve, backlash and stiffness).
  static const std::vector<std::string>& FigureNames();
  /// Throws std::invalid_argument naming the key, the value and what is expected.
  void Validate() const;
};
// --- end of [tolerances] --------------------------------------------------------------------------

/// The nominal case a study varies: the stage as the deck gives it, and what every sample runs.
struct ToleranceCase {
  StageDesign design;
  Sweep sweep;
  double torque = 0.0;                      ///< N*mm, signed
  StiffnessSettings stiffness;              ///< lost motion's loop (ToleranceSettings::lost_motion)
  std::optional<FrictionSettings> friction; ///< the loop's friction
  std::optional<OperationSettings> operation;  ///< the efficiency's operating point (ltca optimise)
};

/// The figures of a sample, in the order of ToleranceSettings::FigureNames(), in the units their
/// names carry (arcsec, MPa, N, arcmin; contacts as counts).
/// The last three are a reducer stage's (`ltca solve`'s stage summary): the largest
/// output-pin force (output pins only), the largest bearing load and the shortest ISO 281 life
/// of its bearings in hours (NaN without [bearing] dynamic_load_rating_n or [operation]).
inline constexpr std::size_t kToleranceFigureCount = 12;
using ToleranceFigures = std::array<double, kToleranceFigureCount>;
enum ToleranceFigure : std::size_t {
  kMeanBacklashArcsec, kPpBacklashArcsec, kMeanTeArcsec, kPpTeArcsec, kMaxContactStressMpa, kMaxPinForceN,
  kContactsMin, kContactsMax, kLostMotionArcmin, kMaxOutputPinForceN, kMaxBearingLoadN, kShortestL10Hours
};

/// Whether a design has the figure: every figure but a reducer stage's; those only with
/// [output], the output pins' force only with output pins. Lost motion is the settings' matter.
bool ReducerHasFigure(const std::optional<solvers::ReducerSettings>& reducer, std::size_t figure);

/// The loaded sweep's figures written into `figures` at their indices: mean and peak-to-peak TE
/// (arcsec), the largest contact stress (MPa) and pin force (N), the least and most pins in
/// contact (only where a position succeeded); with a reducer stage's summary its largest bearing
/// load and, with output pins, output-pin force (N). The others (backlash, lost motion, L10) are
/// left as they are. One rule for a tolerance sample and the allowables check's nominal value.
void LoadedFigures(const SweepSummary& sweep, bool output_pins, ToleranceFigures& figures);

/// The most threads a study runs on (--threads): beyond it a thread costs its stack (8 MiB of
/// address space) and buys nothing on any machine this runs on; starting 40,000 failed.
inline constexpr int kMaxToleranceThreads = 1024;

/// Starts one thread running the work (std::thread's own constructor by default; a test passes
/// one that fails).
using ThreadStarter = std::function<std::thread(std::function<void()>)>;
/// Calls fn(i) for i in 0 .. n - 1 on `threads` threads (the calling thread one of them), the
/// indices handed out one at a time; progress(done) from the calling thread. The first exception
/// thrown by fn is rethrown after every thread has stopped. When a thread cannot be started, the
/// ones already started stop after their current index and are joined, and the error is
/// rethrown: no thread is left running or unjoined.
void ParallelFor(std::int64_t n, int threads, const std::function<void(std::int64_t)>& fn,
                 const std::function<void(std::int64_t)>& progress, const ThreadStarter& start = {});

/// A normal given as a tolerance +-t (t = 3 sigma) is drawn from the normal truncated to +-t, so
/// that no draw lies beyond the worst-case corner; one given by sigma is not truncated
/// (ToleranceDistribution::StandardDeviation() is the truncated normal's then).
inline bool Truncated(const ToleranceDistribution& d) {
  return d.kind == ToleranceDistribution::Kind::kNormal && d.tolerance > 0.0;
}
/// "normal, sigma 0.001 (not truncated)", "normal truncated to +-0.003 (3 sigma, sigma 0.001 before
/// truncation)", "uniform +-0.002", with the centre offset and "per pin" when they apply.
std::string Describe(const ToleranceDistribution& d);

/// One input column of the study: a scalar key, or one pin of a per-pin key.
struct ToleranceInput {
  std::string name;          ///< "pin_circle_deviation_mm" or "pin_radius_deviations_mm[7]" (pin 7, 1-based)
  std::size_t distribution;  ///< index into ToleranceSettings::distributions
  /// 0-based pin of a per-pin key, or hole of a per-hole key (DeckKey::per_hole: "output_hole_radial_deviations_mm[2]"
  /// is hole 2, 1-based); -1 for a scalar key
  int pin = -1;
  /// With [second_disc]: 1 for the second disc's own draw of a disc key, of its bearing play or of its holes'
  /// positions (its name ends " (disc 2)"), else 0 (the first disc's, or the pin ring's, which both discs share).
  int disc = 0;
};

struct ToleranceSample {
  std::int64_t index = 0;
  /// Drawn deviation of every input column from the deck's value (the distribution's mean
  /// included), in the key's unit.
  std::vector<double> inputs;
  ToleranceFigures figures;  ///< NaN: no valid solve produced the figure
  /// kSuccess: every solve succeeded; kFailed: some position did not succeed (its figures are
  /// over the successful positions, as `ltca solve` reports them); kRejected: the pair as drawn
  /// interferes or cannot be built (no figure).
  RunStatus status = RunStatus::kSuccess;
  std::string message;  ///< why, when not success
  /// A preloaded pair (its loaded sweep's SweepSummary::preloaded > 0): the largest contact
  /// stress (MPa) and point force (N) of its preload at zero torque over the sweep; NaN otherwise.
  double preload_stress_mpa = std::numeric_limits<double>::quiet_NaN();
  double preload_force_n = std::numeric_limits<double>::quiet_NaN();
  ToleranceSample() { figures.fill(std::numeric_limits<double>::quiet_NaN()); }
};

/// The Monte Carlo: immutable once built, Run() may be called from any number of threads.
class ToleranceStudy {
 public:
  /// Validates the options and the settings. Requires the material (and a non-zero torque when
  /// lost motion is asked for).
  ToleranceStudy(ToleranceCase nominal, const SolverOptions& options, const ToleranceSettings& settings);

  const ToleranceCase& nominal() const { return nominal_; }
  const SolverOptions& options() const { return options_; }
  const ToleranceSettings& settings() const { return settings_; }
  const std::vector<ToleranceInput>& inputs() const { return inputs_; }
  /// Notes for the user: a sweep shorter than the symmetry the errors break, etc.
  const std::vector<std::string>& notes() const { return notes_; }
  /// Whether a sample of this study has the figure: lost motion when asked for, a stage's figures
  /// on a reducer stage (the output pins' force with output pins).
  bool Runs(std::size_t figure) const;

  /// The input columns of sample i: a pure function of (seed, i).
  std::vector<double> Draw(std::int64_t i) const;
  /// The case of a pair with these input deviations (from the nominal values) applied.
  ToleranceCase Apply(const std::vector<double>& inputs) const;
  /// The figures of one pair (the deterministic run of a case), with status and message.
  ToleranceSample Evaluate(const ToleranceCase& pair) const;
  /// Sample i: Draw, Apply, Evaluate.
  ToleranceSample Run(std::int64_t i) const;
  /// Samples first .. first + count - 1 on `threads` threads (1 .. kMaxToleranceThreads), in
  /// sample order. The callback (if any) is called from the calling thread with the number done
  /// so far.
  std::vector<ToleranceSample> RunRange(std::int64_t first, std::int64_t count, int threads,
                                        const std::function<void(std::int64_t)>& progress = {}) const;
  /// The same samples handed to `sink` one by one in sample order from the calling thread, as
  /// they are produced: they are computed in blocks of 64 per thread, so that at most one block
  /// is held at once whatever the count.
  void RunStream(std::int64_t first, std::int64_t count, int threads, const std::function<void(const ToleranceSample&)>& sink,
                 const std::function<void(std::int64_t)>& progress = {}) const;

 private:
  ToleranceCase nominal_;
  SolverOptions options_;
  ToleranceSettings settings_;
  std::vector<ToleranceInput> inputs_;
  std::vector<std::string> notes_;
};

/// A sample as bytes for an MPI gather (bit for bit: doubles copied, not printed): index,
/// figures, status and message, not the inputs (ToleranceStudy::Draw(i) gives them again).
void AppendSampleBytes(const ToleranceSample& s, std::string& out);
/// Calls each(sample) for every sample of the bytes, in order, its inputs drawn again by the study.
/// Throws std::runtime_error when the bytes are truncated.
void ReadSampleBytes(const std::string& in, const ToleranceStudy& study, const std::function<void(const ToleranceSample&)>& each);

/// What the summary keeps of the samples: each one's figures and status, 97 bytes a sample in two
/// flat arrays (no string or vector per sample). The inputs are not kept: they are drawn again
/// where needed (ToleranceStudy::Draw(i) is a pure function of (seed, i)). Of the messages only
/// the first one of a sample that did not succeed is kept (the text summary shows it).
class SampleTable {
 public:
  /// The bytes the table retains a sample (its capacity reserved for the count).
  static constexpr std::size_t kBytesPerSample = sizeof(ToleranceFigures) + sizeof(RunStatus);

  explicit SampleTable(std::int64_t first = 0) : first_(first) {}
  void Reserve(std::int64_t count);
  /// Adds the next sample: its index must be first() + size() (sample order).
  void Add(const ToleranceSample& s);
  std::int64_t first() const { return first_; }
  std::int64_t size() const { return static_cast<std::int64_t>(status_.size()); }
  std::int64_t index(std::int64_t k) const { return first_ + k; }
  const ToleranceFigures& figures(std::int64_t k) const { return figures_[static_cast<std::size_t>(k)]; }
  RunStatus status(std::int64_t k) const { return status_[static_cast<std::size_t>(k)]; }
  bool succeeded(std::int64_t k) const { return status(k) == RunStatus::kSuccess; }
  /// The preloaded samples (ToleranceSample::preload_stress_mpa finite), in sample order: each one's
  /// largest preload contact stress, MPa, and point force, N (kept as float: 8 bytes a preloaded
  /// sample beyond kBytesPerSample).
  std::int64_t preloaded() const { return static_cast<std::int64_t>(preload_.size() / 2); }
  double preload_stress(std::int64_t j) const { return preload_[2 * static_cast<std::size_t>(j)]; }
  double preload_force(std::int64_t j) const { return preload_[2 * static_cast<std::size_t>(j) + 1]; }
  /// The first sample that did not succeed: its index (-1: none) and message.
  std::int64_t first_failure_index() const { return first_failure_index_; }
  const std::string& first_failure_message() const { return first_failure_message_; }
  /// Bytes held for the samples (the arrays' capacity).
  std::size_t RetainedBytes() const {
    return figures_.capacity() * sizeof(ToleranceFigures) + status_.capacity() + preload_.capacity() * sizeof(float);
  }

 private:
  std::int64_t first_ = 0;
  std::vector<ToleranceFigures> figures_;
  std::vector<RunStatus> status_;
  std::vector<float> preload_;  // per preloaded sample: stress, force
  std::int64_t first_failure_index_ = -1;
  std::string first_failure_message_;
};

/// Percentiles by linear interpolation between order statistics (Hyndman & Fan type 7, numpy's
/// default) over the finite values, each only where the count supports it: the p-th percentile
/// where count x min(p, 1 - p) >= 1 (at least one sample expected beyond it: p1 and p99 from 100
/// samples, p5 and p95 from 20, p50 from 2), else NaN (kPercentileRule). `count` goes with every
/// figure.
inline constexpr const char* kPercentileRule =
    "type-7 percentiles over the finite values, each given only where count x min(p, 1 - p) >= 1 (p1 and p99 from 100 "
    "values, p5 and p95 from 20, p50 from 2), else null";
struct FigureStats {
  std::int64_t count = 0;  ///< samples with a finite value
  double mean = std::numeric_limits<double>::quiet_NaN();
  double std = std::numeric_limits<double>::quiet_NaN();  ///< sample standard deviation (n - 1)
  double p1 = std::numeric_limits<double>::quiet_NaN(), p5 = p1, p50 = p1, p95 = p1, p99 = p1, min = p1, max = p1;
};
FigureStats ComputeStats(std::vector<double> values);
/// The quantile p (0..1) of values sorted ascending (not empty), type 7: h = (n - 1) p, linear
/// between the neighbouring order statistics. ComputeStats's and the optimiser's.
double SortedQuantile(const std::vector<double>& sorted, double p);

struct LimitResult {
  ToleranceLimit limit;
  std::int64_t passed = 0;  ///< samples whose figure is finite and within the limit
  double fraction = 0.0;    ///< passed / samples
};

/// Which tolerance drives a figure's spread: standardised regression coefficients (SRC) of a
/// least-squares fit of the figure on every input column, both standardised (Saltelli et al.,
/// "Global sensitivity analysis: the primer", 2008, section 1.2.5). A key's share is the sum over
/// its columns (one per pin for a per-pin key) of SRC_c x r_c, r_c the sample correlation of
/// column c with the figure (Pratt's measure: Pratt, "Dividing the indivisible", 1987; Thomas et
/// al., Social Indicators Research 45, 1998): at the least-squares solution R^2 = sum_c SRC_c r_c,
/// so the shares add up to R^2 exactly, whatever the sample correlation of the inputs. A share is
/// negative where a column's correlation with the figure has the other sign than its coefficient
/// (a suppressor). The sum of SRC^2 (src_squared) is kept beside it: with independent inputs it is
/// the share in the limit, and the noise floor below is of it.
///
/// The noise floor: with n samples and p columns a key of m columns whose true effect is nil
/// still gets a share, sum of m SRC^2 each of variance (1 - R^2) / (n - p - 1) (the least-squares
/// variance of a coefficient on independent standardised inputs), so share (n - p - 1) / (1 - R^2)
/// is about chi^2 with m degrees of freedom. The floor is its 99.9th percentile (Wilson-Hilferty
/// for m > 1, exact for m = 1) times (1 - R^2) / (n - p - 1); a share below it is not
/// distinguishable from chance. Likewise R^2 by chance alone: q / (q + n - p - 1), q the 99.9th
/// percentile of chi^2 with p degrees of freedom (the F test of the whole fit, its denominator
/// taken at its mean).
inline constexpr double kNoiseFloorLevel = 0.999;
struct KeySensitivity {
  std::string key;
  double src = std::numeric_limits<double>::quiet_NaN();    ///< scalar keys: the signed SRC
  double share = std::numeric_limits<double>::quiet_NaN();  ///< sum of SRC_c r_c over the key's columns (Pratt)
  double src_squared = std::numeric_limits<double>::quiet_NaN();  ///< sum of SRC^2 over the key's columns
  int columns = 0;                                          ///< its columns that vary (m)
  double noise_floor = std::numeric_limits<double>::quiet_NaN();  ///< the src_squared chance reaches (above)
  bool distinguishable = false;                             ///< src_squared above the noise floor
};
struct FigureSensitivity {
  std::string figure;
  std::int64_t samples = 0;  ///< successful samples with a finite figure (n)
  double r_squared = std::numeric_limits<double>::quiet_NaN();
  double r_squared_floor = std::numeric_limits<double>::quiet_NaN();  ///< R^2 that chance reaches (above)
  std::vector<KeySensitivity> keys;  ///< largest share first; the shares add up to r_squared
  std::string note;                  ///< why there is no ranking, when there is none
};
inline constexpr const char* kSensitivityMethod =
    "standardised regression coefficients (SRC): least squares of the standardised figure on the standardised "
    "inputs (normal equations of the correlation matrix, Eigen column-pivoting QR) over the successful samples; a "
    "key's share is the sum over its columns (per pin for per-pin keys) of SRC x the column's correlation with the "
    "figure (Pratt's measure, 1987): the shares add up to R^2 exactly, the fraction of the variance the linear model "
    "explains (a negative share: a suppressor); src_squared is the sum of SRC^2 over the key's columns; noise_floor "
    "is the src_squared a key with no effect reaches by chance at the 99.9th percentile (chi^2 with the key's columns "
    "as degrees of freedom, times (1 - R^2) / (n - p - 1)): a src_squared below it is not distinguishable from chance";

struct ToleranceSummary {
  std::int64_t samples = 0, succeeded = 0, failed = 0, rejected = 0;
  /// Samples that cannot be assembled (RunStatus::kCannotAssemble), and the samples whose pair is
  /// preloaded (both flanks pressed at zero torque somewhere in the sweep), whatever their status.
  std::int64_t cannot_assemble = 0, preloaded = 0;
  /// Over the preloaded samples: the largest preload contact stress, MPa, and point force, N.
  FigureStats preload_stress, preload_force;
  std::uint64_t seed = 0;
  std::array<FigureStats, kToleranceFigureCount> figures;
  std::vector<LimitResult> limits;
  std::int64_t passed_all = 0;    ///< samples within every limit
  double pass_fraction = std::numeric_limits<double>::quiet_NaN();  ///< passed_all / samples (NaN without limits)
  std::vector<FigureSensitivity> sensitivity;
};
/// The summary of samples in sample order (it does not depend on how they were computed). The
/// inputs of the regression are drawn again (Draw(i)), not read from the samples.
ToleranceSummary Summarise(const ToleranceStudy& study, const SampleTable& samples);
ToleranceSummary Summarise(const ToleranceStudy& study, const std::vector<ToleranceSample>& samples);
/// The standard normal's inverse distribution function, to full double accuracy (Acklam's
/// rational approximation, one Halley step on erfc).
double InverseNormalCdf(double p);
/// The p-th quantile of chi^2 with m degrees of freedom: exact for m = 1, Wilson-Hilferty above.
double ChiSquaredQuantile(double p, int m);

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
  /// The corner runs' status (kRejected: e.g. the corner pair interferes; kNotRun: an input's
  /// effect on the figure is unknown, see note).
  RunStatus corner_low_status = RunStatus::kNotRun, corner_high_status = RunStatus::kNotRun;
  /// Why there is no stack and no corner: the input whose run at an end did not succeed. The
  /// effect of such an input is unknown, never taken as 0: the stack and both corners are NaN.
  std::string note;
};
struct WorstCaseResult {
  std::array<WorstCaseFigure, kToleranceFigureCount> figures;
  std::int64_t runs = 0;
  std::int64_t failed_runs = 0;  ///< runs that were rejected or failed
  std::string first_failure;     ///< the first of them: which input at which end, and why
};
/// `progress(done, total)` from the calling thread, over both stages of runs.
WorstCaseResult ExtremeValueWorstCase(const ToleranceStudy& study, int threads,
                                      const std::function<void(std::int64_t, std::int64_t)>& progress = {});

/// The samples of a figure beyond its worst-case corners, and how many of them have an input
/// beyond the range the worst case uses (a normal given by sigma is not truncated: 0.27 % of its
/// draws lie beyond 3 sigma). A sample beyond a corner with every input in range means the figure
/// is not monotonic in the inputs; one with an input out of range means nothing of the kind.
struct CornerExceedance {
  std::int64_t beyond = 0;           ///< successful samples beyond a successful corner
  std::int64_t beyond_in_range = 0;  ///< of them, with every input within its worst-case range
};
std::array<CornerExceedance, kToleranceFigureCount> CompareWithCorners(const ToleranceStudy& study, const SampleTable& samples,
                                                                        const WorstCaseResult& worst);

}  // namespace ltca::analysis
