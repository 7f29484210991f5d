#pragma once
// Manufacturing errors that act on the whole pair (the [errors] section). Per-element and
// per-pin errors (Liu 2021 eq. 4-5 with delta^{n i j}, f_pt) come with the element mode.
#include <string>

namespace ltca::geometry {

struct ManufacturingErrors {
  /// How Liu 2021 eq. 5 applies the pin-circle deviation delta_Rp to the pin centres.
  enum class PinCircleReading {
    kRadius,    ///< the pins move out by delta_Rp: reproduces Liu Fig. 11 (docs/validation.md)
    kDiameter,  ///< the pins move out by delta_Rp / 2, as eq. 5 is printed (a diameter deviation)
  };

  double pin_circle_deviation = 0.0;  ///< delta_Rp, mm (deck: pin_circle_deviation_mm).
  PinCircleReading pin_circle_reading = PinCircleReading::kRadius;
  /// Uniform layer on the cycloid profile, mm (> 0 adds material): Liu's profile upper
  /// deviation F_alpha^c moved as a whole (section 5.2, Fig. 11). Equivalent to reducing the
  /// generating pin radius r_rp + dR_rp by the layer (the equidistant moves by the layer).
  double profile_layer = 0.0;

  /// Radial displacement of every pin centre, mm.
  double PinCircleRadiusChange() const {
    return pin_circle_reading == PinCircleReading::kRadius ? pin_circle_deviation
                                                           : 0.5 * pin_circle_deviation;
  }
  bool IsZero() const { return pin_circle_deviation == 0.0 && profile_layer == 0.0; }
  /// Throws std::invalid_argument naming the key for non-finite values.
  void Validate() const;
};

ManufacturingErrors::PinCircleReading ParsePinCircleReading(const std::string& text);

}  // namespace ltca::geometry
