#include "ltca/contact/point_contact.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::contact {
namespace {

using units::kPi;

// (B - A) / (B + A) as a function of the eccentricity e: increasing from 0 (e = 0) to 1 (e -> 1).
double CurvatureRatio(double e) {
  const double k = std::comp_ellint_1(e), ee = std::comp_ellint_2(e);
  return (ee * (2.0 - e * e) - 2.0 * k * (1.0 - e * e)) / (ee * e * e);
}

}  // namespace

RelativeCurvature CrossedCylinders(double curvature_1, double curvature_2, double crossing) {
  // Johnson, Contact Mechanics, eq. 3.4: A + B = (k1 + k2) / 2,
  // B - A = (1/2) sqrt(k1^2 + k2^2 + 2 k1 k2 cos 2 theta).
  const double sum = 0.5 * (curvature_1 + curvature_2);
  const double diff = 0.5 * std::sqrt(std::max(0.0, curvature_1 * curvature_1 + curvature_2 * curvature_2 +
                                                        2.0 * curvature_1 * curvature_2 * std::cos(2.0 * crossing)));
  return {0.5 * (sum - diff), 0.5 * (sum + diff)};
}

EllipticalContact HertzPointContact(const RelativeCurvature& curvature, double force, double e_star) {
  const double a_cur = std::min(curvature.a, curvature.b), b_cur = std::max(curvature.a, curvature.b);
  if (!(a_cur > 0.0) || !(b_cur > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "point contact: relative curvatures A = {:.6g}, B = {:.6g} 1/mm must both be positive (A = 0 "
        "is a line contact)",
        a_cur, b_cur));
  }
  EllipticalContact c;
  const double target = (b_cur - a_cur) / (b_cur + a_cur);
  double e = 0.0;
  if (target > 0.0) {
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 200 && hi - lo > 1e-17; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (mid >= 1.0 || mid <= 0.0) break;
      (CurvatureRatio(mid) < target ? lo : hi) = mid;
    }
    e = 0.5 * (lo + hi);
  }
  c.eccentricity = e;
  if (!(force > 0.0)) return c;
  // Jiang eq. 16 (Hamrock-Brewe): a^3 = 3 E(e) P / (pi (1 - e^2) E' (A + B)), E' = 2 E*.
  const double e_prime = 2.0 * e_star;
  const double ee = e > 0.0 ? std::comp_ellint_2(e) : kPi / 2.0;
  c.semi_major = std::cbrt(3.0 * ee * force / (kPi * (1.0 - e * e) * e_prime * (a_cur + b_cur)));
  c.semi_minor = c.semi_major * std::sqrt(1.0 - e * e);
  c.max_pressure = 3.0 * force / (2.0 * kPi * c.semi_major * c.semi_minor);  // Jiang eq. 15
  return c;
}

}  // namespace ltca::contact
