#pragma once
// The inspection figures of a deck's disc as made ([inspection], docs/export.md): root and tip
// diameters, and with a roller diameter the dimension over two rollers and where they touch
// (geometry/inspection.hpp has the equations and the metrology convention).
#include <optional>
#include <string>
#include <vector>

#include "ltca/geometry/deviation_fit.hpp"
#include "ltca/geometry/inspection.hpp"
#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/profile_deviation.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/tolerance.hpp"

namespace ltca::analysis {

/// [inspection]: the measuring roller (or ball) of the dimension over rollers.
struct InspectionSettings {
  std::optional<double> roller_diameter;  ///< D_M, mm (> 0); absent: no measurement over rollers
  /// Total width of the profile tolerance band of the deviation chart, mm, centred on the design
  /// (+- half of it; [inspection] profile_tolerance_um); absent: no band drawn.
  std::optional<double> profile_tolerance;

  /// Throws std::invalid_argument naming [inspection] roller_diameter_mm unless it is absent or
  /// positive and finite, and [inspection] profile_tolerance_um likewise.
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

/// One toleranced key's share in the band of the dimension over rollers.
struct RollerToleranceTerm {
  std::string key;            ///< the [tolerances] key
  double sensitivity = 0.0;   ///< dM / d(key), mm of M per key unit (central difference)
  double half_width = 0.0;    ///< the key's worst-case half-width, key unit (uniform: tolerance; normal: 3 sigma)
  double sigma = 0.0;         ///< its standard deviation, key unit
  double mean = 0.0;          ///< its centre's offset from the deck's value, key unit
};

/// The tolerance band of the dimension over rollers from [tolerances], by sensitivity: each
/// toleranced key of the disc's profile (its modification, the profile layer) moved by +-h about
/// its centre (h = 1e-3 of its worst-case half-width), the roller seated again and M measured
/// (geometry::MeasureOverRollers); the effects combined
///   worst case:   centre +- sum |S_i| w_i      (w_i: uniform tolerance, or 3 sigma)
///   statistical:  centre +- sqrt(sum (S_i w_i)^2)   (root sum of squares of the same half-widths:
///                 +-3 sigma of M when the keys are normal, each w_i read as 3 sigma; the classic
///                 RSS stack, never wider than the worst case)
/// with centre = M at every key's mean. The keys of the disc's transverse profile are
/// modification_pin_radius_mm, modification_pin_circle_radius_mm, modification_rotation_deg and
/// cycloid_profile_layer_mm; the others (the pin ring, the lead, the assembly, the stage's holes)
/// do not move the rollers and are not listed (docs/export.md).
struct RollerToleranceBand {
  double nominal = 0.0;       ///< M of the deck, mm
  double centre = 0.0;        ///< M at the keys' means, mm
  double worst_low = 0.0, worst_high = 0.0;  ///< mm
  double rss_low = 0.0, rss_high = 0.0;      ///< mm
  std::vector<RollerToleranceTerm> terms;    ///< the keys that move M
};

/// The band of `design`'s first disc with `roller_diameter` (mm) under `tolerances`.
RollerToleranceBand RollerTolerance(const StageDesign& design, const ToleranceSettings& tolerances, double roller_diameter);

/// The deviation chart of a measured profile trace against the design (docs/export.md): the
/// trace at its own points on tooth space 0 (it applies to every space), the generating
/// modification fitted to it (geometry/deviation_fit.hpp) and that modification's deviation at the
/// same points, the tolerance band.
struct DeviationChart {
  std::string source;             ///< the trace's file
  std::vector<double> u;          ///< the trace's points, profile parameter, rad
  std::vector<double> measured;   ///< its normal deviation there, mm (+ adds material)
  std::vector<double> fitted;     ///< the fitted modification's deviation there, mm
  geometry::DeviationFit fit;
  std::optional<double> tolerance;  ///< the band's full width, mm (+- half about the design)
  /// Every measured point within the band (true without a band).
  bool WithinTolerance() const;
};

/// The chart of `trace` against `design` (the profile as made, without the trace: RealPair::profile()).
DeviationChart ChartProfileDeviation(const geometry::CycloidProfile& design, const geometry::MeasuredProfile& trace,
                                     const InspectionSettings& settings);

}  // namespace ltca::analysis
