#include "stiffness_command.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "ltca/app/stiffness.hpp"
#include "ltca/geometry/units.hpp"
#include "solve_command.hpp"

namespace ltca::cli {
namespace {

using units::NmmToNm;
using units::RadToArcmin;
using units::RadToDeg;

/// N*mm/rad to N*m/arcmin.
double RigidityNmPerArcmin(double nmm_per_rad) { return NmmToNm(nmm_per_rad) / RadToArcmin(1.0); }

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
                      {"status", p.succeeded() ? "success" : "failed"},
                      {"solves", p.solves},
                      {"failed_solves", p.failed},
                      {"curve", CurveJson(p.curve)}};
  if (!p.succeeded()) j["message"] = p.first_failure;
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

nlohmann::json SummaryJson(const app::StiffnessSummary& s, bool sweep) {
  nlohmann::json j = nlohmann::json::object();
  AddSpread(j, "torsional_rigidity", "nm_per_arcmin", s.rigidity, sweep, RigidityNmPerArcmin);
  AddSpread(j, "torsional_rigidity_drive", "nm_per_arcmin", s.rigidity_drive, sweep, RigidityNmPerArcmin);
  AddSpread(j, "torsional_rigidity_coast", "nm_per_arcmin", s.rigidity_coast, sweep, RigidityNmPerArcmin);
  AddSpread(j, "lost_motion", "arcmin", s.lost_motion, sweep, Arcmin);
  AddSpread(j, "backlash", "arcmin", s.backlash, sweep, Arcmin);
  j["hysteresis"] = false;
  j["branch_difference_arcmin"] = FiniteOrNull(RadToArcmin(s.branch_difference.max));
  j["note"] = "no friction in the model: the increasing and decreasing branches coincide (no hysteresis loop); "
              "branch_difference_arcmin is the largest difference found between them (the solver's tolerance)";
  j["curve"] = sweep ? CurveJson(s.curve, &s.curve_min, &s.curve_max) : CurveJson(s.curve);
  j["positions"] = s.positions();
  j["succeeded_positions"] = s.succeeded;
  j["failed_positions"] = s.failed;
  j["solves"] = s.solves;
  j["wall_seconds"] = s.wall_seconds;
  j["status"] = s.all_succeeded() ? "success" : "failed";
  if (!s.first_failure.empty()) j["first_failure"] = s.first_failure;
  return j;
}

/// The loop as a catalogue draws it: twist (arcmin) across, torque (N*m) up, with the three
/// read-off values marked.
void WriteSvg(const app::StiffnessSummary& s, double rated, bool sweep, const std::string& title, std::ostream& os) {
  const double w = 640, h = 460, pad = 70;
  fmt::print(os, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"11\">\n", w, h);
  fmt::print(os, "<text x=\"{}\" y=\"20\">torque-twist loop{}: {}</text>\n", pad, sweep ? " (mean over the positions, band: their range)" : "", title);
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t i = 0; i < s.curve.size(); ++i) {
    for (const double v : {s.curve[i].twist, s.curve_min[i], s.curve_max[i]}) {
      if (std::isfinite(v)) lo = std::min(lo, RadToArcmin(v)), hi = std::max(hi, RadToArcmin(v));
    }
  }
  if (!std::isfinite(lo)) {
    fmt::print(os, "<text x=\"{}\" y=\"{}\">no solve succeeded: nothing to draw</text>\n</svg>\n", pad, h / 2);
    return;
  }
  const double span = std::max(hi - lo, 1e-9), t_nm = NmmToNm(rated);
  lo -= 0.05 * span, hi += 0.05 * span;
  const auto x = [&](double arcmin) { return pad + (arcmin - lo) / (hi - lo) * (w - 2 * pad); };
  const auto y = [&](double nm) { return h - pad - (nm + 1.1 * t_nm) / (2.2 * t_nm) * (h - 2 * pad); };
  // Axes through the origin (twist 0 clamped into the frame), with the extreme values labelled.
  fmt::print(os, "<rect x=\"{0}\" y=\"{0}\" width=\"{1}\" height=\"{2}\" fill=\"none\" stroke=\"#999\"/>\n", pad, w - 2 * pad, h - 2 * pad);
  const double x0 = std::clamp(x(0.0), pad, w - pad);
  fmt::print(os, "<line x1=\"{}\" x2=\"{}\" y1=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"#bbb\"/>\n", pad, w - pad, y(0.0), y(0.0));
  fmt::print(os, "<line x1=\"{:.2f}\" x2=\"{:.2f}\" y1=\"{}\" y2=\"{}\" stroke=\"#bbb\"/>\n", x0, x0, pad, h - pad);
  fmt::print(os, "<text x=\"{}\" y=\"{}\">twist (arcmin, output rotation in the sense of +T from the theoretical position)</text>\n", pad, h - pad + 32);
  fmt::print(os, "<text x=\"{:.2f}\" y=\"{}\" text-anchor=\"middle\">{:.4g}</text><text x=\"{:.2f}\" y=\"{}\" text-anchor=\"middle\">{:.4g}</text>\n",
             x(lo), h - pad + 15, lo, x(hi), h - pad + 15, hi);
  fmt::print(os, "<text x=\"14\" y=\"{:.2f}\" transform=\"rotate(-90 14 {:.2f})\" text-anchor=\"middle\">torque (N*m)</text>\n", h / 2, h / 2);
  for (const double nm : {-t_nm, 0.0, t_nm}) {
    fmt::print(os, "<text x=\"{}\" y=\"{:.2f}\" text-anchor=\"end\">{:.4g}</text>\n", pad - 4, y(nm) + 4, nm);
  }
  const auto polyline = [&](const char* colour, const char* extra, auto twist_of) {
    os << "<polyline fill=\"none\" stroke=\"" << colour << "\" " << extra << " points=\"";
    for (std::size_t i = 0; i < s.curve.size(); ++i) {
      const double v = twist_of(i);
      if (std::isfinite(v)) fmt::print(os, "{:.2f},{:.2f} ", x(RadToArcmin(v)), y(NmmToNm(s.curve[i].torque)));
    }
    os << "\"/>\n";
  };
  if (sweep) {
    polyline("#e6b0aa", "stroke-width=\"1\"", [&](std::size_t i) { return s.curve_min[i]; });
    polyline("#e6b0aa", "stroke-width=\"1\"", [&](std::size_t i) { return s.curve_max[i]; });
  }
  polyline("#c0392b", "stroke-width=\"2\"", [&](std::size_t i) { return s.curve[i].twist; });
  // The read-off values: drawn on the loop, named in a legend in the empty quadrant (twist < 0,
  // torque > 0).
  std::vector<std::pair<const char*, std::string>> legend;
  // Backlash: the width at zero torque (the two zero-torque points of the increasing branch).
  std::vector<double> zero;
  for (const auto& p : s.curve) {
    if (p.torque == 0.0 && p.branch == app::Branch::kIncreasing && std::isfinite(p.twist)) zero.push_back(RadToArcmin(p.twist));
  }
  if (zero.size() == 2) {
    fmt::print(os, "<line x1=\"{:.2f}\" x2=\"{:.2f}\" y1=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"#2c3e50\" stroke-width=\"3\"/>\n",
               x(zero[0]), x(zero[1]), y(0.0), y(0.0));
    legend.emplace_back("#2c3e50", fmt::format("backlash {:.4g} arcmin (loop width at zero torque)", RadToArcmin(s.backlash.mean)));
  }
  // Read-offs: secant (or tangent) points joined; lost motion between the +-f T points.
  const auto& r = s.readoffs;
  const auto mark = [&](const app::CurvePoint& a, const app::CurvePoint& b, const char* colour) {
    if (!std::isfinite(a.twist) || !std::isfinite(b.twist)) return;
    fmt::print(os, "<line x1=\"{:.2f}\" x2=\"{:.2f}\" y1=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"{}\" stroke-width=\"2\" stroke-dasharray=\"5,3\"/>\n",
               x(RadToArcmin(a.twist)), x(RadToArcmin(b.twist)), y(NmmToNm(a.torque)), y(NmmToNm(b.torque)), colour);
    for (const auto* p : {&a, &b}) {
      fmt::print(os, "<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"3\" fill=\"{}\"/>\n", x(RadToArcmin(p->twist)), y(NmmToNm(p->torque)), colour);
    }
  };
  if (r.size() == 6) {  // secant: +T, +T/2, -T/2, -T, then lost motion
    mark(r[1], r[0], "#2471a3");
    mark(r[3], r[2], "#2471a3");
    legend.emplace_back("#2471a3", fmt::format("torsional rigidity {:.4g} N*m/arcmin (secant 50 % .. 100 % of T)",
                                               RigidityNmPerArcmin(s.rigidity.mean)));
  } else if (r.size() == 4) {  // tangent: two torques, then lost motion
    mark(r[1], r[0], "#2471a3");
    legend.emplace_back("#2471a3", fmt::format("torsional rigidity {:.4g} N*m/arcmin (tangent)", RigidityNmPerArcmin(s.rigidity.mean)));
  }
  if (r.size() >= 2) {
    mark(r[r.size() - 1], r[r.size() - 2], "#1e8449");
    legend.emplace_back("#1e8449", fmt::format("lost motion {:.4g} arcmin (at +-{:.3g} % of T)", RadToArcmin(s.lost_motion.mean),
                                               100.0 * NmmToNm(r.back().torque) / -t_nm));
  }
  for (std::size_t i = 0; i < legend.size(); ++i) {
    fmt::print(os, "<text x=\"{}\" y=\"{}\" fill=\"{}\">{}</text>\n", pad + 8, pad + 16 + 15 * static_cast<double>(i),
               legend[i].first, legend[i].second);
  }
  os << "</svg>\n";
}

std::string Figure(double v, int decimals) { return FormatOrNa(v, decimals); }

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

int RunStiffness(const app::Deck& deck, const StiffnessOptions& options, const Streams& streams) {
  const solvers::SolverOptions solver = SolverFor(deck, options.solver, options.kinematics);
  const app::StiffnessSettings settings = StiffnessSettingsFor(deck, options);
  RequireOneStdout({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path}});
  // Outputs first: an unwritable path is an error before anything is computed.
  Output json("--json", options.json_path, streams.out);
  Output csv("--csv", options.csv_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  app::StiffnessRunner runner(deck, solver, settings);  // checks the deck, the options and interference
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
  fmt::print(text, "{:>10} {:>18} {:>18} {:>16} {:>8}\n", "crank_deg", "rigidity_nm/amin", "lost_motion_amin", "backlash_amin", "status");

  if (json.enabled()) {
    nlohmann::json stiffness = {{"rated_torque_nm", NmmToNm(rated)},
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
  Progress progress(streams.err, streams.progress, "stiffness loop at position", static_cast<std::int64_t>(cranks.size()));
  const std::size_t every = std::max<std::size_t>(1, cranks.size() / 10);
  for (std::size_t i = 0; i < cranks.size(); ++i) {
    const app::StiffnessPosition p = runner.Solve(cranks[i]);
    if (i % every == 0) {
      fmt::print(text, "{:>10.4f} {:>18} {:>18} {:>16} {:>8}\n", RadToDeg(p.crank), Figure(RigidityNmPerArcmin(p.rigidity), 4),
                 Figure(RadToArcmin(p.lost_motion), 5), Figure(RadToArcmin(p.backlash), 5), p.succeeded() ? "success" : "failed");
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
    json.stream() << "\n  ],\n  \"summary\": " << Nested(Dump(SummaryJson(s, sweep))) << "\n}\n";
    json.Commit();
  }
  if (csv.enabled()) csv.Commit();
  if (svg.enabled()) {
    WriteSvg(s, rated, sweep, deck.info.title, svg.stream());
    svg.Commit();
  }

  const auto range = [sweep](const app::Spread& v, double (*convert)(double), int decimals, const char* unit) {
    std::string r = fmt::format("{} {}", Figure(convert(v.mean), decimals), unit);
    if (sweep && v.count > 0) r += fmt::format(" (mean; {} .. {} over the positions)", Figure(convert(v.min), decimals), Figure(convert(v.max), decimals));
    return r;
  };
  if (s.failed > 0) fmt::print(text, "failed positions       {} of {}; first: {}\n", s.failed, s.positions(), s.first_failure);
  fmt::print(text, "torsional rigidity     {}\n", range(s.rigidity, RigidityNmPerArcmin, 4, "N*m/arcmin"));
  if (settings.rigidity == app::StiffnessSettings::Rigidity::kSecant) {
    fmt::print(text, "  drive / coast flank  {} / {} N*m/arcmin\n", Figure(RigidityNmPerArcmin(s.rigidity_drive.mean), 4),
               Figure(RigidityNmPerArcmin(s.rigidity_coast.mean), 4));
  }
  fmt::print(text, "lost motion            {}, at +-{:g} % of T\n", range(s.lost_motion, Arcmin, 5, "arcmin"),
             100.0 * settings.lost_motion_fraction);
  fmt::print(text, "backlash               {}, at zero torque\n", range(s.backlash, Arcmin, 5, "arcmin"));
  fmt::print(text, "hysteresis             none: no friction, the branches coincide (largest difference {} arcmin)\n",
             Figure(RadToArcmin(s.branch_difference.max), 12));
  fmt::print(text, "wall time              {:.4f} s for {} solves\n", s.wall_seconds, s.solves);
  return s.all_succeeded() ? kExitSuccess : kExitNotSucceeded;
}

}  // namespace ltca::cli
