#include "ltca/solvers/reducer.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace ltca::solvers {

OutputKind ParseOutputKind(const std::string& text) {
  if (text == "pins") return OutputKind::kPins;
  if (text == "cranks") return OutputKind::kCranks;
  throw std::invalid_argument(fmt::format("[output] kind = \"{}\": expected pins or cranks", text));
}

const char* ToString(OutputKind kind) { return kind == OutputKind::kPins ? "pins" : "cranks"; }

const char* ToString(StageGroup group) {
  switch (group) {
    case StageGroup::kMesh: return "mesh";
    case StageGroup::kOutput: return "output";
    case StageGroup::kBearings: return "bearings";
    case StageGroup::kShafts: return "shafts";
    case StageGroup::kSeats: return "pin_seats";
    case StageGroup::kPinBending: return "pin_bending";
  }
  return "?";
}

void ReducerSettings::Validate(double eccentricity) const {
  if (kind == OutputKind::kPins) {
    pins.Validate(eccentricity);
  } else {
    cranks.Validate();
    if (bearing.kind == contact::BearingKind::kRigid && !std::isfinite(cranks.shaft_stiffness)) {
      // Rigid cranks in rigid holes lock the disc to the carrier and share its load among the
      // cranks in a way no stiffness decides: the crank loads would be numbers no model produced.
      throw std::invalid_argument(
          "[bearing] kind = \"rigid\": with [output] kind = \"cranks\" and rigid shafts the crank loads are statically "
          "indeterminate; expected a linear or rollers needle bearing, or [output] shaft_stiffness_n_per_mm");
    }
  }
  bearing.Validate();
}

}  // namespace ltca::solvers
