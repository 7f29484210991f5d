#pragma once
// Manufacturing errors that act on the whole pair (the [errors] section). Per-element and
// per-pin errors (Liu 2021 eq. 4-5 with delta^{n i j}, f_pt) come with the element mode.
#include <string>
#include <vector>

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
  /// Cumulative pitch deviation of every pin, mm (Liu eq. 5: sum_{z <= n} f_pt^z; Liu Fig. 9):
  /// pin j is moved along the pin circle by this arc length (counterclockwise positive). Empty:
  /// none; otherwise exactly z_p values.
  std::vector<double> cumulative_pitch_deviation;

  /// Radial displacement of every pin centre, mm.
  double PinCircleRadiusChange() const {
    return pin_circle_reading == PinCircleReading::kRadius ? pin_circle_deviation
                                                           : 0.5 * pin_circle_deviation;
  }
  bool IsZero() const {
    return pin_circle_deviation == 0.0 && profile_layer == 0.0 && cumulative_pitch_deviation.empty();
  }
  /// Throws std::invalid_argument naming the key for non-finite values or a pitch list whose
  /// length is not z_p.
  void Validate(int pin_count) const;
};

ManufacturingErrors::PinCircleReading ParsePinCircleReading(const std::string& text);

}  // namespace ltca::geometry
