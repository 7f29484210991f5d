// Jiang 2022 eq. 15-19: the Hertz contact ellipse of a tilted pin.
#include <cmath>
#include <stdexcept>

#include <doctest/doctest.h>

#include "ltca/contact/point_contact.hpp"
#include "ltca/geometry/units.hpp"

using ltca::contact::CrossedCylinders;
using ltca::contact::HertzPointContact;
using ltca::units::kPi;

TEST_CASE("contact: equal cylinders crossed at 90 deg make the Hertz sphere contact") {
  // Two cylinders of radius R crossed at right angles touch like a sphere of radius R on a flat:
  // a = b = (3 P R / (4 E*))^(1/3), p0 = 3 P / (2 pi a^2) (Johnson eq. 4.22-4.23). 1e-9 relative.
  const double r = 10.0, p = 500.0, e_star = 113186.8;
  const auto c = HertzPointContact(CrossedCylinders(1 / r, 1 / r, kPi / 2), p, e_star);
  const double a = std::cbrt(3 * p * r / (4 * e_star));
  CHECK(c.eccentricity < 1e-8);
  CHECK(c.semi_major == doctest::Approx(a).epsilon(1e-9));
  CHECK(c.semi_minor == doctest::Approx(a).epsilon(1e-9));
  CHECK(c.max_pressure == doctest::Approx(3 * p / (2 * kPi * a * a)).epsilon(1e-9));
}

TEST_CASE("contact: the contact ellipse satisfies the Hertz relations for a tilted pin") {
  // A 3 mm pin on a convex 5 mm flank, axes tilted by 0.02 deg (Liu's misalignment) to 30 deg:
  // the solved eccentricity reproduces the curvature ratio B/A = [E/(1-e^2) - K] / [K - E]
  // (Johnson eq. 4.39) to 1e-9 (1e-6 at the extreme tilt), the load is (2/3) pi a b p0, and the ellipse elongates as the
  // tilt shrinks (toward the line contact).
  double last_ratio = 0.0;
  for (const double tilt_deg : {30.0, 5.0, 0.5, 0.02}) {
    CAPTURE(tilt_deg);
    const auto rc = CrossedCylinders(1 / 5.0, 1 / 3.0, tilt_deg * kPi / 180);
    const auto c = HertzPointContact(rc, 1000.0, 113186.8);
    const double e = c.eccentricity;
    const double k = std::comp_ellint_1(e), ee = std::comp_ellint_2(e);
    // At 0.02 deg B/A = 3.5e7 and 1 - e ~ 1e-11: double precision in e limits the ratio to ~1e-7.
    CHECK((ee / (1 - e * e) - k) / (k - ee) == doctest::Approx(rc.b / rc.a).epsilon(tilt_deg < 0.1 ? 1e-6 : 1e-9));
    CHECK(2.0 / 3.0 * kPi * c.semi_major * c.semi_minor * c.max_pressure == doctest::Approx(1000.0).epsilon(1e-12));
    CHECK(c.semi_major / c.semi_minor > last_ratio);
    last_ratio = c.semi_major / c.semi_minor;
  }
  // Parallel axes: a line contact, not a point contact.
  CHECK_THROWS_AS(HertzPointContact(CrossedCylinders(1 / 5.0, 1 / 3.0, 0.0), 1000.0, 113186.8), std::invalid_argument);
}
