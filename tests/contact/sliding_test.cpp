// Issue 14: sliding kinematics (Jiang 2022 eq. 13-14) and the mixed-lubrication friction model
// (Jiang eq. 20-26), checked against independent sources: finite differences of the contact
// points over crank angle, Jiang's pitch-point distance, Pan-Hamrock in SI units, Hertz means.
#include <cmath>

#include <doctest/doctest.h>

#include "ltca/contact/mesh_state.hpp"
#include "ltca/contact/sliding.hpp"
#include "ltca/geometry/units.hpp"
#include "pairs.hpp"

using ltca::contact::MeshModel;
using ltca::contact::PinContact;
using ltca::units::kPi;
namespace c = ltca::contact;

namespace {

using ltca::geometry::Perp;

// Compares the closed-form velocities of every pin with a central difference of the contact
// points over crank angle (h = 1e-5 rad: truncation ~1e-10 of the velocity, the foot point's
// Newton tolerance ~1e-12 mm over 2h ~5e-8). Tolerance 1e-6 mm per rad of crank.
void CheckAgainstFiniteDifference(const MeshModel& model, double crank, bool conjugate) {
  const double h = 1e-5;
  const c::PoseRate rate = c::PoseRatePerCrank(model, crank, 0.0, model.SliceZ(0));
  const ltca::geometry::Pose pose = model.CyclePose(crank, 0.0, model.SliceZ(0));
  const ltca::geometry::Pose plus = model.CyclePose(crank + h, 0.0, model.SliceZ(0));
  const ltca::geometry::Pose minus = model.CyclePose(crank - h, 0.0, model.SliceZ(0));
  int checked = 0;
  for (int pin = 0; pin < model.pin_count(); ++pin) {
    const PinContact p = model.EvaluatePoint(pin, 0, crank);
    if (p.edge || std::abs(p.arm) < 1e-3) continue;  // the cusps (root, tip): no smooth motion
    const PinContact pp = model.EvaluatePoint(p, crank + h, 0.0), pm = model.EvaluatePoint(p, crank - h, 0.0);
    if (pp.tooth_space != p.tooth_space || pm.tooth_space != p.tooth_space) continue;
    const c::ContactVelocities v = c::Velocities(p, pose, rate);
    const Eigen::Vector2d t = Perp(p.normal);
    CAPTURE(pin);
    // The contact point on the pin (pins fixed): dP/dtheta.
    const Eigen::Vector2d dp = (pp.pin_point - pm.pin_point) / (2 * h);
    CHECK(std::abs(t.dot(dp) - v.point_over_pin) < 1e-6);
    CHECK(std::abs(p.normal.dot(dp)) < 1e-6);  // it moves along the pin surface
    // The contact point over the cycloid: the body-frame point's rate, turned into the fixed frame.
    const Eigen::Vector2d body_rate = (plus.ToBody(pp.cycloid_point) - minus.ToBody(pm.cycloid_point)) / (2 * h);
    CHECK(std::abs(t.dot(pose.DirectionToFixed(body_rate)) - v.point_over_cycloid) < 1e-6);
    // The material point of the cycloid at the contact: its velocity relative to the fixed pin.
    const Eigen::Vector2d x = pose.ToBody(p.cycloid_point);
    const Eigen::Vector2d dm = (plus.ToFixed(x) - minus.ToFixed(x)) / (2 * h);
    CHECK(std::abs(t.dot(dm) - v.sliding) < 1e-6);
    CHECK(std::abs(p.normal.dot(dm) - v.normal) < 1e-6);
    if (conjugate && std::abs(p.clearance) < 1e-9) CHECK(std::abs(v.normal) < 1e-6);  // in conjugate contact: no approach rate
    ++checked;
  }
  CHECK(checked >= model.pin_count() / 3);  // the rest: cusps, or a tooth-space change within +-h
}

}  // namespace

TEST_CASE("contact: sliding and contact-point velocities match a finite difference of the contact points") {
  for (const auto& named : ltca::test::AllPairs()) {
    CAPTURE(named.name);
    const MeshModel unmodified(named.pair, {});
    for (const double crank : {0.0, 0.37, 1.9}) CheckAgainstFiniteDifference(unmodified, crank, true);
    const MeshModel modified(named.pair, ltca::test::Mod(4, -9));
    for (const double crank : {0.0, 0.37}) CheckAgainstFiniteDifference(modified, crank, false);
  }
}

TEST_CASE("contact: the sliding speed is omega_c times the distance from the pitch point (Jiang eq. 13)") {
  // Jiang 2022 eq. 13: v_k = omega_c |I_cp k|, |I_cp k| = sqrt(R_b^2 + d^2 - 2 R_b d cos theta_i) - r_p,
  // d = e z_b / (z_b - z_a) from O_b. Per radian of crank omega_c = -(z_p - z_c) / z_c. 1e-9 mm.
  for (const auto& named : ltca::test::AllPairs()) {
    CAPTURE(named.name);
    const MeshModel model(named.pair, {});
    const double omega_c = -static_cast<double>(named.pair.ToothDifference()) / named.pair.tooth_count;
    const double crank = 0.61;
    const c::PoseRate rate = c::PoseRatePerCrank(model, crank, 0.0, model.SliceZ(0));
    CHECK(rate.angular_velocity == doctest::Approx(omega_c).epsilon(1e-9));
    const auto pose = model.CyclePose(crank, 0.0, model.SliceZ(0));
    int checked = 0;
    for (int pin = 0; pin < model.pin_count(); ++pin) {
      const PinContact p = model.EvaluatePoint(pin, 0, crank);
      if (p.edge || std::abs(p.clearance) > 1e-9) continue;  // eq. 13 holds at the conjugate contacts
      const double expected = std::abs(omega_c) * c::PitchPointDistance(named.pair, model.kinematics(), pin, crank);
      CAPTURE(pin);
      CHECK(std::abs(std::abs(c::Velocities(p, pose, rate).sliding) - expected) < 1e-9 * named.pair.pin_circle_radius);
      ++checked;
    }
    CHECK(checked >= 3);
  }
}

TEST_CASE("contact: Pan-Hamrock film thickness in SI units equals the model's in mm, N, MPa, s") {
  // Independent evaluation in SI: E' = 2 E* = 2.286e11 Pa, R = 8 mm, l = 10 mm, F = 300 N,
  // u = 0.2 m/s, eta_0 = 0.03 Pa s, alpha = 1e-8 1/Pa; H = 1.714 W'^-0.128 U^0.694 G^0.568 (Pan and
  // Hamrock 1989). 1e-12 relative.
  const double e_prime = 2 * 1.143e11, r = 8e-3, l = 10e-3, f = 300.0, u = 0.2, eta = 0.03, alpha = 1e-8;
  const double w = f / l / (e_prime * r), uu = eta * u / (e_prime * r), g = alpha * e_prime;
  const double h_si = r * 1.714 * std::pow(w, -0.128) * std::pow(uu, 0.694) * std::pow(g, 0.568);
  c::Lubrication lub;
  lub.viscosity = 30e-9;
  lub.pressure_viscosity = 0.01;
  const double h = c::FilmThickness(lub, 300.0, 10.0, 8.0, 1.143e5, 200.0);
  CHECK(h == doctest::Approx(h_si * 1e3).epsilon(1e-12));
  CHECK(h > 1e-5);  // tenths of a micrometre: the mixed regime at Ra 0.3 um
  CHECK(h < 1e-3);
}

TEST_CASE("contact: Zhu-Hu load sharing (Jiang eq. 21) and the effective pressure (Jiang eq. 22)") {
  CHECK(c::FilmShare(1.0) == doctest::Approx(1.21 / 1.37).epsilon(1e-14));
  CHECK(c::FilmShare(0.0) == 0.0);
  CHECK(c::FilmShare(10.0) == 1.0);  // capped: the fit reaches 1 near lambda = 2.02, then falls
  CHECK(c::FilmShare(1.9) < 1.0);
  CHECK(c::FilmShare(2.1) == 1.0);
  for (double l = 0.05; l < 5.0; l += 0.05) CHECK(c::FilmShare(l) >= c::FilmShare(l - 0.05));  // monotone
  c::Lubrication lub;
  // The quadrature over the Hertz ellipse equals eq. 22 with 2 delta^2 / p_h^2 (1e-9 relative).
  for (const double ph : {50.0, 400.0, 1500.0}) {
    CAPTURE(ph);
    CHECK(c::EffectivePressure(lub, ph, true) == doctest::Approx(c::EffectivePressureClosedForm(lub, ph)).epsilon(1e-9));
    CHECK(c::EffectivePressure(lub, ph, false) < c::EffectivePressure(lub, ph, true) + ph);  // bounded by p_h
    CHECK(c::EffectivePressure(lub, ph, false) < ph);
  }
  // Without pressure-viscosity the effective pressure is the mean Hertz pressure: 2/3 p_h on the
  // ellipse, pi/4 p_h on the line (Johnson eq. 4.23, 4.45). At alpha = 1e-6 1/MPa the next term,
  // (n alpha / 2) var(p), is about 2e-5 of the mean: tolerance 1e-4.
  lub.pressure_viscosity = 1e-6;
  CHECK(c::EffectivePressure(lub, 600.0, true) == doctest::Approx(400.0).epsilon(1e-4));
  CHECK(c::EffectivePressure(lub, 600.0, false) == doctest::Approx(600.0 * kPi / 4).epsilon(1e-4));
}

TEST_CASE("contact: mixed friction is the boundary coefficient without rolling and lies between f_e and f_b") {
  c::Lubrication lub;
  const c::ContactShape line = c::LineShape(300.0, 10.0, 8.0, 1.143e5);
  CHECK(line.max_pressure == doctest::Approx(2 * 300.0 / (kPi * line.half_width * 10.0)));
  const c::MixedFriction still = c::MixedCoefficient(lub, 300.0, line, 10.0, 8.0, 1.143e5, 0.0, 100.0);
  CHECK(still.coefficient == lub.boundary_coefficient);  // no film without entrainment
  const c::MixedFriction moving = c::MixedCoefficient(lub, 300.0, line, 10.0, 8.0, 1.143e5, 2000.0, 200.0);
  CHECK(moving.lambda > 0.0);
  CHECK(moving.coefficient < lub.boundary_coefficient);
  CHECK(moving.coefficient > moving.full_film * std::pow(moving.film_share, 1.2));
  // Thick film: the named warning, f_lambda = 1 and f_mix = f_e.
  lub.roughness_cycloid = lub.roughness_pin = 1e-6;
  const c::MixedFriction thick = c::MixedCoefficient(lub, 300.0, line, 10.0, 8.0, 1.143e5, 2000.0, 200.0);
  CHECK(thick.film_share == 1.0);
  CHECK(thick.coefficient == thick.full_film);
  REQUIRE(!thick.warnings.empty());
  CHECK(thick.warnings.front().rfind("jiang.lambda_above_fit", 0) == 0);
}

TEST_CASE("contact: the limiting shear stress caps the full-film shear point by point (a hand integration on the ellipse)") {
  // Hand computation: Hertz ellipse, p = p_h g with the area density 2 g (Johnson eq. 4.23's
  // ellipsoid), shear tau(g) = min(K exp(c g), gamma p_h g), c = n alpha p_h, tau_L0 = 0 (Bair and
  // Winer 1979's tau_L = gamma p). The power law lies below the cap on [g1, g2] only (a convex
  // function minus a line); piecewise in closed form:
  //   int 2 g gamma p_h g dg = (2/3) gamma p_h g^3,   int 2 g K exp(c g) dg = 2 K exp(c g) (g / c - 1 / c^2),
  // and f_e = (A / W) (the sum), W = (2/3) p_h A. A mineral gear oil's numbers: n = 0.5, alpha =
  // 18 1/GPa, p_h = 1.5 GPa (c = 13.5), K = 0.5 MPa, gamma = 0.06: the crossings near g = 0.007 and 0.29.
  c::Lubrication lub;
  lub.power_law_exponent = 0.5;
  lub.pressure_viscosity = 0.018;
  lub.limiting_shear_coefficient = 0.06;
  c::ContactShape shape;
  shape.point = true;
  shape.max_pressure = 1500.0;
  shape.area = 2.0;
  const double force = 2.0 / 3.0 * shape.max_pressure * shape.area, k = 0.5, gamma = 0.06, ph = 1500.0, cc = 13.5;
  const auto gap = [&](double g) { return k * std::exp(cc * g) - gamma * ph * g; };
  const auto cross = [&](double lo, double hi) {  // gap changes sign on [lo, hi]
    const bool rising = gap(hi) > gap(lo);
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      ((gap(mid) > 0.0) == rising ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  };
  REQUIRE(gap(1e-9) > 0.0);
  REQUIRE(gap(0.1) < 0.0);
  REQUIRE(gap(1.0) > 0.0);
  const double g1 = cross(1e-9, 0.1), g2 = cross(0.1, 1.0);
  CHECK(g1 == doctest::Approx(0.007).epsilon(0.2));
  CHECK(g2 == doctest::Approx(0.29).epsilon(0.05));
  const auto capped = [&](double a, double b) { return 2.0 / 3.0 * gamma * ph * (b * b * b - a * a * a); };
  const auto power = [&](double g) { return 2.0 * k * std::exp(cc * g) * (g / cc - 1.0 / (cc * cc)); };
  const double hand = shape.area / force * (capped(0.0, g1) + power(g2) - power(g1) + capped(g2, 1.0));
  const double model = c::CappedFullFilm(lub, k, shape, force);
  CHECK(model == doctest::Approx(hand).epsilon(1e-9));
  CHECK(model < gamma);  // tau <= gamma p everywhere: f_e <= gamma
  CHECK(model > 0.9 * gamma);
  // Without the cap the same contact's coefficient is (A / W) K mean(exp(c g)), beyond any oil.
  const double uncapped = shape.area / force * (power(1.0) - power(0.0));
  CHECK(uncapped > 10.0);  // 50: fifty times the load in traction
  // A cap that never binds (tau_L0 above the power law's largest stress) gives eq. 23 unchanged.
  lub.limiting_shear_stress = 1e3;
  lub.pressure_viscosity = 0.002;  // c = 1.5: K exp(c) = 2.24 MPa < tau_L0
  const double free_film = shape.area / force * 2.0 * k *
                           (std::exp(1.5) * (1.0 / 1.5 - 1.0 / 2.25) + 1.0 / 2.25);
  CHECK(c::CappedFullFilm(lub, k, shape, force) == doctest::Approx(free_film).epsilon(1e-9));
}
