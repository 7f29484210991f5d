#include "ltca/analysis/inspection.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/analysis/keys.hpp"

namespace ltca::analysis {

void InspectionSettings::Validate() const {
  if (roller_diameter && (!std::isfinite(*roller_diameter) || *roller_diameter <= 0.0)) {
    throw std::invalid_argument(fmt::format(
        "[inspection] roller_diameter_mm = {}: expected a positive roller diameter in mm", *roller_diameter));
  }
  if (profile_tolerance && (!std::isfinite(*profile_tolerance) || *profile_tolerance <= 0.0)) {
    throw std::invalid_argument(fmt::format(
        "[inspection] profile_tolerance_um = {}: expected a positive width of the profile tolerance band in um",
        *profile_tolerance * 1e3));
  }
}

InspectionResult Inspect(const geometry::CycloidProfile& profile, const InspectionSettings& settings) {
  settings.Validate();
  InspectionResult r;
  r.root_diameter = geometry::RootDiameter(profile);
  r.tip_diameter = geometry::TipDiameter(profile);
  if (settings.roller_diameter) r.rollers = geometry::MeasureOverRollers(profile, *settings.roller_diameter);
  return r;
}

RollerToleranceBand RollerTolerance(const StageDesign& design, const ToleranceSettings& tolerances, double roller_diameter) {
  // M of the design with the scalar disc keys moved by v (key units) from the deck's values.
  const auto measure = [&](const std::vector<std::pair<const DeckKey*, double>>& moves) {
    StageDesign d = design;
    const DiscParts parts{&d.modification, &d.errors, &d.assembly};
    for (const auto& [key, v] : moves) *key->real(parts) += key->ToInternal(v);
    return geometry::MeasureOverRollers(d.MakeRealPair().profile(), roller_diameter).dimension;
  };
  RollerToleranceBand band;
  band.nominal = measure({});
  std::vector<std::pair<const DeckKey*, double>> means;
  std::vector<const ToleranceDistribution*> keys;
  for (const ToleranceDistribution& t : tolerances.distributions) {
    // The keys of the disc's transverse profile; the others (the pin ring, the lead, the
    // assembly, the stage's holes) do not move the rollers.
    static const char* const kProfileKeys[] = {"modification_pin_radius_mm", "modification_pin_circle_radius_mm",
                                               "modification_rotation_deg", "cycloid_profile_layer_mm"};
    if (t.IsZero() || std::find(std::begin(kProfileKeys), std::end(kProfileKeys), t.key) == std::end(kProfileKeys)) continue;
    const DeckKey* key = FindToleranceKey(t.key);
    if (key == nullptr || key->real == nullptr) continue;
    means.emplace_back(key, t.mean);
    keys.push_back(&t);
  }
  band.centre = measure(means);
  double worst = 0.0, variance = 0.0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const ToleranceDistribution& t = *keys[i];
    const double w = t.WorstCaseHalfWidth();
    const double h = w > 0.0 ? 1e-3 * w : 1e-3 * std::abs(t.mean);
    std::vector<std::pair<const DeckKey*, double>> up = means, down = means;
    up[i].second += h, down[i].second -= h;
    const double s = (measure(up) - measure(down)) / (2.0 * h);
    band.terms.push_back({t.key, s, w, t.StandardDeviation(), t.mean});
    worst += std::abs(s) * w;
    variance += (s * w) * (s * w);
  }
  band.worst_low = band.centre - worst, band.worst_high = band.centre + worst;
  band.rss_low = band.centre - std::sqrt(variance), band.rss_high = band.centre + std::sqrt(variance);
  return band;
}

bool DeviationChart::WithinTolerance() const {
  if (!tolerance) return true;
  for (const double m : measured) {
    if (std::abs(m) > 0.5 * *tolerance) return false;
  }
  return true;
}

DeviationChart ChartProfileDeviation(const geometry::CycloidProfile& design, const geometry::MeasuredProfile& trace,
                                     const InspectionSettings& settings) {
  settings.Validate();
  DeviationChart chart;
  chart.source = trace.source;
  chart.tolerance = settings.profile_tolerance;
  // The trace's own points in u (arc-length abscissae converted along the profile, as the solve
  // applies them): the knots of the tabulated deviation, and its values there.
  const geometry::ProfileDeviation deviation = geometry::ProfileDeviation::Measured(trace, design);
  const double reach = 2.0 * design.phi_max();
  deviation.NodesIn(-reach, reach, &chart.u);
  for (const double u : chart.u) chart.measured.push_back(deviation.At(0, u));
  chart.fit = geometry::FitModification(design, chart.u, chart.measured);
  const geometry::Modification fitted = chart.fit.AsModification();
  for (const double u : chart.u) chart.fitted.push_back(geometry::ModificationDeviation(design, fitted, u));
  return chart;
}

}  // namespace ltca::analysis
