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
