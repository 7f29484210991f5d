#include "solve_command.hpp"

#include "command.hpp"

#include <algorithm>
#include <tuple>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "ltca/analysis/stage.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::cli {
namespace {

namespace plots = app::plots;
using units::RadToArcsec;
using units::RadToDeg;

double MaxOf(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

/// A reducer stage's solution at one position (issue 25): per disc its pose, the output pins' forces
/// with their direction, the bearings' forces and roller loads; the strain energy per group.
nlohmann::json StageJson(const solvers::StageSolution& st) {
  nlohmann::json discs = nlohmann::json::array();
  const auto angle = [](const Eigen::Vector2d& v) { return FiniteOrNull(RadToDeg(std::atan2(v.y(), v.x()))); };
  for (const auto& d : st.discs) {
    nlohmann::json disc = {{"translation_um", {units::MmToUm(d.translation.x()), units::MmToUm(d.translation.y())}},
                           {"rotation_arcsec", FiniteOrNull(RadToArcsec(d.rotation))}};
    if (!d.output_force.empty()) {
      nlohmann::json directions = nlohmann::json::array();
      for (const auto& n : d.output_direction) directions.push_back(angle(n));
      disc["output_pin_force_n"] = d.output_force;
      disc["output_pin_direction_deg"] = directions;
    }
    nlohmann::json loads = nlohmann::json::array(), directions = nlohmann::json::array();
    for (const auto& f : d.bearing_force) {
      loads.push_back(FiniteOrNull(f.norm()));
      directions.push_back(f.norm() > 0.0 ? angle(f) : nlohmann::json(nullptr));
    }
    disc["bearing_load_n"] = loads;
    disc["bearing_load_direction_deg"] = directions;
    bool rollers = false;
    for (const auto& r : d.roller_load) rollers = rollers || !r.empty();
    if (rollers) disc["roller_load_n"] = d.roller_load;
    if (!d.shaft_deflection.empty()) {
      nlohmann::json shafts = nlohmann::json::array();
      for (const auto& v : d.shaft_deflection) shafts.push_back({units::MmToUm(v.x()), units::MmToUm(v.y())});
      disc["shaft_deflection_um"] = shafts;
    }
    discs.push_back(std::move(disc));
  }
  nlohmann::json energy = nlohmann::json::object();
  for (int g = 0; g < solvers::kStageGroups; ++g) {
    energy[solvers::ToString(static_cast<solvers::StageGroup>(g))] = st.group_energy[static_cast<std::size_t>(g)];
  }
  return {{"discs", discs}, {"strain_energy_nmm", energy}, {"force_balance", st.force_balance_relative},
          {"moment_balance", st.moment_balance_relative}};
}

/// A position as JSON: the figures of a failed solve are null, its status and message kept.
nlohmann::json PositionJson(const app::PositionResult& p) {
  const bool ok = p.succeeded();
  nlohmann::json angles = nlohmann::json::array();
  for (const double a : p.angle) angles.push_back(RadToDeg(a));
  const auto figure = [ok](nlohmann::json value) { return ok ? std::move(value) : nlohmann::json(nullptr); };
  nlohmann::json j = {{"crank_deg", RadToDeg(p.crank)},
                      {"te_arcsec", figure(FiniteOrNull(RadToArcsec(p.result.te)))},
                      {"contacts", figure(p.contacts)},
                      {"pin_force_n", figure(p.pin_force)},
                      {"pin_angle_deg", angles},
                      {"contact_stress_mpa", figure(p.contact_stress)},
                      {"status", solvers::ToString(p.result.status)},
                      {"flank", solvers::ToString(p.result.flank)},
                      {"message", p.result.message},
                      {"warnings", p.result.warnings},
                      {"torque_evaluations", p.result.torque_evaluations},
                      {"residual", FiniteOrNull(p.result.residuals.Normalised())}};
  if (!p.disc_torque.empty()) {
    // Two discs (issue 13): the torque each carries, N*m, signed as T; pin arrays run over disc 1's
    // pins, then disc 2's.
    nlohmann::json torques = nlohmann::json::array();
    for (const double t : p.disc_torque) torques.push_back(FiniteOrNull(units::NmmToNm(t)));
    j["disc_torque_nm"] = figure(torques);
    const double total = p.disc_torque.size() == 2 ? p.disc_torque[0] + p.disc_torque[1] : 0.0;
    j["first_disc_share"] = figure(total != 0.0 ? FiniteOrNull(p.disc_torque[0] / total) : nlohmann::json(nullptr));
  }
  if (p.result.stage) j["stage"] = figure(StageJson(*p.result.stage));
  if (p.slices > 1) {
    const bool complete = p.result.force.size() == p.pin_force.size() * static_cast<std::size_t>(p.slices);
    // The contact pattern (issue 11): per pin its slice forces and stresses and its load centroid.
    nlohmann::json forces = nlohmann::json::array(), stresses = nlohmann::json::array(), centroid = nlohmann::json::array();
    const auto n = static_cast<std::size_t>(p.slices);
    for (std::size_t j = 0; complete && j < p.pin_force.size(); ++j) {
      const auto first = p.result.force.begin() + static_cast<std::ptrdiff_t>(j * n);
      forces.push_back(std::vector<double>(first, first + static_cast<std::ptrdiff_t>(n)));
      const auto s0 = p.point_stress.begin() + static_cast<std::ptrdiff_t>(j * n);
      stresses.push_back(std::vector<double>(s0, s0 + static_cast<std::ptrdiff_t>(n)));
      centroid.push_back(FiniteOrNull(p.load_centroid[j]));
    }
    // Always present in the slice model; null for a position no valid solve produced.
    j["slice_force_n"] = complete ? figure(forces) : nlohmann::json(nullptr);
    j["slice_stress_mpa"] = complete ? figure(stresses) : nlohmann::json(nullptr);
    j["load_centroid_mm"] = complete ? figure(centroid) : nlohmann::json(nullptr);
  }
  return j;
}

/// A reducer stage's summary (issue 25): the largest loads and each bearing's ISO 281 life from its
/// mean equivalent load over the positions (analysis::BearingLives).
nlohmann::json StageSummaryJson(const app::Deck& deck, const app::SweepSummary& s) {
  if (!s.stage || !deck.reducer) return nullptr;
  const analysis::StageSummary& g = *s.stage;
  const analysis::BearingLife life = analysis::BearingLives(deck, g, deck.sweep, s.closed_period, deck.operation ? deck.operation->input_speed : std::numeric_limits<double>::quiet_NaN());
  nlohmann::json shares = nlohmann::json::object();
  for (std::size_t k = 0; k < g.energy_share.size(); ++k) {
    shares[solvers::ToString(static_cast<solvers::StageGroup>(k))] = FiniteOrNull(g.energy_share[k]);
  }
  return {{"max_output_pin_force_n", deck.reducer->kind == solvers::OutputKind::kPins ? FiniteOrNull(g.max_output_force)
                                                                                      : nlohmann::json(nullptr)},
          {"max_bearing_load_n", FiniteOrNull(g.max_bearing_load)},
          {"max_roller_load_n", FiniteOrNull(g.max_roller_load)},
          {"mean_equivalent_load_n", g.mean_equivalent_load},
          {"l10_million_revolutions", life.million_revolutions},
          {"l10_hours", life.hours},
          {"shortest_l10_hours", FiniteOrNull(life.ShortestHours())},  // null when no bearing has a life
          {"life_basis", life.basis},
          {"strain_energy_share", shares}};
}

nlohmann::json SummaryJson(const app::SweepSummary& s, const app::Deck::ModelInfo& model) {
  const auto count = [&s](int v) { return s.succeeded > 0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
  nlohmann::json j = {{"model", model.name},
                      {"width_slices", model.slices},
                      {"mean_te_arcsec", FiniteOrNull(RadToArcsec(s.mean_te))},
                      {"pp_te_arcsec", FiniteOrNull(RadToArcsec(s.pp_te))},
                      {"contacts_min", count(s.contacts_min)},
                      {"contacts_max", count(s.contacts_max)},
                      {"max_pin_force_n", FiniteOrNull(s.max_pin_force)},
                      {"max_contact_stress_mpa", FiniteOrNull(s.max_contact_stress)},
                      {"wall_seconds", s.wall_seconds},
                      {"status", solvers::ToString(s.status)},
                      {"positions", s.positions()},
                      {"succeeded_positions", s.succeeded},
                      {"failed_positions", s.failed},
                      {"warned_positions", s.warned},
                      {"closed_period", s.closed_period}};
  if (s.warned > 0) j["first_warning"] = s.first_warning;
  if (model.discs == 2) {  // issue 13: the share of T the first disc carries, over the successful positions
    j["discs"] = 2;
    j["first_disc_share_mean"] = FiniteOrNull(s.first_disc_share_mean);
    j["first_disc_share_min"] = FiniteOrNull(s.first_disc_share_min);
    j["first_disc_share_max"] = FiniteOrNull(s.first_disc_share_max);
  }
  if (s.failed > 0) {
    j["note"] = s.succeeded > 0
                    ? fmt::format("{} of {} positions failed: the figures are over the {} successful positions only",
                                  s.failed, s.positions(), s.succeeded)
                    : fmt::format("all {} positions failed: no figure", s.positions());
  }
  return j;
}

/// What the figure needs, kept compactly while the sweep streams by: the TE of every position
/// (NaN where the solve failed: a gap in the curve) and the position of the largest pin force.
struct SvgData {
  std::optional<app::PositionResult> peak;
  double f_peak = -1.0;
  /// The pin x crank maps: every stride-th position's pin forces and stresses (NaN when it
  /// failed), at most about kMapColumns columns whatever the sweep.
  static constexpr std::int64_t kMapColumns = 120;
  std::int64_t stride = 1, seen = 0;
  std::vector<double> map_crank;
  std::vector<std::vector<double>> map_force, map_stress;
  /// The TE line (crank deg, TE arcsec): every position up to DecimatedSeries::kBuckets of them;
  /// beyond, the least and the largest TE of every te.stride() positions in crank order, and a gap
  /// (NaN) where one of them failed, so that memory and the figure stay bounded whatever the sweep
  /// (100,000 positions drew a 39 MB SVG and peaked at 190 MB). The mean and the extremes marked
  /// are the sweep's own.
  DecimatedSeries te;
  std::int64_t positions = 0;
  double first_crank = NAN, last_crank = NAN;  ///< the sweep's, deg (the title's range)
  explicit SvgData(std::int64_t n) : stride(std::max<std::int64_t>(1, (n + kMapColumns - 1) / kMapColumns)), te(n) {}
  void Add(const app::PositionResult& p) {
    const double crank = RadToDeg(p.crank);
    if (positions == 0) first_crank = crank;
    last_crank = crank;
    te.Add(positions++, crank, p.succeeded() ? RadToArcsec(p.result.te) : NAN);
    if (seen++ % stride == 0) {
      const auto or_nan = [&p](const std::vector<double>& v) {
        return p.succeeded() ? v : std::vector<double>(v.size(), NAN);
      };
      map_crank.push_back(RadToDeg(p.crank));
      map_force.push_back(or_nan(p.pin_force));
      map_stress.push_back(or_nan(p.contact_stress));
    }
    if (!p.succeeded()) return;
    const double f = MaxOf(p.pin_force);
    if (f > f_peak) f_peak = f, peak = p;
  }
};

/// Bars of one quantity per pin, numbered j + 1 (docs/conventions.md), one series per disc;
/// the loaded pins carry their number above the bar.
plots::Panel PinBars(const std::vector<double>& values, int pin_count, const std::string& y_label, const std::string& title) {
  plots::Panel panel;
  panel.title = title;
  panel.x_label = "pin number";
  panel.y_label = y_label;
  const int discs = pin_count > 0 && values.size() == 2 * static_cast<std::size_t>(pin_count) ? 2 : 1;
  const int n = discs == 2 ? pin_count : static_cast<int>(values.size());
  double top = 0.0;
  for (const double v : values) top = std::max(top, std::isfinite(v) ? v : 0.0);
  for (int d = 0; d < discs; ++d) {
    plots::Series bars;
    bars.label = discs == 2 ? fmt::format("disc {}", d + 1) : "";
    bars.style = plots::Style::kBars;
    bars.colour = d;
    bars.bar_width = discs == 2 ? 0.4 : 0.7;
    for (int j = 0; j < n; ++j) {
      const double v = values[static_cast<std::size_t>(d * n + j)];
      const double x = j + 1 + (discs == 2 ? (d == 0 ? -0.2 : 0.2) : 0.0);
      bars.x.push_back(x);
      bars.y.push_back(v);
      if (std::isfinite(v) && v > 0.0) panel.notes.push_back({x, v + 0.02 * top, fmt::format("{}", j + 1), 0.5, 0.75});
    }
    panel.series.push_back(std::move(bars));
  }
  panel.x_min = 0.0, panel.x_max = n + 1.0;
  // With two discs the legend (top right) sits in headroom above the tallest bar and its number
  // (issue 27: it covered the tallest contact-stress bar where the loaded pins were the last ones).
  panel.y_min = 0.0, panel.y_max = top > 0.0 ? (discs == 2 ? 1.5 : 1.1) * top : 1.0;
  return panel;
}

/// The TE over the sweep with its mean and peak-to-peak marked.
plots::Panel TePanel(const std::vector<double>& crank_deg, const std::vector<double>& te_arcsec, const std::string& label,
                     double mean = NAN) {
  plots::Panel panel;
  panel.title = "loaded transmission error";
  panel.x_label = "crank angle (deg)";
  panel.y_label = "TE (arcsec)";
  panel.series.push_back({label, crank_deg, te_arcsec, plots::Style::kLineMarkers});
  MarkMeanAndPeakToPeak(panel, te_arcsec, "arcsec", mean);
  return panel;
}

void WriteFigure(const app::Deck& deck, const solvers::SolverOptions& solver, SvgData& data, double mean_te_arcsec, Output& output) {
  plots::Figure figure;
  const double c_lo = std::isfinite(data.first_crank) ? data.first_crank : 0.0;
  const double c_hi = std::isfinite(data.last_crank) ? data.last_crank : 0.0;
  figure.title = fmt::format("{}: loaded TE over crank {:.4g} to {:.4g} deg, {} solver", deck.info.title, c_lo, c_hi, solver.name);
  figure.caption = FigureCaption(deck, fmt::format("model {}, solver {} ({} kinematics), T = {:g} N*m, {} positions",
                                                   deck.Model().name, solver.name, contact::ToString(deck.kinematics),
                                                   units::NmmToNm(deck.RequireLoad().torque), data.positions) +
                   (data.te.stride() > 1 ? fmt::format("; TE drawn as the least and largest of every {} positions", data.te.stride())
                                       : std::string()));
  figure.columns = 3;
  figure.width = 1500;
  figure.height = 520;
  // The mean marked is the summary's (a closed period's repeated state weighs once in it).
  figure.panels.push_back(TePanel(data.te.x(), data.te.y(), solver.name, mean_te_arcsec));
  if (data.peak) {
    const auto& p = *data.peak;
    const double crank = RadToDeg(p.crank);
    // Two discs (issue 27): both cranks, the second disc's half a turn on.
    const bool two = deck.disc_count() == 2;
    const std::string at = two ? fmt::format("cranks {:.4g} / {:.4g} deg", crank, RadToDeg(p.crank + contact::kSecondDiscCrankOffset))
                               : fmt::format("crank {:.4g} deg", crank);
    figure.panels.push_back(PinBars(p.pin_force, deck.pair.pin_count, "pin force (N)",
                                    two ? fmt::format("largest pin forces, {}", at)
                                        : fmt::format("pin forces at {} (largest force)", at)));
    figure.panels.push_back(PinBars(p.contact_stress, deck.pair.pin_count, "contact stress (MPa)",
                                    fmt::format("contact stress at {}", at)));
  } else {
    figure.title += ": no position succeeded";
  }
  // Pin x crank-angle maps of force and contact stress. Both discs bear on one pin ring, so the pins
  // are numbered 1 .. z_p for each disc, with a map per disc (issue 26: disc 2's were z_p + 1 ..).
  std::size_t pins = 0;
  for (const auto& f : data.map_force) pins = std::max(pins, f.size());
  if (data.peak && pins > 0) {
    const std::size_t per_disc = deck.disc_count() == 2 && pins == 2 * static_cast<std::size_t>(deck.pair.pin_count)
                                     ? static_cast<std::size_t>(deck.pair.pin_count)
                                     : pins;
    const std::size_t discs = pins / per_disc;
    std::vector<double> pin_numbers;
    for (std::size_t j = 0; j < per_disc; ++j) pin_numbers.push_back(static_cast<double>(j + 1));
    const auto map_panel = [&](const std::vector<std::vector<double>>& z, std::size_t disc, const std::string& label,
                               const std::string& title) {
      plots::Panel panel;
      panel.title = discs == 2 ? fmt::format("{}, disc {}", title, disc + 1) : title;
      // The crank axis is the first disc's: the second disc's crank is 180 deg on (issue 27).
      panel.x_label = disc == 1 ? "crank angle (deg); disc 2 at +180 deg" : "crank angle (deg)";
      panel.y_label = "pin number";
      std::vector<std::vector<double>> columns;
      for (const auto& column : z) {
        std::vector<double> part(per_disc, NAN);
        for (std::size_t j = 0; j < per_disc && disc * per_disc + j < column.size(); ++j) part[j] = column[disc * per_disc + j];
        columns.push_back(std::move(part));
      }
      panel.map = plots::Map{data.map_crank, pin_numbers, std::move(columns), label};
      const double half = data.map_crank.size() > 1 ? (data.map_crank[1] - data.map_crank[0]) / 2 : 0.5;
      panel.x_min = data.map_crank.front() - half, panel.x_max = data.map_crank.back() + half;
      panel.y_min = 0.5, panel.y_max = static_cast<double>(per_disc) + 0.5;
      return panel;
    };
    const std::string every = data.stride > 1 ? fmt::format(" (1 position in {})", data.stride) : "";
    for (std::size_t d = 0; d < discs; ++d) figure.panels.push_back(map_panel(data.map_force, d, "pin force (N)", "pin force map" + every));
    for (std::size_t d = 0; d < discs; ++d) {
      figure.panels.push_back(map_panel(data.map_stress, d, "contact stress (MPa)", "contact stress map" + every));
    }
    figure.height = discs == 2 ? 1480 : 1000;
  }
  // The contact pattern across the face width (the slice model, issue 11): pin x slice forces at
  // the position of the largest pin force.
  if (data.peak && data.peak->slices > 1 &&
      data.peak->result.force.size() == data.peak->pin_force.size() * static_cast<std::size_t>(data.peak->slices)) {
    const auto& p = *data.peak;
    const auto n = static_cast<std::size_t>(p.slices);
    plots::Map map;
    map.z_label = "slice force (N)";
    for (std::size_t k = 0; k < n; ++k) map.x.push_back((static_cast<double>(k) + 0.5) * deck.pair.face_width / static_cast<double>(n));
    for (std::size_t j = 0; j < p.pin_force.size(); ++j) map.y.push_back(static_cast<double>(j + 1));
    for (std::size_t k = 0; k < n; ++k) {
      std::vector<double> column;
      for (std::size_t j = 0; j < p.pin_force.size(); ++j) column.push_back(p.result.force[j * n + k]);
      map.z.push_back(std::move(column));
    }
    plots::Panel panel;
    panel.title = fmt::format("contact pattern at crank {:.4g} deg", RadToDeg(p.crank));
    panel.x_label = "face width position z (mm)";
    panel.y_label = "pin number";
    panel.x_min = 0.0, panel.x_max = deck.pair.face_width;
    panel.y_min = 0.5, panel.y_max = static_cast<double>(p.pin_force.size()) + 0.5;
    panel.map = std::move(map);
    figure.panels.push_back(std::move(panel));
  }
  cli::WriteFigure(figure, output);
}

/// A CSV field: the figure, or empty when no valid solve produced it.
std::string CsvFigure(bool ok, double v) { return ok && std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string(); }

}  // namespace

app::Deck DeckFor(const app::Deck& deck, const std::string& kinematics) {
  app::Deck d = deck;
  if (!kinematics.empty()) d.kinematics = contact::ParseKinematics(kinematics);
  return d;
}

solvers::SolverOptions SolverFor(const app::Deck& deck, const std::string& name) {
  solvers::SolverOptions solver = deck.solver;
  if (!name.empty()) solver.name = name;
  return solver;
}

nlohmann::json SolverJson(const app::Deck& deck, const solvers::SolverOptions& solver) {
  return {{"name", solver.name},
          {"kinematics", contact::ToString(deck.kinematics)},
          {"torque_tolerance", solver.torque_tolerance},
          {"law", contact::ToString(deck.contact.law)},
          {"rho_convention", contact::ToString(deck.contact.rho_convention)}};
}

std::string SolverLine(const app::Deck& deck, const solvers::SolverOptions& solver) {
  return fmt::format("solver    {} ({} kinematics, torque tolerance {:g}), law {} / {}\n", solver.name,
                     contact::ToString(deck.kinematics), solver.torque_tolerance, contact::ToString(deck.contact.law),
                     contact::ToString(deck.contact.rho_convention));
}

nlohmann::json CaseJson(const app::Deck& deck) {
  return {{"title", deck.info.title}, {"source", deck.info.source}, {"deck", deck.name}};
}

std::string FailureNote(const app::SweepSummary& s) {
  if (s.failed == 0) return {};
  if (s.succeeded == 0) return fmt::format("failed positions       all {} (no figure below is an answer)\n", s.positions());
  return fmt::format("failed positions       {} of {}; the figures below are over the {} successful positions only\n",
                     s.failed, s.positions(), s.succeeded);
}

nlohmann::json SolveSummaryJson(const app::Deck& deck, const app::SweepSummary& summary) {
  nlohmann::json j = SummaryJson(summary, deck.Model());
  if (deck.reducer) j["stage"] = StageSummaryJson(deck, summary);
  return j;
}

nlohmann::json SolveJson(const app::Deck& deck, const solvers::SolverOptions& solver, const app::SweepResult& sweep) {
  nlohmann::json j = {{"case", CaseJson(deck)}, {"model", ModelJson(deck.Model())}, {"solver", SolverJson(deck, solver)}};
  nlohmann::json positions = nlohmann::json::array();
  for (const app::PositionResult& p : sweep.positions) positions.push_back(PositionJson(p));
  j["positions"] = std::move(positions);
  j["summary"] = SolveSummaryJson(deck, sweep.summary);
  return j;
}

int RunSolve(const app::Deck& deck_given, const SolveOptions& options, const Streams& streams, const JsonEnvelope& envelope) {
  const app::Deck deck = DeckFor(deck_given, options.kinematics);  // --kinematics, else the deck's
  const solvers::SolverOptions solver = SolverFor(deck, options.solver);
  RequireDistinctOutputs({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path},
                    {"--pattern-csv", options.pattern_csv_path}});
  // Outputs first: an unwritable path is an error before anything is computed.
  Output json("--json", options.json_path, streams.out);
  Output csv("--csv", options.csv_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  Output pattern("--pattern-csv", options.pattern_csv_path, streams.out);

  SvgData svg_data(deck.sweep.positions);
  bool started = false;
  std::int64_t done = 0;
  Progress progress(streams.err, streams.progress, "solving position", deck.sweep.positions);
  const auto start = [&] {  // the headers, once the sweep is accepted (no partial document on bad input)
    started = true;
    if (json.enabled()) {
      nlohmann::json header = {
          {"case", CaseJson(deck)}, {"model", ModelJson(deck.Model())}, {"solver", SolverJson(deck, solver)}};
      json.stream() << envelope.before << OpenObject(header) << ",\n  \"positions\": [";
    }
    if (csv.enabled()) {
      csv.stream() << "crank_deg,te_arcsec,contacts,max_pin_force_n,max_contact_stress_mpa,status"
                   << (deck.disc_count() == 2 ? ",disc1_torque_nm,disc2_torque_nm\n" : "\n");
    }
    if (pattern.enabled()) pattern.stream() << "crank_deg,pin,slice,z_mm,force_n,contact_stress_mpa,status\n";
  };
  app::SweepCallbacks callbacks;
  callbacks.keep_positions = false;
  callbacks.on_position = [&](const app::PositionResult& p) {
    if (!started) start();
    if (json.enabled()) json.stream() << (done == 0 ? "\n    " : ",\n    ") << Dump(PositionJson(p), -1);
    if (csv.enabled()) {
      const bool ok = p.succeeded();
      fmt::print(csv.stream(), "{:.9g},{},{},{},{},{}", RadToDeg(p.crank), CsvFigure(ok, RadToArcsec(p.result.te)),
                 ok ? fmt::format("{}", p.contacts) : std::string(), CsvFigure(ok, MaxOf(p.pin_force)),
                 CsvFigure(ok, MaxOf(p.contact_stress)), solvers::ToString(p.result.status));
      if (p.disc_torque.size() == 2) {  // two discs (issue 13): each disc's torque, N*m
        fmt::print(csv.stream(), ",{},{}", CsvFigure(ok, units::NmmToNm(p.disc_torque[0])), CsvFigure(ok, units::NmmToNm(p.disc_torque[1])));
      }
      csv.stream() << '\n';
    }
    if (svg.enabled()) svg_data.Add(p);
    if (pattern.enabled()) {
      // Pin (1-based) x slice (1-based) of the model that ran; figures empty for a failed position.
      const bool ok = p.succeeded();
      const auto n = static_cast<std::size_t>(p.slices);
      const double width = deck.pair.face_width / static_cast<double>(p.slices);
      for (std::size_t j = 0; j < p.pin_force.size(); ++j) {
        for (std::size_t k = 0; k < n; ++k) {
          const std::size_t i = j * n + k;
          fmt::print(pattern.stream(), "{:.9g},{},{},{:.9g},{},{},{}\n", RadToDeg(p.crank), j + 1, k + 1,
                     (static_cast<double>(k) + 0.5) * width,
                     CsvFigure(ok, i < p.result.force.size() ? p.result.force[i] : NAN),
                     CsvFigure(ok, i < p.point_stress.size() ? p.point_stress[i] : NAN), solvers::ToString(p.result.status));
        }
      }
    }
    progress.Update(++done);
  };
  const app::SweepResult sweep = app::SolveDeckSweep(deck, solver, callbacks);
  progress.Finish();
  if (!started) start();
  const auto& s = sweep.summary;

  if (json.enabled()) {
    json.stream() << "\n  ],\n  \"summary\": " << Nested(Dump(SolveSummaryJson(deck, s))) << "\n}" << envelope.after << '\n';
    json.Commit();
  }
  if (csv.enabled()) csv.Commit();
  if (pattern.enabled()) pattern.Commit();
  if (svg.enabled()) WriteFigure(deck, solver, svg_data, RadToArcsec(sweep.summary.mean_te), svg);

  std::ostream& text = streams.text;
  fmt::print(text, "case      {}\n", deck.info.title);
  text << ModelLine(deck);
  text << SolverLine(deck, solver);
  fmt::print(text, "status                 {}\n", solvers::ToString(s.status));
  text << FailureNote(s);
  if (s.warned > 0) fmt::print(text, "warnings               {} positions, first at {}\n", s.warned, s.first_warning);
  const double torque = deck.RequireLoad().torque;
  fmt::print(text, "loaded flank           {}\n", torque > 0.0 ? "drive (torque > 0)" : (torque < 0.0 ? "coast (torque < 0)" : "none (zero torque)"));
  fmt::print(text, "mean TE                {} arcsec   (Liu eq. 16; < 0 on the drive flank, > 0 on the coast flank)\n", FormatOrNa(RadToArcsec(s.mean_te), 4));
  fmt::print(text, "peak-to-peak TE        {} arcsec\n", FormatOrNa(RadToArcsec(s.pp_te), 4));
  if (s.closed_period) fmt::print(text, "                       (the last position repeats the first: the mean counts it once)\n");
  if (s.succeeded > 0) {
    fmt::print(text, "pins in contact        {} to {}\n", s.contacts_min, s.contacts_max);
  } else {
    fmt::print(text, "pins in contact        n/a\n");
  }
  if (deck.disc_count() == 2) {
    fmt::print(text, "first disc's share     {} mean, {} to {} of T (disc 2: the rest; per crank in --json/--csv)\n",
               FormatOrNa(s.first_disc_share_mean, 4), FormatOrNa(s.first_disc_share_min, 4),
               FormatOrNa(s.first_disc_share_max, 4));
  }
  fmt::print(text, "largest pin force      {} N\n", FormatOrNa(s.max_pin_force, 2));
  fmt::print(text, "largest contact stress {} MPa\n", FormatOrNa(s.max_contact_stress, 2));
  if (deck.reducer && s.stage) {  // issue 25
    const analysis::StageSummary& g = *s.stage;
    const analysis::BearingLife life = analysis::BearingLives(deck, g, deck.sweep, s.closed_period, deck.operation ? deck.operation->input_speed : std::numeric_limits<double>::quiet_NaN());
    if (deck.reducer->kind == solvers::OutputKind::kPins) {
      fmt::print(text, "largest output pin     {} N\n", FormatOrNa(g.max_output_force, 2));
    }
    fmt::print(text, "largest bearing load   {} N{}\n", FormatOrNa(g.max_bearing_load, 2),
               std::isnan(g.max_roller_load) ? std::string() : fmt::format(" (largest roller {} N)", FormatOrNa(g.max_roller_load, 2)));
    double shortest = std::numeric_limits<double>::quiet_NaN();
    for (const double h : life.hours) shortest = std::isnan(shortest) ? h : std::min(shortest, h);
    fmt::print(text, "bearing L10            {} h, the shortest ({})\n", FormatOrNa(shortest, 4), life.basis);
  }
  fmt::print(text, "wall time              {:.4f} s for {} positions\n", s.wall_seconds, s.positions());
  return s.all_succeeded() ? kExitSuccess : kExitNotSucceeded;
}

Command SolveCommand() {
  auto st = std::make_shared<DeckState<SolveOptions>>();
  return {"solve",
          "Loaded tooth contact analysis over the deck's sweep with one solver: loaded TE (Liu eq. 16), pins in contact, "
          "pin forces, contact stresses. JSON, streamed: positions [{crank_deg, te_arcsec, contacts, pin_force_n, "
          "pin_angle_deg, contact_stress_mpa, status, flank, message}], then summary {mean_te_arcsec, pp_te_arcsec, "
          "contacts_min, contacts_max, max_pin_force_n, max_contact_stress_mpa, wall_seconds, status, positions, "
          "succeeded_positions, failed_positions}. A failed position's figures are null; the summary's are over the "
          "successful positions only (null when none succeeded).",
          [st](CLI::App& c) {
            AddLoadInputs(c, st->deck, st->options.solver, st->options.kinematics);
            AddOutput(c, "--json", st->options.json_path, "Write summary and positions as JSON ('-': stdout)");
            AddOutput(c, "--csv", st->options.csv_path, "Write one row per position as CSV");
            AddOutput(c, "--svg", st->options.svg_path, "Draw the TE over the sweep and the load distribution");
            AddOutput(c, "--pattern-csv", st->options.pattern_csv_path,
                      "Write the contact pattern as CSV: one row per position, pin and slice (force, stress, z)");
          },
          [st] {
            return std::vector<std::string>{st->options.json_path, st->options.csv_path, st->options.svg_path,
                                            st->options.pattern_csv_path};
          },
          [st](const Streams& streams) { return RunSolve(st->deck.Read(), st->options, streams); }};
}

}  // namespace ltca::cli
