// Issue 9: the modification and the errors are applied once, in geometry::RealPair. Independent
// references: the profile generated directly with the layer folded into the pin radius, and the
// pin centre placed by hand on the pin circle.
#include <cmath>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/geometry/real_pair.hpp"
#include "pairs.hpp"

using ltca::geometry::CycloidProfile;
using ltca::geometry::ManufacturingErrors;
using ltca::geometry::Modification;
using ltca::geometry::RealPair;

TEST_CASE("geometry: the real pair's profile carries the layer, its pins the pin-circle and pitch deviations") {
  const auto pair = ltca::test::LiuPair();
  const Modification modification{-0.004, -0.017, 0.0, {}};
  ManufacturingErrors errors;
  errors.profile_layer = 0.002;          // 2 um more material on the cycloid
  errors.pin_circle_deviation = 0.005;   // pins 5 um further out (radius reading)
  errors.cumulative_pitch_deviation.assign(40, 0.0);
  errors.cumulative_pitch_deviation[6] = -0.007;
  const RealPair real(pair, modification, errors);

  // The layer acts as the generating pin radius r_rp + dR_rp - t (Liu eq. 1 with the layer).
  const CycloidProfile by_hand(pair, Modification{-0.004 - 0.002, -0.017, 0.0, {}});
  const CycloidProfile nominal(pair, modification);
  for (const double u : {-0.05, 0.0, 0.03}) {
    CHECK((real.profile().Position(u, 3) - by_hand.Position(u, 3)).norm() <= 1e-12);
    CHECK((real.profile().Position(u, 3) - nominal.Position(u, 3)).norm() > 1e-3 * 0.002);
  }
  CHECK(real.pin_circle_radius() == doctest::Approx(64.005).epsilon(1e-15));
  // Pin 7 moved 7 um clockwise along its circle; pin 1 only radially.
  const double a7 = 2.0 * M_PI * 6 / 40 - 0.007 / 64.005;
  CHECK((real.PinCentre(6) - 64.005 * Eigen::Vector2d(std::cos(a7), std::sin(a7))).norm() <= 1e-12);
  CHECK((real.PinCentre(0) - Eigen::Vector2d(64.005, 0.0)).norm() <= 1e-12);
}

TEST_CASE("geometry: a profile layer that makes the profile invalid is blamed on the layer key") {
  ManufacturingErrors errors;
  errors.profile_layer = -20.0;  // generating pin radius 3 + 20 = 23 mm: beyond the locus curvature (undercut)
  std::string message;
  try {
    const RealPair real(ltca::test::LiuPair(), Modification{}, errors);
  } catch (const std::invalid_argument& e) {
    message = e.what();
  }
  CHECK(message.find("[errors] cycloid_profile_layer_mm = -20") != std::string::npos);
}
