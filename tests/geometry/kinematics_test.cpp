// Kinematics and conjugacy: the unmodified profile touches every meshing pin at every crank
// angle, interferes with none, and the mesh repeats after one mesh period.
#include <cmath>

#include <doctest/doctest.h>

#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/meshing.hpp"
#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/units.hpp"
#include "pairs.hpp"

using ltca::geometry::CycloidProfile;
using ltca::geometry::Kinematics;
using ltca::units::kPi;

namespace {

Eigen::Vector2d Rotate(const Eigen::Vector2d& v, double a) {
  return {std::cos(a) * v.x() - std::sin(a) * v.y(), std::sin(a) * v.x() + std::cos(a) * v.y()};
}

}  // namespace

TEST_CASE("geometry: conjugacy - every meshing pin touches the unmodified profile, none interferes") {
  // For d = 1, 2, 3, -1 and the Liu pair, over one mesh period: the pin centre lies on the
  // pin-centre locus at the meshing-equation parameter (1e-9 mm), the profile point there is at
  // distance r along its normal (1e-9 mm), and no point of the whole profile is closer to the
  // pin centre than r (1e-9 mm; golden-section refined sampling, independent of the seed).
  // Pins facing a tip (|d| >= 2) are clear of the profile.
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    CAPTURE(name);
    const CycloidProfile profile(pair);
    const Kinematics kin(pair);
    const double r = pair.pin_radius;
    int meshing = 0, facing_tip = 0;
    for (int step = 0; step < 7; ++step) {
      const double crank = kin.MeshPeriod() * step / 7.0 + 0.123;
      const auto pose = kin.CycloidPose(crank);
      for (int j = 0; j < pair.pin_count; ++j) {
        CAPTURE(j);
        const Eigen::Vector2d pin = pose.ToBody(kin.PinCentre(j));
        const auto seed = kin.Seed(j, crank);
        CHECK((pin - profile.PinCentreLocus(seed.u, seed.tooth_space)).norm() < 1e-9);
        const double dist = ltca::test::DistanceToProfile(profile, pin);
        if (ltca::geometry::IsMeshing(profile, kin, j, crank)) {
          ++meshing;
          const auto p = profile.Evaluate(seed.u, seed.tooth_space);
          CHECK(std::abs((pin - p.position).norm() - r) < 1e-9);
          CHECK(std::abs(p.normal.dot(pin - p.position) - r) < 1e-9);
          CHECK(dist > r - 1e-9);
          CHECK(dist < r + 1e-9);
        } else {
          ++facing_tip;
          CHECK(dist > r);
        }
      }
    }
    // |d| = 1: every pin meshes; |d| >= 2: the share of meshing pins is the contact ratio over z_p
    // (2 * contact ratio pins for a tooth flank seen from both sides, Chen eq. 27).
    if (std::abs(pair.ToothDifference()) == 1) CHECK(facing_tip == 0);
    else CHECK(facing_tip > 0);
    const double share = static_cast<double>(meshing) / (meshing + facing_tip);
    CHECK(share == doctest::Approx(2.0 * profile.contact_ratio() / pair.pin_count).epsilon(0.1));
  }
}

TEST_CASE("geometry: the mesh repeats after one mesh period 2 pi / z_p, up to a rigid rotation") {
  // Derivation in docs/conventions.md: after 2 pi / z_p of crank, pin j + 1 sits where pin j sat,
  // rotated with the cycloid by one tooth 2 pi / z_c. Checked to 1e-9 mm; and half a period is
  // not a period (the test could fail).
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    CAPTURE(name);
    const Kinematics kin(pair);
    const double period = kin.MeshPeriod();
    CHECK(period == doctest::Approx(2 * kPi / pair.pin_count).epsilon(1e-15));
    for (const double crank : {0.0, 0.31, 2.0}) {
      const auto pose0 = kin.CycloidPose(crank), pose1 = kin.CycloidPose(crank + period);
      double worst = 0, worst_half = 0;
      const auto pose_half = kin.CycloidPose(crank + period / 2);
      for (int j = 0; j < pair.pin_count; ++j) {
        const int next = (j + 1) % pair.pin_count;
        const Eigen::Vector2d a = Rotate(pose0.ToBody(kin.PinCentre(j)), 2 * kPi / pair.tooth_count);
        worst = std::max(worst, (pose1.ToBody(kin.PinCentre(next)) - a).norm());
        worst_half = std::max(worst_half, (pose_half.ToBody(kin.PinCentre(next)) - a).norm());
        const auto s0 = kin.Seed(j, crank), s1 = kin.Seed(next, crank + period);
        CHECK(s1.u == doctest::Approx(s0.u).epsilon(1e-9));
        CHECK(s1.tooth_space == (s0.tooth_space + 1) % pair.tooth_count);
      }
      CHECK(worst < 1e-9);
      CHECK(worst_half > 1e-3);
    }
    // Transmission ratio crank / cycloid = -z_c / d: one crank turn turns the cycloid by -2 pi d / z_c.
    CHECK(kin.CycloidPose(2 * kPi).rotation == doctest::Approx(-2 * kPi * pair.ToothDifference() / pair.tooth_count));
    CHECK(kin.TransmissionRatio() == doctest::Approx(-static_cast<double>(pair.tooth_count) / pair.ToothDifference()));
  }
}

TEST_CASE("geometry: contact line and pin contact angle match Chen eq. 22-25 and Liu eq. 2") {
  // Chen eq. 22-23 in his arm-fixed frame (line of centres along +Y, theta_b = -phi with phi the
  // pin's angle from our line of centres) is our contact point seen from the crank, mirrored
  // across y = x (1e-9 mm). Liu eq. 2 gives tan(alpha) = K1 sin(phi) / (1 - K1 cos(phi)) with the
  // signed K1 of Chen eq. 12, and |alpha| <= alpha_max = arcsin |K1| (1e-9).
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    CAPTURE(name);
    const CycloidProfile profile(pair);
    const Kinematics kin(pair);
    const double d = pair.ToothDifference();
    const double k1 = pair.eccentricity * pair.pin_count / (pair.pin_circle_radius * d);  // signed (Chen eq. 12)
    const double sign = d > 0 ? 1 : -1;
    double alpha_peak = 0;
    for (int step = 0; step < 50; ++step) {
      const double crank = 0.05 + step * 0.37;
      for (int j = 0; j < pair.pin_count; ++j) {
        if (!ltca::geometry::IsMeshing(profile, kin, j, crank)) continue;
        const double phi = kin.AngleFromLineOfCentres(j, crank);
        const double theta_b = -phi;
        const double s = std::sqrt(1 + k1 * k1 - 2 * k1 * std::cos(theta_b));
        const double cos_delta = sign * std::sin(theta_b) / s, sin_delta = sign * (k1 - std::cos(theta_b)) / s;
        const Eigen::Vector2d chen(-pair.pin_circle_radius * std::sin(theta_b) + pair.pin_radius * cos_delta,
                                   pair.pin_circle_radius * std::cos(theta_b) + pair.pin_radius * sin_delta);
        const Eigen::Vector2d ours = Rotate(ltca::geometry::ContactPoint(profile, kin, j, crank), -crank);
        CHECK((ours - Eigen::Vector2d(chen.y(), chen.x())).norm() < 1e-9);
        const double alpha = ltca::geometry::PinContactAngle(profile, kin, j, crank);
        // With Chen's signed K1 (negative for d < 0) Liu's eq. 2 covers both signs of d.
        CHECK(std::abs(std::tan(std::abs(alpha)) - std::abs(k1 * std::sin(phi)) / (1 - k1 * std::cos(phi))) < 1e-9);
        CHECK(std::abs(alpha) <= profile.alpha_max() + 1e-12);
        alpha_peak = std::max(alpha_peak, std::abs(alpha));
      }
    }
    if (std::abs(d) == 1) CHECK(alpha_peak > profile.alpha_max() - 0.02);  // reached within the sampling
  }
}
