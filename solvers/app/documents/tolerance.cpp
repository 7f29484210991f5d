#include "documents/tolerance.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "documents/solve.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::app::documents {
namespace {

using units::RadToDeg;

const char* KindName(analysis::ToleranceDistribution::Kind k) {
  return k == analysis::ToleranceDistribution::Kind::kNormal ? "normal" : "uniform";
}

/// A number in the CSV: every bit (17 significant digits), empty when not finite.
std::string CsvNumber(double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : std::string(); }

std::string CsvText(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"') out += '"';
    out += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return out + '"';
}

nlohmann::json StatsJson(const analysis::FigureStats& f) {
  return {{"mean", FiniteOrNull(f.mean)}, {"std", FiniteOrNull(f.std)}, {"p1", FiniteOrNull(f.p1)},
          {"p5", FiniteOrNull(f.p5)},     {"p50", FiniteOrNull(f.p50)}, {"p95", FiniteOrNull(f.p95)},
          {"p99", FiniteOrNull(f.p99)},   {"min", FiniteOrNull(f.min)}, {"max", FiniteOrNull(f.max)},
          {"count", f.count}};
}

/// A worst-case corner in text: the figure, or why there is none ("rejected": the pair interferes).
std::string Corner(double v, analysis::RunStatus status) {
  return status == analysis::RunStatus::kSuccess ? FormatOrNa(v, 4) : analysis::ToString(status);
}

/// The mark of a figure with samples beyond its worst-case corners: '*' when some of them have every
/// input within the range the worst case uses (the figure is not monotonic in the inputs, e.g. a
/// maximum over the pins, whose worst case is pins that differ, not every pin at the same limit);
/// '+' when each of them has an input beyond it (a normal given by sigma, drawn beyond 3 sigma);
/// "" when none lies beyond.
std::string BeyondMark(const analysis::CornerExceedance& e) {
  if (e.beyond == 0) return "";
  return e.beyond_in_range > 0 ? " *" : " +";
}

constexpr const char* kWorstCaseMethod =
    "extreme-value method: every input at the end of its range (uniform: +-tolerance, normal: +-3 sigma) about its "
    "centre; stack = nominal -+ sum over the inputs of |f(+h) - f(-h)| / 2 (linear stacking, as a dimensional chain "
    "by the extreme-value method, Jiang 2022 section 5.1); corner = the deterministic run at the corner that the "
    "stack picks";

/// "mean_te_arcsec" -> "mean TE (arcsec)": a figure's name as an axis label with its unit.
std::string AxisLabel(const std::string& name) {
  static const std::vector<std::pair<std::string, std::string>> units = {
      {"_arcsec", "arcsec"}, {"_arcmin", "arcmin"}, {"_mpa", "MPa"}, {"_n", "N"}, {"_hours", "h"}};
  std::string base = name, unit = "pins";
  for (const auto& [suffix, u] : units) {
    if (base.size() > suffix.size() && base.compare(base.size() - suffix.size(), suffix.size(), suffix) == 0) {
      base.resize(base.size() - suffix.size()), unit = u;
      break;
    }
  }
  std::replace(base.begin(), base.end(), '_', ' ');
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{{"pp ", "peak-to-peak "}, {" te", " TE"}, {"l10", "L10 life"}}) {
    const auto at = base.find(from);
    if (at != std::string::npos) base.replace(at, from.size(), to);
  }
  return fmt::format("{} ({})", base, unit);
}

}  // namespace

analysis::ToleranceSettings ToleranceSettingsFor(const Deck& deck, std::optional<std::int64_t> samples,
                                                 std::optional<std::uint64_t> seed, bool lost_motion) {
  if (!deck.tolerances) {
    throw std::invalid_argument(fmt::format(
        "deck '{}': missing section [tolerances] for ltca tolerance; expected e.g. [tolerances] samples = 1000, seed = 1, "
        "pin_circle_deviation_mm = {{ distribution = \"normal\", sigma = 0.002 }} (docs/tolerance.md)",
        deck.name));
  }
  analysis::ToleranceSettings settings = *deck.tolerances;
  if (samples) settings.samples = *samples;
  if (seed) settings.seed = *seed;
  if (lost_motion) settings.lost_motion = true;
  return settings;
}

std::string ToleranceTextHead(const Deck& deck, const SolverOptions& solver, const analysis::ToleranceStudy& study,
                              std::int64_t first, int threads, int ranks) {
  const analysis::ToleranceSettings& settings = study.settings();
  std::string text = CaseLines(deck);
  text += ModelLine(deck);
  text += SolverLine(deck, solver);
  text += fmt::format("samples   {} from index {}, seed {} (counter-based Philox4x32-10: sample i depends on (seed, i) only), "
                      "{} thread(s){}\n",
                      settings.samples, first, settings.seed, threads, ranks > 1 ? fmt::format(" on each of {} MPI ranks", ranks) : "");
  text += fmt::format("per sample: {} and loaded TCA over {} positions from {:g} to {:g} deg crank{}\n",
                      deck.reducer ? "the stage's free play" : "unloaded TCA", deck.sweep.positions, RadToDeg(deck.sweep.crank_start),
                      RadToDeg(deck.sweep.crank_end),
                      settings.lost_motion ? fmt::format(", lost motion at +-{:g} % of T", 100.0 * deck.stiffness.lost_motion_fraction) : "");
  for (const auto& d : settings.distributions) text += fmt::format("  {:<36} {}\n", d.key, analysis::Describe(d));
  if (settings.profile_random_per_sample) {
    text += fmt::format("  profile random deviation: every sample its own, zone {:g} um ({}), seed drawn from (seed, i)\n",
                        units::MmToUm(deck.errors.profile_random.zone),
                        deck.errors.profile_random.distribution == geometry::ProfileRandomDistribution::kNormal ? "normal" : "uniform");
  }
  for (const auto& note : study.notes()) text += fmt::format("note      {}\n", note);
  return text;
}

std::string ToleranceEstimateText(double seconds, std::int64_t done, std::int64_t count, int threads, bool several_ranks,
                                  double worst_case_seconds, std::int64_t worst_case_runs) {
  const std::string worst =
      worst_case_runs > 0
          ? fmt::format(", then about {:.3g} s for the worst case's {} runs at most, about {:.3g} s in all", worst_case_seconds,
                        worst_case_runs, seconds + worst_case_seconds)
          : "";
  return fmt::format("estimate  about {:.3g} s for the {} samples{}{} (at the rate of samples {} to {} on {} thread(s), after {} that "
                     "warm the caches)\n",
                     seconds, count, several_ranks ? " of this rank" : "", worst, 2 * threads + 1, done, threads, 2 * threads);
}

std::string ToleranceCsvHead(const analysis::ToleranceStudy& study) {
  const auto& names = analysis::ToleranceSettings::FigureNames();
  std::string os = "sample,status";
  for (const auto& in : study.inputs()) os += ',' + in.name;
  for (std::size_t f = 0; f < names.size(); ++f) {
    if (study.Runs(f)) os += ',' + names[f];
  }
  return os + ",message\n";
}

std::string Csv(const analysis::ToleranceStudy& study, const analysis::ToleranceSample& s) {
  std::string os = fmt::format("{},{}", s.index, analysis::ToString(s.status));
  for (const double v : s.inputs) os += ',' + CsvNumber(v);
  for (std::size_t f = 0; f < analysis::kToleranceFigureCount; ++f) {
    if (study.Runs(f)) os += ',' + CsvNumber(s.figures[f]);
  }
  return os + ',' + CsvText(s.message) + '\n';
}

Table DistributionColumns(const analysis::ToleranceSettings& settings) {
  using Kind = analysis::ToleranceDistribution::Kind;
  const auto& ds = settings.distributions;
  const bool normal = std::any_of(ds.begin(), ds.end(), [](const auto& d) { return d.kind == Kind::kNormal; });
  const auto gives_tolerance = [](const analysis::ToleranceDistribution& d) { return d.tolerance != 0.0 || d.kind == Kind::kUniform; };
  const bool tolerance = std::any_of(ds.begin(), ds.end(), gives_tolerance);
  Table t;
  for (const auto& d : ds) {
    t.Add("mean", d.mean);
    t.Add("std", d.StandardDeviation());
    t.Add("worst_case_half_width", d.WorstCaseHalfWidth());
    if (normal) {
      t.Add("sigma", d.kind == Kind::kNormal ? d.sigma : NAN);
      t.Add("truncated_at", d.kind == Kind::kNormal && analysis::Truncated(d) ? d.tolerance : NAN);
    }
    if (tolerance) t.Add("tolerance", gives_tolerance(d) ? d.tolerance : NAN);
  }
  return t;
}

Table RankingColumns(const analysis::FigureSensitivity& sensitivity) {
  Table t;
  for (const auto& k : sensitivity.keys) {
    t.Add("src", k.src);
    t.Add("share", k.share);
    t.Add("src_squared", k.src_squared);
    t.Add("columns", static_cast<double>(k.columns));
    t.Add("noise_floor", k.noise_floor);
  }
  return t;
}

Table LimitColumns(const analysis::ToleranceSummary& summary) {
  Table t;
  for (const auto& l : summary.limits) {
    t.Add("min", l.limit.min);
    t.Add("max", l.limit.max);
    t.Add("passed", static_cast<double>(l.passed));
    t.Add("fraction", l.fraction);
  }
  return t;
}

nlohmann::json Json(const Deck& deck, const SolverOptions& solver, const analysis::ToleranceStudy& study,
                    const analysis::ToleranceResult& result) {
  const analysis::ToleranceSettings& settings = study.settings();
  const analysis::ToleranceSummary& summary = result.summary;
  const auto& names = analysis::ToleranceSettings::FigureNames();
  const auto& worst = result.worst_case;
  nlohmann::json dists = nlohmann::json::array();
  for (const auto& d : settings.distributions) {
    nlohmann::json j = {{"key", d.key}, {"distribution", KindName(d.kind)}, {"mean", d.mean}, {"per_pin", d.per_pin},
                        {"std", d.StandardDeviation()}, {"worst_case_half_width", d.WorstCaseHalfWidth()},
                        {"description", analysis::Describe(d)}};
    if (d.kind == analysis::ToleranceDistribution::Kind::kNormal) {
      j["sigma"] = d.sigma;
      j["truncated_at"] = analysis::Truncated(d) ? nlohmann::json(d.tolerance) : nlohmann::json();
    }
    if (d.tolerance != 0.0 || d.kind == analysis::ToleranceDistribution::Kind::kUniform) j["tolerance"] = d.tolerance;
    dists.push_back(std::move(j));
  }
  nlohmann::json figures = nlohmann::json::object(), sens = nlohmann::json::object(), wc = nlohmann::json::object();
  for (std::size_t f = 0; f < names.size(); ++f) {
    if (!study.Runs(f)) continue;
    figures[names[f]] = StatsJson(summary.figures[f]);
    const auto& fs = summary.sensitivity[f];
    nlohmann::json keys = nlohmann::json::array();
    for (const auto& k : fs.keys) {
      keys.push_back({{"key", k.key}, {"src", FiniteOrNull(k.src)}, {"share", FiniteOrNull(k.share)},
                      {"src_squared", FiniteOrNull(k.src_squared)}, {"columns", k.columns},
                      {"noise_floor", FiniteOrNull(k.noise_floor)}, {"distinguishable_from_chance", k.distinguishable}});
    }
    sens[names[f]] = {{"samples", fs.samples}, {"r_squared", FiniteOrNull(fs.r_squared)},
                      {"r_squared_noise_floor", FiniteOrNull(fs.r_squared_floor)}, {"ranking", keys}};
    if (!fs.note.empty()) sens[names[f]]["note"] = fs.note;
    if (worst) {
      const auto& w = worst->figures[f];
      const auto& beyond = result.beyond[f];
      wc[names[f]] = {{"nominal", FiniteOrNull(w.nominal)},       {"stack_low", FiniteOrNull(w.stack_low)},
                      {"stack_high", FiniteOrNull(w.stack_high)}, {"corner_low", FiniteOrNull(w.corner_low)},
                      {"corner_high", FiniteOrNull(w.corner_high)}, {"corner_low_status", analysis::ToString(w.corner_low_status)},
                      {"corner_high_status", analysis::ToString(w.corner_high_status)},
                      {"monte_carlo_beyond_corners", beyond.beyond > 0},
                      {"samples_beyond_corners", beyond.beyond},
                      {"samples_beyond_corners_inputs_in_range", beyond.beyond_in_range}};
      if (!w.note.empty()) wc[names[f]]["note"] = w.note;
    }
  }
  nlohmann::json limits = nlohmann::json::array();
  for (const auto& l : summary.limits) {
    limits.push_back({{"figure", l.limit.figure}, {"min", FiniteOrNull(l.limit.min)}, {"max", FiniteOrNull(l.limit.max)},
                      {"passed", l.passed}, {"fraction", l.fraction}});
  }
  const std::int64_t n = result.samples;
  nlohmann::json doc = {
      {"case", CaseJson(deck)},
      {"model", ModelJson(deck.Model())},
      {"solver", SolverJson(deck, solver)},
      {"tolerances",
       {{"samples", n}, {"first", result.first}, {"seed", settings.seed}, {"threads", result.threads}, {"mpi_ranks", result.ranks},
        {"lost_motion", settings.lost_motion}, {"profile_random_per_sample", settings.profile_random_per_sample},
        {"distributions", dists},
        {"sweep", {{"crank_start_deg", RadToDeg(deck.sweep.crank_start)}, {"crank_end_deg", RadToDeg(deck.sweep.crank_end)},
                   {"positions", deck.sweep.positions}}},
        {"random_stream", "Philox4x32-10 (counter-based): draw (key, pin) of sample i is a pure function of (seed, i); a normal "
                          "given as +-tolerance is the normal truncated there, drawn by the inverse distribution function"}}},
      {"notes", study.notes()},
      {"summary",
       {{"samples", summary.samples}, {"seed", summary.seed}, {"succeeded", summary.succeeded}, {"failed", summary.failed},
        {"rejected", summary.rejected}, {"cannot_assemble", summary.cannot_assemble},
        {"preloaded", summary.preloaded},
        {"preloaded_share", summary.samples > 0 ? static_cast<double>(summary.preloaded) / static_cast<double>(summary.samples) : 0.0},
        {"preload_max_contact_stress_mpa", StatsJson(summary.preload_stress)},
        {"preload_max_force_n", StatsJson(summary.preload_force)},
        {"figures", figures}, {"percentile_rule", analysis::kPercentileRule}, {"limits", limits},
        {"pass_fraction", FiniteOrNull(summary.pass_fraction)},
        {"sensitivity", {{"method", analysis::kSensitivityMethod}, {"figures", sens}}},
        {"wall_seconds", result.sample_seconds},
        {"samples_per_second", FiniteOrNull(static_cast<double>(n) / result.sample_seconds)}}}};
  if (!result.chains.empty()) {
    nlohmann::json chains = nlohmann::json::object();
    for (const auto& chain : result.chains) {
      chains[chain.name] = {{"extreme_value_um", {{"min", chain.extreme_value.min}, {"max", chain.extreme_value.max}}},
                            {"monte_carlo_um", StatsJson(chain.monte_carlo)},
                            {"method", "extreme-value method (Jiang 2022 section 5.1) and Monte Carlo with every link uniform within its limits"}};
    }
    doc["summary"]["chains"] = chains;
  }
  if (worst) {
    doc["summary"]["worst_case"] = {{"method", kWorstCaseMethod}, {"figures", wc}, {"runs", worst->runs},
                                    {"failed_runs", worst->failed_runs}, {"wall_seconds", result.worst_case_seconds}};
    if (!worst->first_failure.empty()) doc["summary"]["worst_case"]["first_failure"] = worst->first_failure;
  }
  return doc;
}

std::string Text(const analysis::ToleranceStudy& study, const analysis::ToleranceResult& result) {
  const analysis::ToleranceSummary& summary = result.summary;
  const auto& names = analysis::ToleranceSettings::FigureNames();
  const auto& worst = result.worst_case;
  const auto& beyond = result.beyond;
  const std::int64_t n = result.samples;
  // The count of finite values beside every figure; a percentile the count does not support is n/a
  // (analysis::kPercentileRule).
  std::string text = fmt::format("{:<24} {:>6} {:>11} {:>10} {:>11} {:>11} {:>11} {:>11} {:>11}{}\n", "figure", "n", "mean", "std", "p1",
                                 "p5", "p50", "p95", "p99", worst ? fmt::format(" {:>23}", "worst case (corners)") : std::string());
  for (std::size_t f = 0; f < names.size(); ++f) {
    if (!study.Runs(f)) continue;
    const auto& s = summary.figures[f];
    text += fmt::format("{:<24} {:>6} {:>11} {:>10} {:>11} {:>11} {:>11} {:>11} {:>11}{}\n", names[f], s.count, FormatOrNa(s.mean, 4),
                        FormatOrNa(s.std, 4),
                        FormatOrNa(s.p1, 4), FormatOrNa(s.p5, 4), FormatOrNa(s.p50, 4), FormatOrNa(s.p95, 4), FormatOrNa(s.p99, 4),
                        worst ? fmt::format(" {:>11} {:>11}{}", Corner(worst->figures[f].corner_low, worst->figures[f].corner_low_status),
                                            Corner(worst->figures[f].corner_high, worst->figures[f].corner_high_status), BeyondMark(beyond[f]))
                              : std::string());
  }
  if (worst) {
    text += fmt::format("worst case: extreme-value method (every input at +-tolerance or +-3 sigma about its centre, effects stacked "
                        "linearly, the corner the stack picks run): {} runs, {} not succeeded\n",
                        worst->runs, worst->failed_runs);
    if (worst->failed_runs > 0) {
      text += fmt::format("  a corner marked 'rejected' could not be built or assembled, one marked 'failed' did not solve; a figure "
                          "whose effect of an input needs a run that did not succeed has no stack and no corner ('not run'), never "
                          "an effect of 0; first: {}\n",
                          worst->first_failure);
    }
    const auto any = [&](auto&& pred) {
      for (std::size_t f = 0; f < names.size(); ++f) {
        if (study.Runs(f) && pred(beyond[f])) return true;
      }
      return false;
    };
    if (any([](const analysis::CornerExceedance& e) { return e.beyond_in_range > 0; })) {
      text += "  * samples with every input within its range lie beyond the corners: the figure is not monotonic in the "
              "inputs (a maximum or range over the pins: its worst case is pins that differ, not every pin at the same "
              "limit); the corners bound nothing there\n";
    }
    if (any([](const analysis::CornerExceedance& e) { return e.beyond > 0 && e.beyond_in_range == 0; })) {
      text += "  + the samples beyond the corners each have an input beyond 3 sigma: a normal given by sigma is not "
              "truncated (0.27 % of its draws lie beyond the +-3 sigma of the worst case); give it as a tolerance to "
              "truncate it there\n";
    }
  }
  for (const auto& chain : result.chains) {
    const analysis::FigureStats& mc = chain.monte_carlo;
    text += fmt::format("chain {}: closing link by the extreme-value method {:g} .. {:g} um; Monte Carlo (links uniform, n = {}) "
                        "mean {}, p1 {}, p50 {}, p99 {} um\n",
                        chain.name, chain.extreme_value.min, chain.extreme_value.max, mc.count, FormatOrNa(mc.mean, 3),
                        FormatOrNa(mc.p1, 3), FormatOrNa(mc.p50, 3), FormatOrNa(mc.p99, 3));
  }
  for (const auto& l : summary.limits) {
    text += fmt::format("limit     {} in [{:g}, {:g}]: {} of {} samples ({:.2f} %)\n", l.limit.figure, l.limit.min, l.limit.max, l.passed,
                        summary.samples, 100.0 * l.fraction);
  }
  if (!summary.limits.empty()) {
    text += fmt::format("all limits met by {} of {} samples ({:.2f} %)\n", summary.passed_all, summary.samples, 100.0 * summary.pass_fraction);
  }
  text += "sensitivity (standardised regression coefficients; share = sum of SRC x r over the key's columns, r the "
          "column's correlation with the figure (Pratt): the shares add up to R^2; R^2 of the linear fit, beside it the "
          "R^2 chance reaches; n the samples fitted; '~': a key whose sum of SRC^2 is below its noise floor, not "
          "distinguishable from chance at the 99.9th percentile):\n";
  for (std::size_t f = 0; f < names.size(); ++f) {
    if (!study.Runs(f)) continue;
    const auto& fs = summary.sensitivity[f];
    std::string ranking;
    for (std::size_t k = 0; k < std::min<std::size_t>(3, fs.keys.size()); ++k) {
      ranking += fmt::format("{}{} {:.3f}{}", k == 0 ? "" : ", ", fs.keys[k].key, fs.keys[k].share, fs.keys[k].distinguishable ? "" : " ~");
    }
    text += fmt::format("  {:<24} n {:>6} R^2 {:>6} (chance {:>5})  {}\n", names[f], fs.samples, FormatOrNa(fs.r_squared, 3),
                        FormatOrNa(fs.r_squared_floor, 3),
                        fs.note.empty() ? ranking : fs.note);
  }
  if (summary.preloaded > 0) {
    text += fmt::format("preloaded (both flanks pressed at zero torque): {} of {} samples; their largest preload contact "
                        "stress {} MPa (median), {} MPa (max)\n", summary.preloaded, summary.samples,
                        FormatOrNa(summary.preload_stress.p50, 1), FormatOrNa(summary.preload_stress.max, 1));
  }
  if (summary.failed + summary.rejected + summary.cannot_assemble > 0) {
    text += fmt::format("not succeeded: {} failed, {} rejected, {} cannot be assembled of {} samples; first: sample {}: {}\n",
                        summary.failed, summary.rejected, summary.cannot_assemble,
                        summary.samples, result.table.first_failure_index(), result.table.first_failure_message());
  }
  text += fmt::format("wall time {:.3f} s for {} samples ({:.1f} samples/s){}\n", result.sample_seconds, n,
                      static_cast<double>(n) / result.sample_seconds,
                      worst ? fmt::format("; worst case {:.3f} s for {} runs", result.worst_case_seconds, worst->runs) : std::string());
  return text;
}

plots::Figure Figure(const Deck& deck, const analysis::ToleranceStudy& study, const analysis::ToleranceResult& result) {
  const analysis::SampleTable& samples = result.table;
  const analysis::ToleranceSummary& summary = result.summary;
  const analysis::WorstCaseResult* worst = result.worst_case ? &*result.worst_case : nullptr;
  const auto& names = analysis::ToleranceSettings::FigureNames();
  plots::Figure figure;
  figure.title = fmt::format("{}: {} samples (seed {}, {} succeeded), loaded TCA over crank {:g} to {:g} deg", CaseTitle(deck),
                             summary.samples, summary.seed, summary.succeeded, RadToDeg(deck.sweep.crank_start),
                             RadToDeg(deck.sweep.crank_end));
  figure.caption = FigureCaption(deck, "bars: samples per bin; dashed: p5, p50, p95; dotted: the extreme-value corners (worst case); "
                                       "solid: the [tolerances] limits; a limit far beyond the data: an arrow at the axis' edge");
  figure.columns = 3;
  for (std::size_t f = 0; f < analysis::kToleranceFigureCount; ++f) {
    const auto& st = summary.figures[f];
    if (!study.Runs(f) || st.count == 0) continue;
    plots::Panel panel;
    panel.title = fmt::format("mean {:.5g}, std {:.3g}", st.mean, st.std);
    panel.x_label = AxisLabel(names[f]);
    panel.y_label = "samples per bin";
    std::vector<double> span = {st.min, st.max};
    if (worst != nullptr) span.push_back(worst->figures[f].corner_low), span.push_back(worst->figures[f].corner_high);
    double lo = INFINITY, hi = -INFINITY;
    for (const double v : span) {
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    }
    if (!(hi > lo)) lo -= 0.5, hi += 0.5;
    // A limit within a third of the data's span beyond it widens the axis; one further away is an
    // arrow at the edge (a far limit would squeeze the histogram into a quarter).
    std::vector<double> beyond_low, beyond_high, drawn_limits;
    const double reach = (hi - lo) / 3.0;
    for (const auto& l : summary.limits) {
      if (l.limit.figure != names[f]) continue;
      for (const double v : {l.limit.min, l.limit.max}) {
        if (!std::isfinite(v)) continue;
        if (v < lo - reach) beyond_low.push_back(v);
        else if (v > hi + reach) beyond_high.push_back(v);
        else drawn_limits.push_back(v);
      }
    }
    for (const double v : drawn_limits) lo = std::min(lo, v), hi = std::max(hi, v);
    // A count (contacts_min, contacts_max: whole numbers of pins over a short range) gets one bar a
    // value, centred on it; any other figure 30 bins over its padded range.
    bool whole = true;
    for (std::int64_t k = 0; k < samples.size() && whole; ++k) {
      const double v = samples.figures(k)[f];
      if (samples.succeeded(k) && std::isfinite(v)) whole = v == std::round(v);
    }
    whole = whole && std::round(lo) == lo && std::round(hi) == hi && hi - lo <= 29.0;
    int bins = 30;
    if (whole) {
      lo -= 0.5, hi += 0.5;
      bins = static_cast<int>(std::lround(hi - lo));
    } else {
      const double pad = 0.03 * (hi - lo);
      lo -= pad, hi += pad;
    }
    const double width = (hi - lo) / bins;
    plots::Series bars{"samples", {}, {}, plots::Style::kBars};
    bars.bar_width = whole ? 0.6 * width : width;  // a count's bars apart, one a value
    std::vector<double> count(bins, 0.0);
    for (std::int64_t k = 0; k < samples.size(); ++k) {
      const double v = samples.figures(k)[f];
      if (!samples.succeeded(k) || !std::isfinite(v)) continue;
      count[static_cast<std::size_t>(std::clamp(static_cast<int>((v - lo) / width), 0, bins - 1))] += 1.0;
    }
    for (int b = 0; b < bins; ++b) bars.x.push_back(lo + (b + 0.5) * width), bars.y.push_back(count[static_cast<std::size_t>(b)]);
    panel.series.push_back(std::move(bars));
    using Mark = plots::Mark;
    for (const auto& [v, label] : {std::pair{st.p5, "p5"}, std::pair{st.p50, "p50"}, std::pair{st.p95, "p95"}}) {
      if (std::isfinite(v)) panel.marks.push_back({Mark::Axis::kVertical, v, label, true});
    }
    for (const double v : drawn_limits) panel.marks.push_back({Mark::Axis::kVertical, v, "limit", false});
    if (worst != nullptr) {
      for (const double v : {worst->figures[f].corner_low, worst->figures[f].corner_high}) {
        if (std::isfinite(v)) panel.marks.push_back({Mark::Axis::kVertical, v, "", false, true});
      }
    }
    double tallest = 0.0;
    for (const double c : count) tallest = std::max(tallest, c);
    // A far limit's arrow above the tallest bar and below the marks' labels (they hang from the top
    // of the axes, the longest, p50, over its top 14 %).
    if (!beyond_high.empty() || !beyond_low.empty()) panel.y_min = 0.0, panel.y_max = 1.35 * std::max(tallest, 1.0);
    for (const double v : beyond_high) {
      panel.notes.push_back({hi - 0.01 * (hi - lo), 1.08 * std::max(tallest, 1.0), fmt::format("limit {:.4g} ->", v), 1.0, 1.1});
    }
    for (const double v : beyond_low) {
      panel.notes.push_back({lo + 0.01 * (hi - lo), 1.08 * std::max(tallest, 1.0), fmt::format("<- limit {:.4g}", v), 0.0, 1.1});
    }
    panel.x_min = lo, panel.x_max = hi;
    figure.panels.push_back(std::move(panel));
  }
  if (figure.panels.empty()) figure.title += ": no sample succeeded";
  const int rows = static_cast<int>((figure.panels.size() + 2) / 3);
  figure.width = 1500;
  figure.height = 140 + 330 * std::max(rows, 1);
  return figure;
}

}  // namespace ltca::app::documents
