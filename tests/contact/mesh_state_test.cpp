// The mesh state: clearances, arms and closest points against closed forms and brute force.
#include <cmath>
#include <stdexcept>

#include <doctest/doctest.h>

#include "ltca/contact/mesh_state.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/meshing.hpp"
#include "ltca/geometry/units.hpp"
#include "pairs.hpp"

using ltca::contact::ContactKinematics;
using ltca::contact::MeshModel;
using ltca::geometry::ManufacturingErrors;
using ltca::geometry::Modification;
using ltca::units::kPi;

namespace {

// Brute-force gap of a pin (test only): distance from its centre to the whole profile, minus r.
double BruteClearance(const MeshModel& model, int pin, double crank, double psi) {
  const Eigen::Vector2d p = model.CyclePose(crank, psi, model.SliceZ(0)).ToBody(model.PinCentre(pin));
  return ltca::test::DistanceToProfile(model.profile(), p) - model.pair().pin_radius;
}

}  // namespace

TEST_CASE("contact: unmodified pair has zero clearance and arms L_i = (e z_c / |d|) sin(phi_i) / S_i") {
  // Exact conjugacy: c_i = 0 and L_i = e z_c sin(phi_i) / S_i (d = 1; divided by |d| in general,
  // with Chen's signed K1 in S_i) to 1e-9 mm at every meshing pin. Signs: L_i > 0 on the loaded
  // half (0 < phi < pi for d > 0, -pi < phi < 0 for d < 0), docs/conventions.md.
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    CAPTURE(name);
    const MeshModel model(pair, {});
    const double d = pair.ToothDifference();
    const double k1 = pair.eccentricity * pair.pin_count / (pair.pin_circle_radius * d);
    for (const double crank : {0.0, 0.05, 1.0}) {
      for (const auto& c : model.Evaluate(crank).pins) {
        if (!ltca::geometry::IsMeshing(model.profile(), model.kinematics(), c.pin, crank)) {
          CHECK(c.clearance > 0.0);
          continue;
        }
        const double s = std::sqrt(1 + k1 * k1 - 2 * k1 * std::cos(c.angle));
        const double arm = pair.eccentricity * pair.tooth_count / std::abs(d) * std::sin(c.angle) / s;
        CHECK(std::abs(c.clearance) < 1e-9);
        CHECK(std::abs(c.arm - (d > 0 ? arm : -arm)) < 1e-9);
        CHECK(!c.edge);
      }
    }
  }
}

TEST_CASE("contact: clearances of the safeguarded Newton match brute force over the whole tooth") {
  // Modified pairs, rotated poses, every pin (root, flank, inflection, tip; tip corners for
  // |d| >= 2): the Newton clearance equals the densely sampled, golden-section refined distance
  // to the whole profile minus r, to 1e-9 mm.
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    CAPTURE(name);
    const MeshModel model(pair, ltca::test::Mod(4, -9));
    for (const double psi : {0.0, 2e-4}) {
      for (const double crank : {0.02, 0.7}) {
        const auto state = model.Evaluate(crank, psi);
        for (const auto& c : state.pins) {
          CAPTURE(c.pin);
          CHECK(std::abs(c.clearance - BruteClearance(model, c.pin, crank, psi)) < 1e-9);
          CHECK(std::abs((c.pin_point - c.cycloid_point).norm() - std::abs(c.clearance)) < 1e-9);
        }
      }
    }
  }
}

TEST_CASE("contact: clearances of a modified pair match the first-order closed forms") {
  // Issue closed forms, K1 = z_p e / (R_p + dR_p), S_i = sqrt(1 + K1^2 - 2 K1 cos phi_i):
  //   theoretical position:   c_i = dR_rp - dR_p (1 - K1 cos phi_i) / S_i
  //   after first contact:    c_i = dR_rp (1 - sin phi_i / S_i)
  //                                 - dR_p (1 - K1 cos phi_i - sqrt(1 - K1^2) sin phi_i) / S_i
  // (loaded half). They are first order in the modification: 2 % of |dR_rp| + |dR_p|. The
  // rotation to first contact is compared in the linearised model, which is what the closed
  // form is: the exact rotation adds a term of second order in the rotation that is large near
  // the nearly conformal root (0.07 mm between the root and pin radii: a 20 arcsec turn swings
  // the contact normal there by ~0.1 rad), checked in the next test.
  const auto pair = ltca::test::LiuPair();
  for (const auto& [rrp, rp] : {std::pair{5.0, 0.0}, std::pair{0.0, -5.0}, std::pair{3.0, -2.0}, std::pair{1.0, -6.0}}) {
    CAPTURE(rrp);
    CAPTURE(rp);
    const MeshModel model(pair, ltca::test::Mod(rrp, rp));
    const double d_rrp = rrp * 1e-3, d_rp = rp * 1e-3;
    const double k1 = pair.pin_count * pair.eccentricity / (pair.pin_circle_radius + d_rp);
    const double tol = 0.02 * (std::abs(d_rrp) + std::abs(d_rp));
    for (const double crank : {0.0, 0.06}) {
      const auto tca = ltca::contact::AnalyseUnloaded(model, crank, ContactKinematics::kLinearised);
      const auto state = model.Evaluate(crank);
      for (const auto& c : state.pins) {
        const double phi = c.angle, s = std::sqrt(1 + k1 * k1 - 2 * k1 * std::cos(phi));
        CHECK(std::abs(c.clearance - (d_rrp - d_rp * (1 - k1 * std::cos(phi)) / s)) < tol);
        if (std::sin(phi) > 0) {
          const double after = d_rrp * (1 - std::sin(phi) / s) -
                               d_rp * (1 - k1 * std::cos(phi) - std::sqrt(1 - k1 * k1) * std::sin(phi)) / s;
          // Within 10 deg of the line of centres the pin sits in the nearly conformal root, where
          // the modified contact normal (and arm) leaves the conjugate one with a large first-order
          // coefficient (arm 25.15 mm vs 23.76 mm at 5.6 deg for dR_rp = 1, dR_p = -6 um): 5 % there.
          const double bound = std::abs(phi) < ltca::units::DegToRad(10.0) ? 2.5 * tol : tol;
          CHECK(std::abs(tca.clearance_at_c1[static_cast<std::size_t>(c.pin)] - after) < bound);
        }
      }
    }
  }
}

TEST_CASE("contact: exact and linearised mesh states agree to first order in the rotation") {
  // c_exact(psi) - (c - L psi) is second order: halving psi quarters it (within 10 %). Away from
  // the root it is below 1e-2 of the first-order term at psi = 1e-4 rad (20 arcsec); near the
  // nearly conformal root it is larger (the contact normal swings), which is why both models exist.
  const MeshModel model(ltca::test::LiuPair(), ltca::test::Mod(-4, -17));
  const auto base = model.Evaluate(0.1);
  for (const auto& c : base.pins) {
    if (std::abs(c.arm) < 5.0) continue;
    const auto err = [&](double psi) {
      return model.EvaluatePoint(c.pin, c.slice, 0.1, psi).clearance - (c.clearance - c.arm * psi);
    };
    const double e1 = err(1e-4), e2 = err(5e-5);
    if (std::abs(c.angle) > 0.5) CHECK(std::abs(e1) < 1e-2 * std::abs(c.arm * 1e-4));
    CHECK(e1 / e2 == doctest::Approx(4.0).epsilon(0.1));
  }
}

TEST_CASE("contact: an overlap on both flanks is a preload: no backlash, its interference, the jam check names the pins") {
  // Radial clearance dR_rp - dR_p < 0 (d > 0): every pin overlaps, on both flanks. The unloaded
  // analysis reports no free play and the overlap as a rotation, theta_c2 - theta_c1 > 0 (each
  // flank's closing from ClosingRotation on the opening side); the jam check still names the pins.
  const MeshModel model(ltca::test::LiuPair(), ltca::test::Mod(-5, 0));
  const auto u = ltca::contact::AnalyseUnloaded(model, 0.0);
  CHECK(u.backlash == 0.0);
  CHECK(u.interference > 0.0);
  CHECK(u.interference == doctest::Approx(u.theta_c2 - u.theta_c1).epsilon(1e-15));
  CHECK_THROWS_WITH_AS(ltca::contact::RequireNoInterference(model, 0.0), doctest::Contains("pin 1 by 5"),
                       std::invalid_argument);  // pin 1 sits in the root at crank 0
  // d = -1 needs a positive pin-circle offset for relief: a negative one overlaps.
  const MeshModel ring(ltca::test::ChenPair(15, 16, 120, 10, 5), ltca::test::Mod(0, -5));
  CHECK(ltca::contact::AnalyseUnloaded(ring, 0.0).interference > 0.0);
  CHECK(ltca::contact::AnalyseUnloaded(ring, 0.0).backlash == 0.0);
  const MeshModel ring_ok(ltca::test::ChenPair(15, 16, 120, 10, 5), ltca::test::Mod(0, 5));
  CHECK(ltca::contact::AnalyseUnloaded(ring_ok, 0.0).interference == 0.0);
  CHECK(ltca::contact::AnalyseUnloaded(ring_ok, 0.0).backlash > 0.0);
}
