// Arc length along the real profile against a closed form. The real profile is the equidistant
// at r' of the pin-centre locus q (Chen eq. 13-14), so its arc length is the locus's minus
// s r' times the turning angle of the locus tangent (the integral of curvature ds):
//   s(u) = s_q(u) - sign(d) r' (theta(u) - theta(0)),
// and the locus speed R' sqrt(1 + K1^2 - 2 K1 cos(Zd v)) integrates to an incomplete elliptic
// integral of the second kind E (std::ellint_2):
//   K1 >= 0:  s_q(u) = R' (1 + K1) (2 / Zd) [E(Zd u / 2 + pi / 2, k) - E(pi / 2, k)],
//   K1 <  0:  s_q(u) = R' (1 + |K1|) (2 / Zd) E(Zd u / 2, k),   k^2 = 4 |K1| / (1 + |K1|)^2.
// Everything here is written from the pair data, not from the program's profile.
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <doctest/doctest.h>

#include "ltca/geometry/arc_length.hpp"
#include "pairs.hpp"

using ltca::geometry::CycloidProfile;
using ltca::geometry::Modification;
using ltca::geometry::ProfileArcLength;

namespace {

// The closed form above, for the reference tooth space of `pair` generated with `mod`.
double ClosedFormArcLength(const ltca::geometry::PairParameters& pair, const Modification& mod, double u) {
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

}  // namespace

TEST_CASE("geometry: the arc length along the profile matches the elliptic-integral closed form") {
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    for (const Modification& mod : {Modification{}, ltca::test::Mod(-4, -17), ltca::test::Mod(10, 20)}) {
      const CycloidProfile profile(pair, mod);
      const ProfileArcLength arc(profile);
      const double phi = profile.phi_max();
      const double flank = ClosedFormArcLength(pair, mod, phi);
      CAPTURE(name);
      CHECK(flank > 0.0);
      CHECK(std::abs(arc.end() - flank) <= 1e-12 * flank);
      CHECK(std::abs(arc.begin() + flank) <= 1e-12 * flank);
      for (int i = -20; i <= 20; ++i) {
        const double u = phi * (i + (i > -20 && i < 20 ? 0.31 : 0.0)) / 20.0;
        CAPTURE(u);
        CHECK(std::abs(arc.At(u) - ClosedFormArcLength(pair, mod, u)) <= 1e-12 * flank);
      }
      CHECK(arc.At(0.0) == 0.0);
    }
  }
}

TEST_CASE("geometry: the parameter of an arc length inverts the arc length to a few ulp") {
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    const CycloidProfile profile(pair, ltca::test::Mod(-4, -17));
    const ProfileArcLength arc(profile);
    const double phi = profile.phi_max();
    CAPTURE(name);
    for (int i = -50; i <= 50; ++i) {
      const double u = phi * i / 50.0 * 0.999;
      CHECK(std::abs(arc.ParameterAt(arc.At(u)) - u) <= 1e-14 * phi);
      // s -> u -> s, at arc lengths spread evenly along the flank.
      const double s = arc.begin() + (arc.end() - arc.begin()) * (i + 50.5) / 101.0;
      CHECK(std::abs(arc.At(arc.ParameterAt(s)) - s) <= 1e-13 * arc.end());
    }
    CHECK(arc.ParameterAt(arc.end()) == phi);
    CHECK(arc.ParameterAt(arc.begin()) == -phi);
    CHECK_THROWS_AS(arc.At(1.01 * phi), std::out_of_range);
    CHECK_THROWS_AS(arc.ParameterAt(1.01 * arc.end()), std::out_of_range);
  }
}
