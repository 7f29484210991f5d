#include "solve_command.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "contact_commands.hpp"
#include "ltca/geometry/units.hpp"
#include "output.hpp"

namespace ltca::cli {
namespace {

using units::RadToArcsec;
using units::RadToDeg;

nlohmann::json SweepJson(const solvers::Deck& deck, const solvers::SweepResult& sweep) {
  const auto& s = sweep.summary;
  nlohmann::json positions = nlohmann::json::array();
  for (const auto& p : sweep.positions) {
    nlohmann::json angles = nlohmann::json::array();
    for (const double a : p.angle) angles.push_back(RadToDeg(a));
    positions.push_back({{"crank_deg", RadToDeg(p.crank)},
                         {"te_arcsec", RadToArcsec(p.result.te)},
                         {"contacts", p.contacts},
                         {"pin_force_n", p.result.force},
                         {"pin_angle_deg", angles},
                         {"contact_stress_mpa", p.contact_stress},
                         {"status", solvers::ToString(p.result.status)},
                         {"message", p.result.message},
                         {"torque_evaluations", p.result.torque_evaluations},
                         {"residual", p.result.residuals.Normalised()}});
  }
  return {{"case", {{"title", deck.info.title}, {"source", deck.info.source}, {"deck", deck.name}}},
          {"solver", {{"name", sweep.solver},
                      {"kinematics", sweep.options.kinematics == contact::ContactKinematics::kExact ? "exact" : "linearised"},
                      {"torque_tolerance", sweep.options.torque_tolerance},
                      {"law", contact::ToString(deck.contact.law)},
                      {"rho_convention", contact::ToString(deck.contact.rho_convention)}}},
          {"summary", {{"mean_te_arcsec", RadToArcsec(s.mean_te)},
                       {"pp_te_arcsec", RadToArcsec(s.pp_te)},
                       {"contacts_min", s.contacts_min},
                       {"contacts_max", s.contacts_max},
                       {"max_pin_force_n", s.max_pin_force},
                       {"max_contact_stress_mpa", s.max_contact_stress},
                       {"wall_seconds", s.wall_seconds},
                       {"status", solvers::ToString(s.status)}}},
          {"positions", positions}};
}

void WriteSvg(const solvers::SweepResult& sweep, std::ostream& os) {
  // Left: TE over the crank sweep. Right: pin forces at the position of the largest force.
  const double w = 420, h = 300, pad = 50;
  fmt::print(os, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"11\">\n",
             2 * w, h);
  double te_lo = INFINITY, te_hi = -INFINITY, c_lo = INFINITY, c_hi = -INFINITY;
  std::size_t peak = 0;
  double f_peak = -1;
  for (std::size_t i = 0; i < sweep.positions.size(); ++i) {
    const auto& p = sweep.positions[i];
    te_lo = std::min(te_lo, RadToArcsec(p.result.te));
    te_hi = std::max(te_hi, RadToArcsec(p.result.te));
    c_lo = std::min(c_lo, RadToDeg(p.crank));
    c_hi = std::max(c_hi, RadToDeg(p.crank));
    const double f = *std::max_element(p.result.force.begin(), p.result.force.end());
    if (f > f_peak) f_peak = f, peak = i;
  }
  if (te_hi - te_lo < 1e-9) te_hi = te_lo + 1e-3;
  if (c_hi - c_lo < 1e-9) c_hi = c_lo + 1.0;
  const auto x1 = [&](double c) { return pad + (c - c_lo) / (c_hi - c_lo) * (w - 2 * pad); };
  const auto y1 = [&](double t) { return h - pad - (t - te_lo) / (te_hi - te_lo) * (h - 2 * pad); };
  fmt::print(os, "<text x=\"{}\" y=\"20\">loaded TE (arcsec) over crank angle (deg), {}</text>\n", pad, sweep.solver);
  fmt::print(os, "<rect x=\"{0}\" y=\"{0}\" width=\"{1}\" height=\"{2}\" fill=\"none\" stroke=\"#999\"/>\n", pad, w - 2 * pad, h - 2 * pad);
  os << "<polyline fill=\"none\" stroke=\"#c0392b\" points=\"";
  for (const auto& p : sweep.positions) fmt::print(os, "{:.2f},{:.2f} ", x1(RadToDeg(p.crank)), y1(RadToArcsec(p.result.te)));
  os << "\"/>\n";
  fmt::print(os, "<text x=\"5\" y=\"{}\">{:.4f}</text><text x=\"5\" y=\"{}\">{:.4f}</text>\n", pad + 4, te_hi, h - pad, te_lo);
  fmt::print(os, "<text x=\"{}\" y=\"{}\">{:.3g}</text><text x=\"{}\" y=\"{}\">{:.3g}</text>\n", pad, h - pad + 15, c_lo, w - pad - 20, h - pad + 15, c_hi);
  // Load distribution: force against the pin's angle from the line of centres.
  const auto& p = sweep.positions[peak];
  const auto x2 = [&](double a) { return w + pad + (a + 180.0) / 360.0 * (w - 2 * pad); };
  const auto y2 = [&](double f) { return h - pad - f / std::max(f_peak, 1e-300) * (h - 2 * pad); };
  fmt::print(os, "<text x=\"{}\" y=\"20\">pin force (N) over pin angle (deg) at crank {:.3g} deg</text>\n", w + pad, RadToDeg(p.crank));
  fmt::print(os, "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#999\"/>\n", w + pad, pad, w - 2 * pad, h - 2 * pad);
  for (std::size_t i = 0; i < p.result.force.size(); ++i) {
    const double a = RadToDeg(p.angle[i]);
    fmt::print(os, "<line x1=\"{0:.2f}\" x2=\"{0:.2f}\" y1=\"{1:.2f}\" y2=\"{2:.2f}\" stroke=\"#2c3e50\" stroke-width=\"3\"/>\n",
               x2(a), y2(0.0), y2(p.result.force[i]));
  }
  fmt::print(os, "<text x=\"{}\" y=\"{}\">{:.4g}</text>\n", w + 5, pad + 4, f_peak);
  fmt::print(os, "<text x=\"{}\" y=\"{}\">-180</text><text x=\"{}\" y=\"{}\">180</text>\n", w + pad, h - pad + 15, 2 * w - pad - 20, h - pad + 15);
  os << "</svg>\n";
}

}  // namespace

void RunSolve(const solvers::Deck& deck, const SolveOptions& options, std::ostream& out) {
  solvers::SolverOptions solver = deck.solver;
  if (!options.solver.empty()) solver.name = options.solver;
  if (!options.kinematics.empty()) solver.kinematics = ParseKinematics(options.kinematics);
  const solvers::SweepResult sweep = solvers::SolveSweep(deck, solver);
  const auto& s = sweep.summary;
  fmt::print(out, "case      {}\n", deck.info.title);
  fmt::print(out, "solver    {} ({} kinematics, torque tolerance {:g}), law {} / {}\n", sweep.solver,
             solver.kinematics == contact::ContactKinematics::kExact ? "exact" : "linearised", solver.torque_tolerance,
             contact::ToString(deck.contact.law), contact::ToString(deck.contact.rho_convention));
  fmt::print(out, "status                 {}\n", solvers::ToString(s.status));
  fmt::print(out, "mean TE                {:.4f} arcsec   (Liu eq. 16; negative under load)\n", RadToArcsec(s.mean_te));
  fmt::print(out, "peak-to-peak TE        {:.4f} arcsec\n", RadToArcsec(s.pp_te));
  fmt::print(out, "pins in contact        {} to {}\n", s.contacts_min, s.contacts_max);
  fmt::print(out, "largest pin force      {:.2f} N\n", s.max_pin_force);
  fmt::print(out, "largest contact stress {:.2f} MPa\n", s.max_contact_stress);
  fmt::print(out, "wall time              {:.4f} s for {} positions\n", s.wall_seconds, sweep.positions.size());
  if (!options.json_path.empty()) {
    WriteTo(options.json_path, out, [&](std::ostream& os) { os << SweepJson(deck, sweep).dump(2) << '\n'; });
  }
  if (!options.csv_path.empty()) {
    WriteTo(options.csv_path, out, [&](std::ostream& os) {
      os << "crank_deg,te_arcsec,contacts,max_pin_force_n,max_contact_stress_mpa,status\n";
      for (const auto& p : sweep.positions) {
        fmt::print(os, "{:.9g},{:.9g},{},{:.9g},{:.9g},{}\n", RadToDeg(p.crank), RadToArcsec(p.result.te), p.contacts,
                   *std::max_element(p.result.force.begin(), p.result.force.end()),
                   *std::max_element(p.contact_stress.begin(), p.contact_stress.end()), solvers::ToString(p.result.status));
      }
    });
  }
  if (!options.svg_path.empty()) WriteTo(options.svg_path, out, [&](std::ostream& os) { WriteSvg(sweep, os); });
}

}  // namespace ltca::cli
