#pragma once
// Manufacturing and assembly errors (the [errors] section): what Liu 2021 section 2
// (eq. 4-7) puts on the error tooth surfaces. Signs and figures: docs/conventions.md.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ltca/geometry/profile_deviation.hpp"

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
  /// Radius deviation of every pin, mm (> 0: a larger pin). Empty: none; otherwise z_p values.
  std::vector<double> pin_radius_deviations;
  /// Radial position deviation of every pin centre, mm (> 0: further out). Empty: none; otherwise
  /// z_p values.
  std::vector<double> pin_radial_deviations;
  /// Cycloid profile deviation along the profile (Liu eq. 4, delta^{n_c i_c j_c}): random per
  /// element within a tolerance zone (zone 0: none; keys profile_random_*), and a measured trace
  /// applied to every tooth space (profile_measured_csv, already parsed). RealPair builds the
  /// geometry::ProfileDeviation (their sum) once against the profile as made. It does not vary
  /// along the face width. docs/contact.md, "Profile deviation along the profile".
  RandomProfileDeviation profile_random;
  std::optional<MeasuredProfile> profile_measured;
  /// Lead crowning of the cycloid, mm: a circular arc along the face width, symmetric about the
  /// mid-plane, that removes this much material at either face relative to the mid-plane (> 0).
  double lead_crowning = 0.0;
  /// Lead slope error of the cycloid, mm over the face width: the flank carries -s/2 at face B
  /// (z = 0) and +s/2 at the far face (z = B), linear between (> 0: more material at the far face).
  double lead_slope = 0.0;

  /// Radial displacement of every pin centre, mm.
  double PinCircleRadiusChange() const {
    return pin_circle_reading == PinCircleReading::kRadius ? pin_circle_deviation
                                                           : 0.5 * pin_circle_deviation;
  }
  /// Material the lead modifications add at axial position z from face B (0 <= z <= B), mm
  /// (the sum of the crowning and the slope; 0 without them).
  double LeadLayer(double z, double face_width) const;
  /// Something varies along the face width (crowning or slope).
  bool VariesAlongWidth() const { return lead_crowning != 0.0 || lead_slope != 0.0; }
  bool IsZero() const {
    return pin_circle_deviation == 0.0 && profile_layer == 0.0 && cumulative_pitch_deviation.empty() &&
           pin_radius_deviations.empty() && pin_radial_deviations.empty() && !VariesAlongWidth() &&
           !HasProfileDeviation();
  }
  /// A random zone or a measured trace is given (the trace may still be all zeros).
  bool HasProfileDeviation() const { return profile_random.zone != 0.0 || profile_measured.has_value(); }
  /// Throws std::invalid_argument naming the key for non-finite values or a pitch list whose
  /// length is not z_p.
  void Validate(int pin_count) const;
};

/// Assembly errors of the cycloid axis (Liu 2021 section 2, Fig. 3b, eq. 6-7), all default 0.
struct AssemblyErrors {
  /// Where the misalignment tilts the axis about: z measured from face B (Liu's M_ae as meant) or
  /// from the mid-plane.
  enum class Pivot { kFace, kMid };
  double centre_dx = 0.0;  ///< frame-fixed offset of the cycloid centre along X_f, mm (Liu dx)
  double centre_dy = 0.0;  ///< along Y_f, mm (Liu dy)
  /// Eccentricity deviation, mm: the crank's throw is e + this; it turns with the crank.
  double eccentricity_deviation = 0.0;
  double misalignment_xz = 0.0;  ///< phi: tilt of the cycloid axis in the XZ plane, rad
  double misalignment_yz = 0.0;  ///< gamma: tilt in the YZ plane, rad
  Pivot pivot = Pivot::kFace;

  /// Shift of the cycloid centre in the slice at axial position z from face B, fixed frame, mm:
  /// (z' tan phi, z' tan gamma), z' = z (pivot face) or z - B/2 (pivot mid).
  Eigen::Vector2d SliceShift(double z, double face_width) const;
  bool VariesAlongWidth() const { return misalignment_xz != 0.0 || misalignment_yz != 0.0; }
  bool IsZero() const {
    return centre_dx == 0.0 && centre_dy == 0.0 && eccentricity_deviation == 0.0 && !VariesAlongWidth();
  }
  /// Throws std::invalid_argument naming the key for a non-finite value or a tilt of 45 deg or more.
  void Validate() const;
};

AssemblyErrors::Pivot ParseMisalignmentPivot(const std::string& text);

ManufacturingErrors::PinCircleReading ParsePinCircleReading(const std::string& text);

}  // namespace ltca::geometry
