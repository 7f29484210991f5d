#include "ltca/geometry/pair.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::geometry {
namespace {

void RequirePositive(double value, const char* key, const char* what) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw std::invalid_argument(
        fmt::format("[pair] {} = {}: expected a finite positive value ({})", key, value, what));
  }
}

}  // namespace

double PairParameters::CurtateCoefficient() const {
  return eccentricity * pin_count / (pin_circle_radius * std::abs(ToothDifference()));
}

void PairParameters::Validate() const {
  if (pin_count < 2) {
    throw std::invalid_argument(
        fmt::format("[pair] pin_count = {}: expected an integer >= 2", pin_count));
  }
  if (tooth_count < 2) {
    throw std::invalid_argument(
        fmt::format("[pair] tooth_count = {}: expected an integer >= 2", tooth_count));
  }
  if (ToothDifference() == 0) {
    throw std::invalid_argument(fmt::format(
        "[pair] tooth_count = {}: equals pin_count; the tooth difference d = pin_count - "
        "tooth_count must be a nonzero integer",
        tooth_count));
  }
  const int d = ToothDifference();
  if (d != 1 && d != 2 && d != 3 && d != -1) {
    throw std::invalid_argument(fmt::format(
        "[pair] tooth_count = {}: the tooth difference d = pin_count - tooth_count = {} - {} = {} "
        "is outside the checked geometry; expected d = 1, 2 or 3 (cycloid inside the pin ring) "
        "or -1 (cycloid outside it)",
        tooth_count, pin_count, tooth_count, d));
  }
  RequirePositive(pin_radius, "pin_radius_mm", "pin radius r_rp in mm");
  RequirePositive(pin_circle_radius, "pin_circle_radius_mm", "pin-circle radius R_p in mm");
  RequirePositive(eccentricity, "eccentricity_mm", "eccentricity e in mm");
  RequirePositive(face_width, "face_width_mm", "face width B_c in mm");
  // Neighbouring pins must not overlap: the chord between centres is 2 R_p sin(pi / z_p).
  const double half_chord = pin_circle_radius * std::sin(units::kPi / pin_count);
  if (pin_radius >= half_chord) {
    throw std::invalid_argument(fmt::format(
        "[pair] pin_radius_mm = {}: pins overlap; with pin_count = {} on pin_circle_radius_mm = "
        "{} the pin radius must be below R_p sin(pi / z_p) = {:.6g} mm",
        pin_radius, pin_count, pin_circle_radius, half_chord));
  }
  const double k1 = CurtateCoefficient();
  if (k1 >= 1.0) {
    throw std::invalid_argument(fmt::format(
        "[pair] eccentricity_mm = {}: the curtate coefficient K1 = e z_p / (R_p |d|) = {:.6g} "
        "must be below 1 (Chen eq. 12); reduce e or increase pin_circle_radius_mm",
        eccentricity, k1));
  }
}

void Modification::Validate(const PairParameters& pair) const {
  if (!std::isfinite(pin_radius)) {
    throw std::invalid_argument(fmt::format("[modification] pin_radius_mm = {}: expected a finite length in mm", pin_radius));
  }
  if (!std::isfinite(pin_circle_radius)) {
    throw std::invalid_argument(
        fmt::format("[modification] pin_circle_radius_mm = {}: expected a finite length in mm", pin_circle_radius));
  }
  if (!std::isfinite(rotation)) {
    throw std::invalid_argument(fmt::format("[modification] rotation_deg = {}: expected a finite angle in deg", rotation));
  }
  if (!(tip_relief.truncation >= 0.0) || !std::isfinite(tip_relief.truncation)) {
    throw std::invalid_argument(fmt::format(
        "[modification] tip_truncation_mm = {}: expected a finite length >= 0 (0: no truncation)",
        tip_relief.truncation));
  }
  if (!(tip_relief.rounding_radius >= 0.0) || !std::isfinite(tip_relief.rounding_radius)) {
    throw std::invalid_argument(fmt::format(
        "[modification] tip_rounding_radius_mm = {}: expected a finite radius >= 0 (0: sharp corners)",
        tip_relief.rounding_radius));
  }
  if (pair.pin_radius + pin_radius <= 0.0) {
    throw std::invalid_argument(fmt::format(
        "[modification] pin_radius_mm = {}: the generating pin radius r_rp + dR_rp = {} mm must "
        "be positive",
        pin_radius, pair.pin_radius + pin_radius));
  }
  const double generating_radius = pair.pin_circle_radius + pin_circle_radius;
  if (generating_radius <= 0.0) {
    throw std::invalid_argument(fmt::format(
        "[modification] pin_circle_radius_mm = {}: the generating pin-circle radius R_p + dR_p "
        "= {} mm must be positive",
        pin_circle_radius, generating_radius));
  }
  const double k1 =
      pair.eccentricity * pair.pin_count / (generating_radius * std::abs(pair.ToothDifference()));
  if (k1 >= 1.0) {
    throw std::invalid_argument(fmt::format(
        "[modification] pin_circle_radius_mm = {}: the modified curtate coefficient "
        "e z_p / ((R_p + dR_p) |d|) = {:.6g} must be below 1",
        pin_circle_radius, k1));
  }
}

}  // namespace ltca::geometry
