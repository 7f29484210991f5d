#include "ltca/contact/unloaded.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::contact {

double ClosingRotation(const MeshModel& model, const PinContact& at_zero, double crank,
                       ContactKinematics kinematics) {
  double psi = at_zero.clearance / at_zero.arm;
  if (kinematics == ContactKinematics::kLinearised) return psi;
  // Newton on c(psi) = 0; the derivative of the exact gap is -L(psi) (envelope theorem).
  for (int it = 0; it < 50; ++it) {
    const PinContact c = model.EvaluatePin(at_zero.pin, crank, psi);
    // The arm changed sign: this pin cannot close its gap by turning this way.
    if (c.arm * at_zero.arm <= 0.0) return std::copysign(std::numeric_limits<double>::infinity(), at_zero.arm);
    const double step = c.clearance / c.arm;
    psi += step;
    if (std::abs(step) <= 1e-15 * (1.0 + std::abs(psi))) break;
  }
  return psi;
}

void RequireNoInterference(const MeshState& state, double crank, double tolerance_mm) {
  std::string overlaps;
  for (const PinContact& c : state.pins) {
    if (c.clearance < -tolerance_mm) {
      overlaps += fmt::format("{}pin {} by {:.4g} um", overlaps.empty() ? "" : ", ", c.pin + 1,
                              -units::MmToUm(c.clearance));
    }
  }
  if (!overlaps.empty()) {
    throw std::invalid_argument(fmt::format(
        "interference at crank {:.6g} deg: {} overlap the cycloid at the theoretical meshing "
        "position; expected non-negative clearances (for d > 0 the radial clearance "
        "dR_rp - dR_p must be >= 0)",
        units::RadToDeg(crank), overlaps));
  }
}

void RequireNoInterference(const MeshModel& model, double crank, double tolerance_mm) {
  RequireNoInterference(model.Evaluate(crank, 0.0), crank, tolerance_mm);
}

UnloadedContact AnalyseUnloaded(const MeshModel& model, double crank, ContactKinematics kinematics,
                                double interference_tolerance_mm) {
  const MeshState state = model.Evaluate(crank, 0.0);
  RequireNoInterference(state, crank, interference_tolerance_mm);
  UnloadedContact r;
  r.crank = crank;
  for (const PinContact& c : state.pins) r.clearance.push_back(c.clearance);
  r.theta_c1 = std::numeric_limits<double>::infinity();
  r.theta_c2 = -std::numeric_limits<double>::infinity();
  // A pin whose arm is tiny closes only after a rotation far beyond any other: skip it.
  const double min_arm = 1e-9 * model.pair().pin_circle_radius;
  for (const PinContact& c : state.pins) {
    if (std::abs(c.arm) < min_arm) continue;
    const double psi = ClosingRotation(model, c, crank, kinematics);
    if (c.arm > 0.0 && psi < r.theta_c1) r.theta_c1 = psi, r.first_pin_c1 = c.pin;
    if (c.arm < 0.0 && psi > r.theta_c2) r.theta_c2 = psi, r.first_pin_c2 = c.pin;
  }
  r.backlash = r.theta_c1 - r.theta_c2;
  r.clearance_at_c1.reserve(state.pins.size());
  if (kinematics == ContactKinematics::kExact) {
    for (const PinContact& c : model.Evaluate(crank, r.theta_c1).pins) r.clearance_at_c1.push_back(c.clearance);
  } else {
    for (const PinContact& c : state.pins) r.clearance_at_c1.push_back(-LinearisedApproach(c, r.theta_c1));
  }
  return r;
}

UnloadedSweep AnalyseUnloadedSweep(const MeshModel& model, const std::vector<double>& cranks,
                                   ContactKinematics kinematics) {
  UnloadedSweep sweep;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0.0;
  for (const double crank : cranks) {
    sweep.positions.push_back(AnalyseUnloaded(model, crank, kinematics));
    const double b = sweep.positions.back().backlash;
    sum += b;
    lo = std::min(lo, b);
    hi = std::max(hi, b);
  }
  sweep.mean_backlash = sum / static_cast<double>(cranks.size());
  sweep.pp_backlash = hi - lo;
  return sweep;
}

}  // namespace ltca::contact
