// Chen 2008 and Liu 2021 published geometry numbers, and the equivalence of their profile
// equations with ours.
#include <cmath>

#include <doctest/doctest.h>

#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/units.hpp"
#include "pairs.hpp"

using ltca::geometry::CycloidProfile;
using ltca::test::ChenPair;
using ltca::units::DegToRad;
using ltca::units::kPi;
using ltca::units::RadToDeg;

namespace {

double RelErr(double a, double b) { return std::abs(a - b) / std::abs(b); }

// Chen 2008 eq. 13-14 typed in literally (his frame): Z_e = Z_b / d, Z_d = Z_g / d, K1 of eq. 12
// (signed), "+" sign of eq. 14 for Z_b > Z_g, "-" otherwise.
Eigen::Vector2d ChenEq13(const ltca::geometry::PairParameters& p, double phi) {
  const double d = p.pin_count - p.tooth_count;
  const double ze = p.pin_count / d, zd = p.tooth_count / d;
  const double k1 = p.eccentricity * p.pin_count / (p.pin_circle_radius * d);
  const double sign = d > 0 ? 1.0 : -1.0;
  const double s = std::sqrt(1.0 + k1 * k1 - 2.0 * k1 * std::cos(zd * phi));
  const double cos_beta = sign * (k1 * std::sin(ze * phi) - std::sin(phi)) / s;
  const double sin_beta = sign * (-k1 * std::cos(ze * phi) + std::cos(phi)) / s;
  const double rz = p.pin_circle_radius, r = p.pin_radius, e = p.eccentricity;
  return {rz * std::sin(phi) - e * std::sin(ze * phi) + r * cos_beta,
          rz * std::cos(phi) - e * std::cos(ze * phi) - r * sin_beta};
}

// Liu 2021 eq. 1-2 typed in literally (d = 1, modified generating radii).
Eigen::Vector2d LiuEq1(const ltca::geometry::PairParameters& p, double d_rp, double d_rrp,
                       double phi_p) {
  const double zc = p.tooth_count, zp = p.pin_count, e = p.eccentricity;
  const double rp = p.pin_circle_radius + d_rp, rrp = p.pin_radius + d_rrp;
  const double alpha = std::atan(zp * e * std::sin(phi_p) / (rp - zp * e * std::cos(phi_p)));
  return {rp * std::cos(phi_p / zc) - rrp * std::cos(alpha - phi_p / zc) - e * std::cos(zp * phi_p / zc),
          rp * std::sin(phi_p / zc) + rrp * std::sin(alpha - phi_p / zc) - e * std::sin(zp * phi_p / zc)};
}

Eigen::Vector2d Rot90(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }

}  // namespace

TEST_CASE("geometry: Chen 2008 phi_max (eq. 16) and contact ratio (eq. 27), exact roots and printed values") {
  // Chen section 3 prints phi_max = 16.36, 8.77, 5.22, 11.25 deg and contact ratios 6.43 (d=2),
  // 5.74 (d=3). Solving eq. 16 exactly gives 8.7544 and 5.1931 deg (contact ratios 6.420,
  // 5.712): the printed values are rounded or inexact (docs/validation.md). Exact roots: 1e-5
  // relative (the reference values are an independent solution of eq. 16 given to 5 digits;
  // the root itself is checked to 1e-12 in the next test). Printed values within 0.5 %, except
  // the d = 3 phi_max: 5.22 deg is 0.52 % above the root 5.1931 deg, more than rounding to two
  // decimals explains (docs/validation.md); it is checked to lie 0.5-0.55 % off.
  struct Row {
    ltca::geometry::PairParameters pair;
    double printed_phi_deg, exact_phi_deg, printed_ratio, exact_ratio;
  };
  const Row rows[] = {
      {ChenPair(12, 11, 90, 7, 4), 16.36, 180.0 / 11.0, 6.0, 6.0},
      {ChenPair(24, 22, 90, 7, 4), 8.77, 8.7544, 6.43, 6.420},
      {ChenPair(36, 33, 90, 7, 4), 5.22, 5.1931, 5.74, 5.712},
      {ChenPair(15, 16, 120, 10, 5), 11.25, 11.25, 7.5, 7.5},
  };
  for (const Row& row : rows) {
    CAPTURE(row.pair.pin_count);
    const CycloidProfile profile(row.pair);
    const double phi_deg = RadToDeg(profile.phi_max());
    CHECK(RelErr(phi_deg, row.exact_phi_deg) < 1e-5);
    CHECK(RelErr(profile.contact_ratio(), row.exact_ratio) < 2e-4);  // exact ratio printed to 4 digits
    if (row.pair.pin_count == 36) {
      CHECK(RelErr(phi_deg, row.printed_phi_deg) > 5e-3);
      CHECK(RelErr(phi_deg, row.printed_phi_deg) < 5.5e-3);
    } else {
      CHECK(RelErr(phi_deg, row.printed_phi_deg) < 5e-3);
    }
    CHECK(RelErr(profile.contact_ratio(), row.printed_ratio) < 5e-3);
  }
}

TEST_CASE("geometry: phi_max is a root of Chen eq. 16 to 1e-12, and pi / Z_g exactly for |d| = 1") {
  for (const auto& [name, pair] : ltca::test::ChenPairs()) {
    CAPTURE(name);
    const CycloidProfile profile(pair);
    const int d = pair.ToothDifference();
    if (std::abs(d) == 1) CHECK(profile.phi_max() == kPi / pair.tooth_count);
    // Eq. 16 in Chen's frame: the profile point lies on y = x cot(pi / Z_g). Chen's profile is
    // ours mirrored, so his root is at the same phi.
    const Eigen::Vector2d c = ChenEq13(pair, profile.phi_max());
    const double residual = c.y() * std::sin(kPi / pair.tooth_count) - c.x() * std::cos(kPi / pair.tooth_count);
    CHECK(std::abs(residual) < 1e-12 * pair.pin_circle_radius);
    // And no earlier root: the profile stays short of the axis before phi_max.
    for (int i = 1; i < 100; ++i) {
      const Eigen::Vector2d ci = ChenEq13(pair, profile.phi_max() * i / 100.0);
      CHECK(std::atan2(ci.x(), ci.y()) < kPi / pair.tooth_count);
    }
  }
}

TEST_CASE("geometry: Chen eq. 13-14 and Liu eq. 1-2 describe our profile up to a rigid rotation") {
  // For d = 1, 2, 3, -1 Chen's curve is ours mirrored into his frame: Chen(phi) = Rot(90 deg)
  // x(-phi). For d = 1 Liu's eq. 1 (with phi_p = z_c u) is our profile as it is, also with
  // modified generating radii. Tolerance 1e-10 mm: three formulas for one curve in double.
  for (const auto& [name, pair] : ltca::test::ChenPairs()) {
    CAPTURE(name);
    const CycloidProfile profile(pair);
    for (int i = -50; i <= 50; ++i) {
      const double phi = profile.phi_max() * i / 50.0;
      CHECK((ChenEq13(pair, phi) - Rot90(profile.Position(-phi))).norm() < 1e-10);
    }
  }
  const auto liu = ltca::test::LiuPair();
  for (const auto& [d_rrp, d_rp] : {std::pair{0.0, 0.0}, std::pair{0.005, 0.0}, std::pair{-0.004, -0.017}}) {
    ltca::geometry::Modification mod;
    mod.pin_radius = d_rrp;
    mod.pin_circle_radius = d_rp;
    const CycloidProfile profile(liu, mod);
    for (int i = -50; i <= 50; ++i) {
      const double u = profile.phi_max() * i / 50.0;
      CHECK((LiuEq1(liu, d_rp, d_rrp, liu.tooth_count * u) - profile.Position(u)).norm() < 1e-10);
    }
  }
}

TEST_CASE("geometry: Liu 2021 Table 1 alpha_max = arcsin(z_p e / R_p) = 54.3409 deg, not the printed 54.3692") {
  // Liu section 4 prints alpha_max = 54.3692 deg from eq. 2; with z_p = 40, e = 1.3, R_p = 64,
  // eq. 2 peaks at arcsin(0.8125) = 54.3409 deg (docs/validation.md). Eq. 2 is scanned here
  // independently of the library; 1e-4 deg is its 4-decimal rounding.
  const auto pair = ltca::test::LiuPair();
  const CycloidProfile profile(pair);
  CHECK(std::abs(RadToDeg(profile.alpha_max()) - 54.3409) < 1e-4);
  double alpha_scan = 0.0;
  for (int i = 0; i <= 200000; ++i) {
    const double phi = kPi * i / 200000.0;
    alpha_scan = std::max(alpha_scan, std::atan(40 * 1.3 * std::sin(phi) / (64.0 - 40 * 1.3 * std::cos(phi))));
  }
  CHECK(std::abs(alpha_scan - profile.alpha_max()) < 1e-8);
  CHECK(std::abs(RadToDeg(profile.alpha_max()) - 54.3692) > 0.02);  // the printed value is not eq. 2's
  // Chen eq. 20: theta_max = -arctan(sqrt(1 - K1^2) / K1) is alpha_max's complement.
  CHECK(std::abs(profile.theta_max() + kPi / 2 - profile.alpha_max()) < 1e-12);
  CHECK(std::abs(RadToDeg(profile.theta_max()) - (54.3409 - 90.0)) < 1e-4);
}
