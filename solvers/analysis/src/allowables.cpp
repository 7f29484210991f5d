#include "ltca/analysis/allowables.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/contact_fatigue.hpp"
#include "ltca/analysis/efficiency.hpp"
#include "ltca/analysis/spectrum.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/analysis/tolerance_run.hpp"
#include "ltca/contact/bearing.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::analysis {

bool AllowableRange::Given() const { return std::isfinite(min) || std::isfinite(max); }

bool AllowableRange::Holds(double value) const { return std::isfinite(value) && value >= min && value <= max; }

double AllowableRange::Margin(double value) const {
  if (!std::isfinite(value) || !Given()) return std::numeric_limits<double>::quiet_NaN();
  double m = std::numeric_limits<double>::infinity();
  if (std::isfinite(max)) m = std::min(m, max - value);
  if (std::isfinite(min)) m = std::min(m, value - min);
  return m;
}

const char* ToString(AllowableVerdict verdict) {
  switch (verdict) {
    case AllowableVerdict::kPass: return "pass";
    case AllowableVerdict::kFail: return "FAIL";
    case AllowableVerdict::kNoAllowable: return "no allowable";
    case AllowableVerdict::kNotComputed: return "n/a";
  }
  return "n/a";
}

AllowableRow Judge(std::string figure, double value, std::string basis, AllowableRange range, std::optional<double> pass_fraction) {
  AllowableRow row;
  row.figure = std::move(figure);
  row.value = value;
  row.basis = std::move(basis);
  row.range = range;
  row.pass_fraction = pass_fraction;
  row.margin = range.Margin(value);
  row.verdict = !std::isfinite(value) ? AllowableVerdict::kNotComputed
                : !range.Given()      ? AllowableVerdict::kNoAllowable
                : range.Holds(value)  ? AllowableVerdict::kPass
                                      : AllowableVerdict::kFail;
  return row;
}

namespace {

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

/// NaN where not finite (as the documents give null).
double FiniteOrNaN(double v) { return std::isfinite(v) ? v : kNoValue; }

/// The loaded sweep's figure of that name (LoadedFigures), a reducer stage's ("stage") or the
/// mesh's; none when the sweep does not report it. NaN where it is not finite.
std::optional<std::pair<double, bool>> LoadedFigure(const NominalResults& r, const std::string& figure) {
  const auto& names = ToleranceSettings::FigureNames();
  const auto f = static_cast<std::size_t>(std::find(names.begin(), names.end(), figure) - names.begin());
  const bool stage = f == kMaxOutputPinForceN || f == kMaxBearingLoadN || f == kShortestL10Hours;
  const bool sweep = f == kMeanTeArcsec || f == kPpTeArcsec || f == kMaxContactStressMpa || f == kMaxPinForceN ||
                     f == kContactsMin || f == kContactsMax;
  if (r.solve == nullptr || (!sweep && !(stage && r.reducer && r.solve->reducer))) return std::nullopt;
  if (f == kShortestL10Hours) return std::pair{r.solve->bearing_life.value_or(BearingLife{}).ShortestHours(), true};
  ToleranceFigures figures;
  figures.fill(kNoValue);
  LoadedFigures(*r.solve, r.output_pins, figures);
  return std::pair{FiniteOrNaN(figures[f]), stage};
}

}  // namespace

std::pair<double, std::string> NominalFigure(const NominalResults& r, const std::string& figure) {
  if (r.tolerance != nullptr && r.study != nullptr && r.tolerance->worst_case) {
    const auto& names = ToleranceSettings::FigureNames();
    for (std::size_t f = 0; f < names.size(); ++f) {
      if (names[f] != figure || !r.study->Runs(f)) continue;
      const double v = r.tolerance->worst_case->figures[f].nominal;
      if (std::isfinite(v)) return {v, "ltca tolerance, the nominal deck"};
    }
  }
  if (r.reducer) {
    if (figure == "mean_backlash_arcsec") {
      const double v = r.stiffness != nullptr ? 60.0 * FiniteOrNaN(units::RadToArcmin(r.stiffness->summary.backlash.mean)) : kNoValue;
      return {v, std::isfinite(v) ? "ltca stiffness, crank 0: the stage's free play" : "not computed"};
    }
    if (figure == "pp_backlash_arcsec") return {kNoValue, "not computed: the stage's free play over the sweep is the tolerance study's"};
    if (const auto v = LoadedFigure(r, figure); v && v->second) return {v->first, "ltca solve, the stage"};
  }
  if (r.backlash != nullptr) {
    if (figure == "mean_backlash_arcsec") return {units::RadToArcsec(r.backlash->summary.mean()), "ltca backlash"};
    if (figure == "pp_backlash_arcsec") return {units::RadToArcsec(r.backlash->summary.pp()), "ltca backlash"};
  }
  if (const auto v = LoadedFigure(r, figure); v && !v->second) return {v->first, "ltca solve"};
  if (r.stiffness != nullptr && figure == "lost_motion_arcmin") {  // the one tolerance figure the loop gives
    return {FiniteOrNaN(units::RadToArcmin(r.stiffness->summary.lost_motion.mean)), "ltca stiffness, crank 0"};
  }
  return {kNoValue, "not computed"};
}

std::vector<AllowableRow> CheckAllowables(const NominalResults& r, const Allowables& a) {
  std::vector<AllowableRow> rows;
  if (r.solve != nullptr) {
    rows.push_back(Judge("max_contact_stress_mpa", FiniteOrNaN(r.solve->max_contact_stress), "ltca solve, the sweep",
                         AllowableRange{-std::numeric_limits<double>::infinity(), a.contact_stress_limit}));
    rows.back().name = "largest contact stress (MPa)";
  }
  std::vector<std::string> limited;
  for (const ToleranceLimit& limit : a.limits) {
    limited.push_back(limit.figure);
    auto [value, basis] = NominalFigure(r, limit.figure);
    std::optional<double> fraction;  // the Monte Carlo's pass fraction of this limit
    if (r.tolerance != nullptr) {
      for (const LimitResult& x : r.tolerance->summary.limits) {
        if (x.limit.figure == limit.figure) fraction = x.fraction;
      }
    }
    rows.push_back(Judge(limit.figure, value, std::move(basis), AllowableRange{limit.min, limit.max}, fraction));
  }
  // The figures a reviewer signs without a limit in the deck: listed with their values.
  const auto listed = [&](const std::string& key) { return std::find(limited.begin(), limited.end(), key) != limited.end(); };
  for (const std::string key : {"pp_te_arcsec", "mean_backlash_arcsec"}) {
    if (listed(key)) continue;
    auto [value, basis] = NominalFigure(r, key);
    rows.push_back(Judge(key, value, std::move(basis)));
  }
  if (r.stiffness != nullptr) {  // the loop's figures at crank 0 (arcmin, N*m/arcmin)
    const StiffnessSummary& s = r.stiffness->summary;
    const double rigidity = units::NmmPerRadToNmPerArcmin(s.rigidity.mean);
    for (const auto& [key, value] : {std::pair{std::string("lost_motion_arcmin"), units::RadToArcmin(s.lost_motion.mean)},
                                     std::pair{std::string("torsional_rigidity_nm_per_arcmin"), rigidity}}) {
      if (!listed(key)) rows.push_back(Judge(key, FiniteOrNaN(value), "ltca stiffness, crank 0"));
    }
  }
  if (r.efficiency != nullptr && !listed("efficiency")) {  // the sweep's efficiency (full model)
    rows.push_back(Judge("efficiency", FiniteOrNaN(r.efficiency->efficiency), "ltca efficiency"));
  }
  if (r.reducer && r.solve != nullptr && r.solve->reducer) {  // the stage's bearings
    const BearingLife life = r.solve->bearing_life.value_or(BearingLife{});
    for (AllowableRow& row : BearingRatingRows(life, a.targets)) {
      if (row.figure == "stage.shortest_l10_hours" && listed("shortest_l10_hours")) continue;  // a [tolerances] limit's row
      rows.push_back(std::move(row));
    }
  }
  if (r.solve != nullptr && r.solve->contact_fatigue) {  // the pins' and teeth's pitting
    for (AllowableRow& row : ContactFatigueRows(*r.solve->contact_fatigue, a.targets)) rows.push_back(std::move(row));
  }
  return rows;
}

void AllowablesSettings::Validate() const {
  for (const auto& [key, value] : {std::pair{"bearing_life_hours", bearing_life_hours}, std::pair{"min_static_safety", min_static_safety},
                                   std::pair{"contact_life_hours", contact_life_hours},
                                   std::pair{"min_contact_safety", min_contact_safety}}) {
    if (value && !(std::isfinite(*value) && *value > 0.0)) {
      throw std::invalid_argument(fmt::format("[allowables] {} = {}: expected a finite value > 0", key, *value));
    }
  }
}

std::vector<AllowableRow> BearingRatingRows(const BearingLife& life, const AllowablesSettings& targets) {
  const double inf = std::numeric_limits<double>::infinity();
  const AllowableRange hours{targets.bearing_life_hours.value_or(-inf), inf};
  std::vector<AllowableRow> rows;
  rows.push_back(Judge("stage.shortest_l10_hours", life.ShortestHours(), "ltca solve, ISO 281 (" + life.basis + ")", hours));
  rows.back().name = "shortest bearing L10 (h)";
  rows.push_back(Judge("stage.shortest_load_zone_life_hours", life.ShortestLoadZoneHours(),
                       "ltca solve, roller loads, Lundberg-Palmgren on ISO 281's C (" + life.basis + ")", hours));
  rows.back().name = "shortest bearing load-zone life (h)";
  if (life.modified) {  // ISO 281's modified lives, rated only with the oil's viscosity
    rows.push_back(Judge("stage.shortest_modified_life_hours", life.ShortestModifiedHours(),
                         "ltca solve, ISO 281:2007 a_ISO L10 (" + life.basis + ")", hours));
    rows.back().name = "shortest bearing modified life a_ISO L10 (h)";
    rows.push_back(Judge("stage.shortest_load_zone_modified_life_hours", life.ShortestLoadZoneModifiedHours(),
                         "ltca solve, ISO 281:2007 a_ISO on the load-zone life (" + life.basis + ")", hours));
    rows.back().name = "shortest bearing modified load-zone life (h)";
  }
  rows.push_back(Judge("stage.smallest_static_safety", life.SmallestStaticSafety(), "ltca solve, ISO 76: C_0 / P_0,max",
                       AllowableRange{targets.min_static_safety.value_or(-inf), inf}));
  rows.back().name = "smallest bearing static safety s_0";
  rows.push_back(Judge("stage.largest_roller_contact_stress_mpa", life.LargestRollerStress(),
                       "ltca solve, the largest roller on the inner raceway (Hertz)", AllowableRange{-inf, contact::kStaticStressLimitRoller}));
  rows.back().name = "largest roller contact stress (MPa), ISO 76's 4,000 MPa";
  return rows;
}

std::vector<AllowableRow> ContactFatigueRows(const ContactFatigue& fatigue, const AllowablesSettings& targets) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<AllowableRow> rows;
  const std::string basis = fmt::format("ltca solve, Miner on ISO 6336-2 Z_NT ({}), sigma_Hlim {:g} MPa ({})",
                                        contact::ToString(fatigue.curve), fatigue.fatigue_limit, fatigue.basis);
  const double life = fatigue.ShortestHours();
  rows.push_back(Judge("contact.shortest_life_hours", life, basis, AllowableRange{targets.contact_life_hours.value_or(-inf), inf}));
  if (life == inf) {  // no cycle above the curve's floor: a life without damage, above any required life
    rows.back().value = inf;
    rows.back().margin = inf;
    rows.back().verdict = rows.back().range.Given() ? AllowableVerdict::kPass : AllowableVerdict::kNoAllowable;
  }
  rows.back().name = "shortest pitting life of the pins and teeth (h)";
  rows.push_back(Judge("contact.smallest_safety", fatigue.SmallestSafety(), basis + ", at the required life",
                       AllowableRange{targets.min_contact_safety.value_or(-inf), inf}));
  rows.back().name = "smallest pitting safety S_H";
  return rows;
}

std::vector<AllowableRow> SpectrumRatingRows(const SpectrumResult& spectrum, const AllowablesSettings& targets,
                                             double contact_stress_limit, bool reducer) {
  const double inf = std::numeric_limits<double>::infinity();
  const AllowableRange hours{targets.bearing_life_hours.value_or(-inf), inf};
  const std::string miner = "ltca solve, the load spectrum: Palmgren-Miner over the bins' ";
  const auto worst = [](const char* what, int bin) {
    return bin >= 0 ? fmt::format("ltca solve, the load spectrum: {}, set by bin {}", what, bin + 1)
                    : fmt::format("ltca solve, the load spectrum: {}", what);
  };
  std::vector<AllowableRow> rows;
  const auto add = [&](AllowableRow row, const char* name) {
    row.name = name;
    rows.push_back(std::move(row));
  };
  if (reducer) {
    add(Judge("spectrum.shortest_l10_hours", spectrum.ShortestL10Hours(), miner + "ISO 281 L10", hours),
        "shortest bearing L10 over the spectrum (h)");
    add(Judge("spectrum.shortest_load_zone_life_hours", spectrum.ShortestLoadZoneHours(), miner + "load-zone lives", hours),
        "shortest bearing load-zone life over the spectrum (h)");
    if (spectrum.modified()) {
      add(Judge("spectrum.shortest_modified_life_hours", spectrum.ShortestModifiedHours(), miner + "ISO 281:2007 a_ISO L10", hours),
          "shortest bearing modified life a_ISO L10 over the spectrum (h)");
      add(Judge("spectrum.shortest_load_zone_modified_life_hours", spectrum.ShortestLoadZoneModifiedHours(),
                miner + "a_ISO times the load-zone lives", hours),
          "shortest bearing modified load-zone life over the spectrum (h)");
    }
    const auto [s0, s0_bin] = spectrum.SmallestStaticSafety();
    add(Judge("spectrum.smallest_static_safety", s0, worst("ISO 76 C_0 / P_0,max, P_0,max over every bin", s0_bin),
              AllowableRange{targets.min_static_safety.value_or(-inf), inf}),
        "smallest bearing static safety s_0 over the spectrum");
    const auto [roller, roller_bin] = spectrum.LargestRollerStress();
    add(Judge("spectrum.largest_roller_contact_stress_mpa", roller, worst("the largest roller on the inner raceway (Hertz)", roller_bin),
              AllowableRange{-inf, contact::kStaticStressLimitRoller}),
        "largest roller contact stress over the spectrum (MPa), ISO 76's 4,000 MPa");
  }
  add(Judge("spectrum.max_contact_stress_mpa", FiniteOrNaN(spectrum.max_contact_stress),
            worst("the largest pin-cycloid contact stress", spectrum.max_contact_stress_bin),
            AllowableRange{-inf, contact_stress_limit}),
      "largest contact stress over the spectrum (MPa)");
  if (!spectrum.contact_life_hours.empty()) {
    const double life = spectrum.ShortestContactHours();
    AllowableRow row = Judge("spectrum.shortest_pitting_life_hours", life, miner + "pitting lives of the pins and teeth",
                             AllowableRange{targets.contact_life_hours.value_or(-inf), inf});
    if (life == inf) {  // no damage in any bin: above any required life (as ContactFatigueRows)
      row.value = inf;
      row.margin = inf;
      row.verdict = row.range.Given() ? AllowableVerdict::kPass : AllowableVerdict::kNoAllowable;
    }
    add(std::move(row), "shortest pitting life of the pins and teeth over the spectrum (h)");
    if (!spectrum.contact_safety.empty()) {
      add(Judge("spectrum.smallest_pitting_safety", spectrum.SmallestContactSafety(),
                fmt::format("ltca solve, the load spectrum: the factor on every bin's stress that brings Miner's damage over "
                            "{:g} h to 1 (ISO 6336-2 Z_NT)",
                            spectrum.required_contact_hours),
                AllowableRange{targets.min_contact_safety.value_or(-inf), inf}),
          "smallest pitting safety S_H over the spectrum");
    }
  }
  return rows;
}

}  // namespace ltca::analysis
