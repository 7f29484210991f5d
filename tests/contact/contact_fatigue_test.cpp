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
    // Beyond the static value the first sloped segment goes on (ISO 6336-6:2019 Annex C, below):
    // fewer cycles than the static point, never none.
    const double beyond = CyclesToPitting(curve, 1500.0, 1.01 * 1500.0 * LifeFactor(curve, 1.0));
    CHECK(beyond > 0.0);
    CHECK(beyond < CyclesToPitting(curve, 1500.0, 0.999 * 1500.0 * LifeFactor(curve, 1.0)));
  }
}

TEST_CASE("contact: the steel curve's life factor and safety match ISO/TR 6336-30:2017's worked example 1") {
  // ISO/TR 6336-30:2017, Annex A, example 1 (a single helical case-carburized pair, sigma_Hlim 1500
  // MPa, 50,000 h at 360 r/min, z 17 / 103), as transcribed with its printed values in
  // github.com/gfsReboucas/Drivetrain, MATISO_6336.m, example_01 (commit 4a88df3; the TR itself was
  // not at hand): N_L1 = 1.080e9, N_L2 = 1.783e8, Z_NT1 = 0.91, Z_NT2 = 0.962, Z_L = 1.04739,
  // Z_v = 0.96911, Z_R = 0.96599, Z_W = Z_X = 1, sigma_HP1 = 1338.48050, sigma_HP2 = 1414.52551
  // MPa (S_Hmin 1), sigma_H = 1301.35343 MPa, S_H1 = 1.02853, S_H2 = 1.08696. ltca takes Z_L, Z_v,
  // Z_R, Z_W, Z_X as 1 (docs/stage.md); here the TR's are multiplied in to check Z_NT and S_H.
  // Tolerances: Z_NT to half the printed last digit; sigma_HP and S_H to 1e-5 (printed to 6-9
  // digits; the rounded Z_L, Z_v, Z_R leave about 2e-6). The TR's permissible stresses are on the
  // line through the points (Z_NT1 0.910054): the printed power law (5e7 / N)^0.0306 would give
  // 0.91026, 2.3e-4 off, which the printed sigma_HP1 would show.
  const double n1 = 1.080e9, n2 = n1 * 17.0 / 103.0;  // the wheel turns 17 / 103 as often
  const double z1 = LifeFactor(LifeCurve::kSteel, n1), z2 = LifeFactor(LifeCurve::kSteel, n2);
  CHECK(std::abs(z1 - 0.91) <= 0.005);
  CHECK(std::abs(z2 - 0.962) <= 0.0005);
  const double others = 1.04739 * 0.96911 * 0.96599;  // Z_L Z_v Z_R
  CHECK(1500.0 * z1 * others == doctest::Approx(1338.48050).epsilon(1e-5));
  CHECK(1500.0 * z2 * others == doctest::Approx(1414.52551).epsilon(1e-5));
  CHECK(1500.0 * z1 * others / 1301.35343 == doctest::Approx(1.02853).epsilon(1e-5));
  CHECK(1500.0 * z2 * others / 1301.35343 == doctest::Approx(1.08696).epsilon(1e-5));
  // The inverse: the cycles at the TR's permissible stress are its N_L.
  CHECK(CyclesToPitting(LifeCurve::kSteel, 1500.0 * others, 1338.48050) == doctest::Approx(n1).epsilon(1e-3));
}

TEST_CASE("contact: Miner's damage of ISO 6336-6:2019's worked load spectrum on the steel curve is the standard's") {
  // ISO 6336-6:2019, Annex C, Table C.2 (a pinion's 48-bin torque spectrum, 35.2 r/min, 30 years;
  // sigma_Hlim 1500 MPa with Z_R 1.01, Z_v 0.943, Z_L 1.02), as transcribed in
  // github.com/gfsReboucas/Drivetrain, data/table_C2.csv (commit 4a88df3): each loaded bin's contact
  // stress sigma_H S_H (MPa, at the safety factor that makes the damage sum 1) and its cycles n_i;
  // the standard's damage sum, the sum of its printed U_i = n_i / N_i, is 0.9995. Bins 3 to 7 lie
  // above the static value 1.6 x 1457.2 MPa and are counted with Z_NT up to 1.61 and N_i from 90,500
  // (bin 3): the sloped line goes on below 1e5 cycles. Tolerance 1 %: the stresses are printed to
  // 1 MPa, and 1 MPa is about 2 % in N on the line's slope (1 / 0.0756 in log N / log sigma).
  struct Bin {
    double stress, cycles;
  };
  const Bin bins[] = {
      {2349, 2203}, {2344, 1285}, {2344, 825.9}, {2340, 1285}, {2335, 2570}, {2330, 1285}, {2326, 825.9},
      {2321, 1744}, {2316, 2570}, {2312, 3028}, {2307, 2203}, {2297, 2203}, {2293, 1744}, {2283, 2386},
      {2274, 4772}, {2264, 4313}, {2250, 5690}, {2240, 8076}, {2225, 6057}, {2211, 14960}, {2191, 16520},
      {2176, 7617}, {2156, 18350}, {2131, 19460}, {2110, 9544}, {2084, 21840}, {2053, 23220}, {2021, 18350},
      {1988, 18900}, {1955, 27260}, {1916, 29000}, {1870, 30650}, {1823, 32300}, {1785, 25150}, {1742, 26250},
      {1693, 37080}, {1643, 39370}, {1593, 41210}, {1534, 42950}, {1467, 27810}, {1398, 16150}, {1318, 1101}};
  const double reference = 1500.0 * 1.01 * 0.943 * 1.02;  // sigma_Hlim Z_R Z_v Z_L
  double damage = 0.0;
  for (const Bin& b : bins) damage += b.cycles / CyclesToPitting(LifeCurve::kSteel, reference, b.stress);
  CHECK(damage == doctest::Approx(0.9995).epsilon(0.01));
  // Bin 3: Z_NT 1.61, N_i = 90,500 (to the 1 MPa of its printed stress, 2 %).
  CHECK(CyclesToPitting(LifeCurve::kSteel, reference, 2349.0) == doctest::Approx(90500.0).epsilon(0.02));
  // Bin 20 (2,240 MPa, below the static value): N_i = 170,000.
  CHECK(CyclesToPitting(LifeCurve::kSteel, reference, 2240.0) == doctest::Approx(170000.0).epsilon(0.02));
}
