#include "ltca/solvers/reducer.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

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
    case StageGroup::kCarrier: return "carrier";
    case StageGroup::kSupports: return "support_bearings";
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
    if (bearing.kind == contact::BearingKind::kRigid && (cranks.beam.given() || cranks.shaft_compliance)) {
      throw std::invalid_argument(
          "[bearing] kind = \"rigid\" with [output] shaft_diameter_mm: the beam's deflections are the needle bearings' "
          "partners; expected a linear or rollers needle bearing");
    }
  }
  bearing.Validate();
  if (!(carrier_stiffness > 0.0)) {
    throw std::invalid_argument(fmt::format("[output] carrier_torsional_stiffness_nm_per_arcmin = {:g}: "
                                            "expected a torsional stiffness > 0 in N*m/arcmin (leave the key out for a rigid carrier)",
                                            units::NmmPerRadToNmPerArcmin(carrier_stiffness)));
  }
}

}  // namespace ltca::solvers
