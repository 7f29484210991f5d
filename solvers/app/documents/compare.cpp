#include "documents/compare.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::app::documents {

Table Columns(const analysis::CompareResult& result) {
  Table t;
  const bool warned = std::any_of(result.solvers.begin(), result.solvers.end(), [](const auto& s) { return s.summary.warned > 0; });
  for (std::size_t r = 0; r < result.solvers.size(); ++r) {
    const analysis::SweepSummary& s = result.solvers[r].summary;
    const analysis::SolverDifferences& d = result.solvers[r].differences;
    const std::int64_t compared = result.solvers[r].compared(r == 0);
    const auto count = [&s](int v) { return s.succeeded > 0 ? static_cast<double>(v) : NAN; };
    const auto diff = [compared](double v) { return compared > 0 ? v : NAN; };
    t.Add("positions", static_cast<double>(s.positions()));
    t.Add("succeeded_positions", static_cast<double>(s.succeeded));
    t.Add("failed_positions", static_cast<double>(s.failed));
    t.Add("mean_te_arcsec", units::RadToArcsec(s.mean_te));
    t.Add("pp_te_arcsec", units::RadToArcsec(s.pp_te));
    t.Add("contacts_min", count(s.contacts_min));
    t.Add("contacts_max", count(s.contacts_max));
    t.Add("max_pin_force_n", s.max_pin_force);
    t.Add("max_contact_stress_mpa", s.max_contact_stress);
    t.Add("wall_seconds", s.wall_seconds);
    t.Add("compared_positions", static_cast<double>(compared));
    t.Add("max_te_difference_arcsec", diff(units::RadToArcsec(d.te)));
    t.Add("max_pin_force_difference_n", diff(d.force));
    t.Add("max_contact_count_difference", diff(d.pins));
    t.Add("warned_positions", static_cast<double>(s.warned));
    if (!warned) t.Add("first_warning", NAN);
  }
  return t;
}

nlohmann::json Json(const Deck& deck, const analysis::CompareResult& result) {
  nlohmann::json case_json = {{"title", deck.info.title}, {"deck", deck.name}};
  if (!deck.source.overrides.empty()) case_json["overrides"] = OverrideArguments(deck);
  nlohmann::json doc = {{"case", case_json},
                        {"model", ModelJson(deck.Model())},
                        {"reference", result.solvers.front().options.name},
                        {"solvers", nlohmann::json::array()}};
  for (const auto& [name, reason] : result.skipped) doc["skipped"].push_back({{"name", name}, {"reason", reason}});
  for (std::size_t r = 0; r < result.solvers.size(); ++r) {
    const analysis::SweepSummary& s = result.solvers[r].summary;
    const analysis::SolverDifferences& d = result.solvers[r].differences;
    const std::int64_t compared = result.solvers[r].compared(r == 0);
    const auto count = [&s](int v) { return s.succeeded > 0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
    const auto diff = [compared](nlohmann::json v) { return compared > 0 ? std::move(v) : nlohmann::json(nullptr); };
    doc["solvers"].push_back({{"name", result.solvers[r].options.name},
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
                              {"compared_positions", compared},
                              {"max_te_difference_arcsec", diff(units::RadToArcsec(d.te))},
                              {"max_pin_force_difference_n", diff(d.force)},
                              {"max_contact_count_difference", diff(d.pins)},
                              {"warned_positions", s.warned},
                              {"first_warning", s.warned > 0 ? nlohmann::json(s.first_warning) : nlohmann::json(nullptr)},
                              {"closed_period", s.closed_period}});
  }
  return doc;
}

std::string Text(const Deck& deck, const analysis::CompareResult& result) {
  const Deck::ModelInfo model = deck.Model();
  std::string text = CaseLines(deck) + ModelLine(deck);
  text += fmt::format("{} positions, {} model ({} slice{}, {} surface), {} kinematics, law {} / {}; differences against {} where "
                      "both succeeded\n",
                      result.cranks.size(), model.name, model.slices, model.slices == 1 ? "" : "s", model.surface,
                      contact::ToString(deck.kinematics), contact::ToString(deck.contact.law),
                      contact::ToString(deck.contact.rho_convention), result.solvers.front().options.name);
  for (const auto& [name, reason] : result.skipped) text += fmt::format("skipped   {}: {}\n", name, reason);
  text += fmt::format("{:<14} {:<18} {:>9} {:>12} {:>10} {:>7} {:>11} {:>11} {:>12} {:>12} {:>9} {:>9}\n", "solver", "status",
                      "failed", "mean_te_as", "pp_te_as", "pins", "max_F_N", "max_p_MPa", "d_te_as", "d_F_N", "d_pins", "time_s");
  for (std::size_t r = 0; r < result.solvers.size(); ++r) {
    const analysis::SweepSummary& s = result.solvers[r].summary;
    const analysis::SolverDifferences& d = result.solvers[r].differences;
    const bool compared = result.solvers[r].compared(r == 0) > 0;  // no difference over nothing
    const std::string pins = s.succeeded > 0 ? fmt::format("{:>3}-{:<3}", s.contacts_min, s.contacts_max) : "n/a";
    text += fmt::format("{:<14} {:<18} {:>9} {:>12} {:>10} {:>7} {:>11} {:>11} {:>12} {:>12} {:>9} {:>9.4f}\n",
                        result.solvers[r].options.name, solvers::ToString(s.status), s.failed,
                        FormatOrNa(units::RadToArcsec(s.mean_te), 6), FormatOrNa(units::RadToArcsec(s.pp_te), 6), pins,
                        FormatOrNa(s.max_pin_force, 3), FormatOrNa(s.max_contact_stress, 3),
                        compared ? fmt::format("{:.3g}", units::RadToArcsec(d.te)) : "n/a",
                        compared ? fmt::format("{:.3g}", d.force) : "n/a", compared ? fmt::format("{}", d.pins) : "n/a",
                        s.wall_seconds);
  }
  // Warnings as `ltca solve` lists them: a stress beyond the material's limit is no plain success.
  for (const auto& solver : result.solvers) {
    if (solver.summary.warned > 0) {
      text += fmt::format("warnings  {}: {} positions, first at {}\n", solver.options.name, solver.summary.warned,
                          solver.summary.first_warning);
    }
  }
  if (result.any_failed()) text += "some positions failed: the figures of each solver are over its successful positions only\n";
  return text;
}

plots::Figure Figure(const Deck& deck, const analysis::CompareResult& result, const std::vector<double>& crank_deg,
                     const std::vector<std::vector<double>>& te) {
  const std::size_t solvers = result.solvers.size();
  plots::Figure figure;
  figure.title = fmt::format("{}: loaded TE of {} solvers over crank {:.4g} to {:.4g} deg", CaseTitle(deck), solvers,
                             crank_deg.empty() ? 0.0 : crank_deg.front(), crank_deg.empty() ? 0.0 : crank_deg.back());
  const std::string& reference = result.solvers.front().options.name;
  std::string skips;
  for (const auto& [name, reason] : result.skipped) skips += fmt::format("; skipped: {} ({})", name, reason.substr(0, reason.find(" (")));
  figure.caption = FigureCaption(deck, fmt::format("model {}, {} kinematics, {} positions; a failed position is a gap{}",
                                                   deck.Model().name, contact::ToString(deck.kinematics), crank_deg.size(), skips));
  figure.columns = solvers > 1 ? 2 : 1;
  figure.width = solvers > 1 ? 1500 : 900;
  figure.height = 560;
  plots::Panel all;
  all.title = "loaded transmission error";
  all.x_label = "crank angle (deg)";
  all.y_label = "TE (arcsec)";
  all.legend = plots::LegendPlace::kOutsideRight;
  // Solvers that agree draw one curve: each its own marker, the first largest and the later ones
  // smaller inside it, so that every curve stays visible.
  for (std::size_t r = 0; r < solvers; ++r) {
    plots::Series s{result.solvers[r].options.name, crank_deg, te[r], plots::Style::kLineMarkers};
    s.marker_size = 1.0 + 0.6 * static_cast<double>(solvers - 1 - r);
    s.dashed = r % 2 == 1;
    all.series.push_back(std::move(s));
  }
  // A solver that did not run is in the legend with its reason, and draws nothing.
  for (const auto& [name, reason] : result.skipped) {
    plots::Series s{fmt::format("{} (skipped)", name), {}, {}, plots::Style::kLineMarkers};
    s.colour = static_cast<int>(all.series.size());
    all.series.push_back(std::move(s));
  }
  figure.panels.push_back(std::move(all));
  if (solvers > 1) {
    plots::Panel diff;
    diff.title = fmt::format("difference from {}", reference);
    diff.x_label = "crank angle (deg)";
    diff.legend = plots::LegendPlace::kOutsideRight;
    // The differences in a unit of their own size, named in the axis label (PLplot's "x10^-9"
    // multiplier sits above the panel title, where 1e-9 arcsec reads as 1 arcsec).
    double largest = 0.0;
    for (std::size_t r = 1; r < solvers; ++r) {
      for (std::size_t i = 0; i < crank_deg.size(); ++i) {
        const double d = std::abs(te[r][i] - te[0][i]);
        if (std::isfinite(d)) largest = std::max(largest, d);
      }
    }
    const int exponent = largest > 0.0 && largest < 0.01 ? static_cast<int>(std::floor(std::log10(largest))) : 0;
    const double scale = std::pow(10.0, -exponent);
    diff.y_label = exponent == 0 ? fmt::format("TE - TE of {} (arcsec)", reference)
                                 : fmt::format("TE - TE of {} (1e{} arcsec)", reference, exponent);
    for (std::size_t r = 1; r < solvers; ++r) {
      plots::Series d{result.solvers[r].options.name, crank_deg, {}, plots::Style::kLineMarkers};
      d.colour = static_cast<int>(r);  // the colour and marker it has on the left
      d.dashed = r % 2 == 1;
      for (std::size_t i = 0; i < crank_deg.size(); ++i) d.y.push_back(scale * (te[r][i] - te[0][i]));  // NaN where either failed
      diff.series.push_back(std::move(d));
    }
    diff.marks.push_back({plots::Mark::Axis::kHorizontal, 0.0, "", false});
    figure.panels.push_back(std::move(diff));
  }
  return figure;
}

}  // namespace ltca::app::documents
