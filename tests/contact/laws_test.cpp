// Contact laws: inverse, monotonicity, no NaN, derivatives, and the printed formulas.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/contact/bearing.hpp"
#include "ltca/contact/laws.hpp"
#include "ltca/geometry/units.hpp"

using ltca::contact::ContactLaw;
using ltca::contact::ContactSettings;
using ltca::contact::LawKind;
using ltca::contact::Material;
using ltca::contact::RhoConvention;
using ltca::units::kPi;

namespace {

struct Geometry {
  const char* name;
  double curvature;  // cycloid, signed 1/mm
};

// Liu Table 1 contacts: convex flank, the conformal root (rho_c = -3.0714 mm with r = 3 mm),
// a concave flank, the inflection point (rho_c infinite) and a nearly flat convex point.
const Geometry kGeometries[] = {{"convex 5 mm", 1.0 / 5.0},        {"root, conformal", -1.0 / 3.0714},
                                {"concave 12 mm", -1.0 / 12.0},    {"inflection", 0.0},
                                {"nearly flat", 1e-9}};

ContactSettings Settings(LawKind law, RhoConvention rho) {
  ContactSettings s;
  s.law = law;
  s.rho_convention = rho;
  s.stiffness_per_length = law == LawKind::kLinear ? 2e4 : 0.0;
  return s;
}

ltca::contact::PinSeat LinearSeat(double k) {
  ltca::contact::PinSeat seat;
  seat.kind = ltca::contact::PinSeat::Kind::kLinear;
  seat.stiffness_per_length = k;
  return seat;
}

ltca::contact::PinSeat Groove(double radius, double e = 206000.0, double nu = 0.3) {
  ltca::contact::PinSeat seat;
  seat.kind = ltca::contact::PinSeat::Kind::kGroove;
  seat.groove_radius = radius;
  seat.housing_young_modulus = e;
  seat.housing_poisson_ratio = nu;
  return seat;
}

std::vector<ContactLaw> AllLaws() {
  std::vector<ContactLaw> laws;
  const Material steel;  // 206 GPa, 0.3
  for (const LawKind kind : {LawKind::kHertzLine, LawKind::kSagitta, LawKind::kLinear}) {
    for (const RhoConvention rho : {RhoConvention::kSigned, RhoConvention::kAbsolute}) {
      for (const Geometry& g : kGeometries) laws.emplace_back(Settings(kind, rho), steel, g.curvature, 3.0, 12.0, 64.0);
    }
  }
  // Seated pins (issue 25): hertz-line and linear contacts, each on a linear seat and in a groove.
  for (const LawKind kind : {LawKind::kHertzLine, LawKind::kLinear}) {
    for (const ltca::contact::PinSeat& seat : {LinearSeat(3e4), Groove(3.01)}) {
      ContactSettings s = Settings(kind, RhoConvention::kSigned);
      s.seat = seat;
      for (const Geometry& g : kGeometries) laws.emplace_back(s, steel, g.curvature, 3.0, 12.0, 64.0);
    }
  }
  return laws;
}

}  // namespace

TEST_CASE("contact: every law inverts, F(delta(F)) = F to 1e-12 over 1e-6 N .. 1e6 N, and is monotone") {
  int index = 0;
  for (const ContactLaw& law : AllLaws()) {
    CAPTURE(index++);
    double last_delta = 0.0;
    for (double f = 1e-6; f <= 1e6 * 1.0001; f *= std::pow(10.0, 0.25)) {
      if (f >= law.max_force()) break;
      const double delta = law.Approach(f);
      CHECK(std::isfinite(delta));
      CHECK(delta > last_delta);
      last_delta = delta;
      CHECK(std::abs(law.Force(delta) - f) <= 1e-12 * f);
    }
    CHECK(law.Force(0.0) == 0.0);
    CHECK(law.Force(-1e-3) == 0.0);
    CHECK(law.Approach(0.0) == 0.0);
    CHECK(law.Stiffness(-1.0) == 0.0);
  }
}

TEST_CASE("contact: the warm-started inversion returns F(delta(F)) = F to 8 ulp from any hint, and U = F delta - E^c(F) (issue 29)") {
  // Issue 29 inverts the log law by Halley's method from the hint: from a hint 1e-12 to 1e12 times
  // the answer, at the largest force, beyond it, and from none, the force whose approach is given
  // (the forward formula, Liu eq. 22, is the independent side), and the strain energy without a log
  // equals the one from the complementary energy.
  int index = 0;
  for (const ContactLaw& law : AllLaws()) {
    CAPTURE(index++);
    for (double f = 1e-6; f <= 1e6 * 1.0001; f *= 10.0) {
      if (f >= law.max_force()) break;
      const double delta = law.Approach(f);
      for (const double ratio : {0.0, 1e-12, 1e-3, 0.5, 0.999, 1.0, 1.001, 2.0, 1e3, 1e12}) {
        CAPTURE(f);
        CAPTURE(ratio);
        double hint = ratio * f;
        const double got = law.Force(delta, &hint);
        CHECK(std::abs(got - f) <= 8.0 * std::numeric_limits<double>::epsilon() * f);
        CHECK(hint == got);
      }
      const double u = law.StrainEnergy(delta, f);
      CHECK(std::abs(u - (f * delta - law.ComplementaryEnergy(f))) <= 1e-12 * f * delta);
    }
    if (std::isfinite(law.max_approach())) {
      double hint = 1.0;
      CHECK(law.Force(2.0 * law.max_approach(), &hint) == law.max_force());
    }
  }
}

TEST_CASE("contact: a law scaled by w carries w times the force at every approach, with the stresses of the unscaled force (issue 27)") {
  // The definition F_w(delta) = w F(delta) is the independent side: every quantity of the scaled
  // law at w F is the unscaled law's at F (approach, w x energy, compliance / w), and its Hertz
  // half-width and pressure at w F are the contact's at F. Tolerance 1e-12 relative.
  int index = 0;
  for (const ContactLaw& law : AllLaws()) {
    CAPTURE(index++);
    for (const double w : {0.05, 0.6, 1.0, 1.07, 25.0}) {
      CAPTURE(w);
      const ContactLaw scaled = law.Scaled(w);
      if (std::isfinite(law.max_force())) {
        CHECK(std::abs(scaled.max_force() - w * law.max_force()) <= 1e-12 * w * law.max_force());
      } else {
        CHECK(scaled.max_force() == law.max_force());
      }
      if (std::isfinite(law.max_approach())) CHECK(scaled.max_approach() == law.max_approach());
      for (double f = 1e-3; f <= 1e5 * 1.0001; f *= 10.0) {
        if (f >= law.max_force()) break;
        CAPTURE(f);
        const double delta = law.Approach(f);
        const auto near = [](double got, double want) { return std::abs(got - want) <= 1e-12 * std::abs(want); };
        CHECK(near(scaled.Force(delta), w * f));
        CHECK(near(scaled.Approach(w * f), delta));
        CHECK(near(scaled.Stiffness(delta), w * law.Stiffness(delta)));
        CHECK(near(w * scaled.Compliance(w * f), law.Compliance(f)));
        CHECK(near(scaled.ComplementaryEnergy(w * f), w * law.ComplementaryEnergy(f)));
        CHECK(near(scaled.StrainEnergy(delta, w * f), w * law.StrainEnergy(delta, f)));
        CHECK(near(scaled.HalfWidth(w * f), law.HalfWidth(f)));
        CHECK(near(scaled.MaxPressure(w * f), law.MaxPressure(f)));
        CHECK(near(scaled.SeatApproach(w * f), law.SeatApproach(f)));
        CHECK(near(scaled.SeatHalfWidth(w * f), law.SeatHalfWidth(f)));
      }
    }
    for (const double w : {0.0, -1.0, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
      CHECK_THROWS_AS(law.Scaled(w), std::invalid_argument);
    }
  }
}

TEST_CASE("contact: laws stay finite and non-negative for tiny and huge loads and at the inflection") {
  int index = 0;
  for (const ContactLaw& law : AllLaws()) {
    CAPTURE(index++);
    for (const double delta : {1e-300, 1e-12, 1e-6, 1e-3, 0.1, 10.0, 1e6}) {
      const double f = law.Force(delta);
      const double k = law.Stiffness(delta);
      CHECK(std::isfinite(f));
      CHECK(f >= 0.0);
      CHECK(std::isfinite(k));
      CHECK(k >= 0.0);
      CHECK(std::isfinite(law.ComplementaryEnergy(f)));
    }
    for (const double f : {1e-300, 1e-6, 1e12}) {
      CHECK(std::isfinite(law.Approach(f)));
      CHECK(std::isfinite(law.MaxPressure(f)));
    }
  }
}

TEST_CASE("contact: stiffness and complementary energy agree with finite differences") {
  // dF/d(delta) against a central difference of Force (1e-6 relative); d(energy)/dF = delta(F).
  int index = 0;
  for (const ContactLaw& law : AllLaws()) {
    CAPTURE(index++);
    for (const double f : {0.1, 10.0, 1000.0, 5e4}) {
      if (f >= 0.5 * law.max_force()) continue;
      const double delta = law.Approach(f), h = 1e-5 * delta;
      const double fd = (law.Force(delta + h) - law.Force(delta - h)) / (2 * h);
      CHECK(law.Stiffness(delta) == doctest::Approx(fd).epsilon(1e-6));
      const double hf = 1e-5 * f;
      const double de = (law.ComplementaryEnergy(f + hf) - law.ComplementaryEnergy(f - hf)) / (2 * hf);
      CHECK(de == doctest::Approx(delta).epsilon(1e-6));
    }
  }
}

TEST_CASE("contact: the compliance dw/dF agrees with a central difference of the approach and with 1 / stiffness") {
  // Central difference of Approach (1e-6 relative); 1 / Stiffness(Approach(F)) (Stiffness goes
  // through the law's inversion, the compliance does not) to 1e-9. Zero at the largest force.
  int index = 0;
  for (const ContactLaw& law : AllLaws()) {
    CAPTURE(index++);
    for (const double f : {1e-3, 0.1, 10.0, 1000.0, 5e4}) {
      if (f >= 0.5 * law.max_force()) continue;
      CAPTURE(f);
      const double h = 1e-5 * f;
      const double fd = (law.Approach(f + h) - law.Approach(f - h)) / (2 * h);
      CHECK(law.Compliance(f) == doctest::Approx(fd).epsilon(1e-6));
      CHECK(law.Compliance(f) == doctest::Approx(1.0 / law.Stiffness(law.Approach(f))).epsilon(1e-9));
      CHECK(law.Compliance(f) > 0.0);
      double compliance = 0.0;
      CHECK(law.Approach(f, &compliance) == law.Approach(f));  // the fused evaluation, bit for bit
      CHECK(compliance == law.Compliance(f));
    }
    if (std::isfinite(law.max_force())) CHECK(law.Compliance(law.max_force()) == 0.0);
    CHECK(law.Compliance(0.0) > 0.0);  // the right-hand limit (infinite for hertz-line)
  }
}

TEST_CASE("contact: hertz-line is Liu 2021 eq. 22-25 and sagitta is Li eq. 3-10 as printed") {
  // Typed in from the papers: Liu eq. 22 K = F / delta with b of eq. 23, E* of eq. 24, rho* of
  // eq. 25 (|rho_c| in the logarithm); Li eq. 3 (half-width), 4 (rho), 6-7 (sagittas), 8-10
  // (series stiffness). 1e-12 relative: the same formula rearranged.
  const double e = 206000.0, nu = 0.3, b_len = 12.0, r = 3.0;
  const double c = (1 - nu * nu) / e;
  const double e_star = e * e / (e * (1 - nu * nu) + e * (1 - nu * nu));
  for (const double rho_c : {5.0, -3.0714, -12.0, 40.0}) {
    for (const RhoConvention conv : {RhoConvention::kSigned, RhoConvention::kAbsolute}) {
      const double rc = conv == RhoConvention::kSigned ? rho_c : std::abs(rho_c);
      const double rho_star = rc * r / (rc + r);
      const ContactLaw hertz(Settings(LawKind::kHertzLine, conv), Material{}, 1.0 / rho_c, r, b_len, 1e9);
      const ContactLaw sag(Settings(LawKind::kSagitta, conv), Material{}, 1.0 / rho_c, r, b_len, 1e9);
      for (const double f : {10.0, 500.0, 3000.0}) {
        const double b = std::sqrt(4 * f * rho_star / (kPi * b_len * e_star));
        const double k = kPi * b_len / (2 * (c * (std::log(4 * std::abs(rho_c) / b) - 0.5) + c * (std::log(4 * r / b) - 0.5)));
        CHECK(hertz.Approach(f) == doctest::Approx(f / k).epsilon(1e-12));
        CHECK(hertz.HalfWidth(f) == doctest::Approx(b).epsilon(1e-12));
        CHECK(hertz.MaxPressure(f) == doctest::Approx(std::sqrt(f * e_star / (kPi * b_len * rho_star))).epsilon(1e-12));
        const double a = std::sqrt(4 * f * rho_star / (kPi * b_len) * (c + c));
        const double dc = std::abs(rho_c) - std::sqrt(rho_c * rho_c - a * a), dp = r - std::sqrt(r * r - a * a);
        const double kc = f / dc, kp = f / dp, kn = kc * kp / (kc + kp);
        CHECK(sag.Approach(f) == doctest::Approx(f / kn).epsilon(1e-9));  // sagittas computed here with cancellation
      }
    }
  }
}

TEST_CASE("contact: the signed convention makes a concave contact conformal, the absolute one does not") {
  // rho* = rho_c r / (rho_c + r): with rho_c = -3.0714 mm and r = 3 mm signed gives 131 mm
  // (conformal: wide, low pressure), absolute 1.52 mm.
  const ContactLaw signed_law(Settings(LawKind::kHertzLine, RhoConvention::kSigned), Material{}, -1 / 3.0714, 3.0, 12.0, 64.0);
  const ContactLaw abs_law(Settings(LawKind::kHertzLine, RhoConvention::kAbsolute), Material{}, -1 / 3.0714, 3.0, 12.0, 64.0);
  CHECK(signed_law.equivalent_radius() == doctest::Approx(3.0714 * 3 / 0.0714).epsilon(1e-9));
  CHECK(abs_law.equivalent_radius() == doctest::Approx(3.0714 * 3 / 6.0714).epsilon(1e-9));
  CHECK(signed_law.MaxPressure(1000.0) < 0.2 * abs_law.MaxPressure(1000.0));
  // At the inflection the hertz-line stiffness is the smallest, but finite (radius capped at 64 mm).
  const ContactLaw flat(Settings(LawKind::kHertzLine, RhoConvention::kSigned), Material{}, 0.0, 3.0, 12.0, 64.0);
  const ContactLaw convex(Settings(LawKind::kHertzLine, RhoConvention::kSigned), Material{}, 0.2, 3.0, 12.0, 64.0);
  CHECK(flat.Stiffness(flat.Approach(1000.0)) < convex.Stiffness(convex.Approach(1000.0)));
  CHECK(flat.Stiffness(flat.Approach(1000.0)) > 0.0);
}

TEST_CASE("contact: a tip corner is not a line contact") {
  CHECK_THROWS_AS(ContactLaw(Settings(LawKind::kHertzLine, RhoConvention::kSigned), Material{},
                             std::numeric_limits<double>::infinity(), 3.0, 12.0, 64.0),
                  std::invalid_argument);
}

TEST_CASE("contact: a pin in a hole (issue 25's output pins) is a conformal line contact: Hertz's half-width and pressure") {
  // Johnson, Contact Mechanics, 4.3 (two-dimensional Hertz contact): b = sqrt(4 w R* / (pi E*)),
  // p0 = 2 w / (pi b), 1/R* = 1/r_pin - 1/r_hole for a pin inside a hole (the hole's curvature
  // enters as the concave -1/r_hole). r_pin 5 mm, r_hole 5.5 mm, steel 206 GPa / 0.3 both,
  // w = 200 N/mm over 10 mm: R* = 55 mm, b = 0.3517656966 mm, p0 = 361.9567107 MPa (computed
  // independently). Tolerance 1e-9 relative.
  ContactSettings settings;
  settings.law = LawKind::kHertzLine;
  const ContactLaw law(settings, Material{}, -1.0 / 5.5, 5.0, 10.0, 64.0);
  CHECK(law.equivalent_radius() == doctest::Approx(55.0).epsilon(1e-12));
  CHECK(law.HalfWidth(2000.0) == doctest::Approx(0.3517656966).epsilon(1e-9));
  CHECK(law.MaxPressure(2000.0) == doctest::Approx(361.9567107).epsilon(1e-9));
}

TEST_CASE("contact: a seated pin's law is its contact's and its seat's approach in series") {
  // Issue 25, pin seats. The seat's approach typed in from its sources, independently of the law's
  // constants: a linear foundation F / (k_s B); a groove, Johnson (Contact Mechanics, eq. 5.37 and
  // 4.3) for a pin of radius r_p in a concave groove of radius r_g: (2F / (pi B)) [C_p (ln(4 r_p / b)
  // - 1/2) + C_h (ln(4 r_g / b) - 1/2)], b = sqrt(4 F rho* / (pi B E*)), 1/rho* = 1/r_p - 1/r_g,
  // 1/E* = C_p + C_h, C = (1 - nu^2) / E. r_p 3 mm, B 12 mm; a cast-iron housing (E 160 GPa, nu
  // 0.26) in a 3.02 mm groove. Tolerance 1e-12 relative (the same arithmetic in another order).
  const Material steel;
  const double rp = 3.0, length = 12.0, rg = 3.02, eh = 160000.0, nuh = 0.26;
  ContactSettings bare = Settings(LawKind::kHertzLine, RhoConvention::kSigned);
  ContactSettings grooved = bare, linear = bare;
  grooved.seat = Groove(rg, eh, nuh);
  linear.seat = LinearSeat(5e4);
  const double cp = (1.0 - 0.09) / 206000.0, ch = (1.0 - nuh * nuh) / eh;
  const double rho = 1.0 / (1.0 / rp - 1.0 / rg);
  for (const Geometry& g : kGeometries) {
    CAPTURE(g.name);
    const ContactLaw contact(bare, steel, g.curvature, rp, length, 64.0);
    const ContactLaw in_groove(grooved, steel, g.curvature, rp, length, 64.0);
    const ContactLaw on_spring(linear, steel, g.curvature, rp, length, 64.0);
    // The groove on its own, through the law of a pin in a hole: the same formula, another path.
    const ContactLaw groove_alone(bare, Material{eh, nuh, 206000.0, 0.3}, -1.0 / rg, rp, length, 64.0);
    for (const double f : {1.0, 100.0, 5000.0, 20000.0}) {
      if (f >= 0.5 * in_groove.max_force()) continue;
      CAPTURE(f);
      const double b = std::sqrt(4.0 * f * rho * (cp + ch) / (kPi * length));
      const double seat = 2.0 * f / (kPi * length) * (cp * (std::log(4.0 * rp / b) - 0.5) + ch * (std::log(4.0 * rg / b) - 0.5));
      CHECK(in_groove.Approach(f) == doctest::Approx(contact.Approach(f) + seat).epsilon(1e-12));
      CHECK(in_groove.SeatApproach(f) == doctest::Approx(seat).epsilon(1e-12));
      CHECK(groove_alone.Approach(f) == doctest::Approx(seat).epsilon(1e-12));
      CHECK(in_groove.SeatHalfWidth(f) == doctest::Approx(b).epsilon(1e-12));
      CHECK(on_spring.Approach(f) == doctest::Approx(contact.Approach(f) + f / (5e4 * length)).epsilon(1e-12));
      CHECK(on_spring.SeatApproach(f) == doctest::Approx(f / (5e4 * length)).epsilon(1e-12));
      // The complementary energies add as the approaches do.
      CHECK(in_groove.ComplementaryEnergy(f) ==
            doctest::Approx(contact.ComplementaryEnergy(f) + groove_alone.ComplementaryEnergy(f)).epsilon(1e-12));
      CHECK(in_groove.SeatComplementaryEnergy(f) == doctest::Approx(groove_alone.ComplementaryEnergy(f)).epsilon(1e-12));
      CHECK(on_spring.SeatComplementaryEnergy(f) == doctest::Approx(0.5 * f * f / (5e4 * length)).epsilon(1e-12));
      // The stress and the half-width stay the pin-cycloid contact's.
      CHECK(in_groove.MaxPressure(f) == contact.MaxPressure(f));
      CHECK(in_groove.HalfWidth(f) == contact.HalfWidth(f));
    }
    // The series law is as strong as its weaker part: its largest force the smaller of the two.
    CHECK(in_groove.max_force() == std::min(contact.max_force(), groove_alone.max_force()));
    CHECK(contact.SeatApproach(100.0) == 0.0);
    CHECK(contact.SeatHalfWidth(100.0) == 0.0);
  }
  // Linear on linear: springs in series, k = k_c k_s / (k_c + k_s).
  ContactSettings lin = Settings(LawKind::kLinear, RhoConvention::kSigned);
  lin.seat = LinearSeat(6e4);
  const ContactLaw series(lin, steel, 0.2, rp, length, 64.0);
  CHECK(series.Stiffness(1e-3) == doctest::Approx(2e4 * 6e4 / 8e4 * length).epsilon(1e-14));
}

TEST_CASE("contact: a seat's keys are checked and named") {
  const auto rejects = [](const ltca::contact::PinSeat& seat, double rp, const char* text) {
    CAPTURE(text);
    try {
      seat.Validate(rp);
      FAIL("accepted");
    } catch (const std::invalid_argument& e) {
      CHECK(std::string(e.what()).find(text) != std::string::npos);
    }
  };
  rejects(LinearSeat(0.0), 3.0, "[pins] seat_stiffness_n_per_mm2 = 0");
  rejects(LinearSeat(NAN), 3.0, "seat_stiffness_n_per_mm2");
  rejects(Groove(3.0), 3.0, "[pins] groove_radius_mm = 3: expected a finite groove radius larger than the pin radius 3");
  rejects(Groove(2.5), 3.0, "groove_radius_mm = 2.5");
  rejects(Groove(3.1, -1.0), 3.0, "[pins] housing_young_modulus_mpa = -1");
  rejects(Groove(3.1, 2e5, 0.5), 3.0, "[pins] housing_poisson_ratio = 0.5");
  CHECK_THROWS_WITH_AS(ltca::contact::ParsePinSeatKind("loose"), doctest::Contains("[pins] seat = \"loose\""),
                       std::invalid_argument);
  ContactSettings sagitta = Settings(LawKind::kSagitta, RhoConvention::kSigned);
  sagitta.seat = LinearSeat(3e4);
  CHECK_THROWS_WITH_AS(sagitta.Validate(), doctest::Contains("[pins] seat = \"linear\""), std::invalid_argument);
  CHECK_THROWS_AS(ContactLaw(sagitta, Material{}, 0.2, 3.0, 12.0, 64.0), std::invalid_argument);
}

TEST_CASE("contact: the needle roller's law is the bearing's Palmgren roller, and with a linear term inverts, differentiates and integrates consistently") {
  // Without the linear term the law is the bearing's own (contact/bearing.hpp: Harris and
  // Kotzalas, Palmgren's line contact, two raceway contacts in series): Q = RollerLoad(delta, l)
  // and delta = 2 PalmgrenApproach(Q, l), independent formulas (RollerLoad's K_n delta^(10/9)).
  const double l = 12.0;
  const ltca::contact::ContactLaw palmgren = ltca::contact::ContactLaw::Roller(l, 0.0);
  for (const double q : {1e-3, 1.0, 250.0, 1357.0, 2e4}) {
    CAPTURE(q);
    CHECK(palmgren.Approach(q) == doctest::Approx(2.0 * ltca::contact::PalmgrenApproach(q, l)).epsilon(1e-14));
    CHECK(palmgren.Force(palmgren.Approach(q)) == doctest::Approx(q).epsilon(1e-13));
    CHECK(palmgren.Force(palmgren.Approach(q)) ==
          doctest::Approx(ltca::contact::RollerLoad(palmgren.Approach(q), l)).epsilon(1e-13));
  }
  CHECK(std::isinf(palmgren.max_force()));
  CHECK(palmgren.Force(-1e-3) == 0.0);
  // With a negative linear term (an elastic body's correction, -1.2 nm/N on a steel disc):
  // delta = a Q^0.9 + s Q; the inversion to 1e-13, the tangent compliance and the complementary
  // energy against central differences and the trapezoidal rule, F delta - E^c = U.
  for (const double s : {-1.2e-6, 3e-7}) {
    const ltca::contact::ContactLaw law = ltca::contact::ContactLaw::Roller(l, s);
    for (const double q : {0.5, 100.0, 1357.0, 5e4}) {
      CAPTURE(s);
      CAPTURE(q);
      const double delta = law.Approach(q);
      CHECK(delta == doctest::Approx(palmgren.Approach(q) + s * q).epsilon(1e-14));
      double hint = 0.0;
      CHECK(law.Force(delta, &hint) == doctest::Approx(q).epsilon(1e-13));
      const double h = 1e-5 * q;
      CHECK(law.Compliance(q) == doctest::Approx((law.Approach(q + h) - law.Approach(q - h)) / (2.0 * h)).epsilon(1e-7));
      CHECK(law.Stiffness(delta) == doctest::Approx(1.0 / law.Compliance(q)).epsilon(1e-12));
      double energy = 0.0;
      const int steps = 20000;
      for (int i = 0; i < steps; ++i) {
        const double a = q * i / steps, b = q * (i + 1) / steps;
        energy += 0.5 * (law.Approach(a) + law.Approach(b)) * (b - a);
      }
      CHECK(law.ComplementaryEnergy(q) == doctest::Approx(energy).epsilon(1e-5));
      CHECK(law.StrainEnergy(delta, q) == doctest::Approx(q * delta - law.ComplementaryEnergy(q)).epsilon(1e-14));
      // Scaled by w: w times the force at every approach.
      const ltca::contact::ContactLaw w2 = law.Scaled(2.0);
      CHECK(w2.Force(delta) == doctest::Approx(2.0 * q).epsilon(1e-12));
    }
    if (s < 0.0) {
      // The approach rises up to (0.9 a / -s)^10, where its slope vanishes.
      CHECK(law.max_force() > 1e8);
      CHECK(law.Compliance(0.999 * law.max_force()) > 0.0);
    }
  }
  CHECK_THROWS_AS(ltca::contact::ContactLaw::Roller(0.0, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(ltca::contact::ContactLaw::Roller(12.0, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}
