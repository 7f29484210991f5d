// The life factor Z_NT of ISO 6336-2:2006 (method B): its curves pass through the standard's
// points exactly, follow its printed closed forms between them, and CyclesToPitting inverts it.
// The printed exponents are rounded to 3-4 digits and do not quite meet the table's rounded
// points: (3e8 / N)^0.0756 gives 1.293 at 1e7 where the next form, (1e9 / N)^0.057, and the
// table give 1.3. ltca draws the curves through the points, so the closed forms hold to 3e-3.
#include <cmath>

#include <doctest/doctest.h>

#include "ltca/contact/contact_fatigue.hpp"

using ltca::contact::CyclesToPitting;
using ltca::contact::LifeCurve;
using ltca::contact::LifeFactor;

TEST_CASE("contact: the pitting life factor passes through ISO 6336-2's points") {
  // St, V, GGG, GTS, Eh, IF: 1.6 to 1e5 cycles, 1.0 at 5e7, 0.85 at 1e10.
  CHECK(LifeFactor(LifeCurve::kSteel, 1e3) == 1.6);
  CHECK(LifeFactor(LifeCurve::kSteel, 1e5) == doctest::Approx(1.6).epsilon(1e-15));
  CHECK(LifeFactor(LifeCurve::kSteel, 5e7) == doctest::Approx(1.0).epsilon(1e-15));
  CHECK(LifeFactor(LifeCurve::kSteel, 1e10) == doctest::Approx(0.85).epsilon(1e-15));
  CHECK(LifeFactor(LifeCurve::kSteel, 1e12) == 0.85);
  // Limited pitting permitted: 1.6 to 6e5, 1.3 at 1e7, 1.0 at 1e9, 0.85 at 1e10.
  CHECK(LifeFactor(LifeCurve::kSteelLimitedPitting, 6e5) == doctest::Approx(1.6).epsilon(1e-15));
  CHECK(LifeFactor(LifeCurve::kSteelLimitedPitting, 1e7) == doctest::Approx(1.3).epsilon(1e-15));
  CHECK(LifeFactor(LifeCurve::kSteelLimitedPitting, 1e9) == doctest::Approx(1.0).epsilon(1e-15));
  // Nitrided (GG, GGG ferr., NT, NV): 1.3 to 1e5, 1.0 at 2e6; nitrocarburized: 1.1 to 1e5.
  CHECK(LifeFactor(LifeCurve::kNitrided, 1e5) == doctest::Approx(1.3).epsilon(1e-15));
  CHECK(LifeFactor(LifeCurve::kNitrided, 2e6) == doctest::Approx(1.0).epsilon(1e-15));
  CHECK(LifeFactor(LifeCurve::kNitrocarburized, 1e4) == 1.1);
  CHECK(LifeFactor(LifeCurve::kNitrocarburized, 1e10) == doctest::Approx(0.85).epsilon(1e-15));
}

TEST_CASE("contact: between its points the life factor is ISO 6336-2's printed power law") {
  // The standard's closed forms: Z_NT = (5e7 / N)^0.0756 (1e5 .. 5e7) and (5e7 / N)^0.0306
  // (5e7 .. 1e10) for steel; (3e8 / N)^0.0756, (1e9 / N)^0.057, (1e9 / N)^0.0706 with limited
  // pitting; (2e6 / N)^0.0875 and (2e6 / N)^0.0191 nitrided; (2e6 / N)^0.0318 nitrocarburized.
  struct Case {
    LifeCurve curve;
    double n, reference, exponent;
  };
  for (const Case c : {Case{LifeCurve::kSteel, 1e6, 5e7, 0.0756}, Case{LifeCurve::kSteel, 3e9, 5e7, 0.0306},
                       Case{LifeCurve::kSteelLimitedPitting, 2e6, 3e8, 0.0756}, Case{LifeCurve::kSteelLimitedPitting, 1e8, 1e9, 0.057},
                       Case{LifeCurve::kSteelLimitedPitting, 4e9, 1e9, 0.0706}, Case{LifeCurve::kNitrided, 5e5, 2e6, 0.0875},
                       Case{LifeCurve::kNitrided, 1e8, 2e6, 0.0191}, Case{LifeCurve::kNitrocarburized, 5e5, 2e6, 0.0318}}) {
    CAPTURE(c.n);
    CHECK(LifeFactor(c.curve, c.n) == doctest::Approx(std::pow(c.reference / c.n, c.exponent)).epsilon(3e-3));
  }
}

TEST_CASE("contact: the cycles to pitting invert the life factor, with no damage below the curve's floor") {
  for (const LifeCurve curve : {LifeCurve::kSteel, LifeCurve::kSteelLimitedPitting, LifeCurve::kNitrided, LifeCurve::kNitrocarburized}) {
    for (const double n : {2e5, 7e5, 3e6, 1e8, 5e9}) {
      const double stress = 1500.0 * LifeFactor(curve, n);
      if (LifeFactor(curve, n) == LifeFactor(curve, 1.0)) continue;  // on the static plateau
      CHECK(CyclesToPitting(curve, 1500.0, stress) == doctest::Approx(n).epsilon(1e-12));
    }
    CHECK(std::isinf(CyclesToPitting(curve, 1500.0, 0.85 * 1500.0)));  // the floor: no damage
    CHECK(std::isinf(CyclesToPitting(curve, 1500.0, 0.0)));
    CHECK(CyclesToPitting(curve, 1500.0, 1.01 * 1500.0 * LifeFactor(curve, 1.0)) == 0.0);  // beyond the static value
  }
}
