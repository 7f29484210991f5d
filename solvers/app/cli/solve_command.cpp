#include "solve_command.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "contact_commands.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::cli {
namespace {

using units::RadToArcsec;
using units::RadToDeg;

double MaxOf(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

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
                      {"warned_positions", s.warned}};
  if (s.warned > 0) j["first_warning"] = s.first_warning;
  if (s.failed > 0) {
    j["note"] = s.succeeded > 0
                    ? fmt::format("{} of {} positions failed: the figures are over the {} successful positions only",
                                  s.failed, s.positions(), s.succeeded)
                    : fmt::format("all {} positions failed: no figure", s.positions());
  }
  return j;
}

/// What the SVG needs, kept compactly while the sweep streams by.
struct SvgData {
  std::vector<std::pair<double, double>> te;  ///< (crank deg, te arcsec) of successful positions
  std::optional<app::PositionResult> peak;
  double f_peak = -1.0;
  void Add(const app::PositionResult& p) {
    if (!p.succeeded()) return;
    te.emplace_back(RadToDeg(p.crank), RadToArcsec(p.result.te));
    const double f = MaxOf(p.pin_force);
    if (f > f_peak) f_peak = f, peak = p;
  }
};

void WriteSvg(const std::string& solver, const SvgData& data, std::ostream& os) {
  // Left: TE over the crank sweep. Right: pin forces at the position of the largest force.
  const double w = 420, h = 300, pad = 50;
  fmt::print(os, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"11\">\n",
             2 * w, h);
  if (!data.peak) {
    fmt::print(os, "<text x=\"{}\" y=\"{}\">no position succeeded: nothing to draw ({})</text>\n</svg>\n", pad, h / 2, solver);
    return;
  }
  double te_lo = INFINITY, te_hi = -INFINITY, c_lo = INFINITY, c_hi = -INFINITY;
  for (const auto& [c, t] : data.te) {
    te_lo = std::min(te_lo, t), te_hi = std::max(te_hi, t);
    c_lo = std::min(c_lo, c), c_hi = std::max(c_hi, c);
  }
  if (te_hi - te_lo < 1e-9) te_hi = te_lo + 1e-3;
  if (c_hi - c_lo < 1e-9) c_hi = c_lo + 1.0;
  const auto x1 = [&](double c) { return pad + (c - c_lo) / (c_hi - c_lo) * (w - 2 * pad); };
  const auto y1 = [&](double t) { return h - pad - (t - te_lo) / (te_hi - te_lo) * (h - 2 * pad); };
  fmt::print(os, "<text x=\"{}\" y=\"20\">loaded TE (arcsec) over crank angle (deg), {}</text>\n", pad, solver);
  fmt::print(os, "<rect x=\"{0}\" y=\"{0}\" width=\"{1}\" height=\"{2}\" fill=\"none\" stroke=\"#999\"/>\n", pad, w - 2 * pad, h - 2 * pad);
  os << "<polyline fill=\"none\" stroke=\"#c0392b\" points=\"";
  for (const auto& [c, t] : data.te) fmt::print(os, "{:.2f},{:.2f} ", x1(c), y1(t));
  os << "\"/>\n";
  fmt::print(os, "<text x=\"5\" y=\"{}\">{:.4f}</text><text x=\"5\" y=\"{}\">{:.4f}</text>\n", pad + 4, te_hi, h - pad, te_lo);
  fmt::print(os, "<text x=\"{}\" y=\"{}\">{:.3g}</text><text x=\"{}\" y=\"{}\">{:.3g}</text>\n", pad, h - pad + 15, c_lo, w - pad - 20, h - pad + 15, c_hi);
  // Load distribution: force against the pin's angle from the line of centres.
  const auto& p = *data.peak;
  const double f_peak = data.f_peak;
  const auto x2 = [&](double a) { return w + pad + (a + 180.0) / 360.0 * (w - 2 * pad); };
  const auto y2 = [&](double f) { return h - pad - f / std::max(f_peak, 1e-300) * (h - 2 * pad); };
  fmt::print(os, "<text x=\"{}\" y=\"20\">pin force (N) over pin angle (deg) at crank {:.3g} deg</text>\n", w + pad, RadToDeg(p.crank));
  fmt::print(os, "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#999\"/>\n", w + pad, pad, w - 2 * pad, h - 2 * pad);
  for (std::size_t i = 0; i < p.pin_force.size() && i < p.angle.size(); ++i) {
    const double a = RadToDeg(p.angle[i]);
    fmt::print(os, "<line x1=\"{0:.2f}\" x2=\"{0:.2f}\" y1=\"{1:.2f}\" y2=\"{2:.2f}\" stroke=\"#2c3e50\" stroke-width=\"3\"/>\n",
               x2(a), y2(0.0), y2(p.pin_force[i]));
  }
  fmt::print(os, "<text x=\"{}\" y=\"{}\">{:.4g}</text>\n", w + 5, pad + 4, f_peak);
  fmt::print(os, "<text x=\"{}\" y=\"{}\">-180</text><text x=\"{}\" y=\"{}\">180</text>\n", w + pad, h - pad + 15, 2 * w - pad - 20, h - pad + 15);
  os << "</svg>\n";
}

/// A CSV field: the figure, or empty when no valid solve produced it.
std::string CsvFigure(bool ok, double v) { return ok && std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string(); }

}  // namespace

const char* KinematicsName(contact::ContactKinematics k) {
  return k == contact::ContactKinematics::kExact ? "exact" : "linearised";
}

solvers::SolverOptions SolverFor(const app::Deck& deck, const std::string& name, const std::string& kinematics) {
  solvers::SolverOptions solver = deck.solver;
  if (!name.empty()) solver.name = name;
  if (!kinematics.empty()) solver.kinematics = ParseKinematics(kinematics);
  return solver;
}

nlohmann::json SolverJson(const app::Deck& deck, const solvers::SolverOptions& solver) {
  return {{"name", solver.name},
          {"kinematics", KinematicsName(solver.kinematics)},
          {"torque_tolerance", solver.torque_tolerance},
          {"law", contact::ToString(deck.contact.law)},
          {"rho_convention", contact::ToString(deck.contact.rho_convention)}};
}

std::string SolverLine(const app::Deck& deck, const solvers::SolverOptions& solver) {
  return fmt::format("solver    {} ({} kinematics, torque tolerance {:g}), law {} / {}\n", solver.name,
                     KinematicsName(solver.kinematics), solver.torque_tolerance, contact::ToString(deck.contact.law),
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

int RunSolve(const app::Deck& deck, const SolveOptions& options, const Streams& streams, const JsonEnvelope& envelope) {
  const solvers::SolverOptions solver = SolverFor(deck, options.solver, options.kinematics);
  RequireOneStdout({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path},
                    {"--pattern-csv", options.pattern_csv_path}});
  // Outputs first: an unwritable path is an error before anything is computed.
  Output json("--json", options.json_path, streams.out);
  Output csv("--csv", options.csv_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  Output pattern("--pattern-csv", options.pattern_csv_path, streams.out);

  SvgData svg_data;
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
    if (csv.enabled()) csv.stream() << "crank_deg,te_arcsec,contacts,max_pin_force_n,max_contact_stress_mpa,status\n";
    if (pattern.enabled()) pattern.stream() << "crank_deg,pin,slice,z_mm,force_n,contact_stress_mpa,status\n";
  };
  app::SweepCallbacks callbacks;
  callbacks.keep_positions = false;
  callbacks.on_position = [&](const app::PositionResult& p) {
    if (!started) start();
    if (json.enabled()) json.stream() << (done == 0 ? "\n    " : ",\n    ") << Dump(PositionJson(p), -1);
    if (csv.enabled()) {
      const bool ok = p.succeeded();
      fmt::print(csv.stream(), "{:.9g},{},{},{},{},{}\n", RadToDeg(p.crank), CsvFigure(ok, RadToArcsec(p.result.te)),
                 ok ? fmt::format("{}", p.contacts) : std::string(), CsvFigure(ok, MaxOf(p.pin_force)),
                 CsvFigure(ok, MaxOf(p.contact_stress)), solvers::ToString(p.result.status));
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
  const app::SweepResult sweep = app::SolveSweep(deck, solver, callbacks);
  progress.Finish();
  if (!started) start();
  const auto& s = sweep.summary;

  if (json.enabled()) {
    json.stream() << "\n  ],\n  \"summary\": " << Nested(Dump(SummaryJson(s, deck.Model()))) << "\n}" << envelope.after << '\n';
    json.Commit();
  }
  if (csv.enabled()) csv.Commit();
  if (pattern.enabled()) pattern.Commit();
  if (svg.enabled()) {
    WriteSvg(sweep.solver, svg_data, svg.stream());
    svg.Commit();
  }

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
  if (s.succeeded > 0) {
    fmt::print(text, "pins in contact        {} to {}\n", s.contacts_min, s.contacts_max);
  } else {
    fmt::print(text, "pins in contact        n/a\n");
  }
  fmt::print(text, "largest pin force      {} N\n", FormatOrNa(s.max_pin_force, 2));
  fmt::print(text, "largest contact stress {} MPa\n", FormatOrNa(s.max_contact_stress, 2));
  fmt::print(text, "wall time              {:.4f} s for {} positions\n", s.wall_seconds, s.positions());
  return s.all_succeeded() ? kExitSuccess : kExitNotSucceeded;
}

}  // namespace ltca::cli
