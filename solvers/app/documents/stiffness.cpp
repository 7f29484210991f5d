#include "documents/stiffness.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "documents/solve.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::app::documents {
namespace {

using units::NmmToNm;
using units::RadToArcmin;
using units::RadToDeg;

/// N*mm*rad (the loop's work per cycle) to J.
double NmmRadToJ(double nmm_rad) { return NmmToNm(nmm_rad); }
double Arcmin(double rad) { return RadToArcmin(rad); }

/// What the figures cover (docs/stiffness.md).
constexpr const char* kScope =
    "mesh only: the rigidity, lost motion and backlash of the cycloid-pin ring mesh alone; bearings, crankshafts and "
    "the output mechanism are not modelled";
/// The same for a deck with [output] (docs/stage.md).
constexpr const char* kStageScope =
    "the stage: the mesh, the output mechanism, the bearings and the shafts in one balance (docs/stage.md), the input "
    "locked at the crank angle; housing, carrier and output flange rigid";

std::string PositionStatus(const analysis::StiffnessPosition& p) {
  return ToString(p.succeeded() ? analysis::RunStatus::kSuccess : analysis::RunStatus::kFailed);
}

nlohmann::json CurveJson(const std::vector<analysis::CurvePoint>& curve, const std::vector<double>* lo = nullptr,
                         const std::vector<double>* hi = nullptr) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t i = 0; i < curve.size(); ++i) {
    nlohmann::json p = {{"torque_nm", NmmToNm(curve[i].torque)},
                        {"twist_arcmin", FiniteOrNull(RadToArcmin(curve[i].twist))},
                        {"branch", analysis::ToString(curve[i].branch)}};
    if (curve[i].stick_end) p["stick_end"] = true;  // friction: where the stick after the reversal ends
    if (lo != nullptr && hi != nullptr) {
      p["twist_arcmin_min"] = FiniteOrNull(RadToArcmin((*lo)[i]));
      p["twist_arcmin_max"] = FiniteOrNull(RadToArcmin((*hi)[i]));
    }
    out.push_back(std::move(p));
  }
  return out;
}

/// The figure (as a JSON key with its unit) over the positions: the mean, and for a sweep its
/// smallest and largest as key_min / key_max.
void AddSpread(nlohmann::json& j, const std::string& key, const std::string& unit, const analysis::Spread& s, bool sweep,
               double (*convert)(double)) {
  j[key + "_" + unit] = FiniteOrNull(convert(s.mean));
  if (!sweep) return;
  j[key + "_" + unit + "_min"] = FiniteOrNull(convert(s.min));
  j[key + "_" + unit + "_max"] = FiniteOrNull(convert(s.max));
}

/// "crank a to b deg" over a sweep, "crank a deg" at one crank.
std::string When(const Deck& deck, const analysis::StiffnessSettings& settings) {
  return settings.crank ? fmt::format("crank {:g} deg", RadToDeg(*settings.crank))
                        : fmt::format("crank {:g} to {:g} deg", RadToDeg(deck.sweep.crank_start), RadToDeg(deck.sweep.crank_end));
}

}  // namespace

double RigidityNmPerArcmin(double nmm_per_rad) { return units::NmmPerRadToNmPerArcmin(nmm_per_rad); }

std::string StiffnessScope(const Deck& deck) {
  std::string scope = deck.reducer ? kStageScope : kScope;
  if (deck.reducer && std::isfinite(deck.reducer->carrier_stiffness)) {  // issue 49: the carrier in series
    scope = fmt::format("the stage: the mesh, the output mechanism, the bearings and the shafts in one balance "
                        "(docs/stage.md), the input locked at the crank angle; carrier, output flange and housing one torsional "
                        "spring of {:g} N*m/arcmin in series",
                        units::NmmPerRadToNmPerArcmin(deck.reducer->carrier_stiffness));
  }
  if (deck.contact.seat.seated()) {
    scope += fmt::format("; the pins' seats in their housing grooves ([pins] seat = \"{}\") in series with the mesh",
                         contact::ToString(deck.contact.seat.kind));
  }
  return scope;
}

std::string RigidityDefinition(const analysis::StiffnessSettings& s) {
  if (s.rigidity == analysis::StiffnessSettings::Rigidity::kSecant) {
    return "secant between 50 % and 100 % of T on each flank; both flanks: T / (a_drive + a_coast)";
  }
  return fmt::format("tangent at {:g} N*m (central difference over +-1 % of it)", NmmToNm(s.tangent_torque));
}

nlohmann::json StiffnessHead(const Deck& deck, const SolverOptions& solver, const analysis::StiffnessSettings& settings,
                             double rated) {
  nlohmann::json stiffness = {{"scope", StiffnessScope(deck)},
                              {"rated_torque_nm", NmmToNm(rated)},
                              {"steps_per_branch", settings.steps},
                              {"rigidity_definition", RigidityDefinition(settings)},
                              {"lost_motion_fraction", settings.lost_motion_fraction}};
  if (settings.rigidity == analysis::StiffnessSettings::Rigidity::kTangent) {
    stiffness["tangent_torque_nm"] = NmmToNm(settings.tangent_torque);
  }
  if (!settings.crank) {
    stiffness["sweep"] = {{"crank_start_deg", RadToDeg(deck.sweep.crank_start)},
                          {"crank_end_deg", RadToDeg(deck.sweep.crank_end)},
                          {"positions", deck.sweep.positions}};
  } else {
    stiffness["crank_deg"] = RadToDeg(*settings.crank);
  }
  return {{"case", CaseJson(deck)}, {"model", ModelJson(deck.Model())}, {"solver", SolverJson(deck, solver)}, {"stiffness", stiffness}};
}

nlohmann::json Json(const analysis::StiffnessPosition& p) {
  nlohmann::json j = {{"crank_deg", RadToDeg(p.crank)},
                      {"torsional_rigidity_nm_per_arcmin", FiniteOrNull(RigidityNmPerArcmin(p.rigidity))},
                      {"torsional_rigidity_drive_nm_per_arcmin", FiniteOrNull(RigidityNmPerArcmin(p.rigidity_drive))},
                      {"torsional_rigidity_coast_nm_per_arcmin", FiniteOrNull(RigidityNmPerArcmin(p.rigidity_coast))},
                      {"lost_motion_arcmin", FiniteOrNull(RadToArcmin(p.lost_motion))},
                      {"backlash_arcmin", FiniteOrNull(RadToArcmin(p.backlash))},
                      {"branch_difference_arcmin", FiniteOrNull(RadToArcmin(p.branch_difference))},
                      {"hysteresis_j", FiniteOrNull(NmmRadToJ(p.hysteresis))},
                      {"status", PositionStatus(p)},
                      {"solves", p.solves},
                      {"failed_solves", p.failed},
                      {"curve", CurveJson(p.curve)}};
  if (!p.succeeded()) j["message"] = p.first_failure;
  if (std::isfinite(p.stick_end_drive) || std::isfinite(p.stick_end_coast)) {  // friction: where each stick ends
    j["stick_end_drive_nm"] = FiniteOrNull(NmmToNm(p.stick_end_drive));
    j["stick_end_coast_nm"] = FiniteOrNull(NmmToNm(p.stick_end_coast));
  }
  if (std::isfinite(p.first_disc_share_drive) || std::isfinite(p.first_disc_share_coast)) {  // two discs: T_1 / T
    j["first_disc_share_drive"] = FiniteOrNull(p.first_disc_share_drive);
    j["first_disc_share_coast"] = FiniteOrNull(p.first_disc_share_coast);
  }
  if (!p.compliance_share.empty()) {  // a reducer stage: the compliance budget at +T
    nlohmann::json budget = nlohmann::json::object();
    for (std::size_t g = 0; g < p.compliance_share.size(); ++g) {
      budget[solvers::ToString(static_cast<solvers::StageGroup>(g))] = FiniteOrNull(p.compliance_share[g]);
    }
    j["compliance_share"] = budget;
  }
  return j;
}

Table Columns(const std::vector<analysis::StiffnessPosition>& positions) {
  const auto any = [&](double analysis::StiffnessPosition::*a, double analysis::StiffnessPosition::*b) {
    return std::any_of(positions.begin(), positions.end(),
                       [&](const analysis::StiffnessPosition& p) { return std::isfinite(p.*a) || std::isfinite(p.*b); });
  };
  const bool stick = any(&analysis::StiffnessPosition::stick_end_drive, &analysis::StiffnessPosition::stick_end_coast);
  const bool share = any(&analysis::StiffnessPosition::first_disc_share_drive, &analysis::StiffnessPosition::first_disc_share_coast);
  Table t;
  for (const analysis::StiffnessPosition& p : positions) {
    t.Add("crank_deg", RadToDeg(p.crank));
    t.Add("torsional_rigidity_nm_per_arcmin", RigidityNmPerArcmin(p.rigidity));
    t.Add("torsional_rigidity_drive_nm_per_arcmin", RigidityNmPerArcmin(p.rigidity_drive));
    t.Add("torsional_rigidity_coast_nm_per_arcmin", RigidityNmPerArcmin(p.rigidity_coast));
    t.Add("lost_motion_arcmin", RadToArcmin(p.lost_motion));
    t.Add("backlash_arcmin", RadToArcmin(p.backlash));
    t.Add("branch_difference_arcmin", RadToArcmin(p.branch_difference));
    t.Add("hysteresis_j", NmmRadToJ(p.hysteresis));
    t.Add("solves", static_cast<double>(p.solves));
    t.Add("failed_solves", static_cast<double>(p.failed));
    if (stick) {
      t.Add("stick_end_drive_nm", NmmToNm(p.stick_end_drive));
      t.Add("stick_end_coast_nm", NmmToNm(p.stick_end_coast));
    }
    if (share) {
      t.Add("first_disc_share_drive", p.first_disc_share_drive);
      t.Add("first_disc_share_coast", p.first_disc_share_coast);
    }
  }
  return t;
}

Table Columns(const std::vector<analysis::CurvePoint>& curve, const std::vector<double>* lo, const std::vector<double>* hi) {
  Table t;
  for (std::size_t i = 0; i < curve.size(); ++i) {
    t.Add("torque_nm", NmmToNm(curve[i].torque));
    t.Add("twist_arcmin", RadToArcmin(curve[i].twist));
    if (lo != nullptr && hi != nullptr) {
      t.Add("twist_arcmin_min", RadToArcmin((*lo)[i]));
      t.Add("twist_arcmin_max", RadToArcmin((*hi)[i]));
    }
  }
  return t;
}

Table SummaryCurveColumns(const analysis::StiffnessResult& result) {
  const analysis::StiffnessSummary& s = result.summary;
  return result.sweep() ? Columns(s.curve, &s.curve_min, &s.curve_max) : Columns(s.curve);
}

nlohmann::json Json(const analysis::StiffnessResult& result) {
  const analysis::StiffnessSummary& s = result.summary;
  const bool sweep = result.sweep();
  const double friction_mu = result.friction_coefficient;
  nlohmann::json j = nlohmann::json::object();
  AddSpread(j, "torsional_rigidity", "nm_per_arcmin", s.rigidity, sweep, RigidityNmPerArcmin);
  AddSpread(j, "torsional_rigidity_drive", "nm_per_arcmin", s.rigidity_drive, sweep, RigidityNmPerArcmin);
  AddSpread(j, "torsional_rigidity_coast", "nm_per_arcmin", s.rigidity_coast, sweep, RigidityNmPerArcmin);
  AddSpread(j, "lost_motion", "arcmin", s.lost_motion, sweep, Arcmin);
  AddSpread(j, "backlash", "arcmin", s.backlash, sweep, Arcmin);
  if (s.first_disc_share_drive.count + s.first_disc_share_coast.count > 0) {  // two discs: T_1 / T at +-T
    const auto share = [](double v) { return v; };
    AddSpread(j, "first_disc_share", "drive", s.first_disc_share_drive, sweep, share);
    AddSpread(j, "first_disc_share", "coast", s.first_disc_share_coast, sweep, share);
  }
  if (!s.compliance_share.empty()) {  // a reducer stage: each group's share of the strain energy at +T
    nlohmann::json budget = nlohmann::json::object();
    for (std::size_t g = 0; g < s.compliance_share.size(); ++g) {
      budget[solvers::ToString(static_cast<solvers::StageGroup>(g))] = FiniteOrNull(s.compliance_share[g].mean);
    }
    j["compliance_share"] = budget;
  }
  if (sweep) j["closed_period"] = s.closed_period;  // the means weigh a repeated last state once
  j["hysteresis"] = result.with_friction();  // friction separates the branches
  AddSpread(j, "hysteresis", "j", s.hysteresis, sweep, [](double v) { return NmmRadToJ(v); });
  j["branch_difference_arcmin"] = FiniteOrNull(RadToArcmin(s.branch_difference.max));
  if (result.with_friction()) {
    j["friction_coefficient"] = friction_mu;
    if (result.bearing_friction_coefficient > 0.0) j["bearing_friction_coefficient"] = result.bearing_friction_coefficient;
    AddSpread(j, "stick_end_drive", "nm", s.stick_end_drive, sweep, [](double v) { return NmmToNm(v); });
    AddSpread(j, "stick_end_coast", "nm", s.stick_end_coast, sweep, [](double v) { return NmmToNm(v); });
    const std::string balance =
        s.compliance_share.empty()
            ? "Coulomb friction in the torque balance ([friction]): moving up the normal forces carry T - mu sum F a_t, "
              "moving down T + mu sum F a_t."
            : "Coulomb friction on each disc of the stage ([friction]), apart from the output torque: the mesh's "
              "friction forces (mu F at each loaded pin, against the disc's turning) and each bearing's friction moment "
              "mu_b |F| d / 2 (bearing_friction_coefficient) against its relative rotation; the output pins turn with "
              "their disc and the pins sit in their seats (no friction there in the loop).";
    j["note"] = balance + " After each reversal (+T, -T) the twist holds (stick) until the torque "
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
  AddRunRecord(j, s);
  j["solves"] = s.solves;
  return j;
}

nlohmann::json Json(const Deck& deck, const SolverOptions& solver, const analysis::StiffnessResult& result) {
  nlohmann::json doc = StiffnessHead(deck, solver, result.settings, result.rated_torque);
  nlohmann::json list = nlohmann::json::array();
  for (const analysis::StiffnessPosition& p : result.positions) list.push_back(Json(p));
  doc["positions"] = std::move(list);
  doc["summary"] = Json(result);
  return doc;
}

StiffnessJsonWriter::StiffnessJsonWriter(std::ostream& os, const Deck& deck, const SolverOptions& solver,
                                         const analysis::StiffnessSettings& settings, double rated)
    : os_(os) {
  os_ << OpenObject(StiffnessHead(deck, solver, settings, rated)) << ",\n  \"positions\": [";
}

void StiffnessJsonWriter::Add(const analysis::StiffnessPosition& p) {
  os_ << (written_++ == 0 ? "\n    " : ",\n    ") << Dump(Json(p), -1);
}

void StiffnessJsonWriter::Finish(const analysis::StiffnessResult& result) {
  os_ << "\n  ],\n  \"summary\": " << Nested(Dump(Json(result))) << "\n}\n";
}

std::string StiffnessTextHead(const Deck& deck, const SolverOptions& solver, const analysis::StiffnessSettings& settings,
                              double rated, std::size_t positions) {
  std::string text = CaseLines(deck) + ModelLine(deck) + SolverLine(deck, solver);
  text += fmt::format("loop      -T -> +T -> -T, T = {:g} N*m (rated, |[load] torque_nm|), {} torque levels per branch, {}\n",
                      NmmToNm(rated), settings.steps,
                      !settings.crank ? fmt::format("{} positions from {:g} to {:g} deg crank", positions,
                                                    RadToDeg(deck.sweep.crank_start), RadToDeg(deck.sweep.crank_end))
                                      : fmt::format("crank {:g} deg", RadToDeg(*settings.crank)));
  text += fmt::format("rigidity  {}\n", RigidityDefinition(settings));
  text += fmt::format("scope     {}\n", StiffnessScope(deck));
  text += fmt::format("{:>10} {:>18} {:>18} {:>16} {:>8}\n", "crank_deg", "rigidity_nm/amin", "lost_motion_amin", "backlash_amin",
                      "status");
  return text;
}

std::string Text(const analysis::StiffnessPosition& p) {
  return fmt::format("{:>10.4f} {:>18} {:>18} {:>16} {:>8}\n", RadToDeg(p.crank), FormatOrNa(RigidityNmPerArcmin(p.rigidity), 4),
                     FormatOrNa(RadToArcmin(p.lost_motion), 5), FormatOrNa(RadToArcmin(p.backlash), 5), PositionStatus(p));
}

std::string Text(const analysis::StiffnessResult& result) {
  const analysis::StiffnessSummary& s = result.summary;
  const analysis::StiffnessSettings& settings = result.settings;
  const bool sweep = result.sweep();
  const auto range = [sweep](const analysis::Spread& v, double (*convert)(double), int decimals, const char* unit) {
    std::string r = fmt::format("{} {}", FormatOrNa(convert(v.mean), decimals), unit);
    if (sweep && v.count > 0) r += fmt::format(" (mean; {} .. {} over the positions)", FormatOrNa(convert(v.min), decimals), FormatOrNa(convert(v.max), decimals));
    return r;
  };
  std::string text;
  if (s.failed > 0) text += fmt::format("failed positions       {} of {}; first: {}\n", s.failed, s.positions(), s.first_failure);
  text += fmt::format("torsional rigidity     {}\n", range(s.rigidity, RigidityNmPerArcmin, 4, "N*m/arcmin"));
  if (settings.rigidity == analysis::StiffnessSettings::Rigidity::kSecant) {
    text += fmt::format("  drive / coast flank  {} / {} N*m/arcmin\n", FormatOrNa(RigidityNmPerArcmin(s.rigidity_drive.mean), 4),
                        FormatOrNa(RigidityNmPerArcmin(s.rigidity_coast.mean), 4));
  }
  text += fmt::format("lost motion            {}, at +-{:g} % of T\n", range(s.lost_motion, Arcmin, 5, "arcmin"),
                      100.0 * settings.lost_motion_fraction);
  text += fmt::format("backlash               {}, at zero torque\n", range(s.backlash, Arcmin, 5, "arcmin"));
  if (s.first_disc_share_drive.count + s.first_disc_share_coast.count > 0) {  // two discs: T_1 / T at +-T
    const auto share = [](double v) { return v; };
    text += fmt::format("first disc's share     {} at +T (disc 2: the rest)\n", range(s.first_disc_share_drive, share, 4, "of T"));
    text += fmt::format("                       {} at -T\n", range(s.first_disc_share_coast, share, 4, "of T"));
  }
  if (!s.compliance_share.empty()) {  // a reducer stage: each group's share of the strain energy at +T, %
    std::string parts;
    for (std::size_t g = 0; g < s.compliance_share.size(); ++g) {
      parts += fmt::format("{}{} {} %", parts.empty() ? "" : ", ", solvers::ToString(static_cast<solvers::StageGroup>(g)),
                           FormatOrNa(100.0 * s.compliance_share[g].mean, 1));
    }
    text += fmt::format("compliance budget      {} of the strain energy at +T (mean over the positions)\n", parts);
  }
  const auto joules = [](double v) { return NmmRadToJ(v); };
  if (result.with_friction()) {  // the loop's area, the work friction dissipates per cycle
    text += fmt::format("hysteresis             {} per cycle (the loop's area), friction mu = {:g}{}\n",
                        range(s.hysteresis, joules, 6, "J"), result.friction_coefficient,
                        result.bearing_friction_coefficient > 0.0
                            ? fmt::format(", bearings mu = {:g}", result.bearing_friction_coefficient)
                            : std::string());
    text += fmt::format("  stick after reversal the twist holds from +T down to {} and from -T up to {}; the branches "
                        "differ by up to {} arcmin\n",
                        range(s.stick_end_drive, NmmToNm, 5, "N*m"), range(s.stick_end_coast, NmmToNm, 5, "N*m"),
                        FormatOrNa(RadToArcmin(s.branch_difference.max), 6));
  } else {
    const double work = NmmRadToJ(s.hysteresis.mean);
    text += fmt::format("hysteresis             {} J per cycle: none, no friction (zero up to the solver's tolerance); the "
                        "branches coincide (largest difference {} arcmin)\n",
                        std::isfinite(work) ? fmt::format("{:.3g}", work) : std::string("n/a"),
                        FormatOrNa(RadToArcmin(s.branch_difference.max), 12));
  }
  text += fmt::format("wall time              {:.4f} s for {} solves\n", s.wall_seconds, s.solves);
  return text;
}

std::string StiffnessCsvHead() { return "crank_deg,branch,torque_nm,twist_arcmin,status\n"; }

std::string Csv(const analysis::StiffnessPosition& p) {
  std::string csv;
  for (const auto& c : p.curve) {
    csv += fmt::format("{:.9g},{},{:.9g},{},{}\n", RadToDeg(p.crank), analysis::ToString(c.branch), NmmToNm(c.torque),
                       std::isfinite(c.twist) ? fmt::format("{:.12g}", RadToArcmin(c.twist)) : std::string(),
                       solvers::ToString(c.status));
  }
  return csv;
}

plots::Figure Figure(const Deck& deck, const SolverOptions& solver, const analysis::StiffnessResult& result) {
  const analysis::StiffnessSummary& s = result.summary;
  const bool sweep = result.sweep();
  const std::size_t positions = result.cranks.size();
  plots::Panel panel;
  panel.title = sweep ? "mean over the positions; dashed: their smallest and largest twist" : "";
  panel.x_label = "twist (arcmin, output rotation in the sense of +T)";
  panel.y_label = "torque (N*m)";
  // Outside the axes (inside, the legend covers the loop's upper part); short labels, their
  // definitions in the caption.
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
      if (p.torque == 0.0 && p.branch == analysis::Branch::kIncreasing && std::isfinite(p.twist)) zero.push_back(RadToArcmin(p.twist));
    }
    if (zero.size() == 2) {
      plots::Series b{fmt::format("backlash {:.4g} arcmin", RadToArcmin(s.backlash.mean)), zero, {0.0, 0.0},
                      plots::Style::kLineMarkers};
      b.colour = 2;
      panel.series.push_back(std::move(b));
    }
    const auto& r = s.readoffs;
    const auto segment = [&](const std::string& label, const analysis::CurvePoint& a, const analysis::CurvePoint& c, int colour) {
      plots::Series seg{label, {RadToArcmin(a.twist), RadToArcmin(c.twist)}, {NmmToNm(a.torque), NmmToNm(c.torque)},
                        plots::Style::kLineMarkers};
      seg.colour = colour;
      seg.dashed = true;
      if (std::isfinite(a.twist) && std::isfinite(c.twist)) panel.series.push_back(std::move(seg));
    };
    if (r.size() == 6) {  // secant: +T, +T/2, -T/2, -T, then lost motion
      segment(fmt::format("rigidity {:.4g} N*m/arcmin", RigidityNmPerArcmin(s.rigidity.mean)), r[1], r[0], 1);
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
  const double t = NmmToNm(result.rated_torque);
  panel.y_min = -1.15 * t, panel.y_max = 1.15 * t;
  plots::Figure figure;
  const double mu = result.friction_coefficient;
  const std::string hysteresis =  // with friction: the loop's area, J per cycle
      result.with_friction() && std::isfinite(s.hysteresis.mean)
          ? fmt::format(", hysteresis {:.4g} J per cycle (mu {:g}{})", NmmRadToJ(s.hysteresis.mean), mu,
                        result.bearing_friction_coefficient > 0.0
                            ? fmt::format(", bearings {:g}", result.bearing_friction_coefficient)
                            : std::string())
          : std::string();
  figure.title = fmt::format("{}: torque-twist loop -T..+T..-T, T = {:g} N*m, {}{}{}", CaseTitle(deck), t,
                             When(deck, result.settings), hysteresis, any ? "" : ": no solve succeeded");
  // The caption names the definition and fraction the loop was read with (the deck's, or the
  // command line's --rigidity, --tangent-torque-nm and --lost-motion-fraction where given).
  const analysis::StiffnessSettings& read = result.settings;
  const std::string rigidity = read.rigidity == analysis::StiffnessSettings::Rigidity::kSecant
                                   ? "the secant from 50 % to 100 % of T on each flank"
                                   : fmt::format("the tangent at {:g} N*m", NmmToNm(read.tangent_torque));
  figure.caption = FigureCaption(
      deck, fmt::format("backlash: the loop's width at zero torque; rigidity: {}; lost motion: the width at +-{:g} % of T\n"
                        "model {}, solver {} ({} kinematics); {} crank position{}",
                        rigidity, 100.0 * read.lost_motion_fraction, deck.Model().name, solver.name,
                        contact::ToString(deck.kinematics), positions, positions == 1 ? "" : "s"));
  figure.width = 1300;
  figure.height = 640;
  figure.panels.push_back(std::move(panel));
  return figure;
}

}  // namespace ltca::app::documents
