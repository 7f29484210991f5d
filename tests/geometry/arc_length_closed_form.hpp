#pragma once
// A closed form of the arc length along the real profile (tests only). The real profile is the equidistant
// at r' of the pin-centre locus q (Chen eq. 13-14), so its arc length is the locus's minus
// s r' times the turning angle of the locus tangent (the integral of curvature ds):
//   s(u) = s_q(u) - sign(d) r' (theta(u) - theta(0)),
// and the locus speed R' sqrt(1 + K1^2 - 2 K1 cos(Zd v)) integrates to an incomplete elliptic
// integral of the second kind E (std::ellint_2):
//   K1 >= 0:  s_q(u) = R' (1 + K1) (2 / Zd) [E(Zd u / 2 + pi / 2, k) - E(pi / 2, k)],
//   K1 <  0:  s_q(u) = R' (1 + |K1|) (2 / Zd) E(Zd u / 2, k),   k^2 = 4 |K1| / (1 + |K1|)^2.
// Written from the pair data alone, not from the program's profile.
#include <cmath>
#include <numbers>

#include <Eigen/Core>

#include "ltca/geometry/pair.hpp"

namespace ltca::test {

// The closed form above, for the reference tooth space of `pair` generated with `mod`.
inline double ClosedFormArcLength(const geometry::PairParameters& pair, const geometry::Modification& mod, double u) {
  const int d = pair.ToothDifference();
  const double rp = pair.pin_circle_radius + mod.pin_circle_radius;
  const double r = pair.pin_radius + mod.pin_radius;
  const double e = pair.eccentricity;
  const double ze = static_cast<double>(pair.pin_count) / d;
  const double zd = static_cast<double>(pair.tooth_count) / d;
  const double k1 = e * ze / rp;
  const double a = std::abs(k1);
  const double k = 2.0 * std::sqrt(a) / (1.0 + a);
  double s_q = 0.0;
  if (k1 >= 0.0) {
    const double half_pi = std::numbers::pi / 2.0;
    s_q = rp * (1.0 + a) * (2.0 / zd) * (std::ellint_2(k, zd * u / 2.0 + half_pi) - std::ellint_2(k, half_pi));
  } else {
    s_q = rp * (1.0 + a) * (2.0 / zd) * std::ellint_2(k, zd * u / 2.0);
  }
  // Turning angle of q'(v) = (-R' sin v + e Ze sin(Ze v), R' cos v - e Ze cos(Ze v)) from 0 to u,
  // summed over small steps (each under a degree, so atan2 needs no unwrapping).
  const auto q1 = [&](double v) {
    return Eigen::Vector2d(-rp * std::sin(v) + e * ze * std::sin(ze * v), rp * std::cos(v) - e * ze * std::cos(ze * v));
  };
  const int steps = 4000;
  double theta = 0.0;
  Eigen::Vector2d prev = q1(0.0);
  for (int i = 1; i <= steps; ++i) {
    const Eigen::Vector2d next = q1(u * i / steps);
    theta += std::atan2(prev.x() * next.y() - prev.y() * next.x(), prev.dot(next));
    prev = next;
  }
  const double sign = d > 0 ? 1.0 : -1.0;
  return s_q - sign * r * theta;
}

}  // namespace ltca::test
