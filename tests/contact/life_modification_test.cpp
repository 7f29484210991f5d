// ISO 281:2007's modified rating life of a radial roller bearing (9.3): the reference viscosity
// nu_1, the life modification factor a_ISO and Annex B's estimate of C_u.
//
// No published worked example of a_ISO for a radial roller bearing was at hand (ISO 281's own
// annexes and the makers' catalogues print the formulas and diagrams, not a case with its
// numbers), so the expected values below are the standard's formulas evaluated by hand, apart
// from ltca, in Python 3 (double precision) for three cases, and printed here to 15 digits:
//   nu_1 = 45000 n^-0.83 D_pw^-0.5 (n < 1000 r/min), 4500 n^-0.5 D_pw^-0.5 (n >= 1000 r/min);
//   a_ISO = 0.1 [1 - (1.5859 - c / kappa^e) (e_C C_u / P)^0.4]^-9.185 with (c, e) = (1.3993,
//   0.054381), (1.2348, 0.19087), (1.2348, 0.071739) for kappa in [0.1, 0.4), [0.4, 1), [1, 4].
// Tolerance 1e-12 relative (the same arithmetic in another language). The range edges (kappa
// clamped to [0.1, 4], a_ISO capped at 50, a_ISO = 0.1 at e_C C_u / P = 0) are the standard's
// words and are checked exactly.
#include <cmath>
#include <limits>

#include <doctest/doctest.h>

#include "ltca/contact/bearing.hpp"

TEST_CASE("contact: ISO 281's nu_1 and a_ISO of a radial roller bearing, three cases by hand") {
  using ltca::contact::LifeModificationFactor;
  using ltca::contact::ReferenceViscosity;
  struct Case {
    double rpm, pitch_diameter, nu, contamination, fatigue_load_limit, load;  // r/min, mm, mm^2/s, -, N, N
    double nu_1, kappa, a_iso;                                                // by hand
  };
  const Case cases[] = {
      // kappa in [1, 4]: n < 1000 r/min; C_u = C_0r / 8.2 of the cycloidal drive's roller set.
      {500.0, 40.0, 68.0, 0.5, 39424.0 / 8.2, 6000.0, 40.9295919095005, 1.66138964078496, 1.8972606116133},
      // kappa in [1, 4]: n >= 1000 r/min.
      {1500.0, 40.0, 68.0, 0.5, 39424.0 / 8.2, 6000.0, 18.3711730708738, 3.70145116687236, 3.4673547368319},
      // kappa in [0.1, 0.4): a thin oil at a low speed.
      {200.0, 40.0, 32.0, 0.3, 3000.0, 5000.0, 87.5644091778203, 0.365445279657131, 0.167033362711689},
  };
  for (const Case& c : cases) {
    CAPTURE(c.rpm);
    const double nu_1 = ReferenceViscosity(c.rpm, c.pitch_diameter);
    CHECK(nu_1 == doctest::Approx(c.nu_1).epsilon(1e-12));
    CHECK(c.nu / nu_1 == doctest::Approx(c.kappa).epsilon(1e-12));
    CHECK(LifeModificationFactor(c.nu / nu_1, c.contamination * c.fatigue_load_limit / c.load) ==
          doctest::Approx(c.a_iso).epsilon(1e-12));
  }
  // The middle range, kappa in [0.4, 1): kappa 0.5, e_C C_u / P = 0.5, by hand.
  CHECK(LifeModificationFactor(0.5, 0.5) == doctest::Approx(0.373745554845682).epsilon(1e-12));
  CHECK(std::isnan(ReferenceViscosity(0.0, 40.0)));  // no speed, no nu_1
  CHECK(std::isnan(ReferenceViscosity(1500.0, 0.0)));
}

TEST_CASE("contact: a_ISO's range edges are ISO 281's: kappa clamped to [0.1, 4], a_ISO at most 50 and 0.1 without C_u") {
  using ltca::contact::LifeModificationFactor;
  // kappa above 4 is taken as 4, below 0.1 as 0.1 (outside the formulas, where a_ISO is their floor).
  CHECK(LifeModificationFactor(9.0, 0.3) == LifeModificationFactor(4.0, 0.3));
  CHECK(LifeModificationFactor(1e6, 0.3) == LifeModificationFactor(4.0, 0.3));
  CHECK(LifeModificationFactor(0.01, 0.3) == LifeModificationFactor(0.1, 0.3));
  CHECK(LifeModificationFactor(0.1, 3.0) == doctest::Approx(0.1).epsilon(1e-3));
  // e_C C_u / P = 0 (no fatigue limit, or e_C = 0): a_ISO = 0.1 for every kappa.
  for (const double kappa : {0.1, 0.3, 0.4, 0.7, 1.0, 2.0, 4.0}) CHECK(LifeModificationFactor(kappa, 0.0) == 0.1);
  // The cap: kappa 4 and e_C C_u / P = 5 give 0.1 x 0.109^-9.185, far above 50; P = 0 too.
  CHECK(LifeModificationFactor(4.0, 5.0) == ltca::contact::kLifeModificationMax);
  CHECK(LifeModificationFactor(4.0, std::numeric_limits<double>::infinity()) == 50.0);
  CHECK(LifeModificationFactor(2.0, 1.0) < 50.0);
  // The ranges meet: at kappa 1 the two forms are one (c = 1.2348, kappa^e = 1); at 0.4 the
  // printed coefficients meet within 1e-5 of a_ISO.
  CHECK(LifeModificationFactor(1.0 - 1e-12, 0.5) == doctest::Approx(LifeModificationFactor(1.0, 0.5)).epsilon(1e-9));
  CHECK(LifeModificationFactor(0.4 - 1e-12, 0.5) == doctest::Approx(LifeModificationFactor(0.4, 0.5)).epsilon(1e-5));
  // a_ISO grows with kappa and with e_C C_u / P.
  CHECK(LifeModificationFactor(0.3, 0.5) < LifeModificationFactor(0.6, 0.5));
  CHECK(LifeModificationFactor(0.6, 0.5) < LifeModificationFactor(2.0, 0.5));
  CHECK(LifeModificationFactor(2.0, 0.2) < LifeModificationFactor(2.0, 0.5));
  CHECK(std::isnan(LifeModificationFactor(std::nan(""), 0.5)));
  CHECK(std::isnan(LifeModificationFactor(1.0, -0.1)));
}

TEST_CASE("contact: ISO 281 Annex B's C_u of a roller bearing is C_0r / 8.2 up to a pitch diameter of 100 mm, else not estimated") {
  using ltca::contact::FatigueLoadLimitEstimate;
  CHECK(FatigueLoadLimitEstimate(39424.0, 40.0) == 39424.0 / 8.2);
  CHECK(FatigueLoadLimitEstimate(39424.0, 100.0) == 39424.0 / 8.2);
  CHECK(std::isnan(FatigueLoadLimitEstimate(39424.0, 100.5)));
  CHECK(std::isnan(FatigueLoadLimitEstimate(0.0, 40.0)));
}
