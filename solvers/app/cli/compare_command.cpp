#include "compare_command.hpp"

#include "command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "contact_commands.hpp"
#include "ltca/solvers/registry.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/analysis/sweep.hpp"
#include "solve_command.hpp"

namespace ltca::cli {
namespace {

/// Largest differences of one solver from the reference, over positions where both succeeded.
struct Differences {
  double te = 0.0, force = 0.0;  ///< arcsec, N
  int pins = 0;
  std::int64_t compared = 0;     ///< positions where both succeeded
  void Add(const app::PositionResult& a, const app::PositionResult& ref) {
    if (!a.succeeded() || !ref.succeeded()) return;
    ++compared;
    te = std::max(te, std::abs(units::RadToArcsec(a.result.te - ref.result.te)));
    for (std::size_t k = 0; k < a.result.force.size() && k < ref.result.force.size(); ++k) {
      force = std::max(force, std::abs(a.result.force[k] - ref.result.force[k]));
    }
    pins = std::max(pins, std::abs(a.contacts - ref.contacts));
  }
};

namespace plots = app::plots;

/// Every solver's TE over crank angle (left) and its difference from the first solver's (right).
void WriteCompareFigure(const app::Deck& deck, const std::vector<app::SweepRunner>& runners,
                        const std::vector<std::pair<std::string, std::string>>& skipped, const std::vector<double>& crank_deg,
                        const std::vector<std::vector<double>>& te, Output& output) {
  plots::Figure figure;
  figure.title = fmt::format("{}: loaded TE of {} solvers over crank {:.4g} to {:.4g} deg", deck.info.title, runners.size(),
                             crank_deg.empty() ? 0.0 : crank_deg.front(), crank_deg.empty() ? 0.0 : crank_deg.back());
  const auto& ref = runners.front().options();
  std::string skips;
  for (const auto& [name, reason] : skipped) skips += fmt::format("; skipped: {} ({})", name, reason.substr(0, reason.find(" (")));
  figure.caption = FigureCaption(deck, fmt::format("model {}, {} kinematics, {} positions; a failed position is a gap{}",
                                                   deck.Model().name, contact::ToString(deck.kinematics), crank_deg.size(), skips));
  figure.columns = runners.size() > 1 ? 2 : 1;
  figure.width = runners.size() > 1 ? 1500 : 900;
  figure.height = 560;
  plots::Panel all;
  all.title = "loaded transmission error";
  all.x_label = "crank angle (deg)";
  all.y_label = "TE (arcsec)";
  all.legend = plots::LegendPlace::kOutsideRight;
  // Solvers that agree draw one curve: each its own marker, the first largest and the later ones
  // smaller inside it, so that every curve stays visible (issue 27: only the last one was).
  for (std::size_t r = 0; r < runners.size(); ++r) {
    plots::Series s{runners[r].options().name, crank_deg, te[r], plots::Style::kLineMarkers};
    s.marker_size = 1.0 + 0.6 * static_cast<double>(runners.size() - 1 - r);
    s.dashed = r % 2 == 1;
    all.series.push_back(std::move(s));
  }
  // A solver that did not run is in the legend with its reason, and draws nothing.
  for (const auto& [name, reason] : skipped) {
    plots::Series s{fmt::format("{} (skipped)", name), {}, {}, plots::Style::kLineMarkers};
    s.colour = static_cast<int>(all.series.size());
    all.series.push_back(std::move(s));
  }
  figure.panels.push_back(std::move(all));
  if (runners.size() > 1) {
    plots::Panel diff;
    diff.title = fmt::format("difference from {}", ref.name);
    diff.x_label = "crank angle (deg)";
    diff.legend = plots::LegendPlace::kOutsideRight;
    // The differences in a unit of their own size, named in the axis label (issue 27: PLplot's
    // "x10^-9" multiplier sat above the panel title, and 1e-9 arcsec read as 1 arcsec).
    double largest = 0.0;
    for (std::size_t r = 1; r < runners.size(); ++r) {
      for (std::size_t i = 0; i < crank_deg.size(); ++i) {
        const double d = std::abs(te[r][i] - te[0][i]);
        if (std::isfinite(d)) largest = std::max(largest, d);
      }
    }
    const int exponent = largest > 0.0 && largest < 0.01 ? static_cast<int>(std::floor(std::log10(largest))) : 0;
    const double scale = std::pow(10.0, -exponent);
    diff.y_label = exponent == 0 ? fmt::format("TE - TE of {} (arcsec)", ref.name)
                                 : fmt::format("TE - TE of {} (1e{} arcsec)", ref.name, exponent);
    for (std::size_t r = 1; r < runners.size(); ++r) {
      plots::Series d{runners[r].options().name, crank_deg, {}, plots::Style::kLineMarkers};
      d.colour = static_cast<int>(r);  // the colour and marker it has on the left
      d.dashed = r % 2 == 1;
      for (std::size_t i = 0; i < crank_deg.size(); ++i) d.y.push_back(scale * (te[r][i] - te[0][i]));  // NaN where either failed
      diff.series.push_back(std::move(d));
    }
    diff.marks.push_back({plots::Mark::Axis::kHorizontal, 0.0, "", false});
    figure.panels.push_back(std::move(diff));
  }
  WriteFigure(figure, output);
}

}  // namespace

int RunCompare(const app::Deck& deck_given, const CompareOptions& options, const Streams& streams) {
  const app::Deck deck = DeckFor(deck_given, options.kinematics);  // --kinematics, else the deck's
  const std::vector<std::string> asked = options.solvers.empty() ? solvers::SolverNames() : options.solvers;
  RequireDistinctOutputs({{"--json", options.json_path}, {"--svg", options.svg_path}});
  Output json("--json", options.json_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  // Every solver checked (names, options) and the stage (interference) first; one stage for all.
  // A solver that does not solve the deck's model (a reducer stage) is skipped with its reason,
  // named in the text, the JSON and the figure; the exit code judges the solvers that ran.
  deck.RequireMaterial();
  const double torque = deck.RequireLoad().torque;
  std::vector<std::string> names;
  std::vector<std::pair<std::string, std::string>> skipped;  // name, reason
  for (const auto& name : asked) {
    const std::unique_ptr<solvers::LoadSolver> solver = solvers::MakeSolver(name);
    if (deck.reducer && !solver->supports_stage()) {
      skipped.emplace_back(name, "does not solve the reducer stage ([output]; docs/stage.md)");
    } else {
      names.push_back(name);
    }
  }
  if (names.empty()) {
    throw std::invalid_argument(fmt::format("--solvers {}: none of them solves the reducer stage of deck '{}' ([output]); "
                                            "expected one of the solvers that do (docs/stage.md)",
                                            fmt::join(asked, ","), deck.name));
  }
  const analysis::Stage stage = deck.MakeStage();
  std::vector<app::SweepRunner> runners;
  for (const auto& name : names) {
    solvers::SolverOptions o = deck.solver;
    o.name = name;
    runners.emplace_back(stage, o, torque);
  }
  std::vector<Differences> diffs(runners.size());
  const std::vector<double> cranks = deck.sweep.CrankAngles();
  Progress progress(streams.err, streams.progress, "comparing at position", static_cast<std::int64_t>(cranks.size()));
  std::int64_t done = 0;
  // The figure's data: a TE per solver and position (NaN where it failed).
  std::vector<double> plot_crank;
  std::vector<std::vector<double>> plot_te(runners.size());
  const auto te_of = [](const app::PositionResult& p) { return p.succeeded() ? units::RadToArcsec(p.result.te) : NAN; };
  for (const double crank : cranks) {
    const app::PositionResult ref = runners.front().Solve(crank);
    if (svg.enabled()) plot_crank.push_back(units::RadToDeg(crank)), plot_te[0].push_back(te_of(ref));
    for (std::size_t r = 1; r < runners.size(); ++r) {
      const app::PositionResult p = runners[r].Solve(crank);
      if (svg.enabled()) plot_te[r].push_back(te_of(p));
      diffs[r].Add(p, ref);
    }
    progress.Update(++done);
  }
  progress.Finish();

  const auto& ref_options = runners.front().options();
  std::ostream& text = streams.text;
  fmt::print(text, "case      {}\n", deck.info.title);
  text << ModelLine(deck);
  fmt::print(text, "{} positions, {} model ({} slice{}, {} surface), {} kinematics, law {} / {}; differences against {} where both succeeded\n", cranks.size(),
             deck.Model().name, deck.Model().slices, deck.Model().slices == 1 ? "" : "s", deck.Model().surface,
             contact::ToString(deck.kinematics),
             contact::ToString(deck.contact.law), contact::ToString(deck.contact.rho_convention), ref_options.name);
  for (const auto& [name, reason] : skipped) fmt::print(text, "skipped   {}: {}\n", name, reason);
  fmt::print(text, "{:<14} {:<18} {:>9} {:>12} {:>10} {:>7} {:>11} {:>11} {:>12} {:>12} {:>9} {:>9}\n", "solver", "status",
             "failed", "mean_te_as", "pp_te_as", "pins", "max_F_N", "max_p_MPa", "d_te_as", "d_F_N", "d_pins", "time_s");
  nlohmann::json doc = {{"case", {{"title", deck.info.title}, {"deck", deck.name}}},
                        {"model", ModelJson(deck.Model())},
                        {"reference", ref_options.name},
                        {"solvers", nlohmann::json::array()}};
  for (const auto& [name, reason] : skipped) doc["skipped"].push_back({{"name", name}, {"reason", reason}});
  bool all_succeeded = true;
  for (std::size_t r = 0; r < runners.size(); ++r) {
    const app::SweepSummary s = runners[r].Summary();
    const Differences& d = diffs[r];
    all_succeeded = all_succeeded && s.all_succeeded();
    const bool compared = r == 0 ? s.succeeded > 0 : d.compared > 0;  // no difference over nothing
    const std::string pins = s.succeeded > 0 ? fmt::format("{:>3}-{:<3}", s.contacts_min, s.contacts_max) : "n/a";
    fmt::print(text, "{:<14} {:<18} {:>9} {:>12} {:>10} {:>7} {:>11} {:>11} {:>12} {:>12} {:>9} {:>9.4f}\n",
               runners[r].options().name, solvers::ToString(s.status), s.failed,
               FormatOrNa(units::RadToArcsec(s.mean_te), 6), FormatOrNa(units::RadToArcsec(s.pp_te), 6), pins,
               FormatOrNa(s.max_pin_force, 3), FormatOrNa(s.max_contact_stress, 3),
               compared ? fmt::format("{:.3g}", d.te) : "n/a", compared ? fmt::format("{:.3g}", d.force) : "n/a",
               compared ? fmt::format("{}", d.pins) : "n/a", s.wall_seconds);
    const auto count = [&s](int v) { return s.succeeded > 0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
    const auto diff = [compared](nlohmann::json v) { return compared ? std::move(v) : nlohmann::json(nullptr); };
    doc["solvers"].push_back({{"name", runners[r].options().name},
                              {"status", solvers::ToString(s.status)},
                              {"positions", s.positions()},
                              {"succeeded_positions", s.succeeded},
                              {"failed_positions", s.failed},
                              {"mean_te_arcsec", FiniteOrNull(units::RadToArcsec(s.mean_te))},
                              {"pp_te_arcsec", FiniteOrNull(units::RadToArcsec(s.pp_te))},
                              {"contacts_min", count(s.contacts_min)},
                              {"contacts_max", count(s.contacts_max)},
                              {"max_pin_force_n", FiniteOrNull(s.max_pin_force)},
                              {"max_contact_stress_mpa", FiniteOrNull(s.max_contact_stress)},
                              {"wall_seconds", s.wall_seconds},
                              {"compared_positions", r == 0 ? s.succeeded : d.compared},
                              {"max_te_difference_arcsec", diff(d.te)},
                              {"max_pin_force_difference_n", diff(d.force)},
                              {"max_contact_count_difference", diff(d.pins)},
                              {"warned_positions", s.warned},
                              {"first_warning", s.warned > 0 ? nlohmann::json(s.first_warning) : nlohmann::json(nullptr)},
                              {"closed_period", s.closed_period}});
  }
  // Warnings as `ltca solve` lists them (issue 26: a stress far beyond the material's limit was
  // reported as a plain success here).
  for (const auto& runner : runners) {
    const app::SweepSummary s = runner.Summary();
    if (s.warned > 0) {
      fmt::print(text, "warnings  {}: {} positions, first at {}\n", runner.options().name, s.warned, s.first_warning);
    }
  }
  bool any_failed = false;
  for (const auto& runner : runners) any_failed = any_failed || runner.Summary().failed > 0;
  if (any_failed) fmt::print(text, "some positions failed: the figures of each solver are over its successful positions only\n");
  if (json.enabled()) {
    json.stream() << Dump(doc) << '\n';
    json.Commit();
  }
  if (svg.enabled()) WriteCompareFigure(deck, runners, skipped, plot_crank, plot_te, svg);
  return all_succeeded ? kExitSuccess : kExitNotSucceeded;
}

Command CompareCommand() {
  auto st = std::make_shared<DeckState<CompareOptions>>();
  return {"compare",
          "Run several solvers (default: all) on the same sweep and print them side by side with the largest differences "
          "from the first in TE, pin force and contact count, and their times.",
          [st](CLI::App& c) {
            CompareOptions& o = st->options;
            AddDeckInputs(c, st->deck);
            c.add_option("--solvers", o.solvers, "Comma-separated solver names (default: all)")->delimiter(',');
            c.add_option("--kinematics", o.kinematics, "linearised or exact (default: the deck's)")
                ->check(CLI::IsMember({"exact", "linearised"}));
            AddOutput(c, "--json", o.json_path, "Write the comparison as JSON ('-': stdout)");
            AddOutput(c, "--svg", o.svg_path,
                      "Draw every solver's TE over crank angle and its difference from the first (SVG; .png/.pdf by extension)");
          },
          [st] { return std::vector<std::string>{st->options.json_path, st->options.svg_path}; },
          [st](const Streams& streams) {
            for (const auto& name : st->options.solvers) solvers::MakeSolver(name);  // names checked first
            return RunCompare(st->deck.Read(), st->options, streams);
          }};
}

}  // namespace ltca::cli
