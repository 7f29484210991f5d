#include "ltca/contact/output_pins.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::contact {
namespace {

using geometry::Perp;

}  // namespace

void OutputPins::Validate(double eccentricity) const {
  const auto require = [](bool ok, const char* key, double value, const std::string& expected) {
    if (!ok) throw std::invalid_argument(fmt::format("[output] {} = {:g}: expected {}", key, value, expected));
  };
  require(count >= 3 && count <= kMaxCount, "count", count, fmt::format("3 to {} output pins", kMaxCount));
  require(std::isfinite(pin_radius) && pin_radius > 0.0, "pin_radius_mm", pin_radius, "a finite pin radius > 0 mm");
  require(std::isfinite(circle_radius) && circle_radius > 0.0, "circle_radius_mm", circle_radius,
          "a finite pin-circle radius > 0 mm");
  require(std::isfinite(phase), "phase_deg", units::RadToDeg(phase), "a finite angle");
  // A hole below pin_radius_mm + eccentricity_mm overlaps its pin at no load: an output-pin preload
  // (docs/stage.md "Preload"); the hole must still be wider than its pin.
  (void)eccentricity;
  require(std::isfinite(hole_radius) && hole_radius > pin_radius, "hole_radius_mm", hole_radius,
          fmt::format("a hole radius > pin_radius_mm = {:g} mm (below pin_radius_mm + eccentricity_mm = {:g} mm: a "
                      "preload)",
                      pin_radius, pin_radius + eccentricity));
  // Neighbouring holes must leave a web between them: their centres 2 R_w sin(pi / n) apart.
  const double spacing = 2.0 * circle_radius * std::sin(units::kPi / count);
  require(spacing > 2.0 * hole_radius, "hole_radius_mm", hole_radius,
          fmt::format("holes that do not overlap: below {:g} mm for {} holes on circle_radius_mm = {:g}", 0.5 * spacing,
                      count, circle_radius));
  ValidateHoleDeviations(hole_deviation, count);
}

ContactLaw OutputPinLaw(const ContactSettings& contact, const Material& material, const OutputPins& pins,
                        double length, double log_radius_cap, double hole_log_radius) {
  ContactSettings own = contact;
  // The hole's curvature enters with its sign whatever the mesh's convention (the absolute one
  // would make the pin and its hole two convex cylinders, 1/rho* = 1/r_w + 1/r_h, which is wrong for a pin in a hole).
  own.rho_convention = RhoConvention::kSigned;
  own.seat = PinSeat{};
  // The flank's body term is not the hole's; a body condensed at its holes too gives the hole's
  // (the same half-plane split: contact/disc_body.hpp, docs/fe_disc.md "The stage").
  own.cycloid_log_radius = hole_log_radius > 0.0 ? hole_log_radius : 0.0;
  return ContactLaw(own, material, -1.0 / pins.hole_radius, pins.pin_radius, length, log_radius_cap);
}

std::vector<OutputPinContact> EvaluateOutputPins(const OutputPins& pins, const geometry::Pose& disc,
                                                 double output_rotation) {
  std::vector<OutputPinContact> out(static_cast<std::size_t>(pins.count));
  const geometry::Pose output{Eigen::Vector2d::Zero(), output_rotation};  // about the pin-circle centre
  for (int j = 0; j < pins.count; ++j) {
    const double alpha = 2.0 * units::kPi * j / pins.count + pins.phase;
    const Eigen::Vector2d local = pins.circle_radius * Eigen::Vector2d(std::cos(alpha), std::sin(alpha));
    OutputPinContact& c = out[static_cast<std::size_t>(j)];
    c.pin = j;
    c.pin_centre = output.ToFixed(local);
    c.hole_centre = disc.ToFixed(HoleInDisc(pins.circle_radius, alpha, pins.hole_deviation, j));
    const Eigen::Vector2d offset = c.pin_centre - c.hole_centre;
    const double distance = offset.norm();
    if (!(distance > 0.0)) {
      throw std::domain_error(fmt::format("output pin {}: the pin and hole centres coincide (no contact direction)", j + 1));
    }
    c.normal = offset / distance;
    c.gap = pins.hole_radius - pins.pin_radius - distance;
    c.translation_gradient = -c.normal;
    c.disc_arm = -c.normal.dot(Perp(c.hole_centre - disc.centre));
    c.output_arm = c.normal.dot(Perp(c.pin_centre));
  }
  return out;
}

}  // namespace ltca::contact
