// The output pins in holes of issue 25 (contact/output_pins.hpp). Independent references: the
// eccentricity as the nominal offset of every pin from its hole (the W mechanism's parallel
// crank), the textbook load share of a W mechanism, and finite differences of the exact gaps.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/contact/laws.hpp"
#include "ltca/contact/output_pins.hpp"
#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/units.hpp"
#include "pairs.hpp"

using ltca::contact::EvaluateOutputPins;
using ltca::contact::OutputPins;

namespace {

/// Eight pins of radius 5 mm on R_w = 40 mm, pin 0 on +X; holes e + clearance larger.
OutputPins Eight(double eccentricity, double clearance) {
  OutputPins p;
  p.count = 8;
  p.pin_radius = 5.0;
  p.circle_radius = 40.0;
  p.hole_radius = 5.0 + eccentricity + clearance;
  return p;
}

}  // namespace

TEST_CASE("contact: at the nominal poses every output pin is offset from its hole by the eccentricity: its gap is the clearance") {
  // Liu 2021 Table 1's pair (e = 1.3 mm): the output member turns as the disc, so P_j - H_j is
  // minus the disc centre's offset at every crank. Tolerance 1e-12 mm.
  const ltca::geometry::Kinematics kinematics(ltca::test::LiuPair());
  const OutputPins pins = Eight(1.3, 0.02);
  CHECK_NOTHROW(pins.Validate(1.3));
  for (const double crank : {0.0, 0.7, 2.3, -1.1}) {
    CAPTURE(crank);
    const ltca::geometry::Pose disc = kinematics.CycloidPose(crank);
    for (const auto& c : EvaluateOutputPins(pins, disc, disc.rotation)) {
      CHECK(std::abs(c.gap - 0.02) < 1e-12);
      CHECK((c.pin_centre - c.hole_centre + disc.centre).norm() < 1e-12);
    }
  }
}

TEST_CASE("contact: the W mechanism with the disc held and linear pins without clearance: F_j = T sin a_j / (R_w sum sin^2 a_k)") {
  // The textbook load share of the output pins (docs/stage.md): with the disc centre held, the
  // output member turned by psi loads pin j by k R_w psi sin a_j, a_j its angle from the line of
  // centres; T = sum F_j R_w sin a_j over the loaded half. Eight pins, T = 100 N*m, R_w = 40 mm,
  // crank 0 (a pin at a = 90 deg): F_max = 4 T / (n_w R_w) = 1250 N, the pins at 45 and 135 deg
  // 883.8834765 N. The element's output arm must be R_w sin a_j (1e-12), and the forces of the
  // linearised balance the textbook's (1e-9).
  const ltca::geometry::Kinematics kinematics(ltca::test::LiuPair());
  const OutputPins pins = Eight(1.3, 0.0);
  const ltca::geometry::Pose disc = kinematics.CycloidPose(0.0);
  const auto contacts = EvaluateOutputPins(pins, disc, disc.rotation);
  double sum = 0.0;
  for (const auto& c : contacts) {
    const double a = 2.0 * ltca::units::kPi * c.pin / 8;  // from the line of centres (+X at crank 0)
    CHECK(c.output_arm == doctest::Approx(40.0 * std::sin(a)).epsilon(1e-12).scale(40.0));
    if (c.output_arm > 0.0) sum += c.output_arm * c.output_arm;
  }
  const double torque = 1e5;  // N*mm
  std::vector<double> force;
  for (const auto& c : contacts) force.push_back(c.output_arm > 1e-9 ? torque * c.output_arm / sum : 0.0);
  CHECK(force[2] == doctest::Approx(1250.0).epsilon(1e-9));
  CHECK(force[1] == doctest::Approx(883.8834765).epsilon(1e-9));
  CHECK(force[3] == doctest::Approx(883.8834765).epsilon(1e-9));
  for (const std::size_t j : {std::size_t{0}, std::size_t{4}, std::size_t{5}, std::size_t{6}, std::size_t{7}}) {
    CHECK(force[j] == 0.0);
  }
}

TEST_CASE("contact: an output pin in its hole is a conformal line contact under either rho_convention: Johnson's internal contact") {
  // Issue 46. A pin of radius r_w inside a hole of radius r_h touches it from inside: Johnson,
  // Contact Mechanics (1985), section 4.1 takes the relative curvature 1/R = 1/R_1 + 1/R_2 with
  // the radius of a concave surface negative, so 1/R = 1/r_w - 1/r_h; section 4.2(b), the line
  // contact of cylinders: b = sqrt(4 F R / (pi B E*)), p0 = 2 F / (pi b B), 1/E* = C_d + C_w,
  // C = (1 - nu^2) / E; the approach of the two bodies, each to a depth of the order of its own
  // radius (eq. 5.37, as the hertz-line law and the groove seat take it): (2F / (pi B))
  // [C_w (ln(4 r_w / b) - 1/2) + C_d (ln(4 r_h / b) - 1/2)]. [contact] rho_convention = "absolute"
  // (|kappa_c| for the cycloid, Liu's convention) must not turn the hole convex: before the fix the
  // stage built the law with the mesh's convention and got 1/R = 1/r_w + 1/r_h (2.79 mm instead of
  // 23.94 mm on cases/stage/cycloidal_drive.toml). The deck's pins (r_w 5, r_h 6.32 mm, B 12 mm);
  // the disc of a steel 206 GPa / 0.3 and the pins of 210 GPa / 0.28, so that a body's compliance
  // meets its own radius. Typed in here from Johnson; 1e-12 relative.
  const OutputPins pins = Eight(1.3, 0.02);
  const double rw = pins.pin_radius, rh = pins.hole_radius, length = 12.0, cap = 64.0;
  const ltca::contact::Material material{206000.0, 0.3, 210000.0, 0.28};
  const double cd = (1.0 - 0.3 * 0.3) / 206000.0, cw = (1.0 - 0.28 * 0.28) / 210000.0;
  const double conformal = 1.0 / (1.0 / rw - 1.0 / rh);  // Johnson's R of a cylinder in a hole
  CHECK(conformal == doctest::Approx(23.939393939393939).epsilon(1e-15));
  for (const auto convention : {ltca::contact::RhoConvention::kSigned, ltca::contact::RhoConvention::kAbsolute}) {
    for (const auto kind : {ltca::contact::LawKind::kHertzLine, ltca::contact::LawKind::kSagitta, ltca::contact::LawKind::kLinear}) {
      const std::string names = std::string(ltca::contact::ToString(convention)) + ", " + ltca::contact::ToString(kind);
      CAPTURE(names);
      ltca::contact::ContactSettings settings;
      settings.law = kind;
      settings.rho_convention = convention;
      settings.stiffness_per_length = kind == ltca::contact::LawKind::kLinear ? 2e4 : 0.0;
      const ltca::contact::ContactLaw law = ltca::contact::OutputPinLaw(settings, material, pins, length, cap);
      CHECK(law.equivalent_radius() == doctest::Approx(conformal).epsilon(1e-12));
      if (kind != ltca::contact::LawKind::kHertzLine) continue;
      for (const double f : {10.0, 1000.0, 5150.0, 20000.0}) {
        CAPTURE(f);
        const double b = std::sqrt(4.0 * f * conformal * (cd + cw) / (ltca::units::kPi * length));
        const double approach = 2.0 * f / (ltca::units::kPi * length) *
                                (cw * (std::log(4.0 * rw / b) - 0.5) + cd * (std::log(4.0 * rh / b) - 0.5));
        CHECK(law.HalfWidth(f) == doctest::Approx(b).epsilon(1e-12));
        CHECK(law.MaxPressure(f) == doctest::Approx(2.0 * f / (ltca::units::kPi * b * length)).epsilon(1e-12));
        CHECK(law.Approach(f) == doctest::Approx(approach).epsilon(1e-12));
      }
    }
  }
  // A seat belongs to the ring pins in their grooves: the output pins' law has none.
  ltca::contact::ContactSettings seated;
  seated.seat.kind = ltca::contact::PinSeat::Kind::kLinear;
  seated.seat.stiffness_per_length = 5e4;
  CHECK(ltca::contact::OutputPinLaw(seated, material, pins, length, cap).SeatApproach(1000.0) == 0.0);
}

TEST_CASE("contact: the output pins' arms and translation gradient are the derivatives of their exact approach") {
  // Central differences of the exact gaps (steps 1e-7), 1e-6 relative, at a crank off the axes.
  const ltca::geometry::Kinematics kinematics(ltca::test::LiuPair());
  const OutputPins pins = Eight(1.3, 0.01);
  const ltca::geometry::Pose disc = kinematics.CycloidPose(0.83);
  const auto base = EvaluateOutputPins(pins, disc, disc.rotation + 1e-4);
  const auto approach = [&](const ltca::geometry::Pose& d, double out, int j) {
    return -EvaluateOutputPins(pins, d, out)[static_cast<std::size_t>(j)].gap;
  };
  const double h = 1e-7;
  for (int j = 0; j < 8; ++j) {
    CAPTURE(j);
    const auto& c = base[static_cast<std::size_t>(j)];
    const double out = disc.rotation + 1e-4;
    CHECK((approach(disc, out + h, j) - approach(disc, out - h, j)) / (2 * h) == doctest::Approx(c.output_arm).epsilon(1e-6).scale(40.0));
    ltca::geometry::Pose turned = disc, back = disc;
    turned.rotation += h, back.rotation -= h;
    CHECK((approach(turned, out, j) - approach(back, out, j)) / (2 * h) == doctest::Approx(c.disc_arm).epsilon(1e-6).scale(40.0));
    for (int i = 0; i < 2; ++i) {
      ltca::geometry::Pose plus = disc, minus = disc;
      plus.centre[i] += h, minus.centre[i] -= h;
      CHECK((approach(plus, out, j) - approach(minus, out, j)) / (2 * h) == doctest::Approx(c.translation_gradient[i]).epsilon(1e-6).scale(1.0));
    }
  }
}

TEST_CASE("contact: [output] pins are refused with the key, the value and what is expected") {
  OutputPins p = Eight(1.3, 0.0);
  p.hole_radius = 6.0;  // < 5 + 1.3: the pin overlaps its hole at no load, an output-pin preload (issue 52)
  CHECK_NOTHROW(p.Validate(1.3));
  p.hole_radius = 5.0;  // not wider than its pin: no hole
  CHECK_THROWS_WITH_AS(p.Validate(1.3), doctest::Contains("[output] hole_radius_mm = 5: expected a hole radius > pin_radius_mm = 5 mm"),
                       std::invalid_argument);
  p = Eight(1.3, 0.0);
  p.count = 2;
  CHECK_THROWS_WITH_AS(p.Validate(1.3), doctest::Contains("[output] count = 2"), std::invalid_argument);
}

TEST_CASE("contact: a hole's position deviation moves only its own hole: the gap is r_h - r_w - |D + R(phi) d_j|") {
  // At the nominal poses P_j - H_j = -D - R(phi) d_j, d_j = dr (cos a_j, sin a_j) + dt (-sin a_j,
  // cos a_j) in the disc's frame (derived here from the placement of pin and hole, not from the
  // code's). Hole 2 radially +8 um, hole 5 tangentially -6 um. 1e-12 mm. The arms stay the
  // derivatives of the exact gap: the finite differences of the test above, with the deviations.
  const ltca::geometry::Kinematics kinematics(ltca::test::LiuPair());
  OutputPins pins = Eight(1.3, 0.02);
  pins.hole_deviation.assign(8, Eigen::Vector2d::Zero());
  pins.hole_deviation[2] = Eigen::Vector2d(0.008, 0.0);
  pins.hole_deviation[5] = Eigen::Vector2d(0.0, -0.006);
  CHECK_NOTHROW(pins.Validate(1.3));
  for (const double crank : {0.0, 0.7, 2.3}) {
    CAPTURE(crank);
    const ltca::geometry::Pose disc = kinematics.CycloidPose(crank);
    const auto contacts = EvaluateOutputPins(pins, disc, disc.rotation);
    for (int j = 0; j < 8; ++j) {
      CAPTURE(j);
      const double a = 2.0 * ltca::units::kPi * j / 8 + disc.rotation;  // the hole's direction in the fixed frame
      const Eigen::Vector2d r(std::cos(a), std::sin(a)), t(-std::sin(a), std::cos(a));
      const Eigen::Vector2d& d = pins.hole_deviation[static_cast<std::size_t>(j)];
      const double expected = pins.hole_radius - pins.pin_radius - (disc.centre + d.x() * r + d.y() * t).norm();
      CHECK(std::abs(contacts[static_cast<std::size_t>(j)].gap - expected) < 1e-12);
    }
    const double h = 1e-7;
    const auto approach = [&](const ltca::geometry::Pose& p, double out, int j) {
      return -EvaluateOutputPins(pins, p, out)[static_cast<std::size_t>(j)].gap;
    };
    for (const int j : {2, 5}) {
      const auto& c = contacts[static_cast<std::size_t>(j)];
      ltca::geometry::Pose turned = disc, back = disc;
      turned.rotation += h, back.rotation -= h;
      CHECK((approach(turned, disc.rotation, j) - approach(back, disc.rotation, j)) / (2 * h) ==
            doctest::Approx(c.disc_arm).epsilon(1e-6).scale(40.0));
    }
  }
  // One pair per hole, finite.
  pins.hole_deviation.resize(7);
  CHECK_THROWS_WITH_AS(pins.Validate(1.3), doctest::Contains("expected one per hole ([output] count = 8)"), std::invalid_argument);
  pins.hole_deviation.assign(8, Eigen::Vector2d(0.0, NAN));
  CHECK_THROWS_WITH_AS(pins.Validate(1.3), doctest::Contains("[output] hole_tangential_deviations_mm[0]"), std::invalid_argument);
}
