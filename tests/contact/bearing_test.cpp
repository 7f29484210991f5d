// The bearing element of issue 25 (contact/bearing.hpp). References computed independently of
// the code (a separate bisection in Python, from Harris & Kotzalas's formulas as printed), and
// Stribeck's classical factor for a line-contact bearing without clearance.
#include <algorithm>
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
  b = Rollers(-0.001);  // a preload (issue 52)
  CHECK_NOTHROW(b.Validate());
  b = Rollers(std::numeric_limits<double>::infinity());
  CHECK_THROWS_WITH_AS(b.Validate(), doctest::Contains("[bearing] radial_clearance_mm = inf"), std::invalid_argument);
  b = Rollers(0.0);
  b.kind = BearingKind::kLinear;
  CHECK_THROWS_WITH_AS(b.Validate(), doctest::Contains("radial_stiffness_n_per_mm = 0"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(ltca::contact::ParseBearingKind("needle"), doctest::Contains("[bearing] kind = \"needle\""),
                       std::invalid_argument);
  BearingSettings rigid;
  CHECK_THROWS_AS(BearingAt(rigid, {0.01, 0.0}), std::invalid_argument);
}

namespace bearing_life_test {

/// The eccentric bearing of cases/stage/cycloidal_drive.toml: 14 rollers 8 x 10 mm on a 40 mm
/// pitch circle, C = 39.6 kN.
BearingSettings Eccentric(double clearance) {
  BearingSettings b;
  b.kind = BearingKind::kRollers;
  b.roller_count = 14;
  b.roller_diameter = 8.0;
  b.roller_length = 10.0;
  b.pitch_diameter = 40.0;
  b.dynamic_load_rating = 39600.0;
  b.radial_clearance = clearance;
  return b;
}

/// Roller loads without play under `load` (N) along +X, rollers at phase + 2 pi j / z, solved
/// here, not by BearingDisplacement: without play the loads go as max(cos(psi_j - beta), 0)^(10/9)
/// for a displacement along beta; beta by bisection until the force points along +X, then scaled.
std::vector<double> TightLoads(int z, double phase, double load) {
  const double pi = std::acos(-1.0);
  const auto loads = [&](double beta) {
    std::vector<double> q(static_cast<std::size_t>(z));
    for (int j = 0; j < z; ++j) q[static_cast<std::size_t>(j)] = std::pow(std::max(std::cos(phase + 2.0 * pi * j / z - beta), 0.0), 10.0 / 9.0);
    return q;
  };
  const auto force = [&](const std::vector<double>& q, bool y) {
    double f = 0.0;
    for (int j = 0; j < z; ++j) {
      const double a = phase + 2.0 * pi * j / z;
      f += q[static_cast<std::size_t>(j)] * (y ? std::sin(a) : std::cos(a));
    }
    return f;
  };
  double lo = -0.5, hi = 0.5;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (force(loads(mid), true) > 0.0 ? hi : lo) = mid;
  }
  std::vector<double> q = loads(0.5 * (lo + hi));
  const double fx = force(q, false);
  for (double& x : q) x *= load / fx;
  return q;
}

}  // namespace bearing_life_test

TEST_CASE("contact: the Lundberg-Palmgren raceway capacities and damage, against a hand computation") {
  // Harris & Kotzalas (line contact): Q_c,in / Q_c,out = ((1 - g) / (1 + g))^(29/27 + 1/4);
  // g = 8 / 40 = 0.2 gives 0.5845775452. Four rollers carrying 3000, 1200, 0, 0 N: the exponent-4
  // mean 2134.768373 N, the exponent-4.5 mean 2212.484358 N; with the inner raceway turning
  // against the load (exponent 4) L_in = (0.58458 / 2134.77)^4 = 5.622966e-15, L_out = (1 /
  // 2212.48)^4 = 4.173296e-14 (Q_c,out = 1 N), 1/L = (L_in^(-9/8) + L_out^(-9/8))^(8/9) =
  // 1.9432787816e14; with the outer turning 2.1899578806e14. All computed independently in
  // Python from the formulas as printed. Tolerance 1e-9 relative.
  const double ratio = ltca::contact::RacewayCapacityRatio(8.0, 40.0);
  CHECK(ratio == doctest::Approx(0.5845775452).epsilon(1e-9));
  const auto m = ltca::contact::LoadMoments({3000.0, 1200.0, 0.0, 0.0});
  CHECK(std::pow(m.fourth, 0.25) == doctest::Approx(2134.768373).epsilon(1e-9));
  CHECK(std::pow(m.four_and_half, 1.0 / 4.5) == doctest::Approx(2212.484358).epsilon(1e-9));
  CHECK(ltca::contact::LundbergPalmgrenDamage(m, ratio, ltca::contact::Raceway::kInner) ==
        doctest::Approx(1.9432787816e14).epsilon(1e-9));
  CHECK(ltca::contact::LundbergPalmgrenDamage(m, ratio, ltca::contact::Raceway::kOuter) ==
        doctest::Approx(2.1899578806e14).epsilon(1e-9));
}

TEST_CASE("contact: without play, a stationary load and the inner ring turning, the load-zone life is ISO 281's basic life") {
  // The calibration (contact/bearing.hpp): under the reference condition, at any load, the
  // load-zone life equals (C / F)^(10/3). The roller loads are solved by the test's own bisection
  // (TightLoads) over the reference's roller phases; Palmgren-Miner over them. Tolerance 1e-9.
  BearingSettings b = bearing_life_test::Eccentric(0.0);
  const double reference = ltca::contact::LoadZoneReferenceDamage(b);
  const double ratio = ltca::contact::RacewayCapacityRatio(b.roller_diameter, b.pitch_diameter);
  const double pitch = 2.0 * std::acos(-1.0) / b.roller_count;
  for (const double load : {500.0, 5293.0, 20000.0}) {
    CAPTURE(load);
    double damage = 0.0;
    for (int k = 0; k < ltca::contact::kReferencePhases; ++k) {
      const auto q = bearing_life_test::TightLoads(b.roller_count, pitch * k / ltca::contact::kReferencePhases, load);
      damage += ltca::contact::LundbergPalmgrenDamage(ltca::contact::LoadMoments(q), ratio, ltca::contact::Raceway::kInner);
    }
    const double p = ltca::contact::LoadZoneEquivalentLoad(damage / ltca::contact::kReferencePhases, reference);
    CHECK(p == doctest::Approx(load).epsilon(1e-9));
    CHECK(ltca::contact::RatingLife(b.dynamic_load_rating, p) ==
          doctest::Approx(std::pow(b.dynamic_load_rating / load, 10.0 / 3.0)).epsilon(1e-9));
  }
  // The reference does not depend on the deck's play or rating (it is solved without play and
  // scaled to 1 N).
  BearingSettings loose = bearing_life_test::Eccentric(0.005);
  loose.dynamic_load_rating = 20000.0;
  CHECK(ltca::contact::LoadZoneReferenceDamage(loose) == doctest::Approx(reference).epsilon(1e-9));
  // With play the same load gives a shorter life: fewer rollers carry it.
  const Eigen::Vector2d u = BearingDisplacement(loose, Eigen::Vector2d(5293.0, 0.0));
  const auto m = ltca::contact::LoadMoments(BearingAt(loose, u).roller_load);
  CHECK(ltca::contact::LoadZoneEquivalentLoad(ltca::contact::LundbergPalmgrenDamage(m, ratio, ltca::contact::Raceway::kInner),
                                              reference) > 5293.0 * 1.05);
}

TEST_CASE("contact: a roller's contact stress on the inner raceway is Hertz's line contact (ISO 76's basis)") {
  // Johnson eq. 4.45: p0 = sqrt(Q E* / (pi l R)); roller 8 mm on an inner raceway of 32 mm
  // diameter (d_m 40 mm): 1/R = 2/8 + 2/32 = 0.3125 /mm; E* = 207000 / (2 x 0.91) MPa; Q = 1000 N,
  // l = 10 mm: p0 = 1063.651981 MPa (computed independently). Tolerance 1e-9.
  const BearingSettings b = bearing_life_test::Eccentric(0.0);
  CHECK(ltca::contact::RollerContactStress(b, 1000.0) == doctest::Approx(1063.651981).epsilon(1e-9));
  CHECK(ltca::contact::RollerContactStress(b, 0.0) == 0.0);
  // ISO 76's C_0 = 44 (1 - D_w / d_m) l Z D_w = 39,424 N; at Stribeck's Q_max = 5 C_0 / Z (ISO 76's
  // load distribution) the stress is 4,000 MPa within 0.5 % (E = 207 GPa here).
  const double c0 = 44.0 * (1.0 - 0.2) * 10.0 * 14.0 * 8.0;
  CHECK(ltca::contact::RollerContactStress(b, 5.0 * c0 / 14.0) == doctest::Approx(ltca::contact::kStaticStressLimitRoller).epsilon(5e-3));
  BearingSettings no_pitch = b;
  no_pitch.pitch_diameter = 0.0;
  CHECK_THROWS_WITH_AS(ltca::contact::RollerContactStress(no_pitch, 1000.0), doctest::Contains("[bearing] pitch_diameter_mm = 0"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(ltca::contact::LoadZoneReferenceDamage(no_pitch), doctest::Contains("[bearing] pitch_diameter_mm = 0"),
                       std::invalid_argument);
}

TEST_CASE("contact: [bearing] pitch_diameter_mm and static_load_rating_n are refused with the key, the value and what is expected") {
  BearingSettings b = bearing_life_test::Eccentric(0.0);
  CHECK_NOTHROW(b.Validate());
  b.pitch_diameter = 30.0;  // 14 rollers of 8 mm need 8 / sin(pi / 14) = 35.95 mm
  CHECK_THROWS_WITH_AS(b.Validate(), doctest::Contains("[bearing] pitch_diameter_mm = 30: expected 0 (not given) or a pitch diameter"),
                       std::invalid_argument);
  b.pitch_diameter = 0.0;
  CHECK_NOTHROW(b.Validate());
  b.static_load_rating = -1.0;
  CHECK_THROWS_WITH_AS(b.Validate(), doctest::Contains("[bearing] static_load_rating_n = -1"), std::invalid_argument);
}

TEST_CASE("contact: a preloaded bearing, rollers and linear, against a ring of discrete elements pressed by the preload") {
  // Issue 52: radial_clearance_mm < 0. Independent reference: the elements summed one by one.
  // Rollers: Z = 14, each pressed by p = 2 um at no load, Q_j = K_n (u . e_j + p)^(10/9) (the roller
  // law of the first test case, K_n at l = 10 mm); at u = 0 every roller carries K_n p^(10/9) and the
  // forces cancel (to rounding: 1e-9 of one roller's load).
  const double p = 0.002, kn = 288874.8650;
  const BearingSettings rollers = Rollers(-p);
  const auto at_rest = BearingAt(rollers, {0.0, 0.0});
  REQUIRE(at_rest.roller_load.size() == 14);
  for (const double q : at_rest.roller_load) CHECK(q == doctest::Approx(kn * std::pow(p, 10.0 / 9.0)).epsilon(1e-9));
  CHECK(at_rest.force.norm() <= 1e-9 * kn * std::pow(p, 10.0 / 9.0));
  for (const Eigen::Vector2d& u : {Eigen::Vector2d(0.0015, 0.0004), Eigen::Vector2d(-0.004, 0.003)}) {
    Eigen::Vector2d want = Eigen::Vector2d::Zero();
    for (int j = 0; j < 14; ++j) {
      const double t = 2.0 * std::acos(-1.0) * j / 14;
      const Eigen::Vector2d e(std::cos(t), std::sin(t));
      want -= kn * std::pow(std::max(0.0, u.dot(e) + p), 10.0 / 9.0) * e;
    }
    CHECK((BearingAt(rollers, u).force - want).norm() <= 1e-9 * want.norm());
  }
  // Linear, k = 5e4 N/mm: the ring of Z = 200000 linear elements of k_e = 4 k / Z, each pressed by p
  // (the unpreloaded ring's radial stiffness is k_e Z / 4 = k). Force, energy (less its value at
  // u = 0) and the tangent stiffness (central differences of the summed force, step 1e-7 mm)
  // within 1e-6 relative (the sum's discretisation, 1 / Z^2 in the force).
  BearingSettings linear;
  linear.kind = BearingKind::kLinear;
  linear.radial_stiffness = 5e4;
  linear.radial_clearance = -p;
  CHECK_NOTHROW(linear.Validate());
  const int z = 200000;
  const double ke = 4.0 * linear.radial_stiffness / z;
  const auto ring = [&](const Eigen::Vector2d& u, double* energy) {
    Eigen::Vector2d f = Eigen::Vector2d::Zero();
    double e0 = 0.0, e1 = 0.0;
    for (int j = 0; j < z; ++j) {
      const double t = 2.0 * std::acos(-1.0) * (j + 0.5) / z;
      const Eigen::Vector2d e(std::cos(t), std::sin(t));
      const double d = std::max(0.0, u.dot(e) + p);
      f -= ke * d * e;
      e1 += 0.5 * ke * d * d;
      e0 += 0.5 * ke * p * p;
    }
    if (energy != nullptr) *energy = e1 - e0;
    return f;
  };
  for (const Eigen::Vector2d& u : {Eigen::Vector2d(0.0012, -0.0005), Eigen::Vector2d(0.003, 0.0021), Eigen::Vector2d(-0.009, 0.0)}) {
    CAPTURE(u.x());
    double energy = 0.0;
    const Eigen::Vector2d want = ring(u, &energy);
    const auto r = BearingAt(linear, u);
    CHECK((r.force - want).norm() <= 1e-6 * want.norm());
    CHECK(r.energy == doctest::Approx(energy).epsilon(1e-6));
    const double h = 1e-7;
    for (int a = 0; a < 2; ++a) {
      Eigen::Vector2d du = Eigen::Vector2d::Zero();
      du(a) = h;
      const Eigen::Vector2d column = -(ring(u + du, nullptr) - ring(u - du, nullptr)) / (2.0 * h);
      CHECK((r.stiffness.col(a) - column).norm() <= 1e-5 * r.stiffness.norm());
    }
  }
  // While |u| <= p every element works: twice the stiffness without play; as p -> 0 the law without play.
  CHECK((BearingAt(linear, {0.001, 0.0}).force - Eigen::Vector2d(-2.0 * 5e4 * 0.001, 0.0)).norm() <= 1e-9);
  BearingSettings tiny = linear;
  tiny.radial_clearance = -1e-12;
  BearingSettings none = linear;
  none.radial_clearance = 0.0;
  CHECK((BearingAt(tiny, {0.003, 0.001}).force - BearingAt(none, {0.003, 0.001}).force).norm() <= 1e-6);
}
