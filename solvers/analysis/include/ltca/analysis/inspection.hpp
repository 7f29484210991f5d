#pragma once
// The inspection figures of a deck's disc as made ([inspection], docs/export.md): root and tip
// diameters, and with a roller diameter the dimension over two rollers and where they touch
// (geometry/inspection.hpp has the equations and the metrology convention).
#include <optional>

#include "ltca/geometry/inspection.hpp"
#include "ltca/geometry/profile.hpp"

namespace ltca::analysis {

/// [inspection]: the measuring roller (or ball) of the dimension over rollers.
struct InspectionSettings {
  std::optional<double> roller_diameter;  ///< D_M, mm (> 0); absent: no measurement over rollers

  /// Throws std::invalid_argument naming [inspection] roller_diameter_mm unless it is absent or
  /// positive and finite.
  void Validate() const;
};

/// The inspection figures of one profile.
struct InspectionResult {
  double root_diameter = 0.0;  ///< mm
  double tip_diameter = 0.0;   ///< mm
  std::optional<geometry::RollerMeasurement> rollers;  ///< with [inspection] roller_diameter_mm
};

/// The figures of `profile` (the disc as made) with `settings`' roller.
InspectionResult Inspect(const geometry::CycloidProfile& profile, const InspectionSettings& settings);

}  // namespace ltca::analysis
