#include "documents/efficiency.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "documents/solve.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::app::documents {
namespace {

using units::RadToDeg;
constexpr double kMmPerSToMPerS = 1e-3;

std::string PositionStatus(const analysis::EfficiencyPosition& p) {
  return ToString(p.succeeded() ? analysis::RunStatus::kSuccess : analysis::RunStatus::kFailed);
}

/// The loss by source (W; null for a failed position): mesh, output, bearings, seats.
nlohmann::json SourcesJson(double mesh, double output, double bearings, double seats) {
  return {{"mesh", FiniteOrNull(mesh)}, {"output", FiniteOrNull(output)}, {"bearings", FiniteOrNull(bearings)},
          {"seats", FiniteOrNull(seats)}};
}

}  // namespace

nlohmann::json EfficiencyHead(const Deck& deck, const SolverOptions& solver) {
  const analysis::FrictionSettings& f = deck.RequireFriction();
  const analysis::OperationSettings& op = deck.RequireOperation();
  nlohmann::json friction = {{"model", ToString(f.model)},
                             {"coefficient", FiniteOrNull(f.coefficient)},
                             {"boundary_coefficient", f.boundary_coefficient},
                             {"sleeve_bore_radius_mm", f.sleeve_bore_radius ? nlohmann::json(*f.sleeve_bore_radius) : nlohmann::json(nullptr)},
                             {"sleeve_coefficient", FiniteOrNull(f.sleeve_coefficient)},
                             {"limiting_shear_stress_coefficient", FiniteOrNull(f.limiting_shear_coefficient)},
                             {"limiting_shear_stress_mpa", f.limiting_shear_stress},
                             {"output_pin_coefficient", f.output_pin_coefficient},
                             {"bearing_coefficient", f.bearing_coefficient},
                             {"bearing_diameter_mm", FiniteOrNull(f.bearing_diameter)},
                             {"torque_balance", f.torque_balance == analysis::FrictionSettings::TorqueBalance::kSolve ? "solve" : "bound"}};
  nlohmann::json operation = {{"input_speed_rpm", units::RadPerSToRpm(op.input_speed)},
                              {"oil_viscosity_pa_s", op.viscosity * 1e6},
                              {"pressure_viscosity_per_gpa", units::PerMPaToPerGPa(op.pressure_viscosity)},
                              {"roughness_ra_cycloid_um", units::MmToUm(op.roughness_cycloid)},
                              {"roughness_ra_pin_um", units::MmToUm(op.roughness_pin)}};
  return {{"case", CaseJson(deck)},
          {"model", ModelJson(deck.Model())},
          {"solver", SolverJson(deck, solver)},
          {"friction", friction},
          {"operation", operation},
          {"sweep", {{"crank_start_deg", RadToDeg(deck.sweep.crank_start)},
                     {"crank_end_deg", RadToDeg(deck.sweep.crank_end)},
                     {"positions", deck.sweep.positions}}}};
}

nlohmann::json Json(const analysis::EfficiencyPosition& p, bool two_discs) {
  nlohmann::json contacts = nlohmann::json::array();
  for (const auto& c : p.contacts) {
    contacts.push_back({{"pin", c.pin + 1},
                        {"slice", c.slice},
                        {"force_n", c.force},
                        {"sliding_speed_m_per_s", c.sliding * kMmPerSToMPerS},
                        {"entrainment_speed_m_per_s", c.entrainment * kMmPerSToMPerS},
                        {"coefficient", c.coefficient},
                        {"effective_coefficient", c.effective_coefficient},
                        {"power_loss_w", c.loss},
                        {"power_loss_first_order_w", c.loss_first_order},
                        {"film_thickness_um", FiniteOrNull(units::MmToUm(c.film_thickness))},
                        {"lambda", FiniteOrNull(c.lambda)},
                        {"max_pressure_mpa", c.max_pressure},
                        {"shape", c.point_contact ? "ellipse" : "line"}});
    if (two_discs) contacts.back()["disc"] = c.disc + 1;
  }
  nlohmann::json pin_mu = nlohmann::json::array();
  for (const double mu : p.pin_coefficient) pin_mu.push_back(FiniteOrNull(mu));
  nlohmann::json j = {{"crank_deg", RadToDeg(p.crank)},
                      {"status", solvers::ToString(p.status)},
                      {"output_power_w", FiniteOrNull(p.output_power)},
                      {"power_loss_w", FiniteOrNull(p.power_loss)},
                      {"power_loss_first_order_w", FiniteOrNull(p.power_loss_first_order)},
                      {"power_loss_by_source_w", SourcesJson(p.power_loss_by_source.mesh, p.power_loss_by_source.output,
                                                             p.power_loss_by_source.bearings, p.power_loss_by_source.seats)},
                      {"stage_friction_moment_ratio", FiniteOrNull(p.stage_friction_moment_ratio)},
                      {"efficiency", FiniteOrNull(p.efficiency)},
                      {"efficiency_first_order", FiniteOrNull(p.efficiency_first_order)},
                      {"efficiency_malhotra_parameswaran", FiniteOrNull(p.efficiency_malhotra_parameswaran)},
                      {"efficiency_sensinger", FiniteOrNull(p.efficiency_sensinger)},
                      {"mean_coefficient", FiniteOrNull(p.mean_coefficient)},
                      {"friction_moment_ratio", FiniteOrNull(p.friction_moment_ratio)},
                      {"friction_moment_ratio_first_order", FiniteOrNull(p.friction_moment_ratio_first_order)},
                      {"balance_solves", p.balance_solves},
                      {"balance_residual", FiniteOrNull(p.balance_residual)},
                      {"pin_coefficient", pin_mu},
                      {"contacts", contacts}};
  if (!p.succeeded()) j["message"] = p.message;
  if (!p.warnings.empty()) j["warnings"] = p.warnings;
  return j;
}

Table ContactColumns(const analysis::EfficiencyPosition& p, bool two_discs) {
  Table t;
  for (const auto& c : p.contacts) {
    t.Add("pin", c.pin + 1.0);
    t.Add("slice", static_cast<double>(c.slice));
    t.Add("force_n", c.force);
    t.Add("sliding_speed_m_per_s", c.sliding * kMmPerSToMPerS);
    t.Add("entrainment_speed_m_per_s", c.entrainment * kMmPerSToMPerS);
    t.Add("coefficient", c.coefficient);
    t.Add("effective_coefficient", c.effective_coefficient);
    t.Add("power_loss_w", c.loss);
    t.Add("power_loss_first_order_w", c.loss_first_order);
    t.Add("film_thickness_um", units::MmToUm(c.film_thickness));
    t.Add("lambda", c.lambda);
    t.Add("max_pressure_mpa", c.max_pressure);
    if (two_discs) t.Add("disc", c.disc + 1.0);
  }
  return t;
}

Table Columns(const std::vector<analysis::EfficiencyPosition>& positions) {
  Table t;
  for (const analysis::EfficiencyPosition& p : positions) {
    t.Add("crank_deg", RadToDeg(p.crank));
    t.Add("output_power_w", p.output_power);
    t.Add("power_loss_w", p.power_loss);
    t.Add("power_loss_first_order_w", p.power_loss_first_order);
    t.Add("stage_friction_moment_ratio", p.stage_friction_moment_ratio);
    t.Add("efficiency", p.efficiency);
    t.Add("efficiency_first_order", p.efficiency_first_order);
    t.Add("efficiency_malhotra_parameswaran", p.efficiency_malhotra_parameswaran);
    t.Add("efficiency_sensinger", p.efficiency_sensinger);
    t.Add("mean_coefficient", p.mean_coefficient);
    t.Add("friction_moment_ratio", p.friction_moment_ratio);
    t.Add("friction_moment_ratio_first_order", p.friction_moment_ratio_first_order);
    t.Add("balance_solves", p.balance_solves);
    t.Add("balance_residual", p.balance_residual);
    t.Add("pin_coefficient", p.pin_coefficient);
  }
  return t;
}

nlohmann::json Json(const analysis::EfficiencySummary& s) {
  const auto spread = [](nlohmann::json& j, const std::string& key, const analysis::EfficiencySpread& v) {
    j[key] = FiniteOrNull(v.mean);
    j[key + "_min"] = FiniteOrNull(v.min);
    j[key + "_max"] = FiniteOrNull(v.max);
  };
  nlohmann::json j = nlohmann::json::object();
  spread(j, "power_loss_w", s.power_loss);
  spread(j, "power_loss_first_order_w", s.power_loss_first_order);
  spread(j, "output_power_w", s.output_power);
  j["power_loss_by_source_w"] = SourcesJson(s.power_loss_mesh.mean, s.power_loss_output.mean, s.power_loss_bearings.mean,
                                            s.power_loss_seats.mean);
  spread(j, "stage_friction_moment_ratio", s.stage_friction_moment_ratio);
  j["efficiency"] = FiniteOrNull(s.efficiency);
  j["efficiency_first_order"] = FiniteOrNull(s.efficiency_first_order);
  j["efficiency_malhotra_parameswaran"] = FiniteOrNull(s.efficiency_malhotra_parameswaran);
  j["efficiency_sensinger"] = FiniteOrNull(s.efficiency_sensinger);
  spread(j, "mean_coefficient", s.mean_coefficient);
  spread(j, "friction_moment_ratio", s.friction_moment_ratio);
  spread(j, "friction_moment_ratio_first_order", s.friction_moment_ratio_first_order);
  j["energy_loss_per_revolution_j"] = FiniteOrNull(s.energy_loss_per_revolution);
  AddRunRecord(j, s);
  j["solves"] = s.solves;
  j["balance_solves"] = s.balance_solves;
  j["loaded_solve_seconds"] = s.loaded_solve_seconds;
  j["warnings"] = s.warnings;
  return j;
}

nlohmann::json Json(const Deck& deck, const SolverOptions& solver, const std::vector<analysis::EfficiencyPosition>& positions,
                    const analysis::EfficiencySummary& summary) {
  nlohmann::json doc = EfficiencyHead(deck, solver);
  nlohmann::json list = nlohmann::json::array();
  for (const analysis::EfficiencyPosition& p : positions) list.push_back(Json(p, deck.second_disc.has_value()));
  doc["positions"] = std::move(list);
  doc["summary"] = Json(summary);
  return doc;
}

EfficiencyJsonWriter::EfficiencyJsonWriter(std::ostream& os, const Deck& deck, const SolverOptions& solver, bool two_discs)
    : os_(os), two_discs_(two_discs) {
  os_ << OpenObject(EfficiencyHead(deck, solver)) << ",\n  \"positions\": [";
}

void EfficiencyJsonWriter::Add(const analysis::EfficiencyPosition& p) {
  os_ << (written_++ == 0 ? "\n    " : ",\n    ") << Dump(Json(p, two_discs_), -1);
}

void EfficiencyJsonWriter::Finish(const analysis::EfficiencySummary& summary, const analysis::EfficiencySpectrum* spectrum) {
  os_ << "\n  ],\n  \"summary\": " << Nested(Dump(Json(summary)));
  if (spectrum != nullptr) os_ << ",\n  \"spectrum\": " << Nested(Dump(Json(*spectrum)));
  os_ << "\n}\n";
}

namespace {
nlohmann::json BySource(double mesh, double output, double bearings, double seats) {
  return {{"mesh", FiniteOrNull(mesh)}, {"output", FiniteOrNull(output)}, {"bearings", FiniteOrNull(bearings)},
          {"seats", FiniteOrNull(seats)}};
}
}  // namespace

nlohmann::json Json(const analysis::EfficiencySpectrum& spectrum) {
  nlohmann::json bins = nlohmann::json::array();
  for (const analysis::EfficiencySpectrum::Bin& b : spectrum.bins) {
    const analysis::EfficiencySummary& s = b.summary;
    bins.push_back({{"torque_nm", units::NmmToNm(b.bin.torque)},
                    {"speed_rpm", units::RadPerSToRpm(b.bin.input_speed)},
                    {"time_share", b.bin.time_share},
                    {"succeeded", s.all_succeeded()},
                    {"efficiency", FiniteOrNull(s.efficiency)},
                    {"output_power_w", FiniteOrNull(s.output_power.mean)},
                    {"power_loss_w", FiniteOrNull(s.power_loss.mean)},
                    {"power_loss_by_source_w", BySource(s.power_loss_mesh.mean, s.power_loss_output.mean,
                                                        s.power_loss_bearings.mean, s.power_loss_seats.mean)}});
  }
  return {{"bins", bins},
          {"succeeded", spectrum.all_succeeded()},
          {"efficiency", FiniteOrNull(spectrum.efficiency)},
          {"output_power_w", FiniteOrNull(spectrum.output_power)},
          {"power_loss_w", FiniteOrNull(spectrum.power_loss)},
          {"power_loss_by_source_w", BySource(spectrum.power_loss_mesh, spectrum.power_loss_output,
                                              spectrum.power_loss_bearings, spectrum.power_loss_seats)},
          {"note", "each bin's efficiency run over the deck's sweep at its torque and crank speed; over the spectrum the "
                   "energies per hour: efficiency = sum share P_out / sum share (P_out + P_loss), the powers the "
                   "time-weighted means (an idle bin delivers and loses nothing)"}};
}

std::string Text(const analysis::EfficiencySpectrum& spectrum) {
  std::string text = fmt::format("load spectrum          {} bins: efficiency over the duty cycle {} (energy out / energy in), "
                                 "loss {} W, output {} W (time-weighted)\n",
                                 spectrum.bins.size(), FormatOrNa(spectrum.efficiency, 6), FormatOrNa(spectrum.power_loss, 4),
                                 FormatOrNa(spectrum.output_power, 4));
  for (std::size_t i = 0; i < spectrum.bins.size(); ++i) {
    const analysis::EfficiencySpectrum::Bin& b = spectrum.bins[i];
    text += fmt::format("  bin {:<3} {:>10.4g} N*m {:>9.4g} rpm  share {:<8.4g} efficiency {}  loss {} W{}\n", i + 1,
                        units::NmmToNm(b.bin.torque), units::RadPerSToRpm(b.bin.input_speed), b.bin.time_share,
                        FormatOrNa(b.summary.efficiency, 6), FormatOrNa(b.summary.power_loss.mean, 4),
                        b.summary.all_succeeded() ? "" : fmt::format("  (failed: {})", b.summary.first_failure));
  }
  return text;
}

std::string EfficiencyTextHead(const Deck& deck, const SolverOptions& solver) {
  const analysis::FrictionSettings& f = deck.RequireFriction();
  const analysis::OperationSettings& op = deck.RequireOperation();
  std::string text = CaseLines(deck) + ModelLine(deck) + SolverLine(deck, solver);
  const std::string mu = f.model == analysis::FrictionSettings::Model::kCoulomb ? fmt::format("coulomb, mu = {:g}", f.coefficient)
                                                                      : fmt::format("jiang-mixed, f_b = {:g}", f.boundary_coefficient);
  text += fmt::format("friction  {}; {}; torque balance: {}\n", mu,
                      f.sleeve_bore_radius ? fmt::format("pin sleeve, bore radius {:g} mm, mu_bore {}", *f.sleeve_bore_radius,
                                                         std::isnan(f.sleeve_coefficient) ? std::string("= the contact's")
                                                                                          : fmt::format("{:g}", f.sleeve_coefficient))
                                           : std::string("no sleeve"),
                      f.torque_balance == analysis::FrictionSettings::TorqueBalance::kSolve ? "solved" : "bounded");
  text += fmt::format("operation crank {:g} rpm, oil {:g} Pa*s, alpha {:g} 1/GPa, Ra {:g} / {:g} um\n", units::RadPerSToRpm(op.input_speed),
                      units::MPaSToPaS(op.viscosity), units::PerMPaToPerGPa(op.pressure_viscosity), units::MmToUm(op.roughness_cycloid),
                      units::MmToUm(op.roughness_pin));
  return text + fmt::format("{:>10} {:>12} {:>12} {:>12} {:>12} {:>8}\n", "crank_deg", "loss_w", "efficiency", "first_order", "mean_mu",
                            "status");
}

std::string Text(const analysis::EfficiencyPosition& p) {
  return fmt::format("{:>10.4f} {:>12} {:>12} {:>12} {:>12} {:>8}\n", RadToDeg(p.crank), FormatOrNa(p.power_loss, 4),
                     FormatOrNa(p.efficiency, 6), FormatOrNa(p.efficiency_first_order, 6), FormatOrNa(p.mean_coefficient, 4),
                     PositionStatus(p));
}

std::string Text(const analysis::EfficiencySummary& s) {
  std::string text;
  if (s.failed > 0) text += fmt::format("failed positions       {} of {}; first: {}\n", s.failed, s.succeeded + s.failed, s.first_failure);
  text += fmt::format("output power           {} W (|T| |omega_c|)\n", FormatOrNa(s.output_power.mean, 4));
  text += fmt::format("power loss             {} W (mean; {} .. {} over the positions)\n", FormatOrNa(s.power_loss.mean, 4),
                      FormatOrNa(s.power_loss.min, 4), FormatOrNa(s.power_loss.max, 4));
  text += fmt::format("power loss by source   mesh {} W, output pins {} W, bearings {} W, pin seats {} W (means)\n",
                      FormatOrNa(s.power_loss_mesh.mean, 4), FormatOrNa(s.power_loss_output.mean, 4),
                      FormatOrNa(s.power_loss_bearings.mean, 4), FormatOrNa(s.power_loss_seats.mean, 4));
  if (s.stage_friction_moment_ratio.max > 0.0) {
    text += fmt::format("stage friction / T     {} (largest; the output pins' and bearings' friction moments on the discs, "
                        "not in the balance: the bound on the forces' relative change)\n",
                        FormatOrNa(s.stage_friction_moment_ratio.max, 5));
  }
  text += fmt::format("efficiency             {} (full model)\n", FormatOrNa(s.efficiency, 6));
  text += fmt::format("efficiency_first_order {} (pins fixed, no sleeve, frictionless forces)\n", FormatOrNa(s.efficiency_first_order, 6));
  text += fmt::format("classical estimates    {} (Malhotra-Parameswaran load distribution), {} (continuum closed form), "
                      "mean mu {}\n",
                      FormatOrNa(s.efficiency_malhotra_parameswaran, 6), FormatOrNa(s.efficiency_sensinger, 6),
                      FormatOrNa(s.mean_coefficient.mean, 4));
  text += fmt::format("friction moment / T    {} (mean; {} .. {}; the accepted forces), {} with the frictionless forces\n",
                      FormatOrNa(s.friction_moment_ratio.mean, 5), FormatOrNa(s.friction_moment_ratio.min, 5),
                      FormatOrNa(s.friction_moment_ratio.max, 5), FormatOrNa(s.friction_moment_ratio_first_order.mean, 5));
  for (const auto& w : s.warnings) text += fmt::format("warning                {}\n", w);
  return text + fmt::format("wall time              {:.4f} s ({:.4f} s in {} load solves + {} balance solves)\n", s.wall_seconds,
                            s.loaded_solve_seconds, s.solves, s.balance_solves);
}

std::string EfficiencyCsvHead(bool two_discs, bool stage) {
  return std::string("crank_deg,pin,slice,force_n,sliding_speed_m_per_s,entrainment_speed_m_per_s,coefficient,"
                     "effective_coefficient,power_loss_w,film_thickness_um,lambda,max_pressure_mpa,shape") +
         (two_discs ? ",disc" : "") +
         (stage ? ",position_loss_mesh_w,position_loss_output_w,position_loss_bearings_w,position_loss_seats_w\n" : "\n");
}

std::string Csv(const analysis::EfficiencyPosition& p, bool two_discs, bool stage) {
  std::string csv;
  for (const auto& c : p.contacts) {
    csv += fmt::format("{:.9g},{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{},{},{:.9g},{}", RadToDeg(p.crank), c.pin + 1, c.slice,
                       c.force, c.sliding * kMmPerSToMPerS, c.entrainment * kMmPerSToMPerS, c.coefficient, c.effective_coefficient,
                       c.loss, std::isfinite(c.film_thickness) ? fmt::format("{:.9g}", units::MmToUm(c.film_thickness)) : std::string(),
                       std::isfinite(c.lambda) ? fmt::format("{:.9g}", c.lambda) : std::string(), c.max_pressure,
                       c.point_contact ? "ellipse" : "line");
    if (two_discs) csv += fmt::format(",{}", c.disc + 1);
    if (stage) {  // the position's losses by source, on each of its rows
      csv += fmt::format(",{:.9g},{:.9g},{:.9g},{:.9g}", p.power_loss_by_source.mesh, p.power_loss_by_source.output,
                         p.power_loss_by_source.bearings, p.power_loss_by_source.seats);
    }
    csv += '\n';
  }
  return csv;
}

plots::Figure Figure(const Deck& deck, const SolverOptions& solver, const std::vector<analysis::EfficiencyPosition>& positions,
                     const analysis::EfficiencySummary& s) {
  plots::Figure figure;
  figure.title = fmt::format("{}: efficiency and power loss over crank {:g} to {:g} deg", CaseTitle(deck),
                             RadToDeg(deck.sweep.crank_start), RadToDeg(deck.sweep.crank_end));
  // The operating point: speed, torque and the friction model the figures hold for.
  const analysis::FrictionSettings& f = deck.RequireFriction();
  std::string friction = f.model == analysis::FrictionSettings::Model::kCoulomb ? fmt::format("Coulomb mu {:g}", f.coefficient)
                                                                      : fmt::format("{} (f_b {:g})", ToString(f.model), f.boundary_coefficient);
  if (f.output_pin_coefficient > 0.0) friction += fmt::format(", output pins mu {:g}", f.output_pin_coefficient);
  if (f.bearing_coefficient > 0.0) friction += fmt::format(", bearings mu {:g}", f.bearing_coefficient);
  figure.caption = FigureCaption(deck, fmt::format("operating point: input {:g} rpm, T = {:g} N*m, {}{}; model {}, solver {} ({} kinematics); "
                                                   "{} positions; failed positions are gaps",
                                                   units::RadPerSToRpm(deck.RequireOperation().input_speed), units::NmmToNm(deck.RequireLoad().torque),
                                                   friction, f.sleeve_bore_radius ? ", pin sleeves" : "", deck.Model().name, solver.name,
                                                   contact::ToString(deck.kinematics), positions.size()));
  figure.columns = 3;
  figure.width = 1500;
  figure.height = 520;
  std::vector<double> crank;
  for (const auto& p : positions) crank.push_back(RadToDeg(p.crank));
  const auto values = [&](auto get) {
    std::vector<double> v;
    for (const auto& p : positions) v.push_back(p.succeeded() ? get(p) : NAN);
    return v;
  };
  plots::Panel eff;
  eff.title = fmt::format("efficiency, mean {}", FormatOrNa(s.efficiency, 6));
  eff.x_label = "crank angle (deg)";
  eff.y_label = "efficiency (-)";
  eff.legend = plots::LegendPlace::kBottomRight;
  eff.series.push_back({"efficiency", crank, values([](const analysis::EfficiencyPosition& p) { return p.efficiency; }), plots::Style::kLine});
  plots::Series first{"first order", crank, values([](const analysis::EfficiencyPosition& p) { return p.efficiency_first_order; }),
                      plots::Style::kLine};
  first.dashed = true;
  eff.series.push_back(std::move(first));
  figure.panels.push_back(std::move(eff));
  plots::Panel loss;
  loss.title = fmt::format("power loss, mean {} W", FormatOrNa(s.power_loss.mean, 4));
  loss.x_label = "crank angle (deg)";
  loss.y_label = "power loss (W)";
  plots::Series l{"power loss", crank, values([](const analysis::EfficiencyPosition& p) { return p.power_loss; }), plots::Style::kLine};
  l.colour = 1;
  loss.series.push_back(std::move(l));
  // A stage: each source's share beside the total (the pin ring's own with a sleeve is its seats').
  if (deck.reducer) {
    const auto source = [&](const char* name, int colour, double analysis::PowerLossBySource::*member) {
      plots::Series line{name, crank, values([member](const analysis::EfficiencyPosition& p) { return p.power_loss_by_source.*member; }),
                         plots::Style::kLine};
      line.colour = colour;
      line.dashed = true;
      loss.series.push_back(std::move(line));
    };
    source(f.sleeve_bore_radius ? "pin seats" : "mesh", 0, f.sleeve_bore_radius ? &analysis::PowerLossBySource::seats : &analysis::PowerLossBySource::mesh);
    if (f.output_pin_coefficient > 0.0) source("output pins", 3, &analysis::PowerLossBySource::output);
    if (f.bearing_coefficient > 0.0) source("bearings", 4, &analysis::PowerLossBySource::bearings);
    // From zero, with room above the total for the legend.
    double top = 0.0;
    for (const auto& p : positions) {
      if (p.succeeded() && std::isfinite(p.power_loss)) top = std::max(top, p.power_loss);
    }
    if (top > 0.0) {
      loss.y_min = 0.0;
      loss.y_max = 1.6 * top;
    }
  }
  figure.panels.push_back(std::move(loss));
  plots::Panel mu;
  mu.title = "friction coefficient per pin (one line each)";
  mu.x_label = "crank angle (deg)";
  mu.y_label = "friction coefficient (-)";
  std::size_t pins = 0;
  for (const auto& p : positions) pins = std::max(pins, p.pin_coefficient.size());
  for (std::size_t j = 0; j < pins; ++j) {
    plots::Series line{j == 0 ? "pins" : "", crank, values([j](const analysis::EfficiencyPosition& p) {
                         return j < p.pin_coefficient.size() ? p.pin_coefficient[j] : NAN;
                       }),
                       plots::Style::kLine};
    line.colour = 2;
    mu.series.push_back(std::move(line));
  }
  figure.panels.push_back(std::move(mu));
  return figure;
}

}  // namespace ltca::app::documents
