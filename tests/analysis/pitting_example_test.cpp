// The pitting rating against a published calculation: KISSsoft Release 03/2017 A reports of the NREL
// 5 MW drivetrain's gear stages, ISO 6336:2006 method B, "Material quality according to ISO
// 6336:2006 Normal (Life factors ZNT and YNT >= 0.85)", "Limited pitting is permitted: No",
// published in github.com/gfsReboucas/Drivetrain (commit 2a41bf1ce829b76800693e2b52c91e5f74d074d4):
//  - @NREL_5MW/stage_01.rtf (the planetary stage, required life 175,200 h), section 2 "Number of
//    load cycles (in mio.) [NL]" 1124.7 / 419.0 / 381.6 and section 4 "SAFETY AGAINST PITTING"
//    "Finite life factor [ZNT]" 0.909 / 0.937 / 0.940 (sun and planet 18CrNiMo7-6 case-hardened,
//    sigma_Hlim 1500 MPa; ring 34CrNiMo6 through hardened, sigma_Hlim 700 MPa: both on ISO 6336-2's
//    curve for St, V, GGG, GTS, Eh, IF), and for the sun: Z_L 1.020, Z_V 0.961, Z_R 1.024,
//    Z_W 1.000, Z_X 1.000, sigma_HB 996.13 MPa, "Pitting stress limit [sigHG]" 1368.61 MPa,
//    "Safety for stress at single tooth contact [SHBD=sigHG/sigHBD]" 1.37; for the ring: Z_L 1.038,
//    Z_V 0.916, Z_R 1.025, Z_W 1.135, Z_X 1.000, sigma_HD 758.46 MPa, sigma_HG 727.36 MPa, S_H 0.96;
//  - @NREL_5MW/stage_03.rtf (the parallel stage): N_L 12255.788 / 3096.199 (mio.), Z_NT 0.850 / 0.881
//    (the first beyond 1e10 cycles: the curve's floor).
// Tolerances: Z_NT to half the printed last digit (5e-4); sigma_HG to 0.1 % (the product of five
// factors each printed to 3 decimals, each rounded by up to 0.05 %); S_H to half its printed digit
// (5e-3). ltca rates sigma_Hlim Z_NT against its computed Hertz pressure with Z_L = Z_v = Z_R = Z_W =
// Z_X = 1 (contact/contact_fatigue.hpp): KISSsoft's other factors are folded into the endurance limit
// given to ltca, sigma_Hlim' = sigma_Hlim Z_L Z_v Z_R Z_W Z_X, which is what ISO 6336-2's
// sigma_HG = sigma_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X does with them. Recorded in docs/validation.md.
#include <cmath>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/analysis/contact_fatigue.hpp"
#include "ltca/contact/contact_fatigue.hpp"
#include "ltca/contact/material.hpp"
#include "ltca/geometry/units.hpp"

TEST_CASE("analysis: the pitting life factor Z_NT equals KISSsoft's at its printed load cycles (ISO 6336-2 method B)") {
  using ltca::contact::LifeCurve;
  using ltca::contact::LifeFactor;
  struct Case {
    double cycles, z_nt;  // N_L, Z_NT as printed
  };
  for (const Case c : {Case{1124.7e6, 0.909}, Case{419.0e6, 0.937}, Case{381.6e6, 0.940}, Case{12255.788e6, 0.850},
                       Case{3096.199e6, 0.881}}) {
    CAPTURE(c.cycles);
    CHECK(std::abs(LifeFactor(LifeCurve::kSteel, c.cycles) - c.z_nt) <= 5e-4);
  }
}

TEST_CASE("analysis: the pitting safety S_H and limit sigma_HG of a rated contact equal KISSsoft's sun and ring of the NREL 5 MW planetary stage") {
  // One pin loaded once a crank turn at the KISSsoft stress, at the crank speed that gives KISSsoft's
  // N_L over the required life: ltca's S_H = sigma_Hlim' Z_NT(N_L) / sigma (RateContactFatigue).
  struct Case {
    double sigma_hlim, factors, cycles, stress, sigma_hg, s_h;
  };
  const double hours = 175200.0;
  for (const Case c : {Case{1500.0, 1.020 * 0.961 * 1.024 * 1.000 * 1.000, 1124.7e6, 996.13, 1368.61, 1.37},
                       Case{700.0, 1.038 * 0.916 * 1.025 * 1.135 * 1.000, 381.6e6, 758.46, 727.36, 0.96}}) {
    CAPTURE(c.sigma_hlim);
    ltca::analysis::ContactCycles cycles;
    cycles.discs = 1;
    cycles.peaks = {{c.stress}};
    cycles.crank_turns = 1.0;
    cycles.basis = "one cycle a crank turn";
    ltca::contact::Material material;
    material.contact_fatigue_limit = c.sigma_hlim * c.factors;
    material.life_curve = ltca::contact::LifeCurve::kSteel;
    const double rpm = c.cycles / (60.0 * hours);  // one cycle a turn: N_L over the required life
    const auto rated = ltca::analysis::RateContactFatigue(cycles, material, 1, ltca::units::RpmToRadPerS(rpm), hours);
    REQUIRE(rated.discs.size() == 1);
    const double s_h = rated.discs[0].pin_safety;
    CHECK(s_h * c.stress == doctest::Approx(c.sigma_hg).epsilon(1e-3));  // sigma_HG = S_H sigma_H
    CHECK(std::abs(s_h - c.s_h) <= 5e-3);
  }
}
