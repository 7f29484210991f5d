#include "ltca/geometry/errors.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

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
  if (!std::isfinite(pin_circle_deviation)) {
    throw std::invalid_argument(fmt::format(
        "[errors] pin_circle_deviation_mm = {}: expected a finite length", pin_circle_deviation));
  }
  if (!std::isfinite(profile_layer)) {
    throw std::invalid_argument(fmt::format(
        "[errors] cycloid_profile_layer_mm = {}: expected a finite length", profile_layer));
  }
}

ManufacturingErrors::PinCircleReading ParsePinCircleReading(const std::string& text) {
  if (text == "radius") return ManufacturingErrors::PinCircleReading::kRadius;
  if (text == "diameter") return ManufacturingErrors::PinCircleReading::kDiameter;
  throw std::invalid_argument(fmt::format(
      "[errors] pin_circle_reading = \"{}\": expected \"radius\" or \"diameter\"", text));
}

}  // namespace ltca::geometry
