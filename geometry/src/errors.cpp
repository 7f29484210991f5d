#include "ltca/geometry/errors.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::geometry {

void ManufacturingErrors::Validate(int pin_count) const {
  if (!cumulative_pitch_deviation.empty() &&
      cumulative_pitch_deviation.size() != static_cast<std::size_t>(pin_count)) {
    throw std::invalid_argument(fmt::format(
        "[errors] cumulative_pitch_deviation_mm has {} values: expected one per pin ({})",
        cumulative_pitch_deviation.size(), pin_count));
  }
  for (const double v : cumulative_pitch_deviation) {
    if (!std::isfinite(v)) {
      throw std::invalid_argument("[errors] cumulative_pitch_deviation_mm: expected finite lengths");
    }
  }
  for (const auto& [key, list] : {std::pair{"pin_radius_deviations_mm", &pin_radius_deviations},
                                  std::pair{"pin_radial_deviations_mm", &pin_radial_deviations}}) {
    if (!list->empty() && list->size() != static_cast<std::size_t>(pin_count)) {
      throw std::invalid_argument(fmt::format("[errors] {} has {} values: expected one per pin ({})", key,
                                              list->size(), pin_count));
    }
    for (std::size_t j = 0; j < list->size(); ++j) {
      if (!std::isfinite((*list)[j])) {
        throw std::invalid_argument(fmt::format("[errors] {}[{}] = {}: expected a finite length", key, j, (*list)[j]));
      }
    }
  }
  if (!std::isfinite(lead_crowning) || lead_crowning < 0.0) {
    throw std::invalid_argument(fmt::format(
        "[errors] lead_crowning_um = {}: expected a finite amount >= 0 (material removed at either face)",
        units::MmToUm(lead_crowning)));
  }
  if (!std::isfinite(lead_slope)) {
    throw std::invalid_argument(fmt::format("[errors] lead_slope_um = {}: expected a finite length", units::MmToUm(lead_slope)));
  }
  if (!std::isfinite(pin_circle_deviation)) {
    throw std::invalid_argument(fmt::format(
        "[errors] pin_circle_deviation_mm = {}: expected a finite length", pin_circle_deviation));
  }
  if (!std::isfinite(profile_layer)) {
    throw std::invalid_argument(fmt::format(
        "[errors] cycloid_profile_layer_mm = {}: expected a finite length", profile_layer));
  }
}

double ManufacturingErrors::LeadLayer(double z, double face_width) const {
  double layer = 0.0;
  const double x = z - 0.5 * face_width;  // from the mid-plane
  if (lead_crowning > 0.0) {
    // A circular arc through the mid-plane (0) and both faces (-c): radius R with
    // R - sqrt(R^2 - (B/2)^2) = c, the sagitta at x is R - sqrt(R^2 - x^2), written without the
    // cancellation of the difference: x^2 / (R + sqrt(R^2 - x^2)).
    const double half = 0.5 * face_width;
    const double radius = (half * half + lead_crowning * lead_crowning) / (2.0 * lead_crowning);
    layer -= x * x / (radius + std::sqrt(radius * radius - x * x));
  }
  layer += lead_slope * x / face_width;
  return layer;
}

Eigen::Vector2d AssemblyErrors::SliceShift(double z, double face_width) const {
  const double zz = pivot == Pivot::kFace ? z : z - 0.5 * face_width;
  return {zz * std::tan(misalignment_xz), zz * std::tan(misalignment_yz)};
}

void AssemblyErrors::Validate() const {
  for (const auto& [key, value] : {std::pair{"centre_dx_mm", centre_dx}, std::pair{"centre_dy_mm", centre_dy},
                                   std::pair{"eccentricity_deviation_mm", eccentricity_deviation}}) {
    if (!std::isfinite(value)) {
      throw std::invalid_argument(fmt::format("[errors] {} = {}: expected a finite length", key, value));
    }
  }
  for (const auto& [key, value] : {std::pair{"misalignment_xz_deg", misalignment_xz},
                                   std::pair{"misalignment_yz_deg", misalignment_yz}}) {
    if (!std::isfinite(value) || std::abs(value) >= 0.25 * units::kPi) {
      throw std::invalid_argument(fmt::format("[errors] {} = {}: expected a finite tilt below 45 deg", key,
                                              units::RadToDeg(value)));
    }
  }
}

AssemblyErrors::Pivot ParseMisalignmentPivot(const std::string& text) {
  if (text == "face") return AssemblyErrors::Pivot::kFace;
  if (text == "mid") return AssemblyErrors::Pivot::kMid;
  throw std::invalid_argument(fmt::format("[errors] misalignment_pivot = \"{}\": expected \"face\" or \"mid\"", text));
}

ManufacturingErrors::PinCircleReading ParsePinCircleReading(const std::string& text) {
  if (text == "radius") return ManufacturingErrors::PinCircleReading::kRadius;
  if (text == "diameter") return ManufacturingErrors::PinCircleReading::kDiameter;
  throw std::invalid_argument(fmt::format(
      "[errors] pin_circle_reading = \"{}\": expected \"radius\" or \"diameter\"", text));
}

}  // namespace ltca::geometry
