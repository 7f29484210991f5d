#include "ltca/solvers/reducer.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "ltca/contact/holes.hpp"
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
    case StageGroup::kDiscBody: return "disc_body";
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
  if (second_disc_holes) {
    try {
      contact::ValidateHoleDeviations(*second_disc_holes, kind == OutputKind::kPins ? pins.count : cranks.count);
    } catch (const std::invalid_argument& e) {  // the keys are the second disc's
      std::string what = e.what();
      for (const char* key : {"hole_radial_deviations_mm", "hole_tangential_deviations_mm"}) {
        const std::string from = std::string("[output] ") + key;
        if (const auto at = what.find(from); at != std::string::npos) what.replace(at, from.size(), std::string("[second_disc] ") + key);
      }
      throw std::invalid_argument(what);
    }
  }
  if (second_disc_bearing_clearance) {
    contact::BearingSettings second = bearing;
    second.radial_clearance = *second_disc_bearing_clearance;
    try {
      second.Validate();
    } catch (const std::invalid_argument& e) {
      std::string what = e.what();
      const std::string from = "[bearing] radial_clearance_mm";
      if (const auto at = what.find(from); at != std::string::npos) what.replace(at, from.size(), "[second_disc] bearing_radial_clearance_mm");
      throw std::invalid_argument(what);
    }
  }
  if (!(carrier_stiffness > 0.0)) {
    throw std::invalid_argument(fmt::format("[output] carrier_torsional_stiffness_nm_per_arcmin = {:g}: "
                                            "expected a torsional stiffness > 0 in N*m/arcmin (leave the key out for a rigid carrier)",
                                            units::NmmPerRadToNmPerArcmin(carrier_stiffness)));
  }
}

const contact::HoleDeviations& ReducerSettings::Holes(int disc) const {
  if (disc == 1 && second_disc_holes) return *second_disc_holes;
  return kind == OutputKind::kPins ? pins.hole_deviation : cranks.hole_deviation;
}

contact::OutputPins ReducerSettings::PinsOf(int disc) const {
  contact::OutputPins out = pins;
  if (disc == 1 && second_disc_holes) out.hole_deviation = *second_disc_holes;
  return out;
}

contact::Cranks ReducerSettings::CranksOf(int disc) const {
  contact::Cranks out = cranks;
  if (disc == 1 && second_disc_holes) out.hole_deviation = *second_disc_holes;
  return out;
}

contact::BearingSettings ReducerSettings::BearingOf(int disc) const {
  contact::BearingSettings out = bearing;
  if (disc == 1 && second_disc_bearing_clearance) out.radial_clearance = *second_disc_bearing_clearance;
  return out;
}

}  // namespace ltca::solvers
