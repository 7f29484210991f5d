#pragma once
#include <utility>

// Stage designs built from data (no deck) that the analysis tests share.
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/tolerance.hpp"
#include "ltca/contact/material.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::test {

/// Liu 2021 Table 1 (40 pins, R_p 64 mm, r_rp 3 mm, e 1.3 mm, B 12 mm) unmodified; steel.
inline analysis::StageDesign SteelLiuTable1() {
  analysis::StageDesign d;
  d.name = "Liu 2021 Table 1";
  d.pair = {40, 39, 3.0, 64.0, 1.3, 12.0};
  d.material = contact::Material{};
  return d;
}

/// The pair with section 5.2's base modification (dR_rp -4 um, dR_p -17 um): clearance at every pin.
inline analysis::StageDesign SteelLiu52() {
  analysis::StageDesign d = SteelLiuTable1();
  d.name = "Liu 2021 Table 1, section 5.2 base modification";
  d.modification.pin_radius = -0.004;
  d.modification.pin_circle_radius = -0.017;
  return d;
}

/// A design with a second disc of the same modification added half a crank turn on, 5 um ahead
/// along the pin circle.
inline analysis::StageDesign WithSecondDisc(analysis::StageDesign d) {
  analysis::SecondDisc second;
  second.modification = d.modification;
  second.indexing_deviation = 0.005;
  d.second_disc = second;
  return d;
}

inline analysis::StageDesign SteelLiu52TwoDiscs() { return WithSecondDisc(SteelLiu52()); }

/// A tolerance case of the design: 100 N*m on the output over 0 .. 9 deg crank in `positions`.
inline analysis::ToleranceCase Over9DegreesAt100Nm(analysis::StageDesign design, int positions) {
  analysis::ToleranceCase c;
  c.design = std::move(design);
  c.sweep.crank_start = 0.0;
  c.sweep.crank_end = units::DegToRad(9.0);
  c.sweep.positions = positions;
  c.torque = 100'000.0;  // N*mm
  return c;
}

}  // namespace ltca::test
