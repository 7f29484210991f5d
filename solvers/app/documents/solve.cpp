#include "documents/solve.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "ltca/analysis/allowables.hpp"
#include "ltca/analysis/contact_fatigue.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::app::documents {
namespace {

using units::RadToArcsec;
using units::RadToDeg;

double MaxOf(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

/// Each entry, null where not finite.
nlohmann::json Finites(const std::vector<double>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const double x : v) a.push_back(FiniteOrNull(x));
  return a;
}

/// A reducer stage's solution at one position: per disc its pose, the output pins' forces
/// with their direction, the bearings' forces and roller loads; the strain energy per group.
nlohmann::json ReducerJson(const solvers::ReducerSolution& st) {
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
  for (std::size_t g = 0; g < st.group_energy.size(); ++g) {
    energy[solvers::ToString(static_cast<solvers::StageGroup>(g))] = st.group_energy[g];
  }
  return {{"discs", discs}, {"strain_energy_nmm", energy}, {"force_balance", st.force_balance_relative},
          {"moment_balance", st.moment_balance_relative}};
}

/// Rows of the allowables check (analysis::Judge's rule): each figure with its value, bounds
/// (null where open), margin and verdict.
nlohmann::json Verdicts(const std::vector<analysis::AllowableRow>& rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const analysis::AllowableRow& r : rows) {
    out.push_back({{"figure", r.figure},
                   // +inf: a life without damage (the string, as the lives themselves are written)
                   {"value", std::isinf(r.value) && r.value > 0.0 ? nlohmann::json("infinite") : FiniteOrNull(r.value)},
                   {"min", FiniteOrNull(r.range.min)},
                   {"max", FiniteOrNull(r.range.max)},
                   {"margin", FiniteOrNull(r.margin)},
                   {"verdict", analysis::ToString(r.verdict)}});
  }
  return out;
}

/// ISO 281:2007's modified rating life (BearingLife::modified): the oil, kappa, e_C, C_u and per
/// bearing e_C C_u / P, a_ISO and a_ISO L in hours, on the basic life (P the mean equivalent load)
/// and on the load-zone life (P = P_lz).
nlohmann::json ModifiedLifeJson(const analysis::BearingLife& life) {
  return {{"standard", "ISO 281:2007 9.3: L10m = a_1 a_ISO L10, a_1 = 1 (90 % reliability), a_ISO of radial roller bearings, "
                       "kappa clamped to [0.1, 4], a_ISO <= 50"},
          {"kinematic_viscosity_mm2_per_s", FiniteOrNull(life.kinematic_viscosity)},
          {"reference_viscosity_mm2_per_s", FiniteOrNull(life.reference_viscosity)},  // nu_1 at the bearing's speed and d_m
          {"viscosity_ratio", FiniteOrNull(life.viscosity_ratio)},                    // kappa = nu / nu_1 before the clamp
          {"contamination_factor", FiniteOrNull(life.contamination_factor)},
          {"fatigue_load_limit_n", FiniteOrNull(life.fatigue_load_limit)},
          {"fatigue_load_limit_basis", life.fatigue_load_limit_basis},
          {"load_ratio", Finites(life.load_ratio)},  // per bearing: e_C C_u / P, P the mean equivalent load
          {"a_iso", Finites(life.life_modification)},
          {"life_hours", Finites(life.modified_hours)},
          {"shortest_life_hours", FiniteOrNull(life.ShortestModifiedHours())},
          {"load_zone_load_ratio", Finites(life.load_zone_load_ratio)},  // per bearing: e_C C_u / P_lz
          {"load_zone_a_iso", Finites(life.load_zone_life_modification)},
          {"load_zone_life_hours", Finites(life.load_zone_modified_hours)},
          {"shortest_load_zone_life_hours", FiniteOrNull(life.ShortestLoadZoneModifiedHours())}};
}

/// A reducer stage's summary: the largest loads (N) and each bearing's ISO 281 life from its mean
/// equivalent load over the positions, as the sweep's summary carries it (SweepSummary::bearing_life).
nlohmann::json ReducerSummaryJson(const Deck& deck, const analysis::SweepSummary& s) {
  if (!s.reducer || !deck.reducer) return nullptr;
  const analysis::ReducerSummary& g = *s.reducer;
  const analysis::BearingLife life = s.bearing_life.value_or(analysis::BearingLife{});
  std::vector<double> ratios;  // the load-zone life over the basic life, per bearing (docs/stage.md)
  for (std::size_t b = 0; b < life.load_zone_million_revolutions.size() && b < life.million_revolutions.size(); ++b) {
    ratios.push_back(life.load_zone_million_revolutions[b] / life.million_revolutions[b]);
  }
  nlohmann::json turning = nlohmann::json::array();
  for (const contact::Raceway r : life.turning_raceway) turning.push_back(contact::ToString(r));
  nlohmann::json shares = nlohmann::json::object();
  for (std::size_t k = 0; k < g.energy_share.size(); ++k) {
    shares[solvers::ToString(static_cast<solvers::StageGroup>(k))] = FiniteOrNull(g.energy_share[k]);
  }
  nlohmann::json out = {{"max_output_pin_force_n", deck.reducer->kind == solvers::OutputKind::kPins ? FiniteOrNull(g.max_output_force)
                                                                                      : nlohmann::json(nullptr)},
          {"max_bearing_load_n", FiniteOrNull(g.max_bearing_load)},
          {"max_roller_load_n", FiniteOrNull(g.max_roller_load)},
          {"mean_equivalent_load_n", g.mean_equivalent_load},
          {"l10_million_revolutions", life.million_revolutions},
          {"l10_hours", life.hours},
          {"shortest_l10_hours", FiniteOrNull(life.ShortestHours())},  // null when no bearing has a life
          {"life_basis", life.basis},
          // The load-zone life from the roller loads (ISO/TS 16281's Lundberg-Palmgren form,
          // calibrated on ISO 281): null without rollers, [bearing] pitch_diameter_mm or a rating.
          {"turning_raceway", turning},
          {"turning_raceway_basis", life.turning_basis},
          {"load_zone_equivalent_load_n", Finites(life.load_zone_equivalent_load)},
          {"load_zone_life_million_revolutions", Finites(life.load_zone_million_revolutions)},
          {"load_zone_life_hours", Finites(life.load_zone_hours)},
          {"load_zone_to_basic_life_ratio", Finites(ratios)},  // per bearing: load-zone life / ISO 281 L10
          {"shortest_load_zone_life_hours", FiniteOrNull(life.ShortestLoadZoneHours())},
          // ISO 76: s_0 = C_0 / P_0,max (null without static_load_rating_n); the largest roller's
          // stress on the inner raceway against 4,000 MPa (null without rollers and pitch_diameter_mm).
          {"max_bearing_load_per_bearing_n", Finites(g.bearing_max_load)},
          {"static_safety", Finites(life.static_safety)},
          {"smallest_static_safety", FiniteOrNull(life.SmallestStaticSafety())},
          {"max_roller_contact_stress_mpa", Finites(life.max_roller_stress)},
          {"largest_roller_contact_stress_mpa", FiniteOrNull(life.LargestRollerStress())},
          {"roller_contact_stress_limit_mpa", contact::kStaticStressLimitRoller},
          // Each rating against its target ([allowables]; the roller stress against ISO 76's 4,000 MPa).
          {"verdicts", Verdicts(analysis::BearingRatingRows(life, deck.allowables))},
          {"strain_energy_share", shares}};
  // ISO 281's modified life, only when asked ([operation] oil_kinematic_viscosity_mm2_per_s).
  if (life.modified) out["modified_life"] = ModifiedLifeJson(life);
  return out;
}

/// A life in hours: a number, the string "infinite" for +inf (no damage: JSON has no infinity), or
/// null when not rated.
nlohmann::json HoursOrInfinite(double h) {
  return std::isinf(h) && h > 0.0 ? nlohmann::json("infinite") : FiniteOrNull(h);
}

/// The pitting rating of the pin-cycloid contact (analysis::ContactFatigue): per disc its pins'
/// and teeth's cycles, lives and S_H, with the curve, the endurance limit and the counting basis.
nlohmann::json ContactFatigueJson(const Deck& deck, const analysis::ContactFatigue& f) {
  nlohmann::json discs = nlohmann::json::array();
  for (const analysis::ContactFatigueDisc& d : f.discs) {
    discs.push_back({{"max_contact_stress_mpa", FiniteOrNull(d.max_stress)},
                     {"worst_pin", d.worst_pin >= 0 ? nlohmann::json(d.worst_pin + 1) : nlohmann::json(nullptr)},
                     {"pin_cycles_per_crank_turn", FiniteOrNull(d.pin_cycles_per_turn)},
                     {"tooth_cycles_per_crank_turn", FiniteOrNull(d.tooth_cycles_per_turn)},
                     {"pin_damage_per_crank_turn", FiniteOrNull(d.pin_damage_per_turn)},
                     {"tooth_damage_per_crank_turn", FiniteOrNull(d.tooth_damage_per_turn)},
                     // +inf (no cycle above the curve's floor) is written as the string "infinite"
                     {"pin_life_hours", HoursOrInfinite(d.pin_life_hours)},
                     {"tooth_life_hours", HoursOrInfinite(d.tooth_life_hours)},
                     {"pin_safety", FiniteOrNull(d.pin_safety)},
                     {"tooth_safety", FiniteOrNull(d.tooth_safety)}});
  }
  return {{"basis", f.basis},
          {"rule", "Palmgren-Miner over the counted cycles on ISO 6336-2's life factor Z_NT (Z_L = Z_v = Z_R = Z_W = Z_X = 1)"},
          {"life_curve", contact::ToString(f.curve)},
          {"fatigue_limit_mpa", FiniteOrNull(f.fatigue_limit)},
          {"crank_speed_rpm", FiniteOrNull(f.crank_rpm)},
          {"required_life_hours", FiniteOrNull(f.required_hours)},
          {"discs", discs},
          {"shortest_life_hours", HoursOrInfinite(f.ShortestHours())},
          {"smallest_safety", FiniteOrNull(f.SmallestSafety())},
          {"verdicts", Verdicts(analysis::ContactFatigueRows(f, deck.allowables))}};
}

nlohmann::json SummaryJson(const analysis::SweepSummary& s, const Deck::ModelInfo& model) {
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
                      {"closed_period", s.closed_period},
                      {"preloaded_positions", s.preloaded},
                      {"cannot_assemble_positions", s.cannot_assemble},
                      {"max_preload_force_n", FiniteOrNull(s.max_preload_force)},
                      {"max_preload_stress_mpa", FiniteOrNull(s.max_preload_stress)}};
  if (s.warned > 0) j["first_warning"] = s.first_warning;
  if (!s.notes.empty()) j["notes"] = s.notes;
  if (model.discs == 2) {  // the share of T the first disc carries, over the successful positions
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
  // (it covered the tallest contact-stress bar where the loaded pins were the last ones).
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

/// A CSV field: the figure as the shortest text that reads back to the same double, or empty when
/// no valid solve produced it.
std::string CsvFigure(bool ok, double v) { return ok ? ShortestOrEmpty(v) : std::string(); }

}  // namespace

nlohmann::json SolverJson(const Deck& deck, const SolverOptions& solver) {
  return {{"name", solver.name},
          {"kinematics", contact::ToString(deck.kinematics)},
          {"torque_tolerance", solver.torque_tolerance},
          {"law", contact::ToString(deck.contact.law)},
          {"rho_convention", contact::ToString(deck.contact.rho_convention)}};
}

std::string SolverLine(const Deck& deck, const SolverOptions& solver) {
  return fmt::format("solver    {} ({} kinematics, torque tolerance {:g}), law {} / {}\n", solver.name,
                     contact::ToString(deck.kinematics), solver.torque_tolerance, contact::ToString(deck.contact.law),
                     contact::ToString(deck.contact.rho_convention));
}

nlohmann::json SolveHead(const Deck& deck, const SolverOptions& solver) {
  return {{"case", CaseJson(deck)}, {"model", ModelJson(deck.Model())}, {"solver", SolverJson(deck, solver)}};
}

std::string FailureNote(const analysis::SweepSummary& s) {
  if (s.failed == 0) return {};
  if (s.succeeded == 0) return fmt::format("failed positions       all {} (no figure below is an answer)\n", s.positions());
  return fmt::format("failed positions       {} of {}; the figures below are over the {} successful positions only\n",
                     s.failed, s.positions(), s.succeeded);
}

nlohmann::json Json(const Deck& deck, const analysis::SweepSummary& summary) {
  nlohmann::json j = SummaryJson(summary, deck.Model());
  if (deck.reducer) j["stage"] = ReducerSummaryJson(deck, summary);
  if (summary.contact_fatigue) j["contact_fatigue"] = ContactFatigueJson(deck, *summary.contact_fatigue);
  return j;
}

nlohmann::json Json(const Deck& deck, const SolverOptions& solver, const analysis::SweepResult& sweep) {
  nlohmann::json j = SolveHead(deck, solver);
  nlohmann::json positions = nlohmann::json::array();
  for (const analysis::PositionResult& p : sweep.positions) positions.push_back(Json(p));
  j["positions"] = std::move(positions);
  j["summary"] = Json(deck, sweep.summary);
  return j;
}

namespace {
/// A preloaded pair's zero-torque state (null for a pair with free play): its largest pin force
/// (N) and Hertz stress (MPa), its pressed points and the moment of its opposing flank (N*m).
nlohmann::json PreloadJson(const solvers::LoadResult& r) {
  if (!r.preload) return nullptr;
  return {{"max_force_n", r.preload->max_force_n},
          {"max_contact_stress_mpa", r.preload->max_stress_mpa},
          {"contacts", r.preload->contacts},
          {"opposing_torque_nm", units::NmmToNm(r.preload->opposing_torque_nmm)}};
}
}  // namespace

nlohmann::json Json(const analysis::PositionResult& p) {
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
    // Two discs: the torque each carries, N*m, signed as T; pin arrays run over disc 1's
    // pins, then disc 2's.
    nlohmann::json torques = nlohmann::json::array();
    for (const double t : p.disc_torque) torques.push_back(FiniteOrNull(units::NmmToNm(t)));
    j["disc_torque_nm"] = figure(torques);
    const double total = p.disc_torque.size() == 2 ? p.disc_torque[0] + p.disc_torque[1] : 0.0;
    j["first_disc_share"] = figure(total != 0.0 ? FiniteOrNull(p.disc_torque[0] / total) : nlohmann::json(nullptr));
  }
  if (p.result.reducer) j["stage"] = figure(ReducerJson(*p.result.reducer));
  // A preloaded pair: its zero-torque state (null for a pair with free play).
  j["preload"] = PreloadJson(p.result);
  if (p.slices > 1) {
    const bool complete = p.result.force.size() == p.pin_force.size() * static_cast<std::size_t>(p.slices);
    // The contact pattern: per pin its slice forces and stresses and its load centroid.
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


namespace {
void Numbers(std::string& out, const double* v, std::size_t n) {
  out += '[';
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) out += ',';
    AppendJsonNumber(out, v[i]);
  }
  out += ']';
}
void Numbers(std::string& out, const std::vector<double>& v) { Numbers(out, v.data(), v.size()); }
void Key(std::string& out, const char* key) {
  out += ",\"";
  out += key;
  out += "\":";
}
}  // namespace

void AppendJson(std::string& out, const analysis::PositionResult& p) {
  // The members in nlohmann::json's order (its object is a std::map: keys sorted bytewise), each
  // as Json(p) has it; a test holds the two to the same bytes.
  const bool ok = p.succeeded();
  out += "{\"contact_stress_mpa\":";
  ok ? Numbers(out, p.contact_stress) : void(out += "null");
  Key(out, "contacts");
  ok ? AppendJsonNumber(out, std::int64_t{p.contacts}) : void(out += "null");
  Key(out, "crank_deg");
  AppendJsonNumber(out, RadToDeg(p.crank));
  if (!p.disc_torque.empty()) {
    Key(out, "disc_torque_nm");
    if (ok) {
      out += '[';
      for (std::size_t i = 0; i < p.disc_torque.size(); ++i) {
        if (i > 0) out += ',';
        AppendJsonNumber(out, units::NmmToNm(p.disc_torque[i]));
      }
      out += ']';
    } else {
      out += "null";
    }
    Key(out, "first_disc_share");
    const double total = p.disc_torque.size() == 2 ? p.disc_torque[0] + p.disc_torque[1] : 0.0;
    ok && total != 0.0 ? AppendJsonNumber(out, p.disc_torque[0] / total) : void(out += "null");
  }
  Key(out, "flank");
  AppendJsonString(out, solvers::ToString(p.result.flank));
  const auto n = static_cast<std::size_t>(std::max(p.slices, 1));
  const bool complete = p.slices > 1 && p.result.force.size() == p.pin_force.size() * n;
  // The contact pattern: per pin its slice forces and stresses and its load centroid (null for a
  // position no valid solve produced).
  const auto per_pin = [&](const std::vector<double>& values) {
    if (!(ok && complete)) {
      out += "null";
      return;
    }
    out += '[';
    for (std::size_t j = 0; j < p.pin_force.size(); ++j) {
      if (j > 0) out += ',';
      Numbers(out, values.data() + j * n, n);
    }
    out += ']';
  };
  if (p.slices > 1) {
    Key(out, "load_centroid_mm");
    (ok && complete) ? Numbers(out, p.load_centroid.data(), std::min(p.load_centroid.size(), p.pin_force.size()))
                      : void(out += "null");
  }
  Key(out, "message");
  AppendJsonString(out, p.result.message);
  Key(out, "pin_angle_deg");
  out += '[';
  for (std::size_t i = 0; i < p.angle.size(); ++i) {
    if (i > 0) out += ',';
    AppendJsonNumber(out, RadToDeg(p.angle[i]));
  }
  out += ']';
  Key(out, "pin_force_n");
  ok ? Numbers(out, p.pin_force) : void(out += "null");
  Key(out, "preload");
  out += Dump(PreloadJson(p.result), -1);
  Key(out, "residual");
  AppendJsonNumber(out, p.result.residuals.Normalised());
  if (p.slices > 1) {
    Key(out, "slice_force_n");
    per_pin(p.result.force);
    Key(out, "slice_stress_mpa");
    per_pin(p.point_stress);
  }
  if (p.result.reducer) {  // a reducer stage's solution, small beside the pins: through nlohmann
    Key(out, "stage");
    out += ok ? Dump(ReducerJson(*p.result.reducer), -1) : std::string("null");
  }
  Key(out, "status");
  AppendJsonString(out, solvers::ToString(p.result.status));
  Key(out, "te_arcsec");
  ok ? AppendJsonNumber(out, RadToArcsec(p.result.te)) : void(out += "null");
  Key(out, "torque_evaluations");
  AppendJsonNumber(out, std::int64_t{p.result.torque_evaluations});
  Key(out, "warnings");
  out += '[';
  for (std::size_t i = 0; i < p.result.warnings.size(); ++i) {
    if (i > 0) out += ',';
    AppendJsonString(out, p.result.warnings[i]);
  }
  out += "]}";
}

SolveJsonWriter::SolveJsonWriter(std::ostream& os, const Deck& deck, const SolverOptions& solver, std::string before,
                                 std::string after)
    : os_(os), head_(SolveHead(deck, solver)), before_(std::move(before)), after_(std::move(after)) {}

void SolveJsonWriter::Start() {
  if (started_) return;
  started_ = true;
  os_ << before_ << OpenObject(head_) << ",\n  \"positions\": [";
}

void SolveJsonWriter::Add(const analysis::PositionResult& p) {
  Start();
  buffer_.assign(written_++ == 0 ? "\n    " : ",\n    ");
  AppendJson(buffer_, p);
  os_ << buffer_;
}

void SolveJsonWriter::Finish(const Deck& deck, const analysis::SweepSummary& summary, const analysis::SpectrumResult* spectrum) {
  Start();
  os_ << "\n  ],\n  \"summary\": " << Nested(Dump(Json(deck, summary)));
  if (spectrum != nullptr) os_ << ",\n  \"spectrum\": " << Nested(Dump(SpectrumJson(deck, *spectrum)));
  os_ << "\n}" << after_ << '\n';
}

nlohmann::json SpectrumJson(const Deck& deck, const analysis::SpectrumResult& r) {
  nlohmann::json bins = nlohmann::json::array();
  for (const analysis::SpectrumBinResult& b : r.bins) {
    const analysis::SweepSummary& s = b.summary;
    const analysis::BearingLife life = s.bearing_life.value_or(analysis::BearingLife{});
    bins.push_back({{"torque_nm", units::NmmToNm(b.bin.torque)},
                    {"speed_rpm", units::RadPerSToRpm(b.bin.input_speed)},
                    {"time_share", b.bin.time_share},
                    {"status", solvers::ToString(s.status)},
                    {"succeeded_positions", s.succeeded},
                    {"failed_positions", s.failed},
                    {"mean_te_arcsec", FiniteOrNull(RadToArcsec(s.mean_te))},
                    {"pp_te_arcsec", FiniteOrNull(RadToArcsec(s.pp_te))},
                    {"max_pin_force_n", FiniteOrNull(s.max_pin_force)},
                    {"max_contact_stress_mpa", FiniteOrNull(s.max_contact_stress)},
                    {"l10_hours", Finites(life.hours)},
                    {"shortest_l10_hours", FiniteOrNull(life.ShortestHours())},
                    {"load_zone_life_hours", Finites(life.load_zone_hours)},
                    {"shortest_load_zone_life_hours", FiniteOrNull(life.ShortestLoadZoneHours())},
                    {"shortest_pitting_life_hours",
                     HoursOrInfinite(s.contact_fatigue ? s.contact_fatigue->ShortestHours() : std::numeric_limits<double>::quiet_NaN())},
                    // the bin as if it ran the whole required life (the spectrum's S_H is over the bins)
                    {"smallest_pitting_safety",
                     FiniteOrNull(s.contact_fatigue ? s.contact_fatigue->SmallestSafety() : std::numeric_limits<double>::quiet_NaN())},
                    {"static_safety", Finites(life.static_safety)},
                    {"smallest_static_safety", FiniteOrNull(life.SmallestStaticSafety())},
                    {"largest_roller_contact_stress_mpa", FiniteOrNull(life.LargestRollerStress())}});
    if (life.modified) {  // ISO 281's modified lives at the bin's own speed (its nu_1 and kappa)
      bins.back()["viscosity_ratio"] = FiniteOrNull(life.viscosity_ratio);
      bins.back()["shortest_modified_life_hours"] = FiniteOrNull(life.ShortestModifiedHours());
      bins.back()["shortest_load_zone_modified_life_hours"] = FiniteOrNull(life.ShortestLoadZoneModifiedHours());
    }
  }
  nlohmann::json pitting = nlohmann::json::array();
  for (const double h : r.contact_life_hours) pitting.push_back(HoursOrInfinite(h));
  const auto bin_of = [](int bin) { return bin >= 0 ? nlohmann::json(bin + 1) : nlohmann::json(nullptr); };  // 1-based
  nlohmann::json s0_bins = nlohmann::json::array(), stress_bins = nlohmann::json::array();
  for (const int b : r.static_safety_bin) s0_bins.push_back(bin_of(b));
  for (const int b : r.max_roller_stress_bin) stress_bins.push_back(bin_of(b));
  const auto [s0, s0_bin] = r.SmallestStaticSafety();
  const auto [roller, roller_bin] = r.LargestRollerStress();
  nlohmann::json out = {{"rule", "Palmgren-Miner over the time shares: L = 1 / sum(share_i / L_i), each L_i in hours at bin i's crank speed"},
          {"bins", bins},
          {"l10_hours", Finites(r.l10_hours)},
          {"shortest_l10_hours", FiniteOrNull(r.ShortestL10Hours())},
          {"load_zone_life_hours", Finites(r.load_zone_hours)},
          {"shortest_load_zone_life_hours", FiniteOrNull(r.ShortestLoadZoneHours())},
          // per disc: the pins', then the teeth's pitting life (ContactFatigue), Miner over the bins
          {"pitting_life_hours", pitting},
          {"shortest_pitting_life_hours", HoursOrInfinite(r.ShortestContactHours())},
          // Static figures: the worst bin's, each with the bin (1-based) that sets it.
          {"static_rule", "the worst bin: s_0 = C_0 / P_0,max with P_0,max over every bin (ISO 76), the largest stresses over every bin"},
          {"static_safety", Finites(r.static_safety)},
          {"static_safety_bin", s0_bins},
          {"smallest_static_safety", FiniteOrNull(s0)},
          {"smallest_static_safety_bin", bin_of(std::isnan(s0) ? -1 : s0_bin)},
          {"max_roller_contact_stress_mpa", Finites(r.max_roller_stress)},
          {"max_roller_contact_stress_bin", stress_bins},
          {"largest_roller_contact_stress_mpa", FiniteOrNull(roller)},
          {"largest_roller_contact_stress_bin", bin_of(std::isnan(roller) ? -1 : roller_bin)},
          {"max_contact_stress_mpa", FiniteOrNull(r.max_contact_stress)},
          {"max_contact_stress_bin", bin_of(r.max_contact_stress_bin)},
          // The pitting safety over the spectrum (analysis::SpectrumContactSafety): per disc the pins',
          // then the teeth's, at the required life; null without [allowables] contact_life_hours.
          {"pitting_safety", Finites(r.contact_safety)},
          {"smallest_pitting_safety", FiniteOrNull(r.SmallestContactSafety())},
          {"pitting_safety_rule", "ISO 6336-6 for a load spectrum: the factor on every bin's stress (each bin's cycles at its "
                                  "largest stress) that brings Miner's damage over the required life to 1"},
          {"required_pitting_life_hours", FiniteOrNull(r.required_contact_hours)},
          {"verdicts", Verdicts(analysis::SpectrumRatingRows(r, deck.allowables, deck.RequireMaterial().contact_stress_limit,
                                                             deck.reducer.has_value()))}};
  if (r.modified()) {  // ISO 281's modified lives, each bin's a_ISO at its own kappa, Miner over the bins
    out["modified_life_hours"] = Finites(r.modified_hours);
    out["shortest_modified_life_hours"] = FiniteOrNull(r.ShortestModifiedHours());
    out["load_zone_modified_life_hours"] = Finites(r.load_zone_modified_hours);
    out["shortest_load_zone_modified_life_hours"] = FiniteOrNull(r.ShortestLoadZoneModifiedHours());
  }
  return out;
}

std::string SpectrumText(const Deck& deck, const analysis::SpectrumResult& r) {
  std::string text = fmt::format("load spectrum          {} bins; lives by Palmgren-Miner over the time shares\n", r.bins.size());
  for (std::size_t i = 0; i < r.bins.size(); ++i) {
    const analysis::SpectrumBinResult& b = r.bins[i];
    const analysis::SweepSummary& s = b.summary;
    const analysis::BearingLife life = s.bearing_life.value_or(analysis::BearingLife{});
    text += fmt::format("  bin {}: {:g} N*m at {:g} rpm, share {:g}: {}, mean TE {} arcsec, largest pin force {} N, "
                        "largest stress {} MPa, bearing L10 {} h, load-zone life {} h (the shortest)\n",
                        i + 1, units::NmmToNm(b.bin.torque), units::RadPerSToRpm(b.bin.input_speed), b.bin.time_share,
                        solvers::ToString(s.status), FormatOrNa(RadToArcsec(s.mean_te), 4), FormatOrNa(s.max_pin_force, 2),
                        FormatOrNa(s.max_contact_stress, 2), FormatOrNa(life.ShortestHours(), 4),
                        FormatOrNa(life.ShortestLoadZoneHours(), 4));
    if (life.modified) {
      text += fmt::format("         kappa {}: modified life a_ISO L10 {} h, a_ISO times the load-zone life {} h (the shortest)\n",
                          FormatOrNa(life.viscosity_ratio, 4), FormatOrNa(life.ShortestModifiedHours(), 4),
                          FormatOrNa(life.ShortestLoadZoneModifiedHours(), 4));
    }
  }
  text += fmt::format("spectrum bearing L10   {} h, the shortest\n", FormatOrNa(r.ShortestL10Hours(), 4));
  text += fmt::format("spectrum load-zone     {} h, the shortest\n", FormatOrNa(r.ShortestLoadZoneHours(), 4));
  if (r.modified()) {
    text += fmt::format("spectrum modified L10m {} h, load-zone {} h, the shortest (ISO 281 a_ISO per bin)\n",
                        FormatOrNa(r.ShortestModifiedHours(), 4), FormatOrNa(r.ShortestLoadZoneModifiedHours(), 4));
  }
  text += fmt::format("spectrum pitting life  {} h, the shortest of the pins and teeth\n",
                      std::isinf(r.ShortestContactHours()) ? std::string("infinite") : FormatOrNa(r.ShortestContactHours(), 4));
  if (!r.contact_safety.empty()) {
    text += fmt::format("spectrum pitting S_H   {} at {:g} h, the smallest (every bin's stress times S_H: Miner's damage 1)\n",
                        FormatOrNa(r.SmallestContactSafety(), 4), r.required_contact_hours);
  }
  const auto bin_text = [](int bin) { return bin >= 0 ? fmt::format(" (bin {})", bin + 1) : std::string(); };
  text += fmt::format("spectrum tooth stress  {} MPa, the largest{}\n", FormatOrNa(r.max_contact_stress, 2), bin_text(r.max_contact_stress_bin));
  if (deck.reducer) {
    const auto [s0, s0_bin] = r.SmallestStaticSafety();
    const auto [roller, roller_bin] = r.LargestRollerStress();
    text += fmt::format("spectrum static s_0    {}, the smallest{} (ISO 76: C_0 / P_0,max over every bin)\n", FormatOrNa(s0, 4),
                        bin_text(std::isnan(s0) ? -1 : s0_bin));
    text += fmt::format("spectrum roller stress {} MPa, the largest{} (ISO 76's basis of C_0: {:g} MPa)\n", FormatOrNa(roller, 2),
                        bin_text(std::isnan(roller) ? -1 : roller_bin), contact::kStaticStressLimitRoller);
  }
  // The verdicts of the spectrum's figures that have a target (analysis::SpectrumRatingRows, one
  // rule with the JSON and the report).
  for (const analysis::AllowableRow& row :
       analysis::SpectrumRatingRows(r, deck.allowables, deck.RequireMaterial().contact_stress_limit, deck.reducer.has_value())) {
    if (!row.range.Given()) continue;
    const bool below = std::isfinite(row.range.min);
    text += fmt::format("  {:<6} {}: {}, target {} {:g}\n", analysis::ToString(row.verdict), row.name,
                        std::isinf(row.value) && row.value > 0.0 ? std::string("infinite") : FormatOrNa(row.value, 4),
                        below ? ">=" : "<=", below ? row.range.min : row.range.max);
  }
  return text;
}

namespace {

/// A life in hours as text: "infinite" for +inf, "n/a" for NaN.
std::string HoursText(double h) { return std::isinf(h) && h > 0.0 ? std::string("infinite") : FormatOrNa(h, 4); }

/// ISO 281's modified lives (ModifiedLifeJson's figures): the shortest of each with its bearing's
/// a_ISO, and the inputs of a_ISO.
std::string ModifiedLifeText(const analysis::BearingLife& life) {
  const auto shortest = [](const std::vector<double>& hours, const std::vector<double>& a) {
    std::size_t k = hours.size();
    for (std::size_t b = 0; b < hours.size(); ++b) {
      if (std::isfinite(hours[b]) && (k == hours.size() || hours[b] < hours[k])) k = b;
    }
    return k < hours.size() && k < a.size() ? std::pair{hours[k], a[k]}
                                            : std::pair{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  };
  const auto [basic, a_basic] = shortest(life.modified_hours, life.life_modification);
  const auto [zone, a_zone] = shortest(life.load_zone_modified_hours, life.load_zone_life_modification);
  const double kappa = life.viscosity_ratio;
  const std::string clamp = kappa > contact::kViscosityRatioMax   ? fmt::format(", taken as {:g}", contact::kViscosityRatioMax)
                            : kappa < contact::kViscosityRatioMin ? fmt::format(", taken as {:g}: below ISO 281's range", contact::kViscosityRatioMin)
                                                                  : std::string();
  std::string text = fmt::format("modified life L10m     {} h, the shortest (a_ISO {} on the basic L10)\n", FormatOrNa(basic, 4),
                                 FormatOrNa(a_basic, 4));
  text += fmt::format("modified load-zone     {} h, the shortest (a_ISO {} on the load-zone life)\n", FormatOrNa(zone, 4),
                      FormatOrNa(a_zone, 4));
  text += fmt::format("                       (ISO 281:2007 a_ISO, radial roller bearings: kappa = nu / nu_1 = {:g} / {} mm^2/s = {}{}, "
                      "e_C {:g}, C_u {} N, {})\n",
                      life.kinematic_viscosity, FormatOrNa(life.reference_viscosity, 4), FormatOrNa(kappa, 4), clamp,
                      life.contamination_factor, FormatOrNa(life.fatigue_load_limit, 5), life.fatigue_load_limit_basis);
  return text;
}

/// The pitting rating's lines (ContactFatigueJson's figures, the shortest and smallest of them).
std::string ContactFatigueText(const Deck& deck, const analysis::ContactFatigue& f) {
  if (f.discs.empty()) return fmt::format("pitting life           {}\n", f.basis);
  std::string text;
  for (std::size_t d = 0; d < f.discs.size(); ++d) {
    const analysis::ContactFatigueDisc& r = f.discs[d];
    // "1 cycle", "1.026 cycles": a count of load cycles in a crank turn, in words that read right.
    const auto cycles = [](double n) { return fmt::format("{:.4g} {}", n, n == 1.0 ? "cycle" : "cycles"); };
    text += fmt::format("{:<23}pins {} h ({} a crank turn, pin {}), teeth {} h ({} a crank turn)\n",
                        f.discs.size() == 2 ? fmt::format("pitting life disc {}", d + 1) : std::string("pitting life"),
                        HoursText(r.pin_life_hours), cycles(r.pin_cycles_per_turn), r.worst_pin + 1,
                        HoursText(r.tooth_life_hours), cycles(r.tooth_cycles_per_turn));
  }
  text += fmt::format("                       (Miner on ISO 6336-2 Z_NT, {}, sigma_Hlim {:g} MPa; {}{})\n",
                      contact::ToString(f.curve), f.fatigue_limit, f.basis,
                      std::isnan(f.crank_rpm) ? "; no hours without [operation] input_speed_rpm or motor_speed_rpm" : "");
  if (!std::isnan(f.required_hours)) {
    text += fmt::format("pitting safety S_H     {} at {:g} h (the smallest)\n", FormatOrNa(f.SmallestSafety(), 4), f.required_hours);
  }
  for (const analysis::AllowableRow& r : analysis::ContactFatigueRows(f, deck.allowables)) {
    if (!r.range.Given()) continue;
    text += fmt::format("  {:<6} {}: {}, target >= {:g}\n", analysis::ToString(r.verdict), r.name, HoursText(r.value), r.range.min);
  }
  return text;
}

}  // namespace

std::string Text(const Deck& deck, const SolverOptions& solver, const analysis::SweepSummary& s) {
  std::string text = CaseLines(deck);
  text += ModelLine(deck);
  text += SolverLine(deck, solver);
  text += fmt::format("status                 {}\n", solvers::ToString(s.status));
  text += FailureNote(s);
  if (s.warned > 0) text += fmt::format("warnings               {} positions, first at {}\n", s.warned, s.first_warning);
  for (const std::string& note : s.notes) text += fmt::format("note                   {}\n", note);
  const double torque = deck.RequireLoad().torque;
  text += fmt::format("loaded flank           {}\n", torque > 0.0 ? "drive (torque > 0)" : (torque < 0.0 ? "coast (torque < 0)" : "none (zero torque)"));
  text += fmt::format("mean TE                {} arcsec   (Liu eq. 16; < 0 on the drive flank, > 0 on the coast flank)\n", FormatOrNa(RadToArcsec(s.mean_te), 4));
  text += fmt::format("peak-to-peak TE        {} arcsec\n", FormatOrNa(RadToArcsec(s.pp_te), 4));
  if (s.closed_period) text += "                       (the last position repeats the first: the mean counts it once)\n";
  if (s.succeeded > 0) {
    text += fmt::format("pins in contact        {} to {}\n", s.contacts_min, s.contacts_max);
  } else {
    text += "pins in contact        n/a\n";
  }
  if (deck.disc_count() == 2) {
    text += fmt::format("first disc's share     {} mean, {} to {} of T (disc 2: the rest; per crank in --json/--csv)\n",
                        FormatOrNa(s.first_disc_share_mean, 4), FormatOrNa(s.first_disc_share_min, 4),
                        FormatOrNa(s.first_disc_share_max, 4));
  }
  text += fmt::format("largest pin force      {} N\n", FormatOrNa(s.max_pin_force, 2));
  text += fmt::format("largest contact stress {} MPa\n", FormatOrNa(s.max_contact_stress, 2));
  if (s.contact_fatigue) text += ContactFatigueText(deck, *s.contact_fatigue);
  if (deck.reducer && s.reducer) {
    const analysis::ReducerSummary& g = *s.reducer;
    const analysis::BearingLife life = s.bearing_life.value_or(analysis::BearingLife{});
    if (deck.reducer->kind == solvers::OutputKind::kPins) {
      text += fmt::format("largest output pin     {} N\n", FormatOrNa(g.max_output_force, 2));
    }
    text += fmt::format("largest bearing load   {} N{}\n", FormatOrNa(g.max_bearing_load, 2),
                        std::isnan(g.max_roller_load) ? std::string() : fmt::format(" (largest roller {} N)", FormatOrNa(g.max_roller_load, 2)));
    // The JSON's figure (BearingLife::ShortestHours: the least finite life), one rule for both.
    text += fmt::format("bearing L10            {} h, the shortest ({})\n", FormatOrNa(life.ShortestHours(), 4), life.basis);
    // The shortest load-zone life and its bearing's basic life beside it (their ratio).
    double zone = std::numeric_limits<double>::quiet_NaN(), basic = zone;
    for (std::size_t b = 0; b < life.load_zone_hours.size() && b < life.hours.size(); ++b) {
      if (std::isfinite(life.load_zone_hours[b]) && !(life.load_zone_hours[b] >= zone)) zone = life.load_zone_hours[b], basic = life.hours[b];
    }
    text += fmt::format("load-zone life         {} h, the shortest ({} of that bearing's L10; roller loads, Lundberg-Palmgren on "
                        "ISO 281's C; the {} ring turns against the load)\n",
                        FormatOrNa(zone, 4), FormatOrNa(zone / basic, 4),
                        life.turning_raceway.empty() ? "outer" : contact::ToString(life.turning_raceway.front()));
    if (life.modified) text += ModifiedLifeText(life);
    text += fmt::format("static safety s_0      {} (ISO 76: C_0 / P_0,max, the smallest)\n", FormatOrNa(life.SmallestStaticSafety(), 4));
    text += fmt::format("roller contact stress  {} MPa, the largest (ISO 76's basis of C_0: {:g} MPa)\n",
                        FormatOrNa(life.LargestRollerStress(), 2), contact::kStaticStressLimitRoller);
    // The verdicts of the ratings that have a target (analysis::BearingRatingRows, one rule with
    // the JSON and the report).
    for (const analysis::AllowableRow& r : analysis::BearingRatingRows(life, deck.allowables)) {
      if (!r.range.Given()) continue;
      const bool below = std::isfinite(r.range.min);
      text += fmt::format("  {:<6} {}: {}, target {} {:g}\n", analysis::ToString(r.verdict), r.name, FormatOrNa(r.value, 4),
                          below ? ">=" : "<=", below ? r.range.min : r.range.max);
    }
  }
  text += fmt::format("wall time              {:.4f} s for {} positions\n", s.wall_seconds, s.positions());
  return text;
}

std::string SolveCsvHead(const Deck& deck) {
  return std::string("crank_deg,te_arcsec,contacts,max_pin_force_n,max_contact_stress_mpa,status") +
         (deck.disc_count() == 2 ? ",disc1_torque_nm,disc2_torque_nm\n" : "\n");
}

std::string Csv(const analysis::PositionResult& p) {
  const bool ok = p.succeeded();
  std::string row = fmt::format("{},{},{},{},{},{}", ShortestOrEmpty(RadToDeg(p.crank)), CsvFigure(ok, RadToArcsec(p.result.te)),
                                ok ? fmt::format("{}", p.contacts) : std::string(), CsvFigure(ok, MaxOf(p.pin_force)),
                                CsvFigure(ok, MaxOf(p.contact_stress)), solvers::ToString(p.result.status));
  if (p.disc_torque.size() == 2) {  // two discs: each disc's torque, N*m
    row += fmt::format(",{},{}", CsvFigure(ok, units::NmmToNm(p.disc_torque[0])), CsvFigure(ok, units::NmmToNm(p.disc_torque[1])));
  }
  return row + '\n';
}

std::string PatternCsvHead() { return "crank_deg,pin,slice,z_mm,force_n,contact_stress_mpa,status\n"; }

std::string PatternCsv(const Deck& deck, const analysis::PositionResult& p) {
  // Pin (1-based) x slice (1-based) of the model that ran; figures empty for a failed position.
  const bool ok = p.succeeded();
  const auto n = static_cast<std::size_t>(p.slices);
  const double width = deck.pair.face_width / static_cast<double>(p.slices);
  std::string rows;
  for (std::size_t j = 0; j < p.pin_force.size(); ++j) {
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = j * n + k;
      rows += fmt::format("{},{},{},{},{},{},{}\n", ShortestOrEmpty(RadToDeg(p.crank)), j + 1, k + 1,
                          ShortestOrEmpty((static_cast<double>(k) + 0.5) * width),
                          CsvFigure(ok, i < p.result.force.size() ? p.result.force[i] : NAN),
                          CsvFigure(ok, i < p.point_stress.size() ? p.point_stress[i] : NAN), solvers::ToString(p.result.status));
    }
  }
  return rows;
}

SolveSeries::SolveSeries(std::int64_t n)
    : stride_(std::max<std::int64_t>(1, (n + kMapColumns - 1) / kMapColumns)), te_(n) {}

void SolveSeries::Add(const analysis::PositionResult& p) {
  const double crank = RadToDeg(p.crank);
  if (positions_ == 0) first_crank_ = crank;
  last_crank_ = crank;
  te_.Add(positions_++, crank, p.succeeded() ? RadToArcsec(p.result.te) : NAN);
  // A map column holds the largest of each pin's figure over its run of stride_ positions (NaN
  // where none of them succeeded), drawn at the middle of the run's cranks: every peak of a long
  // sweep stays in the map, where one position in stride_ would alias the mesh period.
  if (seen_++ % stride_ == 0) {
    map_first_crank_ = crank;
    map_crank_.push_back(crank);
    map_force_.emplace_back(p.pin_force.size(), NAN);
    map_stress_.emplace_back(p.contact_stress.size(), NAN);
  }
  map_crank_.back() = 0.5 * (map_first_crank_ + crank);
  if (p.succeeded()) {
    const auto keep_largest = [](std::vector<double>& column, const std::vector<double>& v) {
      if (column.size() < v.size()) column.resize(v.size(), NAN);
      for (std::size_t j = 0; j < v.size(); ++j) column[j] = std::fmax(column[j], v[j]);  // fmax: NaN is absent
    };
    keep_largest(map_force_.back(), p.pin_force);
    keep_largest(map_stress_.back(), p.contact_stress);
  }
  if (!p.succeeded()) return;
  const double f = MaxOf(p.pin_force);
  if (f > f_peak_) f_peak_ = f, peak_ = p;
}

plots::Figure Figure(const Deck& deck, const SolverOptions& solver, SolveSeries& data, const analysis::SweepSummary& summary) {
  const double mean_te_arcsec = RadToArcsec(summary.mean_te);
  plots::Figure figure;
  const double c_lo = std::isfinite(data.first_crank_) ? data.first_crank_ : 0.0;
  const double c_hi = std::isfinite(data.last_crank_) ? data.last_crank_ : 0.0;
  figure.title = fmt::format("{}: loaded TE over crank {:.4g} to {:.4g} deg, {} solver", CaseTitle(deck), c_lo, c_hi, solver.name);
  figure.caption = FigureCaption(deck, fmt::format("model {}, solver {} ({} kinematics), T = {:g} N*m, {} positions",
                                                   deck.Model().name, solver.name, contact::ToString(deck.kinematics),
                                                   units::NmmToNm(deck.RequireLoad().torque), data.positions_) +
                   (data.te_.stride() > 1 ? fmt::format("; TE drawn as the least and largest of every {} positions", data.te_.stride())
                                       : std::string()));
  figure.columns = 3;
  figure.width = 1500;
  figure.height = 520;
  // The mean marked is the summary's (a closed period's repeated state weighs once in it).
  figure.panels.push_back(TePanel(data.te_.x(), data.te_.y(), solver.name, mean_te_arcsec));
  if (data.te_.stride() > 1) {  // decimated: the envelope as a line (markers would fill it), said in the title
    figure.panels.back().series.front().style = plots::Style::kLine;
    figure.panels.back().title = fmt::format("loaded TE, least and largest of every {} positions", data.te_.stride());
  }
  if (data.peak_) {
    const auto& p = *data.peak_;
    const double crank = RadToDeg(p.crank);
    // Two discs: both cranks, the second disc's half a turn on.
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
  // are numbered 1 .. z_p for each disc, with a map per disc (disc 2's were z_p + 1 ..).
  std::size_t pins = 0;
  for (const auto& f : data.map_force_) pins = std::max(pins, f.size());
  if (data.peak_ && pins > 0) {
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
      // The crank axis is the first disc's: the second disc's crank is 180 deg on.
      panel.x_label = disc == 1 ? "crank angle (deg); disc 2 at +180 deg" : "crank angle (deg)";
      panel.y_label = "pin number";
      std::vector<std::vector<double>> columns;
      for (const auto& column : z) {
        std::vector<double> part(per_disc, NAN);
        for (std::size_t j = 0; j < per_disc && disc * per_disc + j < column.size(); ++j) part[j] = column[disc * per_disc + j];
        columns.push_back(std::move(part));
      }
      panel.map = plots::Map{data.map_crank_, pin_numbers, std::move(columns), label};
      const double half = data.map_crank_.size() > 1 ? (data.map_crank_[1] - data.map_crank_[0]) / 2 : 0.5;
      panel.x_min = data.map_crank_.front() - half, panel.x_max = data.map_crank_.back() + half;
      panel.y_min = 0.5, panel.y_max = static_cast<double>(per_disc) + 0.5;
      return panel;
    };
    const std::string every = data.stride_ > 1 ? fmt::format(" (max of every {} positions)", data.stride_) : "";
    for (std::size_t d = 0; d < discs; ++d) figure.panels.push_back(map_panel(data.map_force_, d, "pin force (N)", "pin force map" + every));
    for (std::size_t d = 0; d < discs; ++d) {
      figure.panels.push_back(map_panel(data.map_stress_, d, "contact stress (MPa)", "contact stress map" + every));
    }
    figure.height = discs == 2 ? 1480 : 1000;
  }
  // The contact pattern across the face width (the slice model): pin x slice forces at
  // the position of the largest pin force.
  if (data.peak_ && data.peak_->slices > 1 &&
      data.peak_->result.force.size() == data.peak_->pin_force.size() * static_cast<std::size_t>(data.peak_->slices)) {
    const auto& p = *data.peak_;
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
  return figure;
}

}  // namespace ltca::app::documents
