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

/// The [modification] section: how the cycloid profile is generated off the nominal pin data.
/// The pins themselves stay nominal (R_p, r_rp); only the cycloid is modified (Liu eq. 1).
struct Modification {
  double pin_radius = 0.0;         ///< isometric (equidistant) modification dR_rp, mm.
  double pin_circle_radius = 0.0;  ///< offset (move) modification dR_p, mm.
  double rotation = 0.0;           ///< angle-rotation modification, rad: a rigid rotation of the
                                   ///< whole generated profile, counterclockwise in the body frame.

  bool IsZero() const { return pin_radius == 0.0 && pin_circle_radius == 0.0 && rotation == 0.0; }

  /// Throws std::invalid_argument when the generating radii R_p + dR_p or r_rp + dR_rp are not
  /// positive or the modified curtate coefficient reaches 1.
  void Validate(const PairParameters& pair) const;
};

}  // namespace ltca::geometry
