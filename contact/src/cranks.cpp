#include "ltca/contact/cranks.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::contact {

void Cranks::Validate() const {
  const auto require = [](bool ok, const char* key, double value, const std::string& expected) {
    if (!ok) throw std::invalid_argument(fmt::format("[output] {} = {:g}: expected {}", key, value, expected));
  };
  require(count >= 2 && count <= kMaxCount, "count", count,
          fmt::format("2 to {} crankshafts for kind = \"cranks\"", kMaxCount));
  require(std::isfinite(circle_radius) && circle_radius > 0.0, "circle_radius_mm", circle_radius,
          "a finite crank-circle radius > 0 mm");
  require(std::isfinite(phase), "phase_deg", units::RadToDeg(phase), "a finite angle");
  require(shaft_stiffness > 0.0, "shaft_stiffness_n_per_mm", shaft_stiffness,
          "a shaft stiffness > 0 N/mm (leave the key out for a rigid shaft)");
  require(std::isfinite(turns_per_output_turn), "crank_turns_per_output_turn", turns_per_output_turn,
          "a finite number of turns");
  ValidateHoleDeviations(hole_deviation, count);
  if (beam.given()) {
    beam.Validate();
    if (std::isfinite(shaft_stiffness)) {
      throw std::invalid_argument("[output] shaft_stiffness_n_per_mm and shaft_diameter_mm: a crankshaft is one spring "
                                  "per disc or one beam for both; expected one of the two");
    }
  }
}

void CrankshaftBeam::Validate() const {
  const auto require = [](bool ok, const char* key, double value, const std::string& expected) {
    if (!ok) throw std::invalid_argument(fmt::format("[output] {} = {:g}: expected {}", key, value, expected));
  };
  require(std::isfinite(diameter) && diameter > 0.0, "shaft_diameter_mm", diameter, "a finite shaft diameter > 0 mm");
  require(std::isfinite(span) && span > 0.0, "shaft_span_mm", span,
          "a finite span > 0 mm between the two support bearings (required with shaft_diameter_mm)");
  for (const double a : eccentric) {
    require(std::isfinite(a) && a > 0.0 && a < span, "eccentric_positions_mm", a,
            fmt::format("each eccentric between the supports, 0 < a < shaft_span_mm = {:g} mm", span));
  }
  require(std::abs(eccentric[0] - eccentric[1]) > 1e-6 * span, "eccentric_positions_mm", eccentric[1],
          "the second disc's eccentric apart from the first's (the discs sit side by side)");
  require(support_stiffness > 0.0, "support_stiffness_n_per_mm", support_stiffness,
          "a support-bearing stiffness > 0 N/mm (leave the key out for rigid supports)");
}

ShaftCompliance CrankshaftCompliance(const CrankshaftBeam& beam, double young_modulus, double poisson_ratio) {
  const double l = beam.span, d = beam.diameter, e = young_modulus, nu = poisson_ratio;
  const double inertia = units::kPi * d * d * d * d / 64.0, area = units::kPi * d * d / 4.0;
  const double shear_modulus = e / (2.0 * (1.0 + nu));
  const double kappa = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu);  // Cowper 1966, solid circular section
  ShaftCompliance c;
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      // The deflection at x under a unit load at a (Timoshenko's simply supported beam): x <= a on
      // the load's left, else its mirror image (x -> L - x, a -> L - a).
      double x = beam.eccentric[static_cast<std::size_t>(i)], a = beam.eccentric[static_cast<std::size_t>(j)];
      if (x > a) {
        x = l - x;
        a = l - a;
      }
      const double b = l - a;
      c.beam(i, j) = b * x * (l * l - b * b - x * x) / (6.0 * e * inertia * l) + b * x / (kappa * shear_modulus * area * l);
      if (std::isfinite(beam.support_stiffness)) {
        const double xi = beam.eccentric[static_cast<std::size_t>(i)], aj = beam.eccentric[static_cast<std::size_t>(j)];
        c.supports(i, j) = ((l - xi) * (l - aj) + xi * aj) / (beam.support_stiffness * l * l);
      }
    }
  }
  return c;
}

double FirstStageTurns(int sun_teeth, int spur_teeth) {
  if (sun_teeth < 1 || spur_teeth < 1) {
    throw std::invalid_argument(fmt::format("[output] first_stage_teeth = [{}, {}]: expected [z_sun, z_spur], two tooth "
                                            "counts >= 1 (the input's sun gear and each crankshaft's spur gear)",
                                            sun_teeth, spur_teeth));
  }
  // The carrier turns omega_c, the sun is held: the spur gear's pitch point on the sun has no
  // velocity, so its centre (at r_s + r_p from the axis, moving (r_s + r_p) omega_c) turns about
  // that point: omega_p = (r_s + r_p) omega_c / r_p = (1 + z_sun / z_spur) omega_c.
  return 1.0 + static_cast<double>(sun_teeth) / static_cast<double>(spur_teeth);
}

std::vector<CrankContact> EvaluateCranks(const Cranks& cranks, const geometry::Pose& disc, double output_rotation) {
  return EvaluateCranks(cranks, disc, output_rotation, disc.centre);
}

std::vector<CrankContact> EvaluateCranks(const Cranks& cranks, const geometry::Pose& disc, double output_rotation,
                                         const Eigen::Vector2d& eccentric) {
  std::vector<CrankContact> out(static_cast<std::size_t>(cranks.count));
  const geometry::Pose carrier{Eigen::Vector2d::Zero(), output_rotation};  // about the pin-circle centre
  for (int j = 0; j < cranks.count; ++j) {
    const double alpha = 2.0 * units::kPi * j / cranks.count + cranks.phase;
    const Eigen::Vector2d local = cranks.circle_radius * Eigen::Vector2d(std::cos(alpha), std::sin(alpha));
    CrankContact& c = out[static_cast<std::size_t>(j)];
    c.crank = j;
    c.crank_centre = carrier.ToFixed(local);
    c.eccentric_centre = c.crank_centre + eccentric;
    c.hole_centre = disc.ToFixed(HoleInDisc(cranks.circle_radius, alpha, cranks.hole_deviation, j));
    c.offset = c.eccentric_centre - c.hole_centre;
    c.output_gradient = geometry::Perp(c.crank_centre) + cranks.turns_per_output_turn * geometry::Perp(eccentric);
    c.disc_rotation_gradient = -geometry::Perp(c.hole_centre - disc.centre);
  }
  return out;
}

}  // namespace ltca::contact
