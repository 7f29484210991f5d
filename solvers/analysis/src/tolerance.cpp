#include "ltca/analysis/tolerance.hpp"

#include "ltca/analysis/allowables.hpp"

#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/keys.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <new>
#include <stdexcept>
#include <system_error>
#include <thread>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/contact/holes.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/counter_rng.hpp"
#include "ltca/geometry/units.hpp"
#include "bytes.hpp"

namespace ltca::analysis {
namespace {


/// The index of a key in ToleranceSettings::ToleranceKeys(): its random stream.
std::size_t KeyIndex(const std::string& key) {
  const auto& keys = ToleranceSettings::ToleranceKeys();
  for (std::size_t k = 0; k < keys.size(); ++k) {
    if (keys[k].first == key) return k;
  }
  throw std::invalid_argument(fmt::format("[tolerances] unknown key '{}'", key));
}

/// Adds v (key unit) to pin j of a per-pin list, which is z_p zeros when the deck has none.
void AddToPin(std::vector<double>& list, int pins, int j, double v_mm) {
  if (list.empty()) list.assign(static_cast<std::size_t>(pins), 0.0);
  list[static_cast<std::size_t>(j)] += v_mm;
}

/// A key of the reducer stage ([output], [bearing]), not of the discs or the pin ring.
bool IsReducerKey(const DeckKey& k) {
  const std::string_view s(k.section);
  return s == "output" || s == "bearing";
}

/// A stage key each disc has its own of: the play of its bearing (the eccentric bearing, or its
/// cranks' needle bearings); with two discs it is drawn per disc, the second disc's going to
/// ReducerSettings::second_disc_bearing_clearance.
bool IsPerDiscStageKey(const DeckKey& k) { return std::string_view(k.section) == "bearing" && std::string_view(k.name) == "radial_clearance_mm"; }

/// A key of one value per hole of a disc ([output] hole_radial_deviations_mm,
/// hole_tangential_deviations_mm: the output pins' holes or the crank holes), drawn per hole and per disc.
bool IsPerHoleKey(const std::string& tolerance_name) {
  const DeckKey* k = FindToleranceKey(tolerance_name);
  return k != nullptr && k->per_hole;
}

/// Keys drawn once per element (a pin of the ring, or a hole of a disc): one input column each.
bool PerElement(const ToleranceDistribution& d) { return d.per_pin || IsPerHoleKey(d.key); }

/// The holes of a disc of the stage: the output pins' or the crankshafts' (ReducerSettings::Holes).
int HoleCount(const solvers::ReducerSettings& r) { return r.kind == solvers::OutputKind::kPins ? r.pins.count : r.cranks.count; }

/// Adds v (mm) to component `a` (0: radial, 1: tangential) of hole j's position deviation, the list
/// being `count` zeros when the disc has none.
void AddToHole(contact::HoleDeviations& holes, int count, int j, int a, double v_mm) {
  if (holes.empty()) holes.assign(static_cast<std::size_t>(count), Eigen::Vector2d::Zero());
  holes[static_cast<std::size_t>(j)](a) += v_mm;
}

/// The symmetry the errors break: per-pin keys, the holes' position errors and the frame-fixed assembly errors (the centre
/// offset and the tilts stay where they are while the eccentric turns) repeat only after a whole
/// crank revolution, not after one mesh period.
bool BreaksMeshPeriod(const ToleranceDistribution& d) {
  if (d.IsZero()) return false;
  return PerElement(d) || d.key == "centre_dx_mm" || d.key == "centre_dy_mm" || d.key == "misalignment_xz_deg" ||
         d.key == "misalignment_yz_deg";
}

/// The draw of a normal given as a tolerance +-t (t = 3 sigma): the normal truncated to +-3 sigma,
/// drawn exactly by the inverse distribution function of a uniform on [Phi(-3), Phi(3)] (one
/// uniform of the counter-based stream, so the draw stays a pure function of (seed, stream, i)).
/// Evaluated on the lower half by symmetry, so that p near 1 loses no digits.
double TruncatedStandardNormal(double u) {
  static const double lo = 0.5 * std::erfc(3.0 / std::sqrt(2.0));  // Phi(-3)
  const double p = lo + u * (1.0 - 2.0 * lo);                        // in [Phi(-3), Phi(3))
  const double z = p <= 0.5 ? InverseNormalCdf(p) : -InverseNormalCdf(1.0 - p);
  return std::clamp(z, -3.0, 3.0);  // rounding never puts a draw beyond the corner
}

}  // namespace

void ParallelFor(std::int64_t n, int threads, const std::function<void(std::int64_t)>& fn,
                 const std::function<void(std::int64_t)>& progress, const ThreadStarter& start) {
  std::atomic<std::int64_t> next{0}, done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  const auto work = [&](bool report) {
    while (!stop.load()) {
      const std::int64_t i = next.fetch_add(1);
      if (i >= n) break;
      try {
        fn(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        stop = true;
      }
      const std::int64_t d = done.fetch_add(1) + 1;
      if (report && progress) progress(d);
    }
  };
  std::vector<std::thread> pool;
  const int extra = static_cast<int>(std::min<std::int64_t>(std::max(threads, 1), std::max<std::int64_t>(n, 1))) - 1;
  pool.reserve(static_cast<std::size_t>(extra));
  try {
    for (int t = 0; t < extra; ++t) {
      if (start) pool.push_back(start([&work] { work(false); }));
      else pool.emplace_back(work, false);
    }
  } catch (...) {
    // A thread that cannot be started (std::system_error: resources): stop the ones running and
    // join them before the error leaves, or their std::thread destructors would terminate.
    stop = true;
    for (auto& t : pool) {
      if (t.joinable()) t.join();
    }
    try {
      throw;
    } catch (const std::system_error& e) {  // the machine's limit, not a bug: said as such (exit 2)
      throw std::invalid_argument(fmt::format("threads: the system could not start thread {} of {} ({}); give fewer threads",
                                              pool.size() + 2, extra + 1, e.what()));
    } catch (const std::bad_alloc&) {
      throw std::invalid_argument(fmt::format("threads: no memory for thread {} of {}; give fewer threads", pool.size() + 2, extra + 1));
    }
  }
  work(true);
  for (auto& t : pool) t.join();
  if (progress) progress(done.load());
  if (error) std::rethrow_exception(error);
}

double InverseNormalCdf(double p) {
  if (!(p > 0.0 && p < 1.0)) {
    if (p == 0.0) return -INFINITY;
    if (p == 1.0) return INFINITY;
    throw std::invalid_argument(fmt::format("InverseNormalCdf({}): expected a probability in [0, 1]", p));
  }
  // P. J. Acklam's rational approximation (relative error 1.15e-9), then one Halley step on
  // Phi(x) = erfc(-x / sqrt 2) / 2, which brings it to full double accuracy.
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                                 1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                 6.680131188771972e+01,  -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                 -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00, 3.754408661907416e+00};
  const double p_low = 0.02425;
  double x = 0.0;
  if (p < p_low) {
    const double q = std::sqrt(-2.0 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) / ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else if (p <= 1.0 - p_low) {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  } else {
    const double q = std::sqrt(-2.0 * std::log1p(-p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) / ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - p;
  const double u = e * std::sqrt(2.0 * units::kPi) * std::exp(0.5 * x * x);
  return x - u / (1.0 + 0.5 * x * u);
}

double ChiSquaredQuantile(double p, int m) {
  if (m < 1) throw std::invalid_argument(fmt::format("ChiSquaredQuantile: {} degrees of freedom: expected >= 1", m));
  const double z = InverseNormalCdf(p);
  if (m == 1) {
    const double z1 = InverseNormalCdf(0.5 + 0.5 * p);  // chi^2_1 = z^2: P(|Z| <= z1) = p
    return z1 * z1;
  }
  // Wilson & Hilferty (1931): (chi^2_m / m)^(1/3) is nearly normal, mean 1 - 2 / (9 m), variance 2 / (9 m).
  const double k = 2.0 / (9.0 * m);
  const double t = 1.0 - k + z * std::sqrt(k);
  return m * t * t * t;
}

std::string Describe(const ToleranceDistribution& d) {
  using Kind = ToleranceDistribution::Kind;
  std::string out = d.kind == Kind::kUniform ? fmt::format("uniform +-{:g}", d.tolerance)
                    : Truncated(d) ? fmt::format("normal truncated to +-{:g} (3 sigma, sigma {:g} before truncation)", d.tolerance, d.sigma)
                                   : fmt::format("normal, sigma {:g} (not truncated)", d.sigma);
  if (d.mean != 0.0) out += fmt::format(", centre offset {:g}", d.mean);
  if (d.per_pin) out += ", per pin";
  if (IsPerHoleKey(d.key)) out += ", per hole of each disc";
  return out;
}

void SampleTable::Reserve(std::int64_t count) {
  figures_.reserve(static_cast<std::size_t>(count));
  status_.reserve(static_cast<std::size_t>(count));
}

void SampleTable::Add(const ToleranceSample& s) {
  if (s.index != first_ + size()) {
    throw std::logic_error(fmt::format("tolerance: sample {} added after {} samples from {}: expected sample order", s.index, size(), first_));
  }
  const RunStatus status = s.status;
  if (status != RunStatus::kSuccess && first_failure_index_ < 0) first_failure_index_ = s.index, first_failure_message_ = s.message;
  figures_.push_back(s.figures);
  status_.push_back(status);
  if (std::isfinite(s.preload_stress_mpa)) {
    preload_.push_back(static_cast<float>(s.preload_stress_mpa));
    preload_.push_back(static_cast<float>(s.preload_force_n));
  }
}

double ToleranceDistribution::StandardDeviation() const {
  if (kind == Kind::kUniform) return tolerance / std::sqrt(3.0);
  if (tolerance == 0.0) return sigma;  // given by sigma: not truncated
  // Given as +-tolerance (3 sigma): the normal truncated there, as ToleranceStudy::Draw draws it
  // (Johnson, Kotz & Balakrishnan 1994, vol. 1, ch. 13 sec. 10.1).
  constexpr double a = 3.0;
  const double phi = std::exp(-0.5 * a * a) / std::sqrt(2.0 * units::kPi);
  const double mass = std::erf(a / std::sqrt(2.0));  // 2 Phi(a) - 1
  return sigma * std::sqrt(1.0 - 2.0 * a * phi / mass);
}


const std::vector<std::pair<std::string, bool>>& ToleranceSettings::ToleranceKeys() {
  // From the table of deck keys, in the order of their random streams (DeckKey::tolerance_stream:
  // a key's stream is its index here, so a new key takes the next number).
  static const std::vector<std::pair<std::string, bool>> kKeys = [] {
    std::vector<std::pair<std::string, bool>> keys;
    for (const DeckKey* k : ToleranceVariableKeys()) keys.emplace_back(k->ToleranceName(), k->per_pin);
    return keys;
  }();
  return kKeys;
}

const std::vector<std::string>& ToleranceSettings::FigureNames() {
  static const std::vector<std::string> kNames = {
      "mean_backlash_arcsec", "pp_backlash_arcsec", "mean_te_arcsec",         "pp_te_arcsec",
      "max_contact_stress_mpa", "max_pin_force_n",  "contacts_min",           "contacts_max",
      "lost_motion_arcmin", "max_output_pin_force_n", "max_bearing_load_n", "shortest_l10_hours"};
  return kNames;
}

void ToleranceSettings::Validate() const {
  if (samples < 1 || samples > kMaxSamples) {
    throw std::invalid_argument(fmt::format("[tolerances] samples = {}: expected an integer from 1 to {}", samples, kMaxSamples));
  }
  for (const ToleranceDistribution& d : distributions) {
    for (const auto& [name, v] : {std::pair{"sigma", d.sigma}, std::pair{"tolerance", d.tolerance}}) {
      if (!(std::isfinite(v) && v >= 0.0)) {
        throw std::invalid_argument(fmt::format("[tolerances] {}.{} = {}: expected a finite value >= 0 in the key's unit", d.key, name, v));
      }
    }
    if (!std::isfinite(d.mean)) {
      throw std::invalid_argument(fmt::format("[tolerances] {}.mean = {}: expected a finite offset in the key's unit", d.key, d.mean));
    }
  }
  const auto& names = FigureNames();
  for (std::size_t i = 0; i < limits.size(); ++i) {
    const ToleranceLimit& l = limits[i];
    if (std::find(names.begin(), names.end(), l.figure) == names.end()) {
      throw std::invalid_argument(fmt::format("[tolerances] limits.{}: unknown figure; expected one of: {}", l.figure, fmt::join(names, ", ")));
    }
    if (std::isnan(l.min) || std::isnan(l.max) || !(l.min <= l.max) || (std::isinf(l.min) && std::isinf(l.max))) {
      throw std::invalid_argument(fmt::format(
          "[tolerances] limits.{} = {{ min = {}, max = {} }}: expected finite limits with min <= max (at least one given)", l.figure,
          l.min, l.max));
    }
    if (l.figure == "lost_motion_arcmin" && !lost_motion) {
      throw std::invalid_argument("[tolerances] limits.lost_motion_arcmin: lost motion is not run; expected lost_motion = true with this limit");
    }
  }
}

ToleranceStudy::ToleranceStudy(ToleranceCase nominal, const SolverOptions& options, const ToleranceSettings& settings)
    : nominal_(std::move(nominal)), options_(options), settings_(settings) {
  options_.Validate();
  settings_.Validate();
  if (!nominal_.design.material) {
    throw std::invalid_argument(fmt::format("deck '{}': missing required section [material] for this command", nominal_.design.name));
  }
  if (settings_.lost_motion) nominal_.stiffness.Validate();
  // Two discs: a key of one disc (DeckKey::disc: the modification, the disc's own
  // errors) is drawn for each disc on its own, the pin ring's keys once for both, and the second
  // disc's indexing deviation is a key of its own.
  const bool two = nominal_.design.second_disc.has_value();
  const int pins = nominal_.design.pair.pin_count;
  for (std::size_t k = 0; k < settings_.distributions.size(); ++k) {
    const ToleranceDistribution& d = settings_.distributions[k];
    KeyIndex(d.key);  // a known key
    const DeckKey* key = FindToleranceKey(d.key);
    if (key != nullptr && std::string_view(key->section) == "second_disc" && !two) {
      throw std::invalid_argument(fmt::format("deck '{}': [tolerances] {}: the deck has no [second_disc] to index; expected "
                                              "a [second_disc] section, or no such tolerance",
                                              nominal_.design.name, d.key));
    }
    if (key != nullptr && key->per_hole && !nominal_.design.reducer) {
      throw std::invalid_argument(fmt::format("deck '{}': [tolerances] {}: the deck has no reducer stage, so no holes; expected an "
                                              "[output] section (docs/stage.md), or no such tolerance",
                                              nominal_.design.name, d.key));
    }
    if (key != nullptr && IsReducerKey(*key) && !key->per_hole) {  // a clearance of the reducer stage
      const std::string why = StageClearanceRefusal(nominal_.design.reducer, std::string(key->section) + "." + key->name);
      if (!why.empty()) throw std::invalid_argument(fmt::format("deck '{}': [tolerances] {}: {}", nominal_.design.name, d.key, why));
    }
    // Per disc: the disc's own keys, its bearing's play and its holes' positions (discs are machined one by one).
    const bool per_disc = key != nullptr && (key->disc || ((IsPerDiscStageKey(*key) || key->per_hole) && nominal_.design.reducer));
    const int discs = two && per_disc ? 2 : 1;
    for (int disc = 0; disc < discs; ++disc) {
      const std::string suffix = disc == 1 ? " (disc 2)" : "";
      if (key != nullptr && key->per_hole) {  // one column per hole: its stream's low word is hole + 1
        for (int j = 0; j < HoleCount(*nominal_.design.reducer); ++j) {
          inputs_.push_back({fmt::format("{}[{}]{}", d.key, j + 1, suffix), k, j, disc});
        }
      } else if (d.per_pin) {
        for (int j = 0; j < pins; ++j) inputs_.push_back({fmt::format("{}[{}]{}", d.key, j + 1, suffix), k, j, disc});
      } else {
        inputs_.push_back({d.key + suffix, k, -1, disc});
      }
    }
  }
  const double span = nominal_.sweep.crank_end - nominal_.sweep.crank_start;
  const double revolution = 2.0 * units::kPi;
  const double step = nominal_.sweep.positions > 1 ? span / (nominal_.sweep.positions - 1) : revolution;
  if (std::any_of(settings_.distributions.begin(), settings_.distributions.end(), BreaksMeshPeriod) &&
      span + step < revolution * (1.0 - 1e-9)) {
    notes_.push_back(fmt::format(
        "per-pin errors (and the frame-fixed centre offset and tilts) break the mesh-period symmetry: the contact "
        "pattern repeats only after a whole crank revolution (360 deg), but the deck's sweep covers {:g} deg; the "
        "figures are over that part of the revolution only (set [sweep] crank_start_deg = 0, crank_end_deg = 360 - "
        "step for the whole revolution)",
        units::RadToDeg(span)));
  }
  for (const ToleranceLimit& l : settings_.limits) {
    const auto& names = ToleranceSettings::FigureNames();
    const auto f = static_cast<std::size_t>(std::find(names.begin(), names.end(), l.figure) - names.begin());
    if (f < names.size() && !ReducerHasFigure(nominal_.design.reducer, f)) {
      throw std::invalid_argument(fmt::format("deck '{}': [tolerances] limits.{}: a figure of a reducer stage{}; expected an [output] "
                                              "section (docs/stage.md), or no such limit",
                                              nominal_.design.name, l.figure,
                                              f == kMaxOutputPinForceN && nominal_.design.reducer ? " with output pins" : ""));
    }
  }
  if (nominal_.design.reducer && settings_.stage_free_play) {
    if (nominal_.torque == 0.0) {
      throw std::invalid_argument(fmt::format("deck '{}': [tolerances] with [output]: [load] torque_nm = 0: expected a non-zero "
                                              "rated torque (a stage's backlash in each sample is its free play, the output's "
                                              "rotation at +-1e-7 of that torque; docs/tolerance.md)",
                                              nominal_.design.name));
    }
    notes_.push_back(
        "a reducer stage: mean_backlash_arcsec and pp_backlash_arcsec are the stage's free play over the sweep (the "
        "output's rotation at +-1e-7 T from either flank, `ltca stiffness`'s backlash: every clearance of the stage "
        "taken up), not the pin ring's unloaded analysis");
  }
  if (settings_.lost_motion && nominal_.torque == 0.0) {
    throw std::invalid_argument("[tolerances] lost_motion = true: expected a non-zero [load] torque_nm (the rated torque of the loop)");
  }
}

bool ReducerHasFigure(const std::optional<solvers::ReducerSettings>& reducer, std::size_t figure) {
  switch (figure) {
    case kMaxOutputPinForceN: return reducer.has_value() && reducer->kind == solvers::OutputKind::kPins;
    case kMaxBearingLoadN:
    case kShortestL10Hours: return reducer.has_value();
    default: return figure < kToleranceFigureCount;
  }
}

void LoadedFigures(const SweepSummary& sweep, bool output_pins, ToleranceFigures& figures) {
  figures[kMeanTeArcsec] = units::RadToArcsec(sweep.mean_te);
  figures[kPpTeArcsec] = units::RadToArcsec(sweep.pp_te);
  figures[kMaxContactStressMpa] = sweep.max_contact_stress;
  figures[kMaxPinForceN] = sweep.max_pin_force;
  if (sweep.succeeded > 0) {
    figures[kContactsMin] = sweep.contacts_min;
    figures[kContactsMax] = sweep.contacts_max;
  }
  if (sweep.reducer) {  // a reducer stage's loads, as `ltca solve` gives them
    if (output_pins) figures[kMaxOutputPinForceN] = sweep.reducer->max_output_force;
    figures[kMaxBearingLoadN] = sweep.reducer->max_bearing_load;
  }
}

bool ToleranceStudy::Runs(std::size_t figure) const {
  if (figure == kLostMotionArcmin) return settings_.lost_motion;
  return ReducerHasFigure(nominal_.design.reducer, figure);
}

std::vector<double> ToleranceStudy::Draw(std::int64_t i) const {
  std::vector<double> out(inputs_.size());
  const auto index = static_cast<std::uint64_t>(i);
  for (std::size_t c = 0; c < inputs_.size(); ++c) {
    const ToleranceDistribution& d = settings_.distributions[inputs_[c].distribution];
    // Stream: the key's index in the key table (high word) and pin + 1 (low word; 0 for a scalar),
    // bit 31 of the low word set for the second disc's own draw (the first disc's streams are those
    // of one disc, so a one-disc study draws what it drew before two discs existed).
    const std::uint64_t disc_bit = inputs_[c].disc == 1 ? std::uint64_t{1} << 31 : 0;
    const std::uint64_t stream = (static_cast<std::uint64_t>(KeyIndex(d.key)) << 32) |
                                 (static_cast<std::uint64_t>(inputs_[c].pin + 1) | disc_bit);
    if (Truncated(d)) {
      out[c] = d.mean + d.sigma * TruncatedStandardNormal(geometry::rng::Uniform01(settings_.seed, stream, index));
    } else if (d.kind == ToleranceDistribution::Kind::kNormal) {
      out[c] = d.mean + d.sigma * geometry::rng::StandardNormal(settings_.seed, stream, index);
    } else {
      out[c] = d.mean + d.tolerance * (2.0 * geometry::rng::Uniform01(settings_.seed, stream, index) - 1.0);
    }
  }
  return out;
}

ToleranceCase ToleranceStudy::Apply(const std::vector<double>& inputs) const {
  if (inputs.size() != inputs_.size()) {
    throw std::invalid_argument(fmt::format("tolerance: {} input values for {} input columns", inputs.size(), inputs_.size()));
  }
  ToleranceCase out = nominal_;
  StageDesign& d = out.design;
  const int pins = d.pair.pin_count;
  for (std::size_t c = 0; c < inputs_.size(); ++c) {
    const double v = inputs[c];
    if (v == 0.0) continue;  // the deck's own value, untouched (zero tolerances give the deck bit for bit)
    const std::string& key = settings_.distributions[inputs_[c].distribution].key;
    const int j = inputs_[c].pin;
    const DeckKey* k = FindToleranceKey(key);
    SecondDisc* second = d.second_disc ? &*d.second_disc : nullptr;
    if (k != nullptr && std::string_view(k->section) == "second_disc" && second != nullptr) {
      // The indexing deviation turns the second disc in the sense of +T, as the deck reader does.
      const double direction = d.pair.ToothDifference() > 0 ? 1.0 : -1.0;
      second->indexing_deviation += k->ToInternal(v);
      second->modification.rotation += direction * k->ToInternal(v) / d.pair.pin_circle_radius;
      continue;
    }
    if (k != nullptr && k->per_hole) {  // a hole's position on its disc (the constructor checked the stage has holes)
      solvers::ReducerSettings& r = *d.reducer;
      const int a = std::string_view(k->name) == "hole_radial_deviations_mm" ? 0 : 1;
      // With two discs the second has its own list from the first draw on: the deck's own for it, or
      // the common one as the deck gives it (before this sample's draws for the first disc).
      if (second != nullptr && !r.second_disc_holes) r.second_disc_holes = nominal_.design.reducer->Holes(0);
      contact::HoleDeviations& holes =
          inputs_[c].disc == 1 && second != nullptr ? *r.second_disc_holes
          : r.kind == solvers::OutputKind::kPins    ? r.pins.hole_deviation
                                                    : r.cranks.hole_deviation;
      AddToHole(holes, HoleCount(r), j, a, k->ToInternal(v));
      continue;
    }
    if (k != nullptr && IsReducerKey(*k)) {  // the stage's, one for the stage (the constructor checked it has one)
      if (IsPerDiscStageKey(*k) && second != nullptr) {
        // Each disc's bearing its own draw: the second's play starts from its own (or the common) value.
        if (!d.reducer->second_disc_bearing_clearance) d.reducer->second_disc_bearing_clearance = d.reducer->bearing.radial_clearance;
        if (inputs_[c].disc == 1) {
          *d.reducer->second_disc_bearing_clearance += k->ToInternal(v);
          continue;
        }
      }
      double* field = ReducerClearance(*d.reducer, std::string(k->section) + "." + k->name);
      if (field == nullptr) throw std::logic_error(fmt::format("tolerance: key '{}' has no field in the stage's settings", key));
      *field += k->ToInternal(v);
      continue;
    }
    const auto apply = [&](const DiscParts& parts) {
      if (k != nullptr && k->list != nullptr) AddToPin(*k->list(parts), pins, j, k->ToInternal(v));
      else if (k != nullptr && k->real != nullptr) *k->real(parts) += k->ToInternal(v);
      else throw std::logic_error(fmt::format("tolerance: key '{}' has no field in the table of deck keys", key));
    };
    const DiscParts first{&d.modification, &d.errors, &d.assembly};
    if (inputs_[c].disc == 1 && second != nullptr) {
      apply({&second->modification, &second->errors, &second->assembly});
    } else {
      apply(first);
      // The pin ring is common to both discs: the second disc's copy of it moves with it.
      if (second != nullptr && k != nullptr && !k->disc) apply({&second->modification, &second->errors, &second->assembly});
    }
  }
  return out;
}

ToleranceSample ToleranceStudy::Evaluate(const ToleranceCase& pair) const {
  ToleranceSample s;
  try {
    const StageDesign& design = pair.design;
    design.errors.Validate(design.pair.pin_count);
    design.assembly.Validate();
    design.modification.Validate(design.pair);
    if (design.second_disc) {
      design.second_disc->errors.Validate(design.pair.pin_count);
      design.second_disc->assembly.Validate();
      design.second_disc->modification.Validate(design.pair);
    }
    // One stage for every figure of the sample, checked at the sweep's cranks.
    const Stage stage(design, pair.sweep.CrankAngles());
    const std::vector<double>& cranks = stage.cranks();
    // Unloaded TCA over the sweep: the arithmetic of `ltca backlash` (mean = sum / n).
    // The unloaded sweep's rule: a closed period's repeated state weighs once in the mean.
    std::string free_play_failure;  // a reducer stage's free play that could not be solved
    std::string backlash_failure;   // a position where no pin closes a flank's gap
    if (!design.reducer) {
      // `ltca backlash`'s rule (analysis/backlash.hpp): with two discs the first contact of either.
      const BacklashSummary backlash = Backlash(stage, stage.kinematics()).summary;
      s.figures[kMeanBacklashArcsec] = units::RadToArcsec(backlash.mean());
      s.figures[kPpBacklashArcsec] = units::RadToArcsec(backlash.pp());
      if (backlash.failed() > 0) backlash_failure = fmt::format("unloaded backlash: {}", backlash.first_failure());
    } else if (settings_.stage_free_play) {
      // A reducer stage: the pin ring's unloaded analysis is not the reducer's backlash.
      // Its free play takes up every element's clearance: `ltca stiffness`'s backlash (the output's
      // rotation at +-1e-7 T from either flank), over the same sweep.
      StiffnessSettings over_sweep = pair.stiffness;
      over_sweep.crank.reset();
      StiffnessRunner free_play(stage, options_, over_sweep, pair.torque, std::nullopt);
      for (const double crank : cranks) free_play.SolveFreePlay(crank);
      const StiffnessSummary fp = free_play.Summary();
      if (fp.all_succeeded()) {
        s.figures[kMeanBacklashArcsec] = units::RadToArcsec(fp.backlash.mean);
        s.figures[kPpBacklashArcsec] = units::RadToArcsec(fp.backlash.max - fp.backlash.min);
      } else {
        free_play_failure = fmt::format("the stage's free play: {}", fp.first_failure);
      }
    }
    // Loaded TCA over the sweep: `ltca solve`'s summary.
    SweepRunner runner(stage, options_, pair.torque);
    std::string first_failure;  // the first position that did not succeed: where, and the solver's own words
    for (const double crank : cranks) {
      const PositionResult p = runner.Solve(crank);
      if (!p.succeeded() && first_failure.empty()) {
        first_failure = fmt::format("first at crank {:g} deg: {}: {}", units::RadToDeg(crank), solvers::ToString(p.result.status),
                                    p.result.message);
      }
    }
    const SweepSummary sum_loaded = runner.Summary();
    LoadedFigures(sum_loaded, ReducerHasFigure(design.reducer, kMaxOutputPinForceN), s.figures);
    if (design.reducer && sum_loaded.reducer) {  // a reducer stage's life, as `ltca solve` gives it
      s.figures[kShortestL10Hours] = BearingLives(design, *sum_loaded.reducer, pair.sweep, sum_loaded.closed_period,
                                                  pair.operation ? pair.operation->input_speed : kNaN)
                                         .ShortestHours();
    }
    if (sum_loaded.preloaded > 0) {
      s.preload_stress_mpa = sum_loaded.max_preload_stress;
      s.preload_force_n = sum_loaded.max_preload_force;
    }
    if (sum_loaded.cannot_assemble > 0) {
      // A preloaded pair beyond its assembly limits: not a reducer that fails, one that is not built.
      s.status = RunStatus::kCannotAssemble;
      s.message = fmt::format("{} of {} loaded positions cannot be assembled; {}", sum_loaded.cannot_assemble,
                              sum_loaded.positions(), first_failure);
    } else if (!sum_loaded.all_succeeded()) {
      s.status = RunStatus::kFailed;
      s.message = fmt::format("{} of {} loaded positions did not succeed ({}); {}", sum_loaded.failed, sum_loaded.positions(),
                              solvers::ToString(sum_loaded.status), first_failure);
    }
    if (!backlash_failure.empty() && s.status == RunStatus::kSuccess) {
      s.status = RunStatus::kFailed;
      s.message = backlash_failure;
    }
    if (!free_play_failure.empty() && s.status == RunStatus::kSuccess) {
      s.status = RunStatus::kFailed;
      s.message = free_play_failure;
    }
    if (settings_.lost_motion) {
      // Lost motion is solved at its own torques (+-f T), without the loop's curve.
      StiffnessRunner loop(stage, options_, pair.stiffness, pair.torque, pair.friction);
      for (const double crank : loop.cranks()) loop.SolveLostMotion(crank);
      const StiffnessSummary ss = loop.Summary();
      s.figures[kLostMotionArcmin] = units::RadToArcmin(ss.lost_motion.mean);
      if (!ss.all_succeeded() && s.status == RunStatus::kSuccess) {
        s.status = RunStatus::kFailed;
        s.message = fmt::format("lost motion: {}", ss.first_failure);
      }
    }
  } catch (const std::invalid_argument& e) {  // interference, an undercut profile, ...
    s = ToleranceSample{};
    s.status = RunStatus::kRejected;
    s.message = e.what();
  }
  return s;
}

ToleranceSample ToleranceStudy::Run(std::int64_t i) const {
  std::vector<double> inputs = Draw(i);
  ToleranceCase pair = Apply(inputs);
  if (settings_.profile_random_per_sample) {
    // Its own stream, above every key's and chain's: (0xFFFFFFFF << 32), counter i.
    pair.design.errors.profile_random.seed = geometry::rng::Bits128(settings_.seed, std::uint64_t{0xFFFFFFFF} << 32, static_cast<std::uint64_t>(i))[0];
  }
  ToleranceSample s = Evaluate(pair);
  s.index = i;
  s.inputs = std::move(inputs);
  return s;
}

std::vector<ToleranceSample> ToleranceStudy::RunRange(std::int64_t first, std::int64_t count, int threads,
                                                      const std::function<void(std::int64_t)>& progress) const {
  if (first < 0 || count < 0) throw std::invalid_argument(fmt::format("tolerance: samples {} .. {}: expected indices >= 0", first, first + count - 1));
  std::vector<ToleranceSample> out;
  out.reserve(static_cast<std::size_t>(count));
  RunStream(first, count, threads, [&](const ToleranceSample& s) { out.push_back(s); }, progress);
  return out;
}

void ToleranceStudy::RunStream(std::int64_t first, std::int64_t count, int threads,
                               const std::function<void(const ToleranceSample&)>& sink,
                               const std::function<void(std::int64_t)>& progress) const {
  if (first < 0 || count < 0) throw std::invalid_argument(fmt::format("tolerance: samples {} .. {}: expected indices >= 0", first, first + count - 1));
  if (threads < 1 || threads > kMaxToleranceThreads) {
    throw std::invalid_argument(fmt::format("--threads {}: expected 1 to {}", threads, kMaxToleranceThreads));
  }
  // Blocks of 64 samples a thread: the threads wait for one another only at the end of a block
  // (about 1 % of the time), and at most one block of samples is held.
  const std::int64_t block = std::int64_t{64} * threads;
  std::vector<ToleranceSample> part;
  for (std::int64_t start = 0; start < count; start += block) {
    const std::int64_t m = std::min(block, count - start);
    part.assign(static_cast<std::size_t>(m), ToleranceSample{});
    ParallelFor(
        m, threads, [&](std::int64_t k) { part[static_cast<std::size_t>(k)] = Run(first + start + k); },
        progress ? std::function<void(std::int64_t)>([&](std::int64_t done) { progress(start + done); }) : nullptr);
    for (const ToleranceSample& s : part) sink(s);
  }
}

double SortedQuantile(const std::vector<double>& sorted, double p) {
  const double h = (static_cast<double>(sorted.size()) - 1.0) * p;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

FigureStats ComputeStats(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }), values.end());
  FigureStats f;
  f.count = static_cast<std::int64_t>(values.size());
  if (values.empty()) return f;
  std::sort(values.begin(), values.end());
  double sum = 0.0;
  for (const double v : values) sum += v;
  f.mean = sum / static_cast<double>(values.size());
  if (values.size() > 1) {
    double ss = 0.0;
    for (const double v : values) ss += (v - f.mean) * (v - f.mean);
    f.std = std::sqrt(ss / static_cast<double>(values.size() - 1));
  }
  // The p-th percentile only where n min(p, 1 - p) >= 1 (kPercentileRule), in whole percent so
  // that the rule is exact.
  const auto quantile = [&](int percent) {
    return f.count * std::min(percent, 100 - percent) >= 100 ? SortedQuantile(values, percent / 100.0)
                                                             : std::numeric_limits<double>::quiet_NaN();
  };
  f.p1 = quantile(1), f.p5 = quantile(5), f.p50 = quantile(50), f.p95 = quantile(95), f.p99 = quantile(99);
  f.min = values.front(), f.max = values.back();
  return f;
}

ToleranceSummary Summarise(const ToleranceStudy& study, const std::vector<ToleranceSample>& samples) {
  SampleTable table(samples.empty() ? 0 : samples.front().index);
  table.Reserve(static_cast<std::int64_t>(samples.size()));
  for (const auto& s : samples) table.Add(s);
  return Summarise(study, table);
}

ToleranceSummary Summarise(const ToleranceStudy& study, const SampleTable& samples) {
  ToleranceSummary out;
  const std::int64_t n_all = samples.size();
  out.samples = n_all;
  out.seed = study.settings().seed;
  for (std::int64_t k = 0; k < n_all; ++k) {
    switch (samples.status(k)) {
      case RunStatus::kSuccess: ++out.succeeded; break;
      case RunStatus::kFailed: ++out.failed; break;
      case RunStatus::kRejected: ++out.rejected; break;
      case RunStatus::kCannotAssemble: ++out.cannot_assemble; break;
      case RunStatus::kNotRun: break;  // a sample is always run
    }
  }
  {
    std::vector<double> stress, force;
    out.preloaded = samples.preloaded();
    for (std::int64_t j = 0; j < out.preloaded; ++j) {
      stress.push_back(samples.preload_stress(j));
      force.push_back(samples.preload_force(j));
    }
    out.preload_stress = ComputeStats(std::move(stress));
    out.preload_force = ComputeStats(std::move(force));
  }
  const auto& names = ToleranceSettings::FigureNames();
  // A figure's value in a successful sample, NaN otherwise.
  const auto value = [&](std::int64_t k, std::size_t f) { return samples.succeeded(k) ? samples.figures(k)[f] : kNaN; };
  for (std::size_t f = 0; f < kToleranceFigureCount; ++f) {
    std::vector<double> v;
    v.reserve(static_cast<std::size_t>(out.succeeded));
    for (std::int64_t k = 0; k < n_all; ++k) {
      if (samples.succeeded(k)) v.push_back(samples.figures(k)[f]);
    }
    out.figures[f] = ComputeStats(std::move(v));
  }
  // Limits: a sample passes when it succeeded and its figure is within [min, max].
  const auto figure_index = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
  };
  const auto within = [&](std::int64_t k, const ToleranceLimit& l) {  // the allowables check's rule
    return AllowableRange{l.min, l.max}.Holds(value(k, figure_index(l.figure)));
  };
  for (const ToleranceLimit& l : study.settings().limits) {
    LimitResult r;
    r.limit = l;
    for (std::int64_t k = 0; k < n_all; ++k) r.passed += within(k, l) ? 1 : 0;
    r.fraction = out.samples > 0 ? static_cast<double>(r.passed) / static_cast<double>(out.samples) : kNaN;
    out.limits.push_back(r);
  }
  if (!study.settings().limits.empty()) {
    const auto& limits = study.settings().limits;
    for (std::int64_t k = 0; k < n_all; ++k) {
      out.passed_all += std::all_of(limits.begin(), limits.end(), [&](const ToleranceLimit& l) { return within(k, l); }) ? 1 : 0;
    }
    out.pass_fraction = out.samples > 0 ? static_cast<double>(out.passed_all) / static_cast<double>(out.samples) : kNaN;
  }

  // Sensitivity: SRC of every figure on every input column, by the normal equations of the
  // standardised least-squares problem. The inputs are drawn again in chunks of rows (Draw(i) is
  // a pure function of (seed, i)); one pass accumulates, per figure, the counts, the sums of the
  // inputs (shifted by their distributions' centres, so no digits cancel) and the cross products.
  const auto& inputs = study.inputs();
  const auto& dists = study.settings().distributions;
  const auto cols = static_cast<Eigen::Index>(inputs.size());
  Eigen::VectorXd shift(cols);
  for (Eigen::Index c = 0; c < cols; ++c) shift(c) = dists[inputs[static_cast<std::size_t>(c)].distribution].mean;
  struct Sums {
    std::int64_t n = 0;
    double y_mean = 0.0, yy = 0.0, y_sum = 0.0;  // y centred on its mean (computed first, below)
    Eigen::VectorXd x, xy;
    Eigen::MatrixXd xx;
  };
  std::array<Sums, kToleranceFigureCount> sums;
  for (std::size_t f = 0; f < kToleranceFigureCount; ++f) {
    Sums& a = sums[f];
    a.x = Eigen::VectorXd::Zero(cols), a.xy = Eigen::VectorXd::Zero(cols), a.xx = Eigen::MatrixXd::Zero(cols, cols);
    double total = 0.0;
    for (std::int64_t k = 0; k < n_all; ++k) {
      const double y = value(k, f);
      if (std::isfinite(y)) ++a.n, total += y;
    }
    a.y_mean = a.n > 0 ? total / static_cast<double>(a.n) : kNaN;
  }
  const bool fit_any = cols > 0 && std::any_of(sums.begin(), sums.end(), [&](const Sums& a) { return a.n >= cols + 2; });
  if (fit_any) {
    constexpr Eigen::Index kChunk = 512;
    Eigen::MatrixXd x(kChunk, cols), xm(kChunk, cols);
    Eigen::VectorXd y(kChunk);
    std::vector<std::int64_t> rows;
    rows.reserve(kChunk);
    const auto flush = [&] {
      const auto m = static_cast<Eigen::Index>(rows.size());
      if (m == 0) return;
      for (Eigen::Index r = 0; r < m; ++r) {
        const std::vector<double> drawn = study.Draw(samples.index(rows[static_cast<std::size_t>(r)]));
        for (Eigen::Index c = 0; c < cols; ++c) x(r, c) = drawn[static_cast<std::size_t>(c)] - shift(c);
      }
      const auto xs = x.topRows(m);
      Eigen::MatrixXd gram;  // X^T X of the whole chunk, shared by the figures finite in every row
      for (std::size_t f = 0; f < kToleranceFigureCount; ++f) {
        Sums& a = sums[f];
        if (a.n < cols + 2) continue;
        bool all = true;
        for (Eigen::Index r = 0; r < m; ++r) {
          const double v = value(rows[static_cast<std::size_t>(r)], f);
          y(r) = std::isfinite(v) ? v - a.y_mean : 0.0;
          all = all && std::isfinite(v);
        }
        if (all) {
          if (gram.size() == 0) gram.noalias() = xs.transpose() * xs;
          a.xx += gram;
          a.x += xs.colwise().sum().transpose();
        } else {  // rows without the figure weigh 0
          for (Eigen::Index r = 0; r < m; ++r) {
            if (std::isfinite(value(rows[static_cast<std::size_t>(r)], f))) xm.row(r) = xs.row(r);
            else xm.row(r).setZero();
          }
          a.xx.noalias() += xm.topRows(m).transpose() * xm.topRows(m);
          a.x += xm.topRows(m).colwise().sum().transpose();
        }
        a.xy.noalias() += xs.transpose() * y.head(m);
        a.yy += y.head(m).squaredNorm();
        a.y_sum += y.head(m).sum();
      }
      rows.clear();
    };
    for (std::int64_t k = 0; k < n_all; ++k) {
      if (!samples.succeeded(k)) continue;
      rows.push_back(k);
      if (static_cast<Eigen::Index>(rows.size()) == kChunk) flush();
    }
    flush();
  }
  for (std::size_t f = 0; f < kToleranceFigureCount; ++f) {
    FigureSensitivity fs;
    fs.figure = names[f];
    const Sums& a = sums[f];
    const Eigen::Index n = a.n;
    fs.samples = n;
    if (cols == 0) {
      fs.note = "no tolerance given";
      out.sensitivity.push_back(std::move(fs));
      continue;
    }
    if (n < cols + 2) {
      fs.note = fmt::format("{} successful samples for {} input columns: at least {} are needed", n, cols, cols + 2);
      out.sensitivity.push_back(std::move(fs));
      continue;
    }
    // Centred cross products: sum (x - xbar)(x - xbar)^T = sum x x^T - n xbar xbar^T (x shifted).
    const double nn = static_cast<double>(n);
    const Eigen::VectorXd xbar = a.x / nn;
    const Eigen::MatrixXd cxx = a.xx - nn * xbar * xbar.transpose();
    const Eigen::VectorXd cxy = a.xy - xbar * a.y_sum;
    const double syy = a.yy - a.y_sum * a.y_sum / nn;
    if (!(syy > 0.0)) {
      fs.note = "the figure does not vary over the samples";
      out.sensitivity.push_back(std::move(fs));
      continue;
    }
    // Standardised: the correlation matrix R and the correlations r of the inputs with the figure.
    std::vector<Eigen::Index> varying;
    for (Eigen::Index c = 0; c < cols; ++c) {
      if (cxx(c, c) > 0.0) varying.push_back(c);
    }
    const auto p = static_cast<Eigen::Index>(varying.size());
    Eigen::MatrixXd r_xx(p, p);
    Eigen::VectorXd r_xy(p);
    for (Eigen::Index i = 0; i < p; ++i) {
      const Eigen::Index ci = varying[static_cast<std::size_t>(i)];
      r_xy(i) = cxy(ci) / std::sqrt(cxx(ci, ci) * syy);
      for (Eigen::Index j = 0; j < p; ++j) {
        const Eigen::Index cj = varying[static_cast<std::size_t>(j)];
        r_xx(i, j) = cxx(ci, cj) / std::sqrt(cxx(ci, ci) * cxx(cj, cj));
      }
    }
    Eigen::VectorXd beta = Eigen::VectorXd::Zero(cols), correlation = Eigen::VectorXd::Zero(cols);
    if (p > 0) {
      const Eigen::VectorXd b = r_xx.colPivHouseholderQr().solve(r_xy);
      for (Eigen::Index i = 0; i < p; ++i) {
        beta(varying[static_cast<std::size_t>(i)]) = b(i);
        correlation(varying[static_cast<std::size_t>(i)]) = r_xy(i);
      }
      // R^2 = b^T r at the least-squares solution (the standardised figure has unit variance).
      fs.r_squared = std::clamp(b.dot(r_xy), 0.0, 1.0);
    } else {
      fs.r_squared = 0.0;
    }
    const double dof = static_cast<double>(n - p - 1);
    const double q_all = p > 0 ? ChiSquaredQuantile(kNoiseFloorLevel, static_cast<int>(p)) : 0.0;
    fs.r_squared_floor = q_all / (q_all + dof);
    for (std::size_t k = 0; k < dists.size(); ++k) {
      KeySensitivity ks;
      ks.key = dists[k].key;
      double share = 0.0, squared = 0.0;
      for (Eigen::Index c = 0; c < cols; ++c) {
        if (inputs[static_cast<std::size_t>(c)].distribution != k || !(cxx(c, c) > 0.0)) continue;
        share += beta(c) * correlation(c);  // Pratt: sum over every column is b^T r = R^2
        squared += beta(c) * beta(c);
        ++ks.columns;
        if (!PerElement(dists[k])) ks.src = beta(c);
      }
      ks.share = share;
      ks.src_squared = squared;
      if (!PerElement(dists[k]) && std::isnan(ks.src)) ks.src = 0.0;
      if (ks.columns > 0) {
        ks.noise_floor = ChiSquaredQuantile(kNoiseFloorLevel, ks.columns) * (1.0 - fs.r_squared) / dof;
        ks.distinguishable = ks.src_squared > ks.noise_floor;
      }
      fs.keys.push_back(ks);
    }
    std::stable_sort(fs.keys.begin(), fs.keys.end(), [](const KeySensitivity& x, const KeySensitivity& y) { return x.share > y.share; });
    out.sensitivity.push_back(std::move(fs));
  }
  return out;
}

ClosingLink ExtremeValueClosingLink(const std::vector<DimensionLink>& links) {
  ClosingLink c;
  for (const DimensionLink& l : links) {
    if (!(std::isfinite(l.upper) && std::isfinite(l.lower) && l.lower <= l.upper)) {
      throw std::invalid_argument(fmt::format("link {}: deviations {} .. {}: expected finite lower <= upper", l.name, l.lower, l.upper));
    }
    // Jiang 2022 section 5.1: the closing link's limits by the extreme-value method.
    c.max += l.increasing ? l.upper : -l.lower;
    c.min += l.increasing ? l.lower : -l.upper;
  }
  return c;
}

FigureStats ChainMonteCarlo(const std::vector<DimensionLink>& links, std::int64_t samples, std::uint64_t seed,
                            std::uint64_t chain) {
  ExtremeValueClosingLink(links);  // checks the links
  std::vector<double> v(static_cast<std::size_t>(std::max<std::int64_t>(samples, 0)));
  for (std::size_t i = 0; i < v.size(); ++i) {
    double closing = 0.0;
    for (std::size_t k = 0; k < links.size(); ++k) {
      // Streams above every [tolerances] key's: (1 << 16 | chain) in the high word, the link in the low.
      const std::uint64_t stream = ((std::uint64_t{1} << 16 | chain) << 32) | k;
      const double u = geometry::rng::Uniform01(seed, stream, i);
      const double x = links[k].lower + (links[k].upper - links[k].lower) * u;
      closing += links[k].increasing ? x : -x;
    }
    v[i] = closing;
  }
  return ComputeStats(std::move(v));
}

WorstCaseResult ExtremeValueWorstCase(const ToleranceStudy& study, int threads,
                                      const std::function<void(std::int64_t, std::int64_t)>& progress) {
  const auto& inputs = study.inputs();
  const auto& dists = study.settings().distributions;
  const std::size_t cols = inputs.size();
  std::vector<double> centre(cols), half(cols);
  for (std::size_t c = 0; c < cols; ++c) {
    centre[c] = dists[inputs[c].distribution].mean;
    half[c] = dists[inputs[c].distribution].WorstCaseHalfWidth();
  }
  // Stage 1: the centre and every column at either end of its range.
  std::vector<std::vector<double>> points = {centre};
  for (std::size_t c = 0; c < cols; ++c) {
    for (const double sign : {1.0, -1.0}) {
      std::vector<double> p = centre;
      p[c] += sign * half[c];
      points.push_back(std::move(p));
    }
  }
  WorstCaseResult out;
  // The runs of both stages for the progress: the second stage's count is known after the first.
  std::int64_t total = static_cast<std::int64_t>(points.size()) + 2 * static_cast<std::int64_t>(kToleranceFigureCount);
  const auto run_all = [&](const std::vector<std::vector<double>>& pts) {
    std::vector<ToleranceSample> r(pts.size());
    const std::int64_t before = out.runs;
    ParallelFor(
        static_cast<std::int64_t>(pts.size()), threads,
        [&](std::int64_t i) { r[static_cast<std::size_t>(i)] = study.Evaluate(study.Apply(pts[static_cast<std::size_t>(i)])); },
        progress ? std::function<void(std::int64_t)>([&](std::int64_t done) { progress(before + done, total); }) : nullptr);
    out.runs += static_cast<std::int64_t>(pts.size());
    for (const auto& s : r) out.failed_runs += s.status == RunStatus::kSuccess ? 0 : 1;
    return r;
  };
  const std::vector<ToleranceSample> first = run_all(points);
  const auto end_name = [&](std::size_t run) {  // run 1 + 2c: column c at +h; 2 + 2c: at -h
    const std::size_t c = (run - 1) / 2;
    const double at = centre[c] + ((run - 1) % 2 == 0 ? half[c] : -half[c]);
    return fmt::format("{} at {:g}", inputs[c].name, at);
  };
  if (first[0].status != RunStatus::kSuccess) out.first_failure = fmt::format("the nominal pair: {}", first[0].message);
  for (std::size_t run = 1; run < first.size() && out.first_failure.empty(); ++run) {
    if (first[run].status != RunStatus::kSuccess) out.first_failure = fmt::format("{}: {} ({})", end_name(run), ToString(first[run].status), first[run].message);
  }
  // Stage 2: per figure, the corner the linear stack picks, each way. An input whose effect on the
  // figure is unknown (a run at an end failed or was rejected) is not an effect of 0: the figure
  // then has no stack and no corner.
  std::vector<std::vector<double>> corners;
  std::vector<std::size_t> corner_figure;
  for (std::size_t f = 0; f < kToleranceFigureCount; ++f) {
    WorstCaseFigure& w = out.figures[f];
    w.nominal = first[0].status == RunStatus::kSuccess ? first[0].figures[f] : kNaN;
    double stack = 0.0;
    std::vector<double> high = centre, low = centre;
    for (std::size_t c = 0; c < cols && w.note.empty(); ++c) {
      for (const std::size_t run : {1 + 2 * c, 2 + 2 * c}) {
        if (first[run].status != RunStatus::kSuccess || !std::isfinite(first[run].figures[f])) {
          w.note = first[run].status != RunStatus::kSuccess
                       ? fmt::format("{} {}: its effect is unknown ({})", end_name(run), ToString(first[run].status), first[run].message)
                       : fmt::format("{}: no value", end_name(run));
          break;
        }
      }
      if (!w.note.empty()) break;
      const double effect = 0.5 * (first[1 + 2 * c].figures[f] - first[2 + 2 * c].figures[f]);
      stack += std::abs(effect);
      const double sign = effect >= 0.0 ? 1.0 : -1.0;
      high[c] += sign * half[c];
      low[c] -= sign * half[c];
    }
    if (!w.note.empty()) {
      w.stack_low = w.stack_high = w.corner_low = w.corner_high = kNaN;
      w.corner_low_status = w.corner_high_status = RunStatus::kNotRun;
      continue;
    }
    w.stack_low = w.nominal - stack;
    w.stack_high = w.nominal + stack;
    corners.push_back(std::move(low));
    corners.push_back(std::move(high));
    corner_figure.push_back(f);
  }
  total = static_cast<std::int64_t>(points.size() + corners.size());
  const std::vector<ToleranceSample> second = run_all(corners);
  for (std::size_t k = 0; k < corner_figure.size(); ++k) {
    const std::size_t f = corner_figure[k];
    const auto& lo = second[2 * k];
    const auto& hi = second[2 * k + 1];
    out.figures[f].corner_low = lo.status == RunStatus::kSuccess ? lo.figures[f] : kNaN;
    out.figures[f].corner_high = hi.status == RunStatus::kSuccess ? hi.figures[f] : kNaN;
    out.figures[f].corner_low_status = lo.status;
    out.figures[f].corner_high_status = hi.status;
    for (const auto* s : {&lo, &hi}) {
      if (s->status != RunStatus::kSuccess && out.first_failure.empty()) {
        out.first_failure = fmt::format("the {} corner of {}: {} ({})", s == &lo ? "low" : "high", ToleranceSettings::FigureNames()[f],
                                        ToString(s->status), s->message);
      }
    }
  }
  return out;
}

std::array<CornerExceedance, kToleranceFigureCount> CompareWithCorners(const ToleranceStudy& study, const SampleTable& samples,
                                                                        const WorstCaseResult& worst) {
  std::array<CornerExceedance, kToleranceFigureCount> out{};
  const auto& inputs = study.inputs();
  const auto& dists = study.settings().distributions;
  for (std::int64_t k = 0; k < samples.size(); ++k) {
    if (!samples.succeeded(k)) continue;
    std::vector<double> drawn;  // drawn again only for a sample beyond some corner
    for (std::size_t f = 0; f < kToleranceFigureCount; ++f) {
      const WorstCaseFigure& w = worst.figures[f];
      const double v = samples.figures(k)[f];
      // Beyond by more than the arithmetic's noise: 1e-6 of the figure's unit (arcsec, MPa, N,
      // arcmin, pins) plus 1e-9 relative; a figure that is 0 up to round-off (the peak-to-peak of a
      // pair whose pins are all alike, ~1e-11 arcsec) is not "beyond" its corners.
      const auto slack = [](double corner) { return 1e-6 + 1e-9 * std::abs(corner); };
      const bool beyond = (w.corner_high_status == RunStatus::kSuccess && v > w.corner_high + slack(w.corner_high)) ||
                          (w.corner_low_status == RunStatus::kSuccess && v < w.corner_low - slack(w.corner_low));
      if (!beyond) continue;
      ++out[f].beyond;
      if (drawn.empty()) drawn = study.Draw(samples.index(k));
      bool in_range = true;
      for (std::size_t c = 0; c < inputs.size(); ++c) {
        const ToleranceDistribution& d = dists[inputs[c].distribution];
        in_range = in_range && std::abs(drawn[c] - d.mean) <= d.WorstCaseHalfWidth() * (1.0 + 1e-12);  // an ulp of the sum
      }
      out[f].beyond_in_range += in_range ? 1 : 0;
    }
  }
  return out;
}

void AppendSampleBytes(const ToleranceSample& s, std::string& out) {
  bytes::Put(out, s.index);
  for (const double v : s.figures) bytes::Put(out, v);
  bytes::Put(out, s.status);
  bytes::PutString(out, s.message);
}

void ReadSampleBytes(const std::string& in, const ToleranceStudy& study, const std::function<void(const ToleranceSample&)>& each) {
  std::size_t at = 0;
  while (at < in.size()) {
    ToleranceSample s;
    s.index = bytes::Take<std::int64_t>(in, at);
    for (double& v : s.figures) v = bytes::Take<double>(in, at);
    s.status = bytes::Take<RunStatus>(in, at);
    s.message = bytes::TakeString(in, at);
    s.inputs = study.Draw(s.index);
    each(s);
  }
}

}  // namespace ltca::analysis
