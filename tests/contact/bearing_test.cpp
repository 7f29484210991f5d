// The bearing element of issue 25 (contact/bearing.hpp). References computed independently of
// the code (a separate bisection in Python, from Harris & Kotzalas's formulas as printed), and
// Stribeck's classical factor for a line-contact bearing without clearance.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/contact/bearing.hpp"

using ltca::contact::BearingAt;
using ltca::contact::BearingDisplacement;
using ltca::contact::BearingKind;
using ltca::contact::BearingSettings;

namespace {

/// Z = 14 rollers of effective length 10 mm (diameter 4 mm), one on +X, radial play c (mm).
BearingSettings Rollers(double clearance) {
  BearingSettings b;
  b.kind = BearingKind::kRollers;
  b.roller_count = 14;
  b.roller_diameter = 4.0;
  b.roller_length = 10.0;
  b.radial_clearance = clearance;
  return b;
}

}  // namespace

TEST_CASE("contact: a roller between both raceways follows Palmgren's line contact, two contacts in series") {
  // Harris & Kotzalas: delta = 3.84e-5 Q^0.9 / l^0.8 per contact; K_n = (7.68e-5)^(-10/9) l^(8/9)
  // = 288,874.8650 N/mm^(10/9) at l = 10 mm (computed independently). Tolerance 1e-9 relative.
  const double kn = 288874.8650;
  for (const double delta : {1e-4, 3e-3, 2e-2}) {
    CAPTURE(delta);
    CHECK(ltca::contact::RollerLoad(delta, 10.0) == doctest::Approx(kn * std::pow(delta, 10.0 / 9.0)).epsilon(1e-9));
    const double q = ltca::contact::RollerLoad(delta, 10.0);
    CHECK(2.0 * ltca::contact::PalmgrenApproach(q, 10.0) == doctest::Approx(delta).epsilon(1e-12));
    CHECK(ltca::contact::PalmgrenLoad(ltca::contact::PalmgrenApproach(q, 10.0), 10.0) == doctest::Approx(q).epsilon(1e-12));
  }
  CHECK(ltca::contact::RollerLoad(0.0, 10.0) == 0.0);
  CHECK(ltca::contact::RollerLoad(-1e-3, 10.0) == 0.0);
}

TEST_CASE("contact: a 14-roller bearing under 5 kN carries Harris's static load distribution, with and without play") {
  // Harris, "Distribution of internal loading in statically loaded bearings": delta_j =
  // d cos(psi_j) - P_d / 2, Q_j = K_n delta_j^(10/9), F_r = sum Q_j cos(psi_j). Reference values from
  // an independent bisection on d (to 1e-16 mm), Z = 14, l = 10 mm, F_r = 5000 N along +X.
  // Tolerances: 1e-9 relative (the Newton solve stops at 1e-12 of the load).
  struct Reference {
    double clearance, d, q0, q1, q2, q3;
  };
  for (const Reference& ref : {Reference{0.005, 0.014686982934229, 1671.6350193, 1395.1944940, 653.0270188, 0.0},
                               Reference{0.0, 0.0085721593843234, 1459.2958675, 1299.6334811, 863.3282824, 274.7893390}}) {
    CAPTURE(ref.clearance);
    const BearingSettings b = Rollers(ref.clearance);
    const Eigen::Vector2d u = BearingDisplacement(b, {5000.0, 0.0});
    CHECK(u.x() == doctest::Approx(ref.d).epsilon(1e-9));
    CHECK(std::abs(u.y()) < 1e-12);
    const auto r = BearingAt(b, u);
    CHECK(-r.force.x() == doctest::Approx(5000.0).epsilon(1e-11));
    const std::vector<double>& q = r.roller_load;
    REQUIRE(q.size() == 14);
    CHECK(q[0] == doctest::Approx(ref.q0).epsilon(1e-9));
    for (const std::size_t j : {std::size_t{1}, std::size_t{13}}) CHECK(q[j] == doctest::Approx(ref.q1).epsilon(1e-9));
    for (const std::size_t j : {std::size_t{2}, std::size_t{12}}) CHECK(q[j] == doctest::Approx(ref.q2).epsilon(1e-9));
    for (const std::size_t j : {std::size_t{3}, std::size_t{11}}) {
      if (ref.q3 == 0.0) {
        CHECK(q[j] == 0.0);  // with play the loaded zone ends at 70.1 deg: this roller is open
      } else {
        CHECK(q[j] == doctest::Approx(ref.q3).epsilon(1e-9));
      }
    }
    for (std::size_t j = 4; j <= 10; ++j) CHECK(q[j] == 0.0);
    if (ref.clearance == 0.0) {
      // Stribeck: Q_max = 4.08 F_r / Z for line contact without clearance (the continuous
      // integral; 14 discrete rollers give 4.086).
      CHECK(q[0] / (5000.0 / 14) == doctest::Approx(4.08).epsilon(2e-3));
    }
  }
}

TEST_CASE("contact: a bearing carries nothing within its play, and its tangent stiffness is the derivative of its force") {
  for (const BearingKind kind : {BearingKind::kLinear, BearingKind::kRollers}) {
    CAPTURE(ltca::contact::ToString(kind));
    BearingSettings b = Rollers(0.01);
    b.kind = kind;
    b.radial_stiffness = 2e5;
    // Within the play, in any direction: no force, no stiffness, no energy.
    for (int k = 0; k < 12; ++k) {
      const double a = 0.37 + k * 0.5;
      const auto r = BearingAt(b, 0.0099 * Eigen::Vector2d(std::cos(a), std::sin(a)));
      CHECK(r.force.norm() == 0.0);
      CHECK(r.energy == 0.0);
    }
    // Beyond it: -dF/du by central differences (step 1e-7 mm), 1e-5 relative; dE/du = -F.
    const Eigen::Vector2d u(0.013, 0.004);
    const auto r = BearingAt(b, u);
    for (int i = 0; i < 2; ++i) {
      Eigen::Vector2d h = Eigen::Vector2d::Zero();
      h[i] = 1e-7;
      const auto plus = BearingAt(b, u + h), minus = BearingAt(b, u - h);
      const Eigen::Vector2d column = -(plus.force - minus.force) / 2e-7;
      CHECK((column - r.stiffness.col(i)).norm() <= 1e-5 * r.stiffness.norm());
      CHECK((plus.energy - minus.energy) / 2e-7 == doctest::Approx(-r.force[i]).epsilon(1e-5));
    }
  }
  // A linear bearing: F = k (|u| - c) along u, exactly.
  BearingSettings linear;
  linear.kind = BearingKind::kLinear;
  linear.radial_stiffness = 2e5;
  linear.radial_clearance = 0.01;
  const Eigen::Vector2d u = BearingDisplacement(linear, {3000.0, -4000.0});
  CHECK(u.norm() == doctest::Approx(0.01 + 5000.0 / 2e5).epsilon(1e-12));
  CHECK(u.x() / u.norm() == doctest::Approx(0.6).epsilon(1e-12));
}

TEST_CASE("contact: ISO 281 basic rating life of a load that varies over a revolution, against a hand computation") {
  // ISO 281:2007: L10 = (C / P)^(10/3) million revolutions for roller bearings, L10h = 1e6 L10 /
  // (60 n); the mean of loads over equal steps P_m = (sum P_i^p / N)^(1/p). C = 30 kN, eight equal
  // steps, 1500 rpm: P_m = 5326.038022 N, L10 = 317.9728021, L10h = 3533.031134 h (computed
  // independently); with p = 3 (ball bearings) P_m = 5283.609026 N. Tolerance 1e-9 relative.
  const std::vector<double> loads = {4000, 5000, 6000, 7000, 6000, 5000, 4000, 3000};
  const double pm = ltca::contact::MeanEquivalentLoad(loads);
  CHECK(pm == doctest::Approx(5326.038022).epsilon(1e-9));
  const double l10 = ltca::contact::RatingLife(30000.0, pm);
  CHECK(l10 == doctest::Approx(317.9728021).epsilon(1e-9));
  CHECK(ltca::contact::RatingLifeHours(l10, 1500.0) == doctest::Approx(3533.031134).epsilon(1e-9));
  CHECK(ltca::contact::MeanEquivalentLoad(loads, ltca::contact::kBallLifeExponent) == doctest::Approx(5283.609026).epsilon(1e-9));
  // No rating, no load, no speed: no number pretends to be a life.
  CHECK(std::isnan(ltca::contact::RatingLife(0.0, pm)));
  CHECK(std::isinf(ltca::contact::RatingLife(30000.0, 0.0)));
  CHECK(std::isnan(ltca::contact::MeanEquivalentLoad({})));
  CHECK(std::isnan(ltca::contact::RatingLifeHours(l10, 0.0)));
}

TEST_CASE("contact: [bearing] settings are refused with the key, the value and what is expected") {
  BearingSettings b = Rollers(0.005);
  CHECK_NOTHROW(b.Validate());
  b.roller_count = 2;
  CHECK_THROWS_WITH_AS(b.Validate(), doctest::Contains("[bearing] roller_count = 2: expected 3 to 200 rollers"),
                       std::invalid_argument);
  b.roller_count = 201;
  CHECK_THROWS_WITH_AS(b.Validate(), doctest::Contains("[bearing] roller_count = 201: expected 3 to 200 rollers"),
                       std::invalid_argument);
  b.roller_count = 14;
  b = Rollers(-0.001);
  CHECK_THROWS_WITH_AS(b.Validate(), doctest::Contains("[bearing] radial_clearance_mm = -0.001"), std::invalid_argument);
  b = Rollers(0.0);
  b.kind = BearingKind::kLinear;
  CHECK_THROWS_WITH_AS(b.Validate(), doctest::Contains("radial_stiffness_n_per_mm = 0"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(ltca::contact::ParseBearingKind("needle"), doctest::Contains("[bearing] kind = \"needle\""),
                       std::invalid_argument);
  BearingSettings rigid;
  CHECK_THROWS_AS(BearingAt(rigid, {0.01, 0.0}), std::invalid_argument);
}
