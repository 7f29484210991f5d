#include "stiffness_command.hpp"

#include "command.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "ltca/analysis/efficiency.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/geometry/units.hpp"
#include "solve_command.hpp"

namespace ltca::cli {
namespace {

using units::NmmToNm;
using units::RadToArcmin;
using units::RadToDeg;

/// N*mm/rad to N*m/arcmin.
double RigidityNmPerArcmin(double nmm_per_rad) { return NmmToNm(nmm_per_rad) / RadToArcmin(1.0); }
/// N*mm*rad (the loop's work per cycle) to J.
double NmmRadToJ(double nmm_rad) { return NmmToNm(nmm_rad); }

/// What the figures cover (docs/stiffness.md).
constexpr const char* kScope =
    "mesh only: the rigidity, lost motion and backlash of the cycloid-pin ring mesh alone; bearings, crankshafts and "
    "the output mechanism are not modelled";
/// The same for a deck with [output] (issue 25, docs/stage.md).
constexpr const char* kStageScope =
    "the stage: the mesh, the output mechanism, the bearings and the shafts in one balance (docs/stage.md), the input "
    "locked at the crank angle; housing, carrier and output flange rigid";

/// The scope line of a deck: the mesh alone or the stage, and the pins' seats when they are in it.
std::string Scope(const app::Deck& deck) {
  std::string scope = deck.reducer ? kStageScope : kScope;
  if (deck.contact.seat.seated()) {
    scope += fmt::format("; the pins' seats in their housing grooves ([pins] seat = \"{}\") in series with the mesh",
                         contact::ToString(deck.contact.seat.kind));
  }
  return scope;
}

std::string Definition(const app::StiffnessSettings& s) {
  if (s.rigidity == app::StiffnessSettings::Rigidity::kSecant) {
    return "secant between 50 % and 100 % of T on each flank; both flanks: T / (a_drive + a_coast)";
  }
  return fmt::format("tangent at {:g} N*m (central difference over +-1 % of it)", NmmToNm(s.tangent_torque));
}

nlohmann::json CurveJson(const std::vector<app::CurvePoint>& curve, const std::vector<double>* lo = nullptr,
                         const std::vector<double>* hi = nullptr) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t i = 0; i < curve.size(); ++i) {
    nlohmann::json p = {{"torque_nm", NmmToNm(curve[i].torque)},
                        {"twist_arcmin", FiniteOrNull(RadToArcmin(curve[i].twist))},
                        {"branch", app::ToString(curve[i].branch)}};
    if (curve[i].stick_end) p["stick_end"] = true;  // friction: where the stick after the reversal ends
    if (lo != nullptr && hi != nullptr) {
      p["twist_arcmin_min"] = FiniteOrNull(RadToArcmin((*lo)[i]));
      p["twist_arcmin_max"] = FiniteOrNull(RadToArcmin((*hi)[i]));
    }
    out.push_back(std::move(p));
  }
  return out;
}

nlohmann::json PositionJson(const app::StiffnessPosition& p) {
  nlohmann::json j = {{"crank_deg", RadToDeg(p.crank)},
                      {"torsional_rigidity_nm_per_arcmin", FiniteOrNull(RigidityNmPerArcmin(p.rigidity))},
                      {"torsional_rigidity_drive_nm_per_arcmin", FiniteOrNull(RigidityNmPerArcmin(p.rigidity_drive))},
                      {"torsional_rigidity_coast_nm_per_arcmin", FiniteOrNull(RigidityNmPerArcmin(p.rigidity_coast))},
                      {"lost_motion_arcmin", FiniteOrNull(RadToArcmin(p.lost_motion))},
                      {"backlash_arcmin", FiniteOrNull(RadToArcmin(p.backlash))},
                      {"branch_difference_arcmin", FiniteOrNull(RadToArcmin(p.branch_difference))},
                      {"hysteresis_j", FiniteOrNull(NmmRadToJ(p.hysteresis))},
                      {"status", ToString(p.succeeded() ? analysis::RunStatus::kSuccess : analysis::RunStatus::kFailed)},
                      {"solves", p.solves},
                      {"failed_solves", p.failed},
                      {"curve", CurveJson(p.curve)}};
  if (!p.succeeded()) j["message"] = p.first_failure;
  if (std::isfinite(p.stick_end_drive) || std::isfinite(p.stick_end_coast)) {  // friction (review issue 26)
    j["stick_end_drive_nm"] = FiniteOrNull(NmmToNm(p.stick_end_drive));
    j["stick_end_coast_nm"] = FiniteOrNull(NmmToNm(p.stick_end_coast));
  }
  if (std::isfinite(p.first_disc_share_drive) || std::isfinite(p.first_disc_share_coast)) {  // two discs (issue 13)
    j["first_disc_share_drive"] = FiniteOrNull(p.first_disc_share_drive);
    j["first_disc_share_coast"] = FiniteOrNull(p.first_disc_share_coast);
  }
  if (!p.compliance_share.empty()) {  // a reducer stage (issue 25): the compliance budget at +T
    nlohmann::json budget = nlohmann::json::object();
    for (std::size_t g = 0; g < p.compliance_share.size(); ++g) {
      budget[solvers::ToString(static_cast<solvers::StageGroup>(g))] = FiniteOrNull(p.compliance_share[g]);
    }
    j["compliance_share"] = budget;
  }
  return j;
}

/// The figure (as a JSON key with its unit) over the positions: the mean, and for a sweep its
/// smallest and largest as key_min / key_max.
void AddSpread(nlohmann::json& j, const std::string& key, const std::string& unit, const app::Spread& s, bool sweep,
               double (*convert)(double)) {
  j[key + "_" + unit] = FiniteOrNull(convert(s.mean));
  if (!sweep) return;
  j[key + "_" + unit + "_min"] = FiniteOrNull(convert(s.min));
  j[key + "_" + unit + "_max"] = FiniteOrNull(convert(s.max));
}

double Arcmin(double rad) { return RadToArcmin(rad); }

nlohmann::json SummaryJson(const app::StiffnessSummary& s, bool sweep, double friction_mu) {
  nlohmann::json j = nlohmann::json::object();
  AddSpread(j, "torsional_rigidity", "nm_per_arcmin", s.rigidity, sweep, RigidityNmPerArcmin);
  AddSpread(j, "torsional_rigidity_drive", "nm_per_arcmin", s.rigidity_drive, sweep, RigidityNmPerArcmin);
  AddSpread(j, "torsional_rigidity_coast", "nm_per_arcmin", s.rigidity_coast, sweep, RigidityNmPerArcmin);
  AddSpread(j, "lost_motion", "arcmin", s.lost_motion, sweep, Arcmin);
  AddSpread(j, "backlash", "arcmin", s.backlash, sweep, Arcmin);
  if (s.first_disc_share_drive.count + s.first_disc_share_coast.count > 0) {  // two discs (issue 13): T_1 / T at +-T
    const auto share = [](double v) { return v; };
    AddSpread(j, "first_disc_share", "drive", s.first_disc_share_drive, sweep, share);
    AddSpread(j, "first_disc_share", "coast", s.first_disc_share_coast, sweep, share);
  }
  if (!s.compliance_share.empty()) {  // a reducer stage (issue 25): each group's share of the strain energy at +T
    nlohmann::json budget = nlohmann::json::object();
    for (std::size_t g = 0; g < s.compliance_share.size(); ++g) {
      budget[solvers::ToString(static_cast<solvers::StageGroup>(g))] = FiniteOrNull(s.compliance_share[g].mean);
    }
    j["compliance_share"] = budget;
  }
  if (sweep) j["closed_period"] = s.closed_period;  // issue 26: the means weigh a repeated last state once
  j["hysteresis"] = friction_mu > 0.0;  // issue 14: friction separates the branches
  AddSpread(j, "hysteresis", "j", s.hysteresis, sweep, [](double v) { return NmmRadToJ(v); });
  j["branch_difference_arcmin"] = FiniteOrNull(RadToArcmin(s.branch_difference.max));
  if (friction_mu > 0.0) {
    j["friction_coefficient"] = friction_mu;
    AddSpread(j, "stick_end_drive", "nm", s.stick_end_drive, sweep, [](double v) { return NmmToNm(v); });
    AddSpread(j, "stick_end_coast", "nm", s.stick_end_coast, sweep, [](double v) { return NmmToNm(v); });
    j["note"] = "Coulomb friction in the torque balance ([friction]): moving up the normal forces carry T - mu sum F a_t, "
                "moving down T + mu sum F a_t. After each reversal (+T, -T) the twist holds (stick) until the torque "
                "reaches stick_end_drive_nm / stick_end_coast_nm, where the branch of the new sense reaches that twist; "
                "the loop closes at -T. hysteresis_j is its area, the work friction dissipates per cycle; "
                "branch_difference_arcmin is the loop's largest width at a torque level; the rigidity is read on the "
                "loading pass of each flank, the lost motion between the midpoints of the loop's width";
  } else {
    j["note"] = "no friction in the model: the increasing and decreasing branches coincide (no hysteresis loop: "
                "hysteresis_j is zero up to the solver's tolerance); branch_difference_arcmin is the largest difference "
                "found between them (the solver's tolerance)";
  }
  j["curve"] = sweep ? CurveJson(s.curve, &s.curve_min, &s.curve_max) : CurveJson(s.curve);
  app::documents::AddRunRecord(j, s);
  j["solves"] = s.solves;
  return j;
}

/// The loop as a catalogue draws it: twist (arcmin) across, torque (N*m) up, with the three
/// read-off values drawn on it and named in the legend.
void WriteLoopFigure(const app::Deck& deck, const solvers::SolverOptions& solver, const app::StiffnessSummary& s,
                     double rated, const std::string& when, bool sweep, std::size_t positions, Output& output) {
  namespace plots = app::plots;
  plots::Panel panel;
  panel.title = sweep ? "mean over the positions; dashed: their smallest and largest twist" : "";
  panel.x_label = "twist (arcmin, output rotation in the sense of +T)";
  panel.y_label = "torque (N*m)";
  // Outside the axes (issue 27: inside, the legend covered the loop's upper part); short labels,
  // their definitions in the caption.
  panel.legend = plots::LegendPlace::kOutsideRight;
  const auto branch = [&](const std::string& label, int colour, bool dashed, auto twist_of) {
    plots::Series series{label, {}, {}, plots::Style::kLine};
    series.colour = colour;
    series.dashed = dashed;
    for (std::size_t i = 0; i < s.curve.size(); ++i) {
      series.x.push_back(RadToArcmin(twist_of(i)));  // NaN (an unsolved point): a gap
      series.y.push_back(NmmToNm(s.curve[i].torque));
    }
    return series;
  };
  bool any = false;
  for (const auto& c : s.curve) any = any || std::isfinite(c.twist);
  if (any) {
    panel.series.push_back(branch("torque-twist loop", 0, false, [&](std::size_t i) { return s.curve[i].twist; }));
    if (sweep) {
      panel.series.push_back(branch("range over the positions", 6, true, [&](std::size_t i) { return s.curve_min[i]; }));
      panel.series.push_back(branch("", 6, true, [&](std::size_t i) { return s.curve_max[i]; }));
    }
    // Backlash: the loop's width at zero torque (the two zero-torque points of the increasing branch).
    std::vector<double> zero;
    for (const auto& p : s.curve) {
      if (p.torque == 0.0 && p.branch == app::Branch::kIncreasing && std::isfinite(p.twist)) zero.push_back(RadToArcmin(p.twist));
    }
    if (zero.size() == 2) {
      plots::Series b{fmt::format("backlash {:.4g} arcmin", RadToArcmin(s.backlash.mean)), zero, {0.0, 0.0},
                      plots::Style::kLineMarkers};
      b.colour = 2;
      panel.series.push_back(std::move(b));
    }
    const auto& r = s.readoffs;
    const auto segment = [&](const std::string& label, const app::CurvePoint& a, const app::CurvePoint& c, int colour) {
      plots::Series seg{label, {RadToArcmin(a.twist), RadToArcmin(c.twist)}, {NmmToNm(a.torque), NmmToNm(c.torque)},
                        plots::Style::kLineMarkers};
      seg.colour = colour;
      seg.dashed = true;
      if (std::isfinite(a.twist) && std::isfinite(c.twist)) panel.series.push_back(std::move(seg));
    };
    if (r.size() == 6) {  // secant: +T, +T/2, -T/2, -T, then lost motion
      segment(fmt::format("rigidity {:.4g} N*m/arcmin", RigidityNmPerArcmin(s.rigidity.mean)),
              r[1], r[0], 1);
      segment("", r[3], r[2], 1);
    } else if (r.size() == 4) {  // tangent: two torques, then lost motion
      segment(fmt::format("rigidity {:.4g} N*m/arcmin", RigidityNmPerArcmin(s.rigidity.mean)), r[1], r[0], 1);
    }
    if (r.size() >= 2) {
      segment(fmt::format("lost motion {:.4g} arcmin", RadToArcmin(s.lost_motion.mean)), r[r.size() - 1], r[r.size() - 2], 3);
    }
    // A panel shows a legend from two labelled series: with fewer, the one label goes in the title.
    if (panel.LabelledSeries() < 2 && !panel.series.empty()) panel.title = panel.series.front().label;
  }
  panel.marks.push_back({plots::Mark::Axis::kHorizontal, 0.0, "", false});
  panel.marks.push_back({plots::Mark::Axis::kVertical, 0.0, "", false});
  const double t = NmmToNm(rated);
  panel.y_min = -1.15 * t, panel.y_max = 1.15 * t;
  plots::Figure figure;
  const std::string hysteresis =  // with friction the loop's area (review issue 26)
      app::LoopFrictionCoefficient(deck.friction) > 0.0 && std::isfinite(s.hysteresis.mean)
          ? fmt::format(", hysteresis {:.4g} J per cycle (mu {:g})", NmmRadToJ(s.hysteresis.mean), app::LoopFrictionCoefficient(deck.friction))
          : std::string();
  figure.title = fmt::format("{}: torque-twist loop -T..+T..-T, T = {:g} N*m, {}{}{}", deck.info.title, t, when, hysteresis,
                             any ? "" : ": no solve succeeded");
  const std::string rigidity = deck.stiffness.rigidity == app::StiffnessSettings::Rigidity::kSecant
                                  ? "the secant from 50 % to 100 % of T on each flank"
                                  : "the tangent at the deck's tangent torque";
  figure.caption = FigureCaption(
      deck, fmt::format("backlash: the loop's width at zero torque; rigidity: {}; lost motion: the width at +-{:g} % of T\n"
                        "model {}, solver {} ({} kinematics); {} crank position{}",
                        rigidity, 100.0 * deck.stiffness.lost_motion_fraction, deck.Model().name, solver.name,
                        contact::ToString(deck.kinematics), positions, positions == 1 ? "" : "s"));
  figure.width = 1300;
  figure.height = 640;
  figure.panels.push_back(std::move(panel));
  WriteFigure(figure, output);
}

}  // namespace

app::StiffnessSettings StiffnessSettingsFor(const app::Deck& deck, const StiffnessOptions& options) {
  app::StiffnessSettings s = deck.stiffness;
  if (options.crank_deg) s.crank = units::DegToRad(*options.crank_deg);
  if (options.steps) s.steps = *options.steps;
  if (!options.rigidity.empty()) {
    if (options.rigidity == "secant") s.rigidity = app::StiffnessSettings::Rigidity::kSecant;
    else if (options.rigidity == "tangent") s.rigidity = app::StiffnessSettings::Rigidity::kTangent;
    else throw std::invalid_argument(fmt::format("--rigidity {}: expected secant or tangent", options.rigidity));
  }
  if (options.tangent_torque_nm) s.tangent_torque = units::NmToNmm(*options.tangent_torque_nm);
  if (options.lost_motion_fraction) s.lost_motion_fraction = *options.lost_motion_fraction;
  s.Validate();
  return s;
}

int RunStiffness(const app::Deck& deck_given, const StiffnessOptions& options, const Streams& streams) {
  const app::Deck deck = DeckFor(deck_given, options.kinematics);  // --kinematics, else the deck's
  const solvers::SolverOptions solver = SolverFor(deck, options.solver);
  const app::StiffnessSettings settings = StiffnessSettingsFor(deck, options);
  RequireDistinctOutputs({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path}});
  // Outputs first: an unwritable path is an error before anything is computed.
  Output json("--json", options.json_path, streams.out);
  Output csv("--csv", options.csv_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  deck.RequireMaterial();
  const double torque = deck.RequireLoad().torque;
  // The stage checks interference at the loop's cranks; the runner checks the options and the torque.
  app::StiffnessRunner runner(deck.MakeStage(settings.crank ? std::vector<double>{*settings.crank} : deck.sweep.CrankAngles()),
                              solver, settings, torque, deck.friction);
  const bool sweep = !settings.crank.has_value();
  const std::vector<double>& cranks = runner.cranks();
  const double rated = runner.rated_torque();

  std::ostream& text = streams.text;
  fmt::print(text, "case      {}\n", deck.info.title);
  text << ModelLine(deck);
  text << SolverLine(deck, solver);
  fmt::print(text, "loop      -T -> +T -> -T, T = {:g} N*m (rated, |[load] torque_nm|), {} torque levels per branch, {}\n",
             NmmToNm(rated), settings.steps,
             sweep ? fmt::format("{} positions from {:g} to {:g} deg crank", cranks.size(), RadToDeg(deck.sweep.crank_start),
                                 RadToDeg(deck.sweep.crank_end))
                   : fmt::format("crank {:g} deg", RadToDeg(*settings.crank)));
  fmt::print(text, "rigidity  {}\n", Definition(settings));
  fmt::print(text, "scope     {}\n", Scope(deck));
  fmt::print(text, "{:>10} {:>18} {:>18} {:>16} {:>8}\n", "crank_deg", "rigidity_nm/amin", "lost_motion_amin", "backlash_amin", "status");

  if (json.enabled()) {
    nlohmann::json stiffness = {{"scope", Scope(deck)},
                                {"rated_torque_nm", NmmToNm(rated)},
                                {"steps_per_branch", settings.steps},
                                {"rigidity_definition", Definition(settings)},
                                {"lost_motion_fraction", settings.lost_motion_fraction}};
    if (settings.rigidity == app::StiffnessSettings::Rigidity::kTangent) {
      stiffness["tangent_torque_nm"] = NmmToNm(settings.tangent_torque);
    }
    if (sweep) {
      stiffness["sweep"] = {{"crank_start_deg", RadToDeg(deck.sweep.crank_start)},
                            {"crank_end_deg", RadToDeg(deck.sweep.crank_end)},
                            {"positions", deck.sweep.positions}};
    } else {
      stiffness["crank_deg"] = RadToDeg(*settings.crank);
    }
    const nlohmann::json header = {
        {"case", CaseJson(deck)}, {"model", ModelJson(deck.Model())}, {"solver", SolverJson(deck, solver)}, {"stiffness", stiffness}};
    json.stream() << OpenObject(header) << ",\n  \"positions\": [";
  }
  if (csv.enabled()) csv.stream() << "crank_deg,branch,torque_nm,twist_arcmin,status\n";
  Progress progress(streams.err, streams.progress, "stiffness loop at position", static_cast<std::int64_t>(cranks.size()),
                    streams.progress_delay_seconds);
  const std::size_t every = std::max<std::size_t>(1, cranks.size() / 10);
  for (std::size_t i = 0; i < cranks.size(); ++i) {
    const app::StiffnessPosition p = runner.Solve(cranks[i]);
    if (i % every == 0) {
      progress.Clear();  // a row of the table never lands on the progress line (review issue 26, item 16)
      fmt::print(text, "{:>10.4f} {:>18} {:>18} {:>16} {:>8}\n", RadToDeg(p.crank), FormatOrNa(RigidityNmPerArcmin(p.rigidity), 4),
                 FormatOrNa(RadToArcmin(p.lost_motion), 5), FormatOrNa(RadToArcmin(p.backlash), 5), ToString(p.succeeded() ? analysis::RunStatus::kSuccess : analysis::RunStatus::kFailed));
    }
    if (json.enabled()) json.stream() << (i == 0 ? "\n    " : ",\n    ") << Dump(PositionJson(p), -1);
    if (csv.enabled()) {
      for (const auto& c : p.curve) {
        fmt::print(csv.stream(), "{:.9g},{},{:.9g},{},{}\n", RadToDeg(p.crank), app::ToString(c.branch), NmmToNm(c.torque),
                   std::isfinite(c.twist) ? fmt::format("{:.12g}", RadToArcmin(c.twist)) : std::string(),
                   solvers::ToString(c.status));
      }
    }
    progress.Update(static_cast<std::int64_t>(i + 1));
  }
  progress.Finish();
  const app::StiffnessSummary s = runner.Summary();
  if (json.enabled()) {
    json.stream() << "\n  ],\n  \"summary\": " << Nested(Dump(SummaryJson(s, sweep, app::LoopFrictionCoefficient(deck.friction)))) << "\n}\n";
    json.Commit();
  }
  if (csv.enabled()) csv.Commit();
  if (svg.enabled()) {
    const std::string when = sweep ? fmt::format("crank {:g} to {:g} deg", RadToDeg(deck.sweep.crank_start), RadToDeg(deck.sweep.crank_end))
                                   : fmt::format("crank {:g} deg", RadToDeg(*settings.crank));
    WriteLoopFigure(deck, solver, s, rated, when, sweep, cranks.size(), svg);
  }

  const auto range = [sweep](const app::Spread& v, double (*convert)(double), int decimals, const char* unit) {
    std::string r = fmt::format("{} {}", FormatOrNa(convert(v.mean), decimals), unit);
    if (sweep && v.count > 0) r += fmt::format(" (mean; {} .. {} over the positions)", FormatOrNa(convert(v.min), decimals), FormatOrNa(convert(v.max), decimals));
    return r;
  };
  if (s.failed > 0) fmt::print(text, "failed positions       {} of {}; first: {}\n", s.failed, s.positions(), s.first_failure);
  fmt::print(text, "torsional rigidity     {}\n", range(s.rigidity, RigidityNmPerArcmin, 4, "N*m/arcmin"));
  if (settings.rigidity == app::StiffnessSettings::Rigidity::kSecant) {
    fmt::print(text, "  drive / coast flank  {} / {} N*m/arcmin\n", FormatOrNa(RigidityNmPerArcmin(s.rigidity_drive.mean), 4),
               FormatOrNa(RigidityNmPerArcmin(s.rigidity_coast.mean), 4));
  }
  fmt::print(text, "lost motion            {}, at +-{:g} % of T\n", range(s.lost_motion, Arcmin, 5, "arcmin"),
             100.0 * settings.lost_motion_fraction);
  fmt::print(text, "backlash               {}, at zero torque\n", range(s.backlash, Arcmin, 5, "arcmin"));
  if (s.first_disc_share_drive.count + s.first_disc_share_coast.count > 0) {  // two discs (issue 13)
    const auto share = [](double v) { return v; };
    fmt::print(text, "first disc's share     {} at +T (disc 2: the rest)\n", range(s.first_disc_share_drive, share, 4, "of T"));
    fmt::print(text, "                       {} at -T\n", range(s.first_disc_share_coast, share, 4, "of T"));
  }
  if (!s.compliance_share.empty()) {  // issue 25
    std::string parts;
    for (std::size_t g = 0; g < s.compliance_share.size(); ++g) {
      parts += fmt::format("{}{} {} %", parts.empty() ? "" : ", ", solvers::ToString(static_cast<solvers::StageGroup>(g)),
                           FormatOrNa(100.0 * s.compliance_share[g].mean, 1));
    }
    fmt::print(text, "compliance budget      {} of the strain energy at +T (mean over the positions)\n", parts);
  }
  const auto joules = [](double v) { return NmmRadToJ(v); };
  if (app::LoopFrictionCoefficient(deck.friction) > 0.0) {  // issue 14, review issue 26
    fmt::print(text, "hysteresis             {} per cycle (the loop's area), friction mu = {:g}\n",
               range(s.hysteresis, joules, 6, "J"), app::LoopFrictionCoefficient(deck.friction));
    fmt::print(text, "  stick after reversal the twist holds from +T down to {} and from -T up to {}; the branches "
                     "differ by up to {} arcmin\n",
               range(s.stick_end_drive, NmmToNm, 5, "N*m"), range(s.stick_end_coast, NmmToNm, 5, "N*m"),
               FormatOrNa(RadToArcmin(s.branch_difference.max), 6));
  } else {
    const double work = NmmRadToJ(s.hysteresis.mean);
    fmt::print(text, "hysteresis             {} J per cycle: none, no friction (zero up to the solver's tolerance); the "
                     "branches coincide (largest difference {} arcmin)\n",
               std::isfinite(work) ? fmt::format("{:.3g}", work) : std::string("n/a"),
               FormatOrNa(RadToArcmin(s.branch_difference.max), 12));
  }
  fmt::print(text, "wall time              {:.4f} s for {} solves\n", s.wall_seconds, s.solves);
  return s.all_succeeded() ? kExitSuccess : kExitNotSucceeded;
}

Command StiffnessCommand() {
  auto st = std::make_shared<DeckState<StiffnessOptions>>();
  return {"stiffness",
          "Torsional stiffness, lost motion and backlash (docs/stiffness.md): with the crank locked, the output torque "
          "runs from -T to +T and back (T = |[load] torque_nm|, the rated torque) and the twist of the output (the "
          "cycloid about its centre, in the sense of +T from the theoretical position, -TE) is read at each level, at "
          "one crank (--crank-deg) or at every position of the deck's sweep (mean, min, max). Summary keys "
          "torsional_rigidity_nm_per_arcmin, lost_motion_arcmin, backlash_arcmin (for a sweep also _min, _max), curve "
          "[{torque_nm, twist_arcmin, branch}], hysteresis. Options replace the deck's [stiffness] keys.",
          [st](CLI::App& c) {
            StiffnessOptions& o = st->options;
            AddLoadInputs(c, st->deck, o.solver, o.kinematics);
            c.add_option("--crank-deg", o.crank_deg, "One crank angle in degrees ([stiffness] crank_deg; default: the deck's sweep)")
                ->check(CrankAngle());
            c.add_option("--steps", o.steps, "Torque levels per branch from -T to +T, odd ([stiffness] steps_per_branch, default 41)");
            c.add_option("--rigidity", o.rigidity,
                         "secant (between 50 % and 100 % of T on each flank, default) or tangent ([stiffness] rigidity)")
                ->check(CLI::IsMember({"secant", "tangent"}));
            c.add_option("--tangent-torque-nm", o.tangent_torque_nm,
                         "Torque of the tangent rigidity in N*m, signed ([stiffness] tangent_torque_nm)");
            c.add_option("--lost-motion-fraction", o.lost_motion_fraction,
                         "Lost motion at +-this fraction of T ([stiffness] lost_motion_fraction, default 0.03)");
            AddOutput(c, "--json", o.json_path, "Write the positions and the summary as JSON ('-': stdout)");
            AddOutput(c, "--csv", o.csv_path,
                      "Write the curve as CSV: crank_deg, branch, torque_nm, twist_arcmin, status");
            AddOutput(c, "--svg", o.svg_path, "Draw the loop with the read-off values");
          },
          [st] { return std::vector<std::string>{st->options.json_path, st->options.csv_path, st->options.svg_path}; },
          [st](const Streams& streams) { return RunStiffness(st->deck.Read(), st->options, streams); }};
}

}  // namespace ltca::cli
