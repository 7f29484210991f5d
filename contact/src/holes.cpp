#include "ltca/contact/holes.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace ltca::contact {

Eigen::Vector2d HoleInDisc(double circle_radius, double alpha, const HoleDeviations& deviations, int j) {
  const Eigen::Vector2d radial(std::cos(alpha), std::sin(alpha));
  Eigen::Vector2d hole = circle_radius * radial;
  if (!deviations.empty()) {
    const Eigen::Vector2d& d = deviations[static_cast<std::size_t>(j)];
    hole += d.x() * radial + d.y() * Eigen::Vector2d(-radial.y(), radial.x());
  }
  return hole;
}

std::vector<Eigen::Vector2d> HolesInDisc(double circle_radius, int count, double phase, const HoleDeviations& deviations) {
  std::vector<Eigen::Vector2d> holes;
  for (int j = 0; j < count; ++j) {
    holes.push_back(HoleInDisc(circle_radius, 2.0 * std::acos(-1.0) * j / count + phase, deviations, j));
  }
  return holes;
}

void ValidateHoleDeviations(const HoleDeviations& deviations, int count) {
  if (deviations.empty()) return;
  if (static_cast<int>(deviations.size()) != count) {
    throw std::invalid_argument(fmt::format(
        "[output] hole_radial_deviations_mm: {} values; expected one per hole ([output] count = {}), or none",
        deviations.size(), count));
  }
  for (std::size_t j = 0; j < deviations.size(); ++j) {
    for (int a = 0; a < 2; ++a) {
      if (!std::isfinite(deviations[j](a))) {
        throw std::invalid_argument(fmt::format("[output] {}[{}] = {}: expected a finite deviation in mm",
                                                a == 0 ? "hole_radial_deviations_mm" : "hole_tangential_deviations_mm",
                                                j, deviations[j](a)));
      }
    }
  }
}

}  // namespace ltca::contact
