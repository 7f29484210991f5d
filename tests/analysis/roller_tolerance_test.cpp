// The tolerance band of the dimension over rollers (analysis::RollerTolerance, docs/export.md)
// against relations derived here, not from the band's code:
//  - an isometric change dR_rp moves the profile along its normal by -dR_rp (away from the pin
//    centres' locus, which the seated roller's centre lies r' - r from), which seats a roller
//    exactly as a roller smaller by dR_rp on the unchanged profile: s(dR_rp + x, r) =
//    s(dR_rp, r - x). With M = 2 c s + D_M (c = cos(90 deg / z_c) for z_c odd, 1 for even),
//    dM/d(dR_rp) = -2 c s'(r) = -2 (dM/dD_M - 1), dM/dD_M taken from geometry::MeasureOverRollers
//    with two roller diameters (central difference, 1e-4 mm); the profile layer removes what dR_rp
//    adds: its sensitivity is the opposite;
//  - the worst-case corners against M measured directly with every key at its corner (the band
//    is linear: the difference is of second order, M''/2 x 7 um^2, 1.3e-5 mm on Liu's pair);
//  - keys that do not touch the disc's profile (the pin circle, a lead crowning) have no share.
#include <cmath>

#include <doctest/doctest.h>

#include "ltca/analysis/inspection.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/tolerance.hpp"
#include "ltca/geometry/inspection.hpp"
#include "pairs.hpp"

namespace roller_tolerance_test {

using ltca::analysis::ToleranceDistribution;

ToleranceDistribution Uniform(const char* key, double tolerance, double mean = 0.0) {
  ToleranceDistribution t;
  t.key = key;
  t.kind = ToleranceDistribution::Kind::kUniform;
  t.tolerance = tolerance;
  t.mean = mean;
  return t;
}

double M(const ltca::analysis::StageDesign& d, double roller) {
  return ltca::geometry::MeasureOverRollers(d.MakeRealPair().profile(), roller).dimension;
}

void Check(const ltca::geometry::PairParameters& pair, const ltca::geometry::Modification& mod, double roller) {
  ltca::analysis::StageDesign d;
  d.pair = pair;
  d.modification = mod;
  REQUIRE(ltca::geometry::MeasureOverRollers(d.MakeRealPair().profile(), roller).OnWorkingFlanks());
  ltca::analysis::ToleranceSettings tolerances;
  tolerances.distributions = {Uniform("modification_pin_radius_mm", 0.005), Uniform("cycloid_profile_layer_mm", 0.002),
                              Uniform("pin_circle_deviation_mm", 0.01), Uniform("lead_crowning_um", 2.0)};
  const auto band = ltca::analysis::RollerTolerance(d, tolerances, roller);
  // Own sensitivity of the isometric modification, through the roller's diameter.
  const double dm_dd = (M(d, roller + 1e-4) - M(d, roller - 1e-4)) / 2e-4;
  const double s_rp = -2.0 * (dm_dd - 1.0);
  REQUIRE(band.terms.size() == 2);
  CHECK(band.terms[0].key == "modification_pin_radius_mm");
  CHECK(band.terms[1].key == "cycloid_profile_layer_mm");
  MESSAGE("S(dR_rp) " << band.terms[0].sensitivity << " against " << s_rp << "; band " << band.worst_low << " .. "
                      << band.worst_high << " mm about " << band.centre);
  CHECK(std::abs(band.terms[0].sensitivity - s_rp) <= 1e-5);
  CHECK(std::abs(band.terms[1].sensitivity + band.terms[0].sensitivity) <= 1e-6);
  // The corners measured directly: dR_rp +- 5 um with the layer -+ 2 um move M the same way.
  ltca::analysis::StageDesign high = d, low = d;
  const double sign = s_rp > 0.0 ? 1.0 : -1.0;
  high.modification.pin_radius += sign * 0.005, high.errors.profile_layer -= sign * 0.002;
  low.modification.pin_radius -= sign * 0.005, low.errors.profile_layer += sign * 0.002;
  MESSAGE("corners measured " << M(low, roller) << " .. " << M(high, roller) << ", differences " << band.worst_low - M(low, roller) << ", " << band.worst_high - M(high, roller));
  // The band is linear; M bends: the corners differ by M''/2 x (7 um)^2, the same sign at both
  // (measured 1.3e-5 mm on Liu's pair with 8 mm rollers, 1e-7 on Chen's with 30 mm).
  CHECK(std::abs(band.worst_high - M(high, roller)) <= 3e-5);
  CHECK(std::abs(band.worst_low - M(low, roller)) <= 3e-5);
  // Statistical: the root sum of squares of the same half-widths.
  const double rss = std::abs(s_rp) * std::sqrt(0.005 * 0.005 + 0.002 * 0.002);
  CHECK(std::abs(band.rss_high - band.centre - rss) <= 1e-6);
  CHECK(band.centre == band.nominal);  // every mean 0: the deck itself
}

}  // namespace roller_tolerance_test

TEST_CASE("analysis: the tolerance band of the dimension over rollers by sensitivity against dM/dR_rp = -2 (dM/dD_M - "
          "1) and the corners measured directly (d = 1 Liu z_c odd, d = 2 Chen z_c even)") {
  SUBCASE("Liu Table 1 as modified, 8 mm rollers") {
    roller_tolerance_test::Check(ltca::test::LiuPair(), ltca::test::Mod(-4.0, -17.0), 8.0);
  }
  SUBCASE("Chen d = 2, 30 mm rollers") {
    roller_tolerance_test::Check(ltca::test::ChenPairs()[1].pair, ltca::test::Mod(10.0, 0.0), 30.0);
  }
}

TEST_CASE("analysis: the band's centre moves with the tolerances' means") {
  ltca::analysis::StageDesign d;
  d.pair = ltca::test::LiuPair();
  ltca::analysis::ToleranceSettings tolerances;
  tolerances.distributions = {roller_tolerance_test::Uniform("modification_pin_radius_mm", 0.001, -0.003)};
  const auto band = ltca::analysis::RollerTolerance(d, tolerances, 8.0);
  ltca::analysis::StageDesign shifted = d;
  shifted.modification.pin_radius -= 0.003;
  CHECK(std::abs(band.centre - roller_tolerance_test::M(shifted, 8.0)) <= 1e-12);
  CHECK(band.centre != band.nominal);
}
