#include "ltca/analysis/optimise.hpp"

#include <nlopt.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "bytes.hpp"
#include "ltca/analysis/efficiency.hpp"

namespace ltca::analysis {
namespace {

using Clock = std::chrono::steady_clock;

/// The variable index of a key, or -1.
int VariableIndex(const OptimiseSettings& s, const std::string& key) {
  for (std::size_t j = 0; j < s.variables.size(); ++j) {
    if (s.variables[j].key == key) return static_cast<int>(j);
  }
  return -1;
}

const char* NloptStop(nlopt_result r) {
  switch (r) {
    case NLOPT_SUCCESS: return "success";
    case NLOPT_STOPVAL_REACHED: return "stopval reached";
    case NLOPT_FTOL_REACHED: return "ftol reached";
    case NLOPT_XTOL_REACHED: return "xtol reached (the step fell below the tolerance)";
    case NLOPT_MAXEVAL_REACHED: return "maxeval reached (the budget)";
    case NLOPT_MAXTIME_REACHED: return "maxtime reached";
    case NLOPT_FAILURE: return "failure";
    case NLOPT_INVALID_ARGS: return "invalid arguments";
    case NLOPT_OUT_OF_MEMORY: return "out of memory";
    case NLOPT_ROUNDOFF_LIMITED: return "roundoff limited";
    case NLOPT_FORCED_STOP: return "forced stop";
    default: return "unknown";
  }
}

/// Whether e is a better design than b (both successful): a feasible one before an infeasible one;
/// among feasible ones the lower objective (higher when maximising), among infeasible ones the
/// less violation. Equals are not better, so a fold in index order keeps the lowest index.
bool Better(const DesignEvaluation& e, const DesignEvaluation& b, bool maximise) {
  if (e.feasible != b.feasible) return e.feasible;
  return e.feasible ? (maximise ? e.objective > b.objective : e.objective < b.objective) : e.violation < b.violation;
}

/// The best evaluation so far (Better, over the successful ones with an objective; only the feasible
/// ones when feasible_only), kept as the evaluations go by: the fold over the history in index
/// order that the search once made over the whole kept history, so it picks the same one.
struct BestSoFar {
  bool feasible_only = false;
  std::optional<DesignEvaluation> best;
  void Offer(const DesignEvaluation& e, bool maximise) {
    if (e.status != RunStatus::kSuccess || !std::isfinite(e.objective)) return;
    if (feasible_only && !e.feasible) return;
    if (!best || Better(e, *best, maximise)) best = e;
  }
};

/// The state of one search, handed to NLopt's callbacks. Of the evaluations it keeps the last (NLopt
/// asks for the objective and the constraints at one point), the best of all (the local phase
/// starts there) and the best feasible one (the result); each goes to the sink as it is made.
struct Search {
  const Optimiser* optimiser = nullptr;
  const OptimiseSettings* settings = nullptr;
  OptimiseResult* result = nullptr;
  std::string phase;
  double scale = 1.0;       ///< |f| at the centre (1 when that is 0 or failed)
  bool penalised = true;    ///< the phase's method takes no constraints: the stated penalty
  std::int64_t budget = 0;  ///< evaluations this search may make in all
  std::exception_ptr error;
  nlopt_opt opt = nullptr;  ///< the phase under way: stopped when an evaluation throws
  const EvaluationSink* sink = nullptr;
  std::optional<DesignEvaluation> last;
  BestSoFar best_any{false, {}}, best_feasible{true, {}};

  std::vector<double> X(const double* u) const {
    std::vector<double> x(settings->variables.size());
    for (std::size_t j = 0; j < x.size(); ++j) {
      const OptimiseVariable& v = settings->variables[j];
      x[j] = v.lower + std::clamp(u[j], 0.0, 1.0) * (v.upper - v.lower);
    }
    return x;
  }
  /// The evaluation at u: the last one when u is its point (NLopt asks for the objective and the
  /// constraints at the same point), else a new one.
  const DesignEvaluation& At(const double* u) {
    const std::vector<double> x = X(u);
    if (last && last->x == x) return *last;
    DesignEvaluation e = optimiser->Evaluate(x);
    e.index = result->evaluations++;
    e.phase = phase;
    // A preloaded design beyond its assembly limits is not built: counted with the designs that
    // cannot be (rejected), infeasible as they are.
    if (e.status == RunStatus::kRejected || e.status == RunStatus::kCannotAssemble) ++result->rejected;
    if (e.status == RunStatus::kFailed) ++result->failed;
    if (e.status != RunStatus::kSuccess && result->first_failure.empty()) {
      result->first_failure = fmt::format("evaluation {}: {}", e.index, e.message);
    }
    best_any.Offer(e, settings->maximise);
    best_feasible.Offer(e, settings->maximise);
    last = std::move(e);
    if (sink != nullptr && *sink) (*sink)(*last);
    return *last;
  }
  /// After an exception in a callback: kept for Run to rethrow, and the phase stopped (no more
  /// evaluations).
  void Fail() {
    error = std::current_exception();
    if (opt != nullptr) nlopt_force_stop(opt);
  }
  /// The objective as NLopt minimises it: scaled, its sign for maximising, with the penalty in a
  /// phase without constraints; a failed evaluation a large finite value.
  double Value(const DesignEvaluation& e) const {
    if (e.status != RunStatus::kSuccess || !std::isfinite(e.objective)) return 1e6;
    const double f = (settings->maximise ? -e.objective : e.objective) / scale;
    return penalised ? f + OptimiseSettings::kPenaltyWeight * e.violation : f;
  }
};

double Objective(unsigned /*n*/, const double* u, double* grad, void* data) {
  auto* s = static_cast<Search*>(data);
  if (grad != nullptr || s->error) return HUGE_VAL;  // derivative-free methods only; nothing after an error
  try {
    return s->Value(s->At(u));
  } catch (...) {
    s->Fail();
    return HUGE_VAL;
  }
}

/// One side of one constraint, relative: <= 0 when met.
struct ConstraintSide {
  Search* search;
  int figure;
  bool upper;
  double bound;
};

double Constraint(unsigned /*n*/, const double* u, double* grad, void* data) {
  auto* c = static_cast<ConstraintSide*>(data);
  if (grad != nullptr || c->search->error) return HUGE_VAL;
  try {
    const DesignEvaluation& e = c->search->At(u);
    const double g = e.figures[static_cast<std::size_t>(c->figure)];
    if (e.status != RunStatus::kSuccess || !std::isfinite(g)) return 1.0;
    const double scale = std::max(std::abs(c->bound), 1e-9);
    return (c->upper ? g - c->bound : c->bound - g) / scale;
  } catch (...) {
    c->search->Fail();
    return HUGE_VAL;
  }
}

void AppendBytes(const DesignEvaluation& e, std::string& out) {
  bytes::Put(out, e.index);
  bytes::PutString(out, e.phase);
  bytes::Put(out, static_cast<std::uint64_t>(e.x.size()));
  for (const double v : e.x) bytes::Put(out, v);
  for (const double v : e.figures) bytes::Put(out, v);
  bytes::Put(out, e.objective);
  bytes::Put(out, e.violation);
  bytes::Put(out, static_cast<std::uint8_t>(e.feasible ? 1 : 0));
  bytes::Put(out, e.status);
  bytes::PutString(out, e.message);
  bytes::Put(out, e.samples);
  bytes::Put(out, e.samples_failed);
}

DesignEvaluation TakeEvaluation(const std::string& in, std::size_t& at) {
  DesignEvaluation e;
  e.index = bytes::Take<std::int64_t>(in, at);
  e.phase = bytes::TakeString(in, at);
  const auto n = bytes::Take<std::uint64_t>(in, at);
  if (n > (in.size() - at) / sizeof(double)) throw std::runtime_error("gathered bytes are truncated");
  e.x.resize(static_cast<std::size_t>(n));
  for (double& v : e.x) v = bytes::Take<double>(in, at);
  for (double& v : e.figures) v = bytes::Take<double>(in, at);
  e.objective = bytes::Take<double>(in, at);
  e.violation = bytes::Take<double>(in, at);
  e.feasible = bytes::Take<std::uint8_t>(in, at) != 0;
  e.status = bytes::Take<RunStatus>(in, at);
  e.message = bytes::TakeString(in, at);
  e.samples = bytes::Take<std::int64_t>(in, at);
  e.samples_failed = bytes::Take<std::int64_t>(in, at);
  return e;
}

/// Items 0 .. count - 1 computed by `one(i)` on this rank's static block (on `threads` threads)
/// and shared with every rank through `ranks`; `append` and `take` carry an item as bytes.
template <typename T, typename One, typename Append, typename TakeOne>
std::vector<T> Divided(std::int64_t count, int threads, const RankGroup& ranks, One one, Append append, TakeOne take) {
  const std::int64_t begin = count * ranks.rank / ranks.size, end = count * (ranks.rank + 1) / ranks.size;
  std::vector<T> mine(static_cast<std::size_t>(end - begin));
  ParallelFor(end - begin, threads, [&](std::int64_t i) { mine[static_cast<std::size_t>(i)] = one(begin + i); }, {});
  if (ranks.size <= 1) return mine;
  std::string out;
  for (const T& t : mine) append(t, out);
  std::vector<T> all;
  all.reserve(static_cast<std::size_t>(count));
  for (const std::string& part : ranks.all_gather(out)) {
    std::size_t at = 0;
    while (at < part.size()) all.push_back(take(part, at));
  }
  if (static_cast<std::int64_t>(all.size()) != count) throw std::runtime_error("optimise: the ranks gathered a wrong number of items");
  return all;
}

}  // namespace

const char* ToString(OptimiseSettings::Global global) {
  switch (global) {
    case OptimiseSettings::Global::kDirect: return "direct";
    case OptimiseSettings::Global::kCrs2: return "crs2";
    case OptimiseSettings::Global::kIsres: return "isres";
    case OptimiseSettings::Global::kNone: return "none";
  }
  return "none";
}

const char* ToString(OptimiseSettings::Local local) {
  switch (local) {
    case OptimiseSettings::Local::kCobyla: return "cobyla";
    case OptimiseSettings::Local::kBobyqa: return "bobyqa";
    case OptimiseSettings::Local::kNone: return "none";
  }
  return "none";
}

std::int64_t ConfidenceRank(std::int64_t n, double q, double c) {
  if (n < 1 || !(q > 0.0 && q < 1.0) || !(c >= 0.0 && c < 1.0)) return 0;
  // P(Bin(n, q) <= j) summed from j = 0, each term in logarithms (n up to 10^6).
  const double nn = static_cast<double>(n), lq = std::log(q), l1q = std::log1p(-q);
  double cdf = 0.0;
  for (std::int64_t j = 0; j < n; ++j) {
    const double jj = static_cast<double>(j);
    cdf += std::exp(std::lgamma(nn + 1.0) - std::lgamma(jj + 1.0) - std::lgamma(nn - jj + 1.0) + jj * lq + (nn - jj) * l1q);
    if (cdf >= c) return j + 1;  // X_(j + 1) >= the quantile unless more than j samples fall below it
  }
  return 0;  // P(Bin <= n - 1) = 1 - q^n < c: not even the largest sample
}

std::int64_t ConfidenceSamples(double q, double c) {
  if (!(q > 0.0 && q < 1.0) || !(c > 0.0 && c < 1.0)) return 1;
  std::int64_t n = static_cast<std::int64_t>(std::ceil(std::log1p(-c) / std::log(q)));
  while (n > 1 && ConfidenceRank(n - 1, q, c) > 0) --n;  // rounding of the logarithms
  while (ConfidenceRank(n, q, c) == 0) ++n;
  return n;
}

const std::vector<std::string>& OptimiseFigureNames() {
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> names = ToleranceSettings::FigureNames();
    names.push_back("power_loss_w");
    names.push_back("efficiency");
    return names;
  }();
  return kNames;
}

int FigureIndex(const std::string& figure) {
  const auto& names = OptimiseFigureNames();
  for (std::size_t f = 0; f < names.size(); ++f) {
    if (names[f] == figure) return static_cast<int>(f);
  }
  return -1;
}

bool OptimiseSettings::NeedsLostMotion() const {
  if (objective == "lost_motion_arcmin") return true;
  return std::any_of(constraints.begin(), constraints.end(), [](const ToleranceLimit& l) { return l.figure == "lost_motion_arcmin"; });
}

bool OptimiseSettings::NeedsBacklash() const {
  const auto backlash = [](const std::string& f) { return f == "mean_backlash_arcsec" || f == "pp_backlash_arcsec"; };
  return backlash(objective) || std::any_of(constraints.begin(), constraints.end(), [&](const ToleranceLimit& l) { return backlash(l.figure); });
}

bool OptimiseSettings::NeedsEfficiency() const {
  const auto efficiency = [](const std::string& f) { return f == "power_loss_w" || f == "efficiency"; };
  return efficiency(objective) ||
         std::any_of(constraints.begin(), constraints.end(), [&](const ToleranceLimit& l) { return efficiency(l.figure); });
}

void OptimiseSettings::Validate() {
  const auto figures = [] {
    std::string names;
    for (const auto& f : OptimiseFigureNames()) names += (names.empty() ? "" : ", ") + f;
    return names;
  };
  if (variables.empty() || static_cast<int>(variables.size()) > kMaxVariables) {
    throw std::invalid_argument(fmt::format(
        "[optimise] variables: {} given; expected 1 to {} keys with bounds, e.g. {{ \"modification.pin_radius_mm\" = "
        "[-0.03, 0.0] }}",
        variables.size(), kMaxVariables));
  }
  for (OptimiseVariable& v : variables) {
    const std::size_t dot = v.key.find('.');
    const DeckKey* k = dot == std::string::npos ? nullptr : FindKey(v.key.substr(0, dot), v.key.substr(dot + 1));
    solvers::ReducerSettings any;  // only asks whether the key is one of the stage's clearances
    if (k == nullptr || (k->real == nullptr && ReducerClearance(any, v.key) == nullptr)) {
      throw std::invalid_argument(fmt::format(
          "[optimise] variables.\"{}\": expected a real key of [modification] or [errors], or a clearance of the "
          "stage (\"bearing.radial_clearance_mm\", \"output.hole_radius_mm\", \"output.pin_radius_mm\"), as "
          "\"section.key\" (e.g. \"modification.pin_radius_mm\", \"errors.lead_crowning_um\"; docs/decks.md)",
          v.key));
    }
    v.deck_key = k;
    if (!(std::isfinite(v.lower) && std::isfinite(v.upper) && v.lower < v.upper)) {
      throw std::invalid_argument(fmt::format("[optimise] variables.\"{}\" = [{}, {}]: expected finite bounds [lower, upper] with "
                                              "lower < upper, in {}",
                                              v.key, v.lower, v.upper, k->unit));
    }
    if (std::count_if(variables.begin(), variables.end(), [&](const OptimiseVariable& o) { return o.key == v.key; }) > 1) {
      throw std::invalid_argument(fmt::format("[optimise] variables.\"{}\": given twice", v.key));
    }
  }
  if (FigureIndex(objective) < 0 && VariableIndex(*this, objective) < 0) {
    throw std::invalid_argument(fmt::format("[optimise] objective = \"{}\": expected a figure ({}) or one of the variables' keys",
                                            objective, figures()));
  }
  for (const ToleranceLimit& l : constraints) {
    if (FigureIndex(l.figure) < 0) {
      throw std::invalid_argument(fmt::format("[optimise] constraints.{}: unknown figure; expected one of {}", l.figure, figures()));
    }
    if (std::isnan(l.min) || std::isnan(l.max) || l.min > l.max || (std::isinf(l.min) && std::isinf(l.max))) {
      throw std::invalid_argument(fmt::format("[optimise] constraints.{}: min = {}, max = {}: expected a bound, min <= max", l.figure,
                                              l.min, l.max));
    }
  }
  if (evaluations < 1 || evaluations > kMaxEvaluations) {
    throw std::invalid_argument(fmt::format("[optimise] evaluations = {}: expected 1 to {}", evaluations, kMaxEvaluations));
  }
  if (!(global_share > 0.0 && global_share <= 1.0)) {
    throw std::invalid_argument(fmt::format("[optimise] global_share = {}: expected a fraction of the budget in (0, 1]", global_share));
  }
  if (!(std::isfinite(tolerance) && tolerance > 0.0 && tolerance < 1.0)) {
    throw std::invalid_argument(fmt::format("[optimise] tolerance = {}: expected a step, relative to the box, in (0, 1)", tolerance));
  }
  if (global == Global::kNone && local == Local::kNone) {
    throw std::invalid_argument("[optimise] global = \"none\" and local = \"none\": expected at least one method");
  }
  if (robust) {
    if (tolerances.distributions.empty()) {
      throw std::invalid_argument(
          "[optimise] robust = true: the deck's [tolerances] gives no distribution; expected e.g. [tolerances] "
          "pin_circle_deviation_mm = { distribution = \"normal\", tolerance = 0.003 }");
    }
    if (robust_samples < 2 || robust_samples > 1'000'000) {
      throw std::invalid_argument(fmt::format("[optimise] robust_samples = {}: expected 2 to 1000000", robust_samples));
    }
    if (!(percentile > 0.0 && percentile < 100.0)) {
      throw std::invalid_argument(fmt::format("[optimise] percentile = {}: expected a percentile in (0, 100), e.g. 95", percentile));
    }
    if (!(confidence >= 0.0 && confidence < 1.0)) {
      throw std::invalid_argument(fmt::format("[optimise] confidence = {}: expected 0 (the point estimate) or a probability in (0, 1), e.g. 0.9",
                                              confidence));
    }
    if (NeedsEfficiency()) {
      throw std::invalid_argument(
          "[optimise] robust = true with power_loss_w or efficiency: expected figures of the tolerance samples (the efficiency "
          "is run on the nominal pair only; optimise it with robust = false)");
    }
    if (confidence > 0.0 && ConfidenceRank(robust_samples, percentile / 100.0, confidence) == 0) {
      throw std::invalid_argument(fmt::format(
          "[optimise] robust_samples = {}: too few to bound the p{:g} with confidence {:g} (even the largest sample does so with "
          "probability 1 - {:g}^{} = {:.3g}); expected at least {} samples, or a lower confidence",
          robust_samples, percentile, confidence, percentile / 100.0, robust_samples,
          1.0 - std::pow(percentile / 100.0, static_cast<double>(robust_samples)), ConfidenceSamples(percentile / 100.0, confidence)));
    }
  }
}

Optimiser::Optimiser(ToleranceCase nominal, SolverOptions options, OptimiseSettings settings, int threads, RankGroup ranks)
    : nominal_(std::move(nominal)), options_(std::move(options)), settings_(std::move(settings)), threads_(threads),
      ranks_(std::move(ranks)) {
  settings_.Validate();
  options_.Validate();
  if (threads_ < 1 || threads_ > kMaxToleranceThreads) {
    throw std::invalid_argument(fmt::format("threads = {}: expected 1 to {}", threads_, kMaxToleranceThreads));
  }
  if (ranks_.size < 1 || ranks_.rank < 0 || ranks_.rank >= ranks_.size || (ranks_.size > 1 && !ranks_.all_gather)) {
    throw std::invalid_argument(fmt::format("optimise: rank {} of {}: expected 0 <= rank < size and, for more than one rank, a gather",
                                            ranks_.rank, ranks_.size));
  }
  if (settings_.NeedsEfficiency()) {
    if (!nominal_.friction) {
      throw std::invalid_argument("[optimise] power_loss_w / efficiency: expected a [friction] section (e.g. [friction] coefficient = 0.05)");
    }
    if (!nominal_.operation) {
      throw std::invalid_argument("[optimise] power_loss_w / efficiency: expected an [operation] section (e.g. [operation] input_speed_rpm = 1500)");
    }
    if (nominal_.torque == 0.0) throw std::invalid_argument("[optimise] power_loss_w / efficiency: expected a non-zero [load] torque_nm");
  }
  for (const OptimiseVariable& v : settings_.variables) {
    if (v.deck_key->real != nullptr) continue;  // a key of the discs
    // A clearance of the reducer stage: the deck must have the element it belongs to.
    if (const std::string why = StageClearanceRefusal(nominal_.design.reducer, v.key); !why.empty()) {
      throw std::invalid_argument(fmt::format("[optimise] variables.\"{}\" = [{}, {}]: {}", v.key, v.lower, v.upper, why));
    }
  }
  {  // a figure of a reducer stage needs one; the output pins' force needs output pins
    const auto& r = nominal_.design.reducer;
    std::vector<std::string> named = {settings_.objective};
    for (const ToleranceLimit& l : settings_.constraints) named.push_back(l.figure);
    for (const std::string& name : named) {
      const int f = FigureIndex(name);
      // A variable's key (-1) and the efficiency's figures (beyond the tolerance table) are not a stage's.
      if (f < 0 || f >= static_cast<int>(kToleranceFigureCount) || ReducerHasFigure(r, static_cast<std::size_t>(f))) continue;
      throw std::invalid_argument(fmt::format("[optimise] {}: a figure of a reducer stage{}; expected an [output] section{} "
                                              "(docs/stage.md)",
                                              name, r ? " with output pins" : "", r ? " with kind = \"pins\"" : ""));
    }
  }
  if (nominal_.design.reducer && settings_.NeedsBacklash() && nominal_.torque == 0.0) {
    throw std::invalid_argument("[optimise] mean_backlash_arcsec / pp_backlash_arcsec on a reducer stage: [load] torque_nm = 0: "
                                "expected a non-zero rated torque (the stage's backlash is its free play at +-1e-7 of it)");
  }
  if (settings_.NeedsLostMotion() && nominal_.torque == 0.0) {
    throw std::invalid_argument("[optimise] lost_motion_arcmin: expected a non-zero [load] torque_nm (the rated torque of the loop)");
  }
}

ToleranceCase Optimiser::Apply(const std::vector<double>& x) const {
  if (x.size() != settings_.variables.size()) {
    throw std::invalid_argument(fmt::format("optimise: {} values for {} variables", x.size(), settings_.variables.size()));
  }
  ToleranceCase pair = nominal_;
  StageDesign& d = pair.design;
  for (std::size_t j = 0; j < x.size(); ++j) {
    const DeckKey& k = *settings_.variables[j].deck_key;
    if (k.real == nullptr) {  // a clearance of the reducer stage, one for the stage (Validate, the constructor)
      *ReducerClearance(*d.reducer, settings_.variables[j].key) = k.ToInternal(x[j]);
      // A second disc with its own bearing play ([second_disc] bearing_radial_clearance_mm) takes the
      // design's value too: the discs of one design share it, as they share the other variables.
      if (settings_.variables[j].key == "bearing.radial_clearance_mm" && d.reducer->second_disc_bearing_clearance) {
        d.reducer->second_disc_bearing_clearance = k.ToInternal(x[j]);
      }
      continue;
    }
    *k.real({&d.modification, &d.errors, &d.assembly}) = k.ToInternal(x[j]);
    if (d.second_disc) {  // the discs of one part share their design; the pin ring's keys move both
      *k.real({&d.second_disc->modification, &d.second_disc->errors, &d.second_disc->assembly}) = k.ToInternal(x[j]);
    }
  }
  return pair;
}

DesignEvaluation Optimiser::Evaluate(const std::vector<double>& x) const {
  DesignEvaluation e;
  e.x = x;
  const ToleranceCase pair = Apply(x);
  const OptimiseSettings& s = settings_;
  OptimiseFigures lower{};  // robust: each figure at 100 - percentile
  lower.fill(kNaN);
  if (!s.robust) {
    ToleranceSettings one;
    one.samples = 1;
    one.lost_motion = s.NeedsLostMotion();
    one.stage_free_play = s.NeedsBacklash();
    const ToleranceStudy study(pair, options_, one);
    const ToleranceSample sample = study.Evaluate(pair);
    std::copy(sample.figures.begin(), sample.figures.end(), e.figures.begin());
    e.status = sample.status;
    e.message = sample.message;
    if (s.NeedsEfficiency() && e.status == RunStatus::kSuccess) {
      // The efficiency over the same sweep: `ltca efficiency`'s summary (both discs with [second_disc]).
      const Stage stage(pair.design, pair.sweep.CrankAngles());
      EfficiencyRunner runner(stage, options_, pair.torque, *pair.friction, *pair.operation);
      for (const double crank : runner.cranks()) runner.Solve(crank);
      const EfficiencySummary sum = runner.Summary();
      e.figures[kPowerLossW] = sum.power_loss.mean;
      e.figures[kEfficiency] = sum.efficiency;
      if (!sum.all_succeeded()) {
        e.status = RunStatus::kFailed;
        e.message = fmt::format("efficiency: {} of {} positions did not succeed", sum.failed, sum.positions());
      }
    }
    lower = e.figures;
  } else {
    ToleranceSettings ts = s.tolerances;
    ts.samples = s.robust_samples;
    ts.lost_motion = s.NeedsLostMotion();
    ts.stage_free_play = s.NeedsBacklash();
    ts.limits.clear();
    const ToleranceStudy study(pair, options_, ts);
    std::vector<ToleranceSample> samples;
    if (ranks_.size > 1) {  // this rank's block of the samples, then every rank's
      const std::int64_t n = ts.samples, begin = n * ranks_.rank / ranks_.size, end = n * (ranks_.rank + 1) / ranks_.size;
      std::string mine;
      for (const ToleranceSample& t : study.RunRange(begin, end - begin, threads_)) AppendSampleBytes(t, mine);
      samples.reserve(static_cast<std::size_t>(n));
      for (const std::string& part : ranks_.all_gather(mine)) {
        ReadSampleBytes(part, study, [&](const ToleranceSample& t) { samples.push_back(t); });
      }
    } else {
      samples = study.RunRange(0, ts.samples, threads_);
    }
    e.samples = static_cast<std::int64_t>(samples.size());
    e.status = RunStatus::kSuccess;
    for (const ToleranceSample& t : samples) {
      if (t.status == RunStatus::kSuccess) continue;
      if (e.samples_failed++ == 0) e.message = fmt::format("sample {}: {}: {}", t.index, ToString(t.status), t.message);
    }
    if (e.samples_failed > 0) {
      e.status = RunStatus::kFailed;
      e.message = fmt::format("{} of {} samples did not succeed; the first, {}", e.samples_failed, e.samples, e.message);
    } else {
      for (std::size_t f = 0; f < kToleranceFigureCount; ++f) {
        std::vector<double> v;
        for (const ToleranceSample& t : samples) {
          if (std::isfinite(t.figures[f])) v.push_back(t.figures[f]);
        }
        if (v.empty()) continue;  // NaN: no sample produced the figure
        std::sort(v.begin(), v.end());
        if (s.confidence > 0.0) {
          // The order statistics that bound the percentile with the stated confidence.
          const std::int64_t n = static_cast<std::int64_t>(v.size());
          const std::int64_t k = ConfidenceRank(n, s.percentile / 100.0, s.confidence);
          e.figures[f] = k > 0 ? v[static_cast<std::size_t>(k - 1)] : kNaN;
          lower[f] = k > 0 ? v[static_cast<std::size_t>(n - k)] : kNaN;
        } else {
          e.figures[f] = SortedQuantile(v, s.percentile / 100.0);
          lower[f] = SortedQuantile(v, 1.0 - s.percentile / 100.0);
        }
      }
    }
  }
  if (e.status != RunStatus::kSuccess) {
    if (e.status == RunStatus::kFailed && e.message.empty()) e.message = "failed";
    return e;  // infeasible: objective and violation NaN
  }
  const int fo = FigureIndex(s.objective);
  if (fo >= 0) {
    const auto f = static_cast<std::size_t>(fo);
    e.objective = s.maximise ? lower[f] : e.figures[f];
  } else {
    e.objective = x[static_cast<std::size_t>(VariableIndex(s, s.objective))];
  }
  e.violation = 0.0;
  for (const ToleranceLimit& l : s.constraints) {
    const auto f = static_cast<std::size_t>(FigureIndex(l.figure));
    const double hi = e.figures[f], lo = lower[f];
    if (!std::isfinite(hi) || !std::isfinite(lo)) {
      e.violation = kNaN;
      break;
    }
    if (hi > l.max) e.violation += (hi - l.max) / std::max(std::abs(l.max), 1e-9);
    if (lo < l.min) e.violation += (l.min - lo) / std::max(std::abs(l.min), 1e-9);
  }
  if (!std::isfinite(e.objective) || !std::isfinite(e.violation)) {
    e.status = RunStatus::kFailed;
    e.message = "a figure of the objective or a constraint is not defined for this design (no valid solve produced it)";
    e.objective = e.violation = kNaN;
    return e;
  }
  e.feasible = e.violation == 0.0;
  return e;
}

OptimiseResult Optimiser::Run(const EvaluationSink& sink) const {
  const auto start = Clock::now();
  const OptimiseSettings& s = settings_;
  OptimiseResult result;
  const auto n = static_cast<unsigned>(s.variables.size());
  Search search;
  search.optimiser = this;
  search.settings = &s;
  search.result = &result;
  search.sink = &sink;
  // The centre of the box: the objective's scale.
  std::vector<double> u(n, 0.5);
  search.phase = "centre";
  const DesignEvaluation& centre = search.At(u.data());
  if (centre.status == RunStatus::kSuccess && std::isfinite(centre.objective) && centre.objective != 0.0) {
    search.scale = std::abs(centre.objective);
  }
  const std::int64_t budget = s.evaluations;
  const bool has_local = s.local != OptimiseSettings::Local::kNone;
  const std::int64_t global_budget =
      s.global == OptimiseSettings::Global::kNone ? 0
      : has_local ? std::max<std::int64_t>(1, std::llround(s.global_share * static_cast<double>(budget)))
                  : budget;
  std::vector<ConstraintSide> sides;
  for (const ToleranceLimit& l : s.constraints) {
    const int f = FigureIndex(l.figure);
    if (std::isfinite(l.max)) sides.push_back({&search, f, true, l.max});
    if (std::isfinite(l.min)) sides.push_back({&search, f, false, l.min});
  }
  const auto run_phase = [&](nlopt_algorithm algorithm, const char* method, const char* phase, std::int64_t evaluations,
                             std::vector<double>& x0, bool constrained, double step) {
    const std::int64_t before = result.evaluations;
    if (evaluations <= 0) return;
    nlopt_opt opt = nlopt_create(algorithm, n);
    if (opt == nullptr) throw std::runtime_error(fmt::format("optimise: NLopt could not create {}", method));
    std::vector<double> lo(n, 0.0), hi(n, 1.0);
    nlopt_set_lower_bounds(opt, lo.data());
    nlopt_set_upper_bounds(opt, hi.data());
    search.phase = phase;
    search.penalised = !constrained;
    search.opt = opt;
    nlopt_set_min_objective(opt, Objective, &search);
    if (constrained) {
      for (ConstraintSide& c : sides) nlopt_add_inequality_constraint(opt, Constraint, &c, 0.0);
    }
    nlopt_set_maxeval(opt, static_cast<int>(evaluations));
    if (std::string(phase) == "local") {
      nlopt_set_xtol_abs1(opt, s.tolerance);
      nlopt_set_initial_step1(opt, step);
    }
    if (algorithm == NLOPT_GN_CRS2_LM || algorithm == NLOPT_GN_ISRES) nlopt_srand(static_cast<unsigned long>(s.seed));
    double f = 0.0;
    const nlopt_result r = nlopt_optimize(opt, x0.data(), &f);
    search.opt = nullptr;
    nlopt_destroy(opt);
    if (search.error) std::rethrow_exception(search.error);
    result.phases.push_back({method, NloptStop(r), result.evaluations - before});
  };
  std::vector<double> x0(n, 0.5);
  if (s.global != OptimiseSettings::Global::kNone) {
    const nlopt_algorithm a = s.global == OptimiseSettings::Global::kDirect ? NLOPT_GN_DIRECT_L
                              : s.global == OptimiseSettings::Global::kCrs2 ? NLOPT_GN_CRS2_LM
                                                                             : NLOPT_GN_ISRES;
    // ISRES takes the constraints; DIRECT-L and CRS2 the stated penalty. The centre counts.
    run_phase(a, ToString(s.global), "global", global_budget - 1, x0, s.global == OptimiseSettings::Global::kIsres, 0.0);
  }
  if (has_local) {
    // From the best evaluation so far, feasible or not.
    std::vector<double> start_u(n, 0.5);
    if (search.best_any.best) {
      const std::vector<double>& x = search.best_any.best->x;
      for (unsigned j = 0; j < n; ++j) {
        const OptimiseVariable& v = s.variables[j];
        start_u[j] = (x[j] - v.lower) / (v.upper - v.lower);
      }
    }
    const std::int64_t left = budget - result.evaluations;
    const bool after_global = s.global != OptimiseSettings::Global::kNone;
    run_phase(s.local == OptimiseSettings::Local::kCobyla ? NLOPT_LN_COBYLA : NLOPT_LN_BOBYQA, ToString(s.local), "local", left,
              start_u, s.local == OptimiseSettings::Local::kCobyla, after_global ? 0.05 : 0.25);
  }
  if (search.best_feasible.best) {
    result.best = search.best_feasible.best->index;
    result.best_design = std::move(*search.best_feasible.best);
  }
  result.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

std::vector<DesignEvaluation> Optimiser::Grid(int points) const {
  if (points < 2 || points > 1001) throw std::invalid_argument(fmt::format("optimise: a map of {} points a variable: expected 2 to 1001", points));
  const std::size_t n = settings_.variables.size();
  std::int64_t total = 1;
  for (std::size_t j = 0; j < n; ++j) {
    total *= points;
    if (total > 10'000'000) throw std::invalid_argument("optimise: the map has more than 10,000,000 points");
  }
  // One design a thread at a time, a robust design's samples on that thread alone; the points in
  // static blocks by rank.
  const Optimiser serial(nominal_, options_, settings_, 1);
  return Divided<DesignEvaluation>(
      total, threads_, ranks_,
      [&](std::int64_t i) {
        std::vector<double> x(n);
        std::int64_t rest = i;
        for (std::size_t j = 0; j < n; ++j) {
          const OptimiseVariable& v = settings_.variables[j];
          const std::int64_t k = rest % points;
          rest /= points;
          x[j] = v.lower + (v.upper - v.lower) * static_cast<double>(k) / static_cast<double>(points - 1);
        }
        DesignEvaluation e = serial.Evaluate(x);
        e.index = i;
        e.phase = "map";
        return e;
      },
      AppendBytes, TakeEvaluation);
}

std::vector<ParetoPoint> Optimiser::Pareto(const std::string& figure, double lo, double hi, int steps) const {
  if (FigureIndex(figure) < 0) throw std::invalid_argument(fmt::format("optimise: --pareto {}: unknown figure", figure));
  if (steps < 2 || steps > 1000 || !(std::isfinite(lo) && std::isfinite(hi) && lo < hi)) {
    throw std::invalid_argument(fmt::format("optimise: a Pareto sweep of {} steps from {} to {}: expected 2 to 1000 steps, lo < hi",
                                            steps, lo, hi));
  }
  const bool random = settings_.global == OptimiseSettings::Global::kCrs2 || settings_.global == OptimiseSettings::Global::kIsres;
  return Divided<ParetoPoint>(
      steps, random ? 1 : threads_, ranks_,
      [&](std::int64_t k) {
        OptimiseSettings s = settings_;
        const double bound = lo + (hi - lo) * static_cast<double>(k) / static_cast<double>(steps - 1);
        s.constraints.push_back({figure, -std::numeric_limits<double>::infinity(), bound});
        const Optimiser step(nominal_, options_, s, 1);
        const OptimiseResult r = step.Run();
        ParetoPoint p;
        p.epsilon = bound;
        p.best = r.best;
        if (r.best >= 0) p.design = r.best_design;
        p.design.phase = "pareto";
        return p;
      },
      [](const ParetoPoint& p, std::string& out) {
        bytes::Put(out, p.epsilon);
        bytes::Put(out, p.best);
        AppendBytes(p.design, out);
      },
      [](const std::string& in, std::size_t& at) {
        ParetoPoint p;
        p.epsilon = bytes::Take<double>(in, at);
        p.best = bytes::Take<std::int64_t>(in, at);
        p.design = TakeEvaluation(in, at);
        return p;
      });
}

OptimiseRun RunOptimisation(const Optimiser& optimiser, const OptimiseRunPlan& plan) {
  OptimiseRun run;
  run.threads = optimiser.threads();
  run.ranks = optimiser.ranks().size;
  run.search = optimiser.Run(plan.sink);
  run.map = plan.map;
  if (plan.map > 0) run.grid = optimiser.Grid(plan.map);
  run.pareto = plan.pareto;
  if (!plan.pareto.empty()) run.front = optimiser.Pareto(plan.pareto, plan.pareto_from, plan.pareto_to, plan.pareto_steps);
  return run;
}

}  // namespace ltca::analysis
