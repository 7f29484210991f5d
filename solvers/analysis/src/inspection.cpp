#include "ltca/analysis/inspection.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace ltca::analysis {

void InspectionSettings::Validate() const {
  if (roller_diameter && (!std::isfinite(*roller_diameter) || *roller_diameter <= 0.0)) {
    throw std::invalid_argument(fmt::format(
        "[inspection] roller_diameter_mm = {}: expected a positive roller diameter in mm", *roller_diameter));
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

}  // namespace ltca::analysis
