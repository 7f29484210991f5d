// The inspection figures (geometry::RootDiameter, TipDiameter, MeasureOverRollers) against a
// derivation of their own here: the profile evaluated from its equations (docs/conventions.md,
// geometry/profile.hpp: q(u) = R'(cos u, sin u) - e (cos Ze u, sin Ze u), the real profile its
// equidistant at r', inward for d > 0 and outward for d < 0), the tips and roots found where the
// profile crosses a symmetry axis, and a seated roller found where the profile's normal through a
// flank point meets the space's axis at the roller's radius (a roller touching both flanks has its
// centre there), checked to clear every point of the profile. 0.1 um throughout.
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include "ltca/geometry/inspection.hpp"
#include "ltca/geometry/profile.hpp"

using ltca::geometry::CycloidProfile;
using ltca::geometry::Modification;
using ltca::geometry::PairParameters;
using ltca::geometry::RollerContact;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTol = 1e-4;  // mm: 0.1 um

struct Own {
  int zp, zc;
  double R, r, e;  // generating radii (modification applied), eccentricity
  int d() const { return zp - zc; }
  double s() const { return d() > 0 ? 1.0 : -1.0; }
  // Position and unit normal out of the material (toward the pin), space 0, no rotation.
  std::pair<Eigen::Vector2d, Eigen::Vector2d> At(double u) const {
    const double ze = static_cast<double>(zp) / d();
    const Eigen::Vector2d q(R * std::cos(u) - e * std::cos(ze * u), R * std::sin(u) - e * std::sin(ze * u));
    const Eigen::Vector2d q1(-R * std::sin(u) + e * ze * std::sin(ze * u), R * std::cos(u) - e * ze * std::cos(ze * u));
    const Eigen::Vector2d n_in = Eigen::Vector2d(-q1.y(), q1.x()) / q1.norm();
    return {q + s() * r * n_in, -s() * n_in};
  }
};

// Bisection of f on [a, b] (a sign change there).
template <class F>
double Bisect(const F& f, double a, double b) {
  double fa = f(a);
  REQUIRE(fa * f(b) < 0.0);
  for (int i = 0; i < 200; ++i) {
    const double m = 0.5 * (a + b);
    const double fm = f(m);
    if ((fm < 0.0) == (fa < 0.0)) {
      a = m, fa = fm;
    } else {
      b = m;
    }
  }
  return 0.5 * (a + b);
}

Eigen::Vector2d Turn(const Eigen::Vector2d& v, double a) {
  return {std::cos(a) * v.x() - std::sin(a) * v.y(), std::sin(a) * v.x() + std::cos(a) * v.y()};
}

// The u > 0 where the profile of space 0 crosses the polar angle pi / z_c (a tooth's axis for
// d > 0, a ring's space axis for d < 0).
double CrossingOfHalfPitch(const Own& own) {
  const auto f = [&](double u) {
    const Eigen::Vector2d x = own.At(u).first;
    return std::atan2(x.y(), x.x()) - kPi / own.zc;
  };
  // Up to the lobe tip of the locus (|d| pi / z_c); past the smooth tip of |d| = 1, where it is pi / z_c.
  return Bisect(f, 1e-9, (std::abs(own.d()) == 1 ? 1.2 : 1.0) * std::abs(own.d()) * kPi / own.zc);
}

// A roller of radius rr touching both flanks: the flank point whose normal meets the space's axis
// at distance rr. Returns the centre's radius and the contact's u; checks that the roller clears
// the whole profile of its space and of both neighbours (no point closer than rr).
std::pair<double, double> SeatOnFlanks(const Own& own, double rr, double u_lo, double u_hi) {
  const double axis = own.d() > 0 ? 0.0 : kPi / own.zc;
  const auto centre = [&](double u) {
    const auto [x, n] = own.At(u);
    return Turn(x + rr * n, -axis);  // in the axis frame
  };
  // The one sign change of the centre's distance from the axis over the flank's interior.
  constexpr int kScan = 4000;
  double found = -1.0;
  for (int i = 1; i < kScan; ++i) {
    const double a = u_lo + (u_hi - u_lo) * i / kScan, b = u_lo + (u_hi - u_lo) * (i + 1) / kScan;
    if (centre(a).y() * centre(b).y() < 0.0) {
      REQUIRE(found < 0.0);
      found = Bisect([&](double u) { return centre(u).y(); }, a, b);
    }
  }
  REQUIRE(found > 0.0);
  const Eigen::Vector2d c_axis = centre(found);
  CHECK(std::abs(c_axis.y()) < 1e-9);
  const Eigen::Vector2d c = Turn(c_axis, axis);
  // The roller clears the profile: every point of spaces -1, 0, 1 at least rr away (1 nm).
  const double phi = CrossingOfHalfPitch(own);  // phi_max: the real profile of a space
  double least = 1e9;
  for (int k = -1; k <= 1; ++k) {
    for (int i = 0; i <= 20000; ++i) {
      const double u = -phi + 2.0 * phi * i / 20000;
      least = std::min(least, (Turn(own.At(u).first, 2.0 * kPi * k / own.zc) - c).norm());
    }
  }
  CHECK(least > rr - 1e-6);
  return {c.norm(), found};
}

double OverRollers(int zc, double s, double diameter, int d) {
  const double chord = zc % 2 == 0 ? 2.0 * s : 2.0 * s * std::cos(kPi / (2.0 * zc));
  return chord + (d > 0 ? diameter : -diameter);
}

PairParameters Liu() { return {40, 39, 3.0, 64.0, 1.3, 12.0}; }
PairParameters ChenD2() { return {24, 22, 7.0, 90.0, 4.0, 10.0}; }
PairParameters ChenDm1() { return {15, 16, 10.0, 120.0, 5.0, 10.0}; }

Modification Mod(double d_rrp, double d_rp, double rotation = 0.0) {
  Modification m;
  m.pin_radius = d_rrp;
  m.pin_circle_radius = d_rp;
  m.rotation = rotation;
  return m;
}

Own OwnOf(const PairParameters& p, const Modification& m) {
  return {p.pin_count, p.tooth_count, p.pin_circle_radius + m.pin_circle_radius, p.pin_radius + m.pin_radius,
          p.eccentricity};
}

}  // namespace

TEST_CASE("geometry: root and tip diameters are R' -+ e - r' for d = 1, the tip corner on the tooth axis for d = 2 "
          "(the top of its rounding arc when rounded), and the ring's root on its space axis for d = -1") {
  for (const double rotation : {0.0, 0.002}) {
    CAPTURE(rotation);
    // d = 1, Liu's pair with dR_rp = 8 um, dR_p = -10 um: 2 (R' - e - r') and 2 (R' + e - r').
    const Modification m1 = Mod(0.008, -0.010, rotation);
    const CycloidProfile liu(Liu(), m1);
    CHECK(std::abs(ltca::geometry::RootDiameter(liu) - 2.0 * (63.99 - 1.3 - 3.008)) < kTol);
    CHECK(std::abs(ltca::geometry::TipDiameter(liu) - 2.0 * (63.99 + 1.3 - 3.008)) < kTol);
    // d = 2: the root as for d = 1; the tip where the flank reaches the tooth's axis (pi / z_c).
    const Modification m2 = Mod(0.010, -0.020, rotation);
    const Own own2 = OwnOf(ChenD2(), m2);
    const CycloidProfile d2(ChenD2(), m2);
    CHECK(std::abs(ltca::geometry::RootDiameter(d2) - 2.0 * (own2.R - own2.e - own2.r)) < kTol);
    const double tip2 = 2.0 * own2.At(CrossingOfHalfPitch(own2)).first.norm();
    CHECK(std::abs(ltca::geometry::TipDiameter(d2) - tip2) < kTol);
    CHECK(ltca::geometry::TipDiameter(d2) > ltca::geometry::RootDiameter(d2) + 2.0);
    // d = 2 with its tips rounded (rho = 2 mm, no truncation): an arc tangent to both flanks, its centre
    // C = x(u) - rho n(u) on the tooth's axis; the tip circle runs over its top, 2 (|C| + rho).
    Modification rounded = m2;
    rounded.tip_relief = {0.0, 2.0};
    const CycloidProfile d2r(ChenD2(), rounded);
    const auto arc_centre = [&](double u) {
      const auto [x, n] = own2.At(u);
      return Eigen::Vector2d(x - 2.0 * n);
    };
    const double u_j = Bisect([&](double u) {
      const Eigen::Vector2d c = arc_centre(u);
      return std::atan2(c.y(), c.x()) - kPi / own2.zc;
    }, 1e-6, CrossingOfHalfPitch(own2));
    CHECK(std::abs(ltca::geometry::TipDiameter(d2r) - 2.0 * (arc_centre(u_j).norm() + 2.0)) < kTol);
    CHECK(ltca::geometry::TipDiameter(d2r) < tip2 - 0.4);  // 0.25 mm cut off the tip, on the radius
    // d = -1, a ring: its tips at u = 0 (2 (R' - e + r')), its roots on the space axis pi / z_c.
    const Own ownm = OwnOf(ChenDm1(), m2);
    const CycloidProfile dm1(ChenDm1(), m2);
    CHECK(std::abs(ltca::geometry::TipDiameter(dm1) - 2.0 * (ownm.R - ownm.e + ownm.r)) < kTol);
    CHECK(std::abs(ltca::geometry::RootDiameter(dm1) - 2.0 * ownm.At(CrossingOfHalfPitch(ownm)).first.norm()) < kTol);
  }
}

TEST_CASE("geometry: a roller no larger than the generating pin rests on the root, the generating pin's own size "
          "on the unmodified profile has its centre at R_p - e, the pin's at the mesh") {
  // Unmodified, D_M = 2 r_rp: the centre at R_p - e exactly, z_c odd (Liu, 39) and even (Chen d = 2, 22).
  for (const PairParameters& p : {Liu(), ChenD2()}) {
    CAPTURE(p.tooth_count);
    const CycloidProfile profile(p);
    const auto m = ltca::geometry::MeasureOverRollers(profile, 2.0 * p.pin_radius);
    CHECK(m.contact == RollerContact::kRoot);
    CHECK_FALSE(m.OnWorkingFlanks());
    CHECK(std::abs(m.centre_radius - (p.pin_circle_radius - p.eccentricity)) < 1e-9);
    CHECK(std::abs(m.dimension - OverRollers(p.tooth_count, p.pin_circle_radius - p.eccentricity, 2.0 * p.pin_radius, 1)) < kTol);
    CHECK(std::abs(m.contact_diameter - 2.0 * (p.pin_circle_radius - p.eccentricity - p.pin_radius)) < kTol);
  }
  // A smaller roller on a modified profile: on the root, its centre at the root radius plus its radius.
  const Modification mod = Mod(0.008, -0.010);
  const CycloidProfile liu(Liu(), mod);
  const auto m = ltca::geometry::MeasureOverRollers(liu, 5.0);
  CHECK(m.contact == RollerContact::kRoot);
  CHECK(std::abs(m.centre_radius - (63.99 - 1.3 - 3.008 + 2.5)) < kTol);
  CHECK(std::abs(m.dimension - (2.0 * (63.99 - 1.3 - 3.008 + 2.5) * std::cos(kPi / 78.0) + 5.0)) < kTol);
}

TEST_CASE("geometry: a larger roller touches both working flanks, its centre where their normals meet the axis "
          "(d = 1 odd z_c, d = 2 even z_c, d = -1 a ring measured between rollers)") {
  struct Case {
    PairParameters pair;
    Modification mod;
    double diameter;
  };
  for (const Case& c : {Case{Liu(), Mod(0.008, -0.010, 0.001), 8.0}, Case{Liu(), {}, 7.2},
                        Case{ChenD2(), Mod(0.010, -0.020), 24.0}, Case{ChenDm1(), Mod(0.010, -0.020), 30.0}}) {
    CAPTURE(c.pair.ToothDifference());
    CAPTURE(c.diameter);
    const CycloidProfile profile(c.pair, c.mod);
    const Own own = OwnOf(c.pair, c.mod);
    const double tip_end = c.pair.ToothDifference() > 0 ? CrossingOfHalfPitch(own) : 0.0;
    const double root_end = c.pair.ToothDifference() > 0 ? 0.0 : CrossingOfHalfPitch(own);
    const auto [s, u] = SeatOnFlanks(own, 0.5 * c.diameter, std::min(tip_end, root_end), std::max(tip_end, root_end));
    const auto m = ltca::geometry::MeasureOverRollers(profile, c.diameter);
    CHECK(m.contact == RollerContact::kFlanks);
    CHECK(m.OnWorkingFlanks());
    CHECK(std::abs(m.centre_radius - s) < kTol);
    CHECK(std::abs(m.contact_u - u) < 1e-6);
    CHECK(std::abs(m.dimension - OverRollers(c.pair.tooth_count, s, c.diameter, c.pair.ToothDifference())) < kTol);
    CHECK(std::abs(m.contact_diameter - 2.0 * own.At(u).first.norm()) < kTol);
  }
}

TEST_CASE("geometry: a roller too large for the space bears on the tips, and a roller diameter must be positive") {
  const CycloidProfile d2(ChenD2(), Mod(0.010, -0.020));
  const auto m = ltca::geometry::MeasureOverRollers(d2, 80.0);
  CHECK(m.contact == RollerContact::kTips);
  CHECK_FALSE(m.OnWorkingFlanks());
  const CycloidProfile liu(Liu());
  CHECK_THROWS_WITH_AS(ltca::geometry::MeasureOverRollers(liu, 0.0),
                       doctest::Contains("[inspection] roller_diameter_mm = 0"), std::invalid_argument);
  CHECK_THROWS_AS(ltca::geometry::MeasureOverRollers(liu, std::nan("")), std::invalid_argument);
}
