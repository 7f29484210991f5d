#include "ltca/app/tolerance.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "ltca/app/stiffness.hpp"
#include "ltca/app/sweep.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/counter_rng.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::app {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

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

/// Calls fn(i) for i in 0 .. n - 1 on `threads` threads (the calling thread one of them), the
/// indices handed out one at a time; progress(done) from the calling thread. The first
/// exception thrown by fn is rethrown after every thread has stopped.
void ParallelFor(std::int64_t n, int threads, const std::function<void(std::int64_t)>& fn,
                 const std::function<void(std::int64_t)>& progress) {
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
  for (int t = 0; t < extra; ++t) pool.emplace_back(work, false);
  work(true);
  for (auto& t : pool) t.join();
  if (progress) progress(done.load());
  if (error) std::rethrow_exception(error);
}

/// The symmetry the errors break: per-pin keys and the frame-fixed assembly errors (the centre
/// offset and the tilts stay where they are while the eccentric turns) repeat only after a whole
/// crank revolution, not after one mesh period.
bool BreaksMeshPeriod(const ToleranceDistribution& d) {
  if (d.IsZero()) return false;
  return d.per_pin || d.key == "centre_dx_mm" || d.key == "centre_dy_mm" || d.key == "misalignment_xz_deg" ||
         d.key == "misalignment_yz_deg";
}

}  // namespace

ToleranceStudy::ToleranceStudy(const Deck& deck, const SolverOptions& options, const ToleranceSettings& settings)
    : deck_(deck), options_(options), settings_(settings) {
  options_.Validate();
  settings_.Validate();
  deck_.RequireMaterial();
  deck_.RequireLoad();
  if (settings_.lost_motion) deck_.stiffness.Validate();
  if (deck_.second_disc) {
    throw std::invalid_argument(fmt::format(
        "deck '{}': [second_disc] with [tolerances]: the draws would move the first disc only; expected one disc "
        "(the two-disc tolerance study is not built yet)",
        deck_.name));
  }
  const int pins = deck_.pair.pin_count;
  for (std::size_t k = 0; k < settings_.distributions.size(); ++k) {
    const ToleranceDistribution& d = settings_.distributions[k];
    KeyIndex(d.key);  // a known key
    if (d.per_pin) {
      for (int j = 0; j < pins; ++j) inputs_.push_back({fmt::format("{}[{}]", d.key, j + 1), k, j});
    } else {
      inputs_.push_back({d.key, k, -1});
    }
  }
  const double span = deck_.sweep.crank_end - deck_.sweep.crank_start;
  const double revolution = 2.0 * units::kPi;
  const double step = deck_.sweep.positions > 1 ? span / (deck_.sweep.positions - 1) : revolution;
  if (std::any_of(settings_.distributions.begin(), settings_.distributions.end(), BreaksMeshPeriod) &&
      span + step < revolution * (1.0 - 1e-9)) {
    notes_.push_back(fmt::format(
        "per-pin errors (and the frame-fixed centre offset and tilts) break the mesh-period symmetry: the contact "
        "pattern repeats only after a whole crank revolution (360 deg), but the deck's sweep covers {:g} deg; the "
        "figures are over that part of the revolution only (set [sweep] crank_start_deg = 0, crank_end_deg = 360 - "
        "step for the whole revolution)",
        units::RadToDeg(span)));
  }
  if (settings_.lost_motion && deck_.RequireLoad().torque == 0.0) {
    throw std::invalid_argument("[tolerances] lost_motion = true: expected a non-zero [load] torque_nm (the rated torque of the loop)");
  }
}

std::vector<double> ToleranceStudy::Draw(std::int64_t i) const {
  std::vector<double> out(inputs_.size());
  const auto index = static_cast<std::uint64_t>(i);
  for (std::size_t c = 0; c < inputs_.size(); ++c) {
    const ToleranceDistribution& d = settings_.distributions[inputs_[c].distribution];
    // Stream: the key's index in the key table (high word) and pin + 1 (low word; 0 for a scalar).
    const std::uint64_t stream = (static_cast<std::uint64_t>(KeyIndex(d.key)) << 32) | static_cast<std::uint64_t>(inputs_[c].pin + 1);
    if (d.kind == ToleranceDistribution::Kind::kNormal) {
      out[c] = d.mean + d.sigma * geometry::rng::StandardNormal(settings_.seed, stream, index);
    } else {
      out[c] = d.mean + d.tolerance * (2.0 * geometry::rng::Uniform01(settings_.seed, stream, index) - 1.0);
    }
  }
  return out;
}

Deck ToleranceStudy::Apply(const std::vector<double>& inputs) const {
  if (inputs.size() != inputs_.size()) {
    throw std::invalid_argument(fmt::format("tolerance: {} input values for {} input columns", inputs.size(), inputs_.size()));
  }
  Deck d = deck_;
  const int pins = d.pair.pin_count;
  for (std::size_t c = 0; c < inputs_.size(); ++c) {
    const double v = inputs[c];
    if (v == 0.0) continue;  // the deck's own value, untouched (zero tolerances give the deck bit for bit)
    const std::string& key = settings_.distributions[inputs_[c].distribution].key;
    const int j = inputs_[c].pin;
    auto& e = d.errors;
    auto& a = d.assembly;
    auto& m = d.modification;
    if (key == "pin_circle_deviation_mm") e.pin_circle_deviation += v;
    else if (key == "cycloid_profile_layer_mm") e.profile_layer += v;
    else if (key == "cumulative_pitch_deviation_mm") AddToPin(e.cumulative_pitch_deviation, pins, j, v);
    else if (key == "pin_radius_deviations_mm") AddToPin(e.pin_radius_deviations, pins, j, v);
    else if (key == "pin_radial_deviations_mm") AddToPin(e.pin_radial_deviations, pins, j, v);
    else if (key == "lead_crowning_um") e.lead_crowning += units::UmToMm(v);
    else if (key == "lead_slope_um") e.lead_slope += units::UmToMm(v);
    else if (key == "centre_dx_mm") a.centre_dx += v;
    else if (key == "centre_dy_mm") a.centre_dy += v;
    else if (key == "eccentricity_deviation_mm") a.eccentricity_deviation += v;
    else if (key == "misalignment_xz_deg") a.misalignment_xz += units::DegToRad(v);
    else if (key == "misalignment_yz_deg") a.misalignment_yz += units::DegToRad(v);
    else if (key == "modification_pin_radius_mm") m.pin_radius += v;
    else if (key == "modification_pin_circle_radius_mm") m.pin_circle_radius += v;
    else if (key == "modification_rotation_deg") m.rotation += units::DegToRad(v);
    else throw std::logic_error(fmt::format("tolerance: key '{}' has no effect coded", key));
  }
  return d;
}

ToleranceSample ToleranceStudy::Evaluate(const Deck& pair) const {
  ToleranceSample s;
  try {
    pair.errors.Validate(pair.pair.pin_count);
    pair.assembly.Validate();
    pair.modification.Validate(pair.pair);
    // Unloaded TCA over the sweep: the arithmetic of `ltca backlash` (mean = sum / n).
    const contact::MeshModel model = pair.MakeModel();
    const std::vector<double> cranks = pair.sweep.CrankAngles();
    double sum = 0.0, lo = INFINITY, hi = -INFINITY;
    for (const double crank : cranks) {
      const double b = contact::AnalyseUnloaded(model, crank, options_.kinematics).backlash;
      sum += b;
      lo = std::min(lo, b);
      hi = std::max(hi, b);
    }
    s.figures[kMeanBacklashArcsec] = units::RadToArcsec(sum / static_cast<double>(cranks.size()));
    s.figures[kPpBacklashArcsec] = units::RadToArcsec(hi - lo);
    // Loaded TCA over the sweep: `ltca solve`'s summary.
    SweepRunner runner(pair, options_);
    for (const double crank : cranks) runner.Solve(crank);
    const SweepSummary sum_loaded = runner.Summary();
    s.figures[kMeanTeArcsec] = units::RadToArcsec(sum_loaded.mean_te);
    s.figures[kPpTeArcsec] = units::RadToArcsec(sum_loaded.pp_te);
    s.figures[kMaxContactStressMpa] = sum_loaded.max_contact_stress;
    s.figures[kMaxPinForceN] = sum_loaded.max_pin_force;
    if (sum_loaded.succeeded > 0) {
      s.figures[kContactsMin] = sum_loaded.contacts_min;
      s.figures[kContactsMax] = sum_loaded.contacts_max;
    }
    if (!sum_loaded.all_succeeded()) {
      s.status = "failed";
      s.message = fmt::format("{} of {} loaded positions did not succeed ({})", sum_loaded.failed, sum_loaded.positions(),
                              solvers::ToString(sum_loaded.status));
    }
    if (settings_.lost_motion) {
      // Lost motion is solved at its own torques (+-f T); the curve needs only its 3 levels.
      StiffnessSettings st = pair.stiffness;
      st.steps = 3;
      StiffnessRunner loop(pair, options_, st);
      for (const double crank : loop.cranks()) loop.Solve(crank);
      const StiffnessSummary ss = loop.Summary();
      s.figures[kLostMotionArcmin] = units::RadToArcmin(ss.lost_motion.mean);
      if (!ss.all_succeeded() && s.status == "success") {
        s.status = "failed";
        s.message = fmt::format("lost motion: {}", ss.first_failure);
      }
    }
  } catch (const std::invalid_argument& e) {  // interference, an undercut profile, ...
    s = ToleranceSample{};
    s.status = "rejected";
    s.message = e.what();
  }
  return s;
}

ToleranceSample ToleranceStudy::Run(std::int64_t i) const {
  std::vector<double> inputs = Draw(i);
  Deck pair = Apply(inputs);
  if (settings_.profile_random_per_sample) {
    // Its own stream, above every key's and chain's: (0xFFFFFFFF << 32), counter i.
    pair.errors.profile_random.seed = geometry::rng::Bits128(settings_.seed, std::uint64_t{0xFFFFFFFF} << 32, static_cast<std::uint64_t>(i))[0];
  }
  ToleranceSample s = Evaluate(pair);
  s.index = i;
  s.inputs = std::move(inputs);
  return s;
}

std::vector<ToleranceSample> ToleranceStudy::RunRange(std::int64_t first, std::int64_t count, int threads,
                                                      const std::function<void(std::int64_t)>& progress) const {
  if (first < 0 || count < 0) throw std::invalid_argument(fmt::format("tolerance: samples {} .. {}: expected indices >= 0", first, first + count - 1));
  if (threads < 1) throw std::invalid_argument(fmt::format("--threads {}: expected at least 1", threads));
  std::vector<ToleranceSample> out(static_cast<std::size_t>(count));
  ParallelFor(count, threads, [&](std::int64_t k) { out[static_cast<std::size_t>(k)] = Run(first + k); }, progress);
  return out;
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
  const auto quantile = [&](double p) {  // type 7: h = (n - 1) p, linear between neighbours
    const double h = (static_cast<double>(values.size()) - 1.0) * p;
    const auto lo = static_cast<std::size_t>(std::floor(h));
    const std::size_t hi = std::min(lo + 1, values.size() - 1);
    return values[lo] + (h - static_cast<double>(lo)) * (values[hi] - values[lo]);
  };
  f.p1 = quantile(0.01), f.p5 = quantile(0.05), f.p50 = quantile(0.5), f.p95 = quantile(0.95), f.p99 = quantile(0.99);
  f.min = values.front(), f.max = values.back();
  return f;
}

ToleranceSummary Summarise(const ToleranceStudy& study, const std::vector<ToleranceSample>& samples) {
  ToleranceSummary out;
  out.samples = static_cast<std::int64_t>(samples.size());
  out.seed = study.settings().seed;
  std::vector<const ToleranceSample*> ok;
  for (const auto& s : samples) {
    if (s.status == "success") ++out.succeeded, ok.push_back(&s);
    else if (s.status == "failed") ++out.failed;
    else ++out.rejected;
  }
  const auto& names = ToleranceSettings::FigureNames();
  for (std::size_t f = 0; f < kToleranceFigureCount; ++f) {
    std::vector<double> v;
    v.reserve(ok.size());
    for (const auto* s : ok) v.push_back(s->figures[f]);
    out.figures[f] = ComputeStats(std::move(v));
  }
  // Limits: a sample passes when it succeeded and its figure is within [min, max].
  const auto figure_index = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
  };
  const auto within = [&](const ToleranceSample& s, const ToleranceLimit& l) {
    const double v = s.figures[figure_index(l.figure)];
    return s.status == "success" && std::isfinite(v) && v >= l.min && v <= l.max;
  };
  for (const ToleranceLimit& l : study.settings().limits) {
    LimitResult r;
    r.limit = l;
    for (const auto& s : samples) r.passed += within(s, l) ? 1 : 0;
    r.fraction = out.samples > 0 ? static_cast<double>(r.passed) / static_cast<double>(out.samples) : kNaN;
    out.limits.push_back(r);
  }
  if (!study.settings().limits.empty()) {
    for (const auto& s : samples) {
      const auto& limits = study.settings().limits;
      out.passed_all += std::all_of(limits.begin(), limits.end(), [&](const ToleranceLimit& l) { return within(s, l); }) ? 1 : 0;
    }
    out.pass_fraction = out.samples > 0 ? static_cast<double>(out.passed_all) / static_cast<double>(out.samples) : kNaN;
  }
  // Sensitivity: SRC of every figure on every input column.
  const auto& inputs = study.inputs();
  const auto& dists = study.settings().distributions;
  const auto cols = static_cast<Eigen::Index>(inputs.size());
  for (std::size_t f = 0; f < kToleranceFigureCount; ++f) {
    FigureSensitivity fs;
    fs.figure = names[f];
    std::vector<const ToleranceSample*> rows;
    for (const auto* s : ok) {
      if (std::isfinite(s->figures[f])) rows.push_back(s);
    }
    const auto n = static_cast<Eigen::Index>(rows.size());
    if (cols == 0) {
      fs.note = "no tolerance given";
    } else if (n < cols + 2) {
      fs.note = fmt::format("{} successful samples for {} input columns: at least {} are needed", n, cols, cols + 2);
    } else {
      Eigen::MatrixXd x(n, cols);
      Eigen::VectorXd y(n);
      for (Eigen::Index r = 0; r < n; ++r) {
        y(r) = rows[static_cast<std::size_t>(r)]->figures[f];
        for (Eigen::Index c = 0; c < cols; ++c) x(r, c) = rows[static_cast<std::size_t>(r)]->inputs[static_cast<std::size_t>(c)];
      }
      const auto standardise = [n](auto&& v) {
        const double mean = v.mean();
        const double sd = std::sqrt((v.array() - mean).square().sum() / static_cast<double>(n - 1));
        v.array() -= mean;
        if (sd > 0.0) v /= sd;
        return sd;
      };
      const double sy = standardise(y);
      std::vector<bool> varies(static_cast<std::size_t>(cols));
      for (Eigen::Index c = 0; c < cols; ++c) varies[static_cast<std::size_t>(c)] = standardise(x.col(c)) > 0.0;
      if (!(sy > 0.0)) {
        fs.note = "the figure does not vary over the samples";
      } else {
        const Eigen::VectorXd beta = x.colPivHouseholderQr().solve(y);
        const double ss_res = (y - x * beta).squaredNorm();
        fs.r_squared = 1.0 - ss_res / y.squaredNorm();
        for (std::size_t k = 0; k < dists.size(); ++k) {
          KeySensitivity ks;
          ks.key = dists[k].key;
          double share = 0.0;
          for (Eigen::Index c = 0; c < cols; ++c) {
            if (inputs[static_cast<std::size_t>(c)].distribution != k || !varies[static_cast<std::size_t>(c)]) continue;
            share += beta(c) * beta(c);
            if (!dists[k].per_pin) ks.src = beta(c);
          }
          ks.share = share;
          if (!dists[k].per_pin && std::isnan(ks.src)) ks.src = 0.0;
          fs.keys.push_back(ks);
        }
        std::stable_sort(fs.keys.begin(), fs.keys.end(), [](const KeySensitivity& a, const KeySensitivity& b) { return a.share > b.share; });
      }
    }
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

WorstCaseResult ExtremeValueWorstCase(const ToleranceStudy& study, int threads) {
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
  const auto run_all = [&](const std::vector<std::vector<double>>& pts) {
    std::vector<ToleranceSample> r(pts.size());
    ParallelFor(static_cast<std::int64_t>(pts.size()), threads,
                [&](std::int64_t i) { r[static_cast<std::size_t>(i)] = study.Evaluate(study.Apply(pts[static_cast<std::size_t>(i)])); }, {});
    out.runs += static_cast<std::int64_t>(pts.size());
    for (const auto& s : r) out.failed_runs += s.status == "success" ? 0 : 1;
    return r;
  };
  const std::vector<ToleranceSample> first = run_all(points);
  // Stage 2: per figure, the corner the linear stack picks, each way.
  std::vector<std::vector<double>> corners;
  for (std::size_t f = 0; f < kToleranceFigureCount; ++f) {
    WorstCaseFigure& w = out.figures[f];
    w.nominal = first[0].status == "success" ? first[0].figures[f] : kNaN;
    double stack = 0.0;
    std::vector<double> high = centre, low = centre;
    for (std::size_t c = 0; c < cols; ++c) {
      const double up = first[1 + 2 * c].figures[f], down = first[2 + 2 * c].figures[f];
      const bool ok = first[1 + 2 * c].status == "success" && first[2 + 2 * c].status == "success" && std::isfinite(up) &&
                      std::isfinite(down);
      const double effect = ok ? 0.5 * (up - down) : 0.0;
      stack += std::abs(effect);
      const double sign = effect >= 0.0 ? 1.0 : -1.0;
      high[c] += sign * half[c];
      low[c] -= sign * half[c];
    }
    w.stack_low = w.nominal - stack;
    w.stack_high = w.nominal + stack;
    corners.push_back(std::move(low));
    corners.push_back(std::move(high));
  }
  const std::vector<ToleranceSample> second = run_all(corners);
  for (std::size_t f = 0; f < kToleranceFigureCount; ++f) {
    const auto& lo = second[2 * f];
    const auto& hi = second[2 * f + 1];
    out.figures[f].corner_low = lo.status == "success" ? lo.figures[f] : kNaN;
    out.figures[f].corner_high = hi.status == "success" ? hi.figures[f] : kNaN;
    out.figures[f].corner_low_status = lo.status;
    out.figures[f].corner_high_status = hi.status;
  }
  return out;
}

}  // namespace ltca::app
