#pragma once
// Nominal data of a cycloid-pin gear pair and its profile modifications.
// Units: mm and rad (docs/units.md). Names follow Liu 2021; Chen 2008's symbols in brackets.

namespace ltca::geometry {

/// The [pair] section of a deck.
struct PairParameters {
  int pin_count = 0;               ///< z_p  [Chen Z_b], number of pins.
  int tooth_count = 0;             ///< z_c  [Chen Z_g], number of cycloid teeth.
  double pin_radius = 0.0;         ///< r_rp [Chen r_Z], mm.
  double pin_circle_radius = 0.0;  ///< R_p  [Chen R_Z], mm.
  double eccentricity = 0.0;       ///< e, mm.
  double face_width = 0.0;         ///< B_c, mm.

  /// Tooth difference d = z_p - z_c (any nonzero integer; negative: the cycloid is the outer member).
  int ToothDifference() const { return pin_count - tooth_count; }

  /// Curtate coefficient |K1| = e z_p / (R_p |d|) of the nominal pair (Chen eq. 12).
  double CurtateCoefficient() const;

  /// Throws std::invalid_argument naming the deck key, its value and what is expected, for:
  /// non-positive or non-finite sizes, d = 0, pins that overlap on the pin circle, |K1| >= 1.
  void Validate() const;
};

/// Tip relief of the cycloid teeth ([modification] tip_truncation_mm, tip_rounding_radius_mm; issue
/// 12): Chen 2008 leaves the addendum of a |d| >= 2 profile open, where consecutive tooth spaces
/// meet in sharp tip corners. The relief cuts the tip back by `truncation` along the tooth's
/// symmetry axis (a straight line across the tooth, perpendicular to the axis) and rounds each
/// corner with a circular arc of `rounding_radius`, tangent to the working flank and to the
/// truncation line, or to the neighbouring flank when the line does not reach the arc
/// (geometry/tip_relief.hpp). Both 0: the sharp tips (no relief).
struct TipRelief {
  double truncation = 0.0;       ///< mm, >= 0, measured from the sharp corner along the tooth axis.
  double rounding_radius = 0.0;  ///< mm, >= 0.
  bool IsZero() const { return truncation == 0.0 && rounding_radius == 0.0; }
};

/// The [modification] section: how the cycloid profile is generated off the nominal pin data.
/// The pins themselves stay nominal (R_p, r_rp); only the cycloid is modified (Liu eq. 1).
struct Modification {
  double pin_radius = 0.0;         ///< isometric (equidistant) modification dR_rp, mm.
  double pin_circle_radius = 0.0;  ///< offset (move) modification dR_p, mm.
  double rotation = 0.0;           ///< angle-rotation modification, rad: a rigid rotation of the
                                   ///< whole generated profile, counterclockwise in the body frame.

  TipRelief tip_relief;            ///< of the generated profile; not a generating change.

  /// No generating modification (dR_rp, dR_p, rotation); the tip relief is not one.
  bool IsZero() const { return pin_radius == 0.0 && pin_circle_radius == 0.0 && rotation == 0.0; }

  /// Throws std::invalid_argument when the generating radii R_p + dR_p or r_rp + dR_rp are not
  /// positive, the modified curtate coefficient reaches 1, or a tip relief value is negative or
  /// not finite (its fit to the tooth is checked by the profile, geometry::TipCap).
  void Validate(const PairParameters& pair) const;
};

}  // namespace ltca::geometry
