#pragma once
// Closed-form pieces of a relieved tip without truncation (issue 12), computed here from the
// flank alone, not from geometry::TipCap: the rounding arc is the circle of radius rho centred on
// the tooth's symmetry axis whose distance to the flank is rho. Found by bisection on the distance
// of the centre from the body origin, with the flank distance taken by dense sampling refined by
// golden section (tests only).
#include <cmath>

#include <Eigen/Core>

#include "ltca/geometry/profile.hpp"

namespace ltca::test {

/// Smallest distance from c to the flank u in [0, phi_max] of tooth space k.
inline double DistanceToFlank(const geometry::CycloidProfile& profile, int k, const Eigen::Vector2d& c) {
  const int n = 2000;
  const double phi = profile.phi_max();
  double best = 1e300, best_u = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double u = phi * i / n;
    const double d = (profile.Position(u, k) - c).norm();
    if (d < best) best = d, best_u = u;
  }
  double a = std::max(0.0, best_u - phi / n), b = std::min(phi, best_u + phi / n);
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 200; ++it) {
    const double x1 = b - g * (b - a), x2 = a + g * (b - a);
    if ((profile.Position(x1, k) - c).norm() < (profile.Position(x2, k) - c).norm()) b = x2; else a = x1;
  }
  return std::min(best, (profile.Position(0.5 * (a + b), k) - c).norm());
}

/// Centre of the rounding arc of tip k (between spaces k and k + 1, rotation modification 0) of a
/// d > 0 profile with rounding radius rho and no truncation.
inline Eigen::Vector2d RoundingCentre(const geometry::CycloidProfile& profile, int tip, double rho) {
  const double pitch = profile.tooth_pitch();
  const double angle = (tip + 0.5) * pitch;
  const Eigen::Vector2d axis(std::cos(angle), std::sin(angle));
  const double corner = profile.Position(profile.phi_max(), tip).norm();
  // The distance to the flank minus rho falls as the centre moves out toward the corner.
  double lo = corner - 50.0 * rho, hi = corner;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (DistanceToFlank(profile, tip, mid * axis) > rho) lo = mid; else hi = mid;
  }
  return 0.5 * (lo + hi) * axis;
}

}  // namespace ltca::test
