#pragma once
// Design optimisation (docs/optimise.md): the modification that meets a specification,
// optionally robust to the tolerances.
//
// A design is the values of a few real keys of [modification] and [errors] (deck units, within
// bounds), set on the deck's stage (on both discs with [second_disc]: the discs of one part share
// their design). Its figures are those of a tolerance sample (ToleranceStudy::Evaluate: backlash,
// loaded TE, stress, pin force, contacts, lost motion), of the nominal pair or, robust, each
// figure's percentile over the same seeded samples of [tolerances] for every design (common random
// numbers). The search is NLopt's: a global method (DIRECT-L, CRS2 or ISRES) over the box, then a
// local polish (COBYLA or BOBYQA) from the best point, in the box scaled to [0, 1]^n. COBYLA and
// ISRES take the constraints as NLopt inequality constraints; DIRECT-L, CRS2 and BOBYQA minimise
// the stated penalty f / |f_0| + kPenaltyWeight * V (V the sum of the relative violations,
// f_0 the objective at the centre of the box). An evaluation that fails (interference, a solve
// that does not converge, a robust sample that does) is infeasible, its figures NaN and its
// reason counted; the search sees a large finite value there.
//
// Deterministic: the evaluations follow one another in NLopt's order, and a robust evaluation's
// samples depend on (seed, i) only, so the result is the same for any number of threads (they
// share the samples of a robust evaluation, the points of a map and the steps of a Pareto sweep).
// NLopt stays out of this header.
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "ltca/analysis/keys.hpp"
#include "ltca/analysis/tolerance.hpp"

namespace ltca::analysis {

/// The figures a design is judged by: those of a tolerance sample (ToleranceSettings::FigureNames,
/// in that order) and the efficiency's over the sweep (EfficiencyRunner: the mean power loss of the
/// full model in W, the energy-weighted efficiency), run only when the objective or a constraint
/// names them, on the nominal pair (not in robust mode), with the deck's [friction] and [operation].
inline constexpr std::size_t kOptimiseFigureCount = kToleranceFigureCount + 2;
inline constexpr std::size_t kPowerLossW = kToleranceFigureCount, kEfficiency = kToleranceFigureCount + 1;
using OptimiseFigures = std::array<double, kOptimiseFigureCount>;
const std::vector<std::string>& OptimiseFigureNames();

/// One design variable: a real key of [modification] or [errors] with its bounds.
struct OptimiseVariable {
  std::string key;                  ///< "section.name", e.g. "modification.pin_radius_mm"
  const DeckKey* deck_key = nullptr;  ///< its row of the table of deck keys (set by Validate)
  double lower = 0.0, upper = 0.0;  ///< bounds, the key's unit (lower < upper)
};

struct OptimiseSettings {
  enum class Global { kNone, kDirect, kCrs2, kIsres };
  enum class Local { kNone, kCobyla, kBobyqa };
  static constexpr int kMaxVariables = 8;
  static constexpr int kMaxEvaluations = 1'000'000;
  /// The penalty weight of the methods without constraints (relative violation against the
  /// objective scaled by its value at the centre of the box).
  static constexpr double kPenaltyWeight = 100.0;

  std::vector<OptimiseVariable> variables;
  /// A figure (OptimiseFigureNames()) or a variable's key.
  std::string objective;
  bool maximise = false;
  std::vector<ToleranceLimit> constraints;  ///< on figures, as [tolerances] limits
  Global global = Global::kDirect;
  Local local = Local::kCobyla;
  int evaluations = 200;        ///< the budget, global and local together
  double global_share = 0.6;    ///< of the budget, for the global phase (when there is a local one)
  double tolerance = 1e-6;      ///< the local phase stops when a step moves x by less (relative to the box)
  std::uint64_t seed = 1;       ///< CRS2 and ISRES's random numbers
  /// Robust: every design over the samples of `tolerances` (its distributions and seed; its
  /// samples replaced by robust_samples), each figure taken at `percentile`: the upper one for a
  /// maximum or a minimised objective, 100 - percentile for a minimum or a maximised objective.
  bool robust = false;
  ToleranceSettings tolerances;
  std::int64_t robust_samples = 64;
  double percentile = 95.0;
  /// Robust: the confidence that the figure taken bounds the percentile (distribution-free, from
  /// the binomial law of the order statistics: the least k with P(Bin(n, p/100) <= k - 1) >= c,
  /// so the k-th smallest of n samples lies at or above the p-th percentile with probability at
  /// least c; mirrored for a lower bound). 0: the point estimate instead (linear interpolation
  /// between order statistics, Hyndman & Fan type 7), which a fresh Monte Carlo exceeds about as
  /// often as not.
  double confidence = 0.9;
  /// Throws std::invalid_argument naming the key, the value and what is expected; finds each
  /// variable's deck key.
  void Validate();
  /// Whether the objective or a constraint needs lost motion.
  bool NeedsLostMotion() const;
  /// Whether the objective or a constraint needs the efficiency (power_loss_w, efficiency).
  bool NeedsEfficiency() const;
  /// Whether the objective or a constraint names a backlash figure (on a reducer stage its free
  /// play, solved only then).
  bool NeedsBacklash() const;
};
const char* ToString(OptimiseSettings::Global global);  ///< "direct" | "crs2" | "isres" | "none"
const char* ToString(OptimiseSettings::Local local);    ///< "cobyla" | "bobyqa" | "none"

/// One evaluated design.
struct DesignEvaluation {
  std::int64_t index = 0;
  std::string phase;       ///< "centre", "global", "local", "map", "pareto"
  std::vector<double> x;   ///< the variables, their keys' units
  /// Nominal: the pair's figures; robust: each at its percentile (OptimiseSettings). NaN: none.
  OptimiseFigures figures{};
  double objective = std::numeric_limits<double>::quiet_NaN();  ///< NaN when the evaluation failed
  /// Sum over the constraints of the violation relative to max(|limit|, 1e-9); 0 when feasible,
  /// NaN when the evaluation failed.
  double violation = std::numeric_limits<double>::quiet_NaN();
  bool feasible = false;
  RunStatus status = RunStatus::kNotRun;  ///< success; failed or rejected (the reason in message)
  std::string message;
  std::int64_t samples = 0, samples_failed = 0;  ///< robust only
  DesignEvaluation() { figures.fill(std::numeric_limits<double>::quiet_NaN()); }
};

/// What stopped an NLopt phase, in NLopt's words ("maxeval reached", "xtol reached", ...).
struct OptimisePhase {
  std::string method;
  std::string stop;
  std::int64_t evaluations = 0;
};

/// Where a search hands its evaluations: each one, once, in index order, from the thread
/// that called Optimiser::Run, as soon as it is made. The search keeps none of them but the last
/// and the best, so its memory does not grow with the evaluations; whoever wants the history
/// writes or keeps it here.
using EvaluationSink = std::function<void(const DesignEvaluation&)>;

struct OptimiseResult {
  std::int64_t evaluations = 0;  ///< how many were made (the sink saw each, indices 0 .. evaluations - 1)
  std::int64_t best = -1;  ///< the best feasible evaluation's index (lowest index among equals), -1: none feasible
  DesignEvaluation best_design;  ///< that evaluation (when best >= 0)
  std::vector<OptimisePhase> phases;
  std::int64_t failed = 0, rejected = 0;  ///< evaluations by outcome
  std::string first_failure;              ///< the first failed or rejected evaluation's reason
  double wall_seconds = 0.0;
};

/// The Pareto front of the objective against a second figure by epsilon constraints.
struct ParetoPoint {
  double epsilon = 0.0;  ///< the bound on the second figure
  std::int64_t best = -1;  ///< the index of the step's best evaluation in its search; -1: nothing feasible
  DesignEvaluation design;
};

/// The ranks of an MPI job as the optimiser sees them (MPI itself stays in the command line).
/// Every rank runs the same search in lockstep; what divides (a robust design's samples, the
/// points of a map, the steps of a Pareto front) is split into static blocks by rank and shared
/// through all_gather, so the result is the same bit for bit on any number of ranks. A nominal
/// design is one run: every rank computes it.
struct RankGroup {
  int rank = 0;
  int size = 1;
  /// Every rank passes its bytes and gets every rank's, in rank order (MPI_Allgatherv).
  std::function<std::vector<std::string>(const std::string&)> all_gather;
};

/// The search: immutable once built. Without ranks, Evaluate may be called from any number of
/// threads; with ranks, every call that divides its work (Evaluate of a robust design, Run, Grid,
/// Pareto) is collective: every rank makes it, in the same order, from one thread.
class Optimiser {
 public:
  /// Validates the settings (std::invalid_argument naming the key).
  Optimiser(ToleranceCase nominal, SolverOptions options, OptimiseSettings settings, int threads = 1, RankGroup ranks = {});
  const OptimiseSettings& settings() const { return settings_; }
  const ToleranceCase& nominal() const { return nominal_; }
  const SolverOptions& options() const { return options_; }
  int threads() const { return threads_; }
  const RankGroup& ranks() const { return ranks_; }
  /// The case of a design: each variable's key set to its value (both discs).
  ToleranceCase Apply(const std::vector<double>& x) const;
  /// One design, judged by the objective and constraints (phase and index left to the caller).
  DesignEvaluation Evaluate(const std::vector<double>& x) const;
  /// The search: every evaluation to `sink` as it is made (EvaluationSink), none kept.
  OptimiseResult Run(const EvaluationSink& sink = {}) const;
  /// Every design of an n x n ... grid over the box (n points per variable, the bounds
  /// included), in parallel over the threads; index order: the first variable fastest.
  std::vector<DesignEvaluation> Grid(int n) const;
  /// The front of the objective against `figure` (epsilon constraints): for `steps` bounds evenly
  /// from lo to hi, the search with the extra constraint figure <= bound; the steps in parallel
  /// over the threads (one after another for CRS2 and ISRES, whose random numbers NLopt keeps).
  std::vector<ParetoPoint> Pareto(const std::string& figure, double lo, double hi, int steps) const;

 private:
  ToleranceCase nominal_;
  SolverOptions options_;
  OptimiseSettings settings_;
  int threads_ = 1;
  RankGroup ranks_;
};

/// What a whole optimisation runs besides the search: the objective's map over the two variables
/// and a Pareto front, and where the search's evaluations go.
struct OptimiseRunPlan {
  int map = 0;         ///< points a variable of the map (2 .. 201, two variables), 0: none
  std::string pareto;  ///< the second figure of a Pareto front, "": none
  double pareto_from = std::numeric_limits<double>::quiet_NaN();  ///< its first bound, the figure's unit
  double pareto_to = std::numeric_limits<double>::quiet_NaN();    ///< its last bound
  int pareto_steps = 11;  ///< bounds from pareto_from to pareto_to
  EvaluationSink sink;    ///< every evaluation of the search, in index order (the map's are in the result)
};

/// A whole optimisation: the search's result, the map's designs (first variable fastest) and the
/// Pareto front, with the threads and ranks it ran on.
struct OptimiseRun {
  OptimiseResult search;
  int map = 0;                         ///< points a variable of the map, 0: none
  std::vector<DesignEvaluation> grid;  ///< the map's designs, map x map of them
  std::string pareto;                  ///< the front's second figure, "": none
  std::vector<ParetoPoint> front;
  int threads = 1, ranks = 1;
  /// The best feasible design of the search, or nullptr when none met the constraints.
  const DesignEvaluation* best() const { return search.best >= 0 ? &search.best_design : nullptr; }
};

/// The search (collective with ranks), then the map and the front when the plan asks for them.
OptimiseRun RunOptimisation(const Optimiser& optimiser, const OptimiseRunPlan& plan);

/// The index of a figure in OptimiseFigureNames(), or -1.
int FigureIndex(const std::string& figure);

/// The order statistic (1-based) of n samples that bounds the q-quantile (0 < q < 1) from above
/// with probability at least c: the least k with P(Bin(n, q) <= k - 1) >= c; 0 when even the
/// largest does not (1 - q^n < c). Distribution-free for a continuous figure (Hahn & Meeker,
/// Statistical Intervals, Wiley 1991, ch. 5: distribution-free bounds on percentiles).
std::int64_t ConfidenceRank(std::int64_t n, double q, double c);
/// The least n for which ConfidenceRank(n, q, c) > 0: ceil(ln(1 - c) / ln q).
std::int64_t ConfidenceSamples(double q, double c);

}  // namespace ltca::analysis
