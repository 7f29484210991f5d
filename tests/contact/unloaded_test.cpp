// Unloaded tooth contact analysis: backlash against the closed form and the published slopes.
#include <cmath>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"
#include "pairs.hpp"

using ltca::contact::MeshModel;
using ltca::geometry::ManufacturingErrors;
using ltca::geometry::Modification;
using ltca::units::RadToArcsec;

namespace {

// Mean backlash over one mesh period (91 positions, Liu's 0.1 deg step), arcsec.
double MeanBacklash(const MeshModel& model) {
  double sum = 0;
  const int n = 91;
  for (int i = 0; i < n; ++i) {
    sum += ltca::contact::AnalyseUnloaded(model, model.kinematics().MeshPeriod() * i / (n - 1)).backlash;
  }
  return RadToArcsec(sum / n);
}

}  // namespace

TEST_CASE("contact: backlash matches the first-order closed form on the 20 cases of Liu 2021 Table 2") {
  // Liu section 5.1 Table 2 (dR_rp, dR_p in um). Closed form of the issue:
  //   backlash = 2 [dR_rp - dR_p sqrt(1 - K1^2)] / (e z_c),  K1 = z_p e / (R_p + dR_p);
  // it is first order and continuous in the pin angle; 1 % covers both.
  const double rrp[20] = {2, 3, 4, 5, 0, 0, 0, 0, -4, -3, -2, -1, 1, 2, 3, 4, 6, 7, 8, 9};
  const double rp[20] = {0, 0, 0, 0, -2, -3, -4, -5, -9, -8, -7, -6, -4, -3, -2, -1, 1, 2, 3, 4};
  const auto pair = ltca::test::LiuPair();
  for (int i = 0; i < 20; ++i) {
    CAPTURE(i + 1);
    const MeshModel model(pair, ltca::test::Mod(rrp[i], rp[i]));
    const double k1 = pair.pin_count * pair.eccentricity / (pair.pin_circle_radius + rp[i] * 1e-3);
    const double closed = 2 * (rrp[i] - rp[i] * std::sqrt(1 - k1 * k1)) * 1e-3 / (pair.eccentricity * pair.tooth_count);
    for (const double crank : {0.0, 0.04, 0.1}) {
      CHECK(ltca::contact::AnalyseUnloaded(model, crank).backlash == doctest::Approx(closed).epsilon(0.01));
    }
  }
}

TEST_CASE("contact: Liu 2021 Fig. 11 backlash slopes (pin-circle deviation, profile layer)") {
  // Liu section 5.2, base modification dR_rp = -0.004, dR_p = -0.017 mm. Published mean-backlash
  // slopes: +4.7578 arcsec/um against the pin-circle deviation, -8.4004 arcsec/um against the
  // cycloid profile upper deviation (a uniform layer). The first is reproduced when the deviation
  // moves the pins by delta_Rp (radius reading) within 0.1 %; Liu eq. 5's delta_Rp / 2 halves it.
  // The layer slope is reproduced to a few percent (tolerance 4 %; docs/validation.md).
  const auto pair = ltca::test::LiuPair();
  const auto slope = [&](auto set) {
    ManufacturingErrors lo, hi;
    set(lo, -1e-3);
    set(hi, +1e-3);
    return (MeanBacklash(MeshModel(pair, ltca::test::Mod(-4, -17), hi)) - MeanBacklash(MeshModel(pair, ltca::test::Mod(-4, -17), lo))) / 2.0;
  };
  const double pin_radius_reading = slope([](ManufacturingErrors& e, double v) { e.pin_circle_deviation = v; });
  const double pin_diameter_reading = slope([](ManufacturingErrors& e, double v) {
    e.pin_circle_deviation = v;
    e.pin_circle_reading = ManufacturingErrors::PinCircleReading::kDiameter;
  });
  const double layer = slope([](ManufacturingErrors& e, double v) { e.profile_layer = v; });
  MESSAGE("slopes arcsec/um: pin circle (radius) ", pin_radius_reading, ", (diameter) ", pin_diameter_reading, ", layer ", layer);
  CHECK(pin_radius_reading == doctest::Approx(4.7578).epsilon(1e-3));
  CHECK(pin_diameter_reading == doctest::Approx(4.7578 / 2).epsilon(1e-3));
  CHECK(layer == doctest::Approx(-8.4004).epsilon(0.04));
}

TEST_CASE("contact: Li Table 1 pair touches first at the pin about arccos(K1) from the line of centres") {
  // Li Table 1: z_p 40, z_c 39, r 2, e 0.9, B 10, R_p 52.15, dR_rp +0.01, dR_p -0.012 mm. Li's
  // first-contact pin (No. 35 in his numbering) is the one nearest arccos(K1) = 46.3 deg from the
  // line of centres (where the closed-form c_i / L_i is smallest): within half a pin pitch.
  const ltca::geometry::PairParameters li{40, 39, 2.0, 52.15, 0.9, 10.0};
  const MeshModel model(li, ltca::test::Mod(10, -12));
  const double k1 = 40 * 0.9 / (52.15 - 0.012);
  for (const double crank : {0.0, 0.03, 0.1}) {
    const auto tca = ltca::contact::AnalyseUnloaded(model, crank);
    const double angle = model.kinematics().AngleFromLineOfCentres(tca.first_pin_c1, crank);
    CHECK(std::abs(angle - std::acos(k1)) <= ltca::units::kPi / 40 + 1e-12);
  }
}

TEST_CASE("contact: an exact closing rotation stays within a quarter tooth pitch, so backlash stays finite") {
  // Issue 10: on the Liu section 5.2 base pair (dR_rp -4 um, dR_p -17 um) at crank
  // 8.99756997569976 deg, pin 2 lies near the line of centres with an arm of 0.015 mm; its
  // linearised closing rotation is 0.86 rad, and an unguarded exact Newton iteration from there
  // found a "closing" 1281.77 rad away (the exact geometry repeats every tooth pitch). Every
  // closing rotation must be infinite or within contact::RotationWindow, and the backlash at that
  // crank must match the first-order closed form of the Table 2 test within 1 %.
  const auto pair = ltca::test::LiuPair();
  const MeshModel model(pair, ltca::test::Mod(-4, -17));
  const double crank = ltca::units::DegToRad(8.99756997569976);
  const double window = ltca::contact::RotationWindow(model);
  CHECK(window == doctest::Approx(0.25 * 2 * M_PI / 39).epsilon(1e-12));
  for (const auto& pin : model.Evaluate(crank).pins) {
    if (std::abs(pin.arm) < 1e-9 * pair.pin_circle_radius) continue;
    CAPTURE(pin.pin + 1);
    const double psi = ltca::contact::ClosingRotation(model, pin, crank, ltca::contact::ContactKinematics::kExact);
    CHECK((std::isinf(psi) || std::abs(psi) <= window));
    if (std::isfinite(psi)) CHECK(psi * pin.arm > 0.0);  // a pin with clearance closes in the sense of its arm
  }
  const double k1 = pair.pin_count * pair.eccentricity / (pair.pin_circle_radius - 0.017);
  const double closed = 2 * (-0.004 + 0.017 * std::sqrt(1 - k1 * k1)) / (pair.eccentricity * pair.tooth_count);
  CHECK(ltca::contact::AnalyseUnloaded(model, crank).backlash == doctest::Approx(closed).epsilon(0.01));
}
