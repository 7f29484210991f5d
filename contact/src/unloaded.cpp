#include "ltca/contact/unloaded.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::contact {

double RotationWindow(const MeshModel& model) { return 0.25 * model.profile().tooth_pitch(); }

std::string InterferenceReport(const MeshState& state, double tolerance_mm) {
  // Per pin, its deepest overlap over the slices (and which slice, in the slice model).
  std::string overlaps;
  const bool sliced = std::any_of(state.pins.begin(), state.pins.end(), [](const PinContact& c) { return c.slice > 0; });
  for (std::size_t i = 0; i < state.pins.size();) {
    const PinContact* worst = &state.pins[i];
    std::size_t next = i;
    for (; next < state.pins.size() && state.pins[next].pin == state.pins[i].pin && state.pins[next].disc == state.pins[i].disc;
         ++next) {
      if (state.pins[next].clearance < worst->clearance) worst = &state.pins[next];
    }
    if (worst->clearance < -tolerance_mm) {
      overlaps += fmt::format("{}{}pin {}{} by {:.4g} um", overlaps.empty() ? "" : ", ",
                              worst->disc > 0 ? fmt::format("disc {} ", worst->disc + 1) : "", worst->pin + 1,
                              sliced ? fmt::format(" (slice {})", worst->slice + 1) : "", -units::MmToUm(worst->clearance));
    }
    i = next;
  }
  return overlaps;
}

double ClosingRotation(const MeshModel& model, const PinContact& at_zero, double crank,
                       ContactKinematics kinematics) {
  const double linear = at_zero.clearance / at_zero.arm;
  if (kinematics == ContactKinematics::kLinearised || at_zero.clearance == 0.0) return linear;
  // Exact: the root of the pin's gap c(psi), searched only within a quarter of a cycloid tooth
  // pitch of the theoretical position. The exact geometry repeats every pitch, so an unguarded
  // Newton step from a pin with a tiny arm (c/L of order 1 rad) lands whole pitches away and
  // finds a root there: a rotation thousands of pitches off. Within the window the
  // gap falls monotonically in the closing direction s = sign(L(0)) while L keeps its sign
  // (dc/dpsi = -L(psi), envelope theorem), so a bracketed Newton iteration on
  // g(x) = c(s x), g'(x) = -s L(s x), converges; x > 0 closes, x < 0 opens.
  const double s = at_zero.arm > 0.0 ? 1.0 : -1.0;
  const double window = RotationWindow(model);
  const double never = s * std::numeric_limits<double>::infinity();
  // The root lies on the closing side when the pin has clearance, on the opening side when it
  // overlaps; bracket [a, b] with g(a) > 0 > g(b) once both ends are known.
  const bool closing = at_zero.clearance > 0.0;
  double a = closing ? 0.0 : -window, b = closing ? window : 0.0;
  bool have_a = closing, have_b = !closing;
  double x = std::clamp(s * linear, a, b);
  for (int it = 0; it < 100; ++it) {
    const PinContact c = model.EvaluateSection(at_zero.pin, at_zero.slice, at_zero.z, crank, s * x);
    const bool arm_kept = c.arm * at_zero.arm > 0.0;
    if (c.clearance > 0.0) {
      // Past the turning point of the gap (the arm changed sign) with the gap still open: the
      // pin cannot close by turning this way within the window.
      if (!arm_kept && x > 0.0) return never;
      a = x, have_a = true;
    } else {
      b = x, have_b = true;
    }
    if (c.clearance == 0.0) return s * x;
    double next = arm_kept ? x + c.clearance / std::abs(c.arm) : 0.5 * (a + b);
    if (!(next > a && next < b)) {
      if (!have_b) {  // no closing found yet: try the end of the window once
        if (x >= b) return never;  // the gap is still open at the end of the window
        next = b;
      } else if (!have_a) {
        if (x <= a) return never;  // still overlapping a quarter pitch back: no root in the window
        next = a;
      } else {
        next = 0.5 * (a + b);
      }
    }
    if (std::abs(next - x) <= 1e-15 * (1.0 + std::abs(x))) return s * next;
    x = next;
  }
  return s * x;
}

std::string JamReport(const MeshState& state, double tolerance_mm) {
  // The report is formatted only for a jam (every position of a sweep asks).
  if (std::none_of(state.pins.begin(), state.pins.end(), [&](const PinContact& c) { return c.clearance < -tolerance_mm; })) {
    return {};
  }
  // Some pins overlap at the theoretical position (a pitch or position error of one pin does
  // that): the pair still fits when a rotation of the cycloid about its centre frees every pin,
  // i.e. when the gaps c_i - L_i psi >= -tolerance have a common psi (linearised about the
  // theoretical position): max over L < 0 of (c + tol) / L <= min over L > 0 of (c + tol) / L,
  // and no pin with a vanishing arm overlaps.
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  bool stuck = false;
  for (const PinContact& c : state.pins) {
    const double slack = c.clearance + tolerance_mm;
    if (std::abs(c.arm) <= 1e-9 * std::abs(c.pin_point.norm())) {
      stuck = stuck || slack < 0.0;
    } else if (c.arm > 0.0) {
      hi = std::min(hi, slack / c.arm);
    } else {
      lo = std::max(lo, slack / c.arm);
    }
  }
  return stuck || lo > hi ? InterferenceReport(state, tolerance_mm) : std::string();
}

const char* ToString(ContactKinematics kinematics) {
  return kinematics == ContactKinematics::kExact ? "exact" : "linearised";
}

ContactKinematics ParseKinematics(const std::string& text) {
  if (text == "linearised") return ContactKinematics::kLinearised;
  if (text == "exact") return ContactKinematics::kExact;
  throw std::invalid_argument(fmt::format("[solver] kinematics = \"{}\": expected \"linearised\" or \"exact\"", text));
}

void RequireNoInterference(const MeshState& state, double crank, double tolerance_mm) {
  const std::string overlaps = JamReport(state, tolerance_mm);
  if (!overlaps.empty()) {
    throw std::invalid_argument(fmt::format(
        "interference at crank {:.6g} deg: {} overlap the cycloid at the theoretical meshing "
        "position and no rotation of the cycloid frees every pin; expected non-negative clearances "
        "(for d > 0 the radial clearance dR_rp - dR_p must be >= 0): check [modification] "
        "pin_radius_mm and pin_circle_radius_mm and the [errors] section",
        units::RadToDeg(crank), overlaps));
  }
}

void RequireNoInterference(const MeshModel& model, double crank) {
  RequireNoInterference(model.Evaluate(crank, 0.0), crank, model.interference_tolerance());
}

namespace {

/// The face sections the first contact is sought in: every point of the state (the slice
/// centres) and, in the slice model, each pin's two face edges (z = 0 and z = B). Under
/// misalignment a pin's gap varies linearly along the face, so its first contact lies at an edge,
/// which the slice centres miss by B / (2 n): the backlash would depend on the slice count.
std::vector<PinContact> FaceSections(const MeshModel& model, const MeshState& state) {
  std::vector<PinContact> sections = state.pins;
  if (model.slice_count() == 1) return sections;
  const int last = model.slice_count() - 1;
  for (int j = 0; j < model.pin_count(); ++j) {
    sections.push_back(model.EvaluateSection(j, 0, 0.0, state.crank, state.loaded_rotation));
    sections.push_back(model.EvaluateSection(j, last, model.pair().face_width, state.crank, state.loaded_rotation));
  }
  return sections;
}

/// A lead modification (crowning) makes a pin's gap curve along the face, so its smallest closing
/// rotation can lie between two sampled sections: golden-section search of s psi(z) over the
/// sections next to the best one (psi is unimodal there: a convex lead layer over a linear gap).
double RefineAlongWidth(const MeshModel& model, const PinContact& best, const std::vector<PinContact>& sections,
                        double crank, ContactKinematics kinematics, double s, double psi_best) {
  double a = 0.0, b = model.pair().face_width;
  for (const PinContact& c : sections) {
    if (c.pin != best.pin) continue;
    if (c.z < best.z) a = std::max(a, c.z);
    if (c.z > best.z) b = std::min(b, c.z);
  }
  const auto f = [&](double z) {
    const double psi = ClosingRotation(model, model.EvaluateSection(best.pin, z, crank), crank, kinematics);
    return std::isfinite(psi) ? s * psi : std::numeric_limits<double>::infinity();
  };
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - g * (b - a), x2 = a + g * (b - a), f1 = f(x1), f2 = f(x2);
  while (b - a > 1e-9 * model.pair().face_width) {
    if (f1 <= f2) {
      b = x2, x2 = x1, f2 = f1, x1 = b - g * (b - a), f1 = f(x1);
    } else {
      a = x1, x1 = x2, f1 = f2, x2 = a + g * (b - a), f2 = f(x2);
    }
  }
  return std::min(s * psi_best, std::min(f1, f2)) * s;
}

}  // namespace

UnloadedContact AnalyseUnloaded(const MeshModel& model, double crank, ContactKinematics kinematics,
                                double interference_tolerance_mm) {
  const MeshState state = model.Evaluate(crank, 0.0);
  (void)interference_tolerance_mm;  // an overlap on both flanks is a preload (UnloadedContact::interference)
  UnloadedContact r;
  r.crank = crank;
  const std::vector<PinContact> sections = FaceSections(model, state);
  // Per pin, the smallest clearance over its face sections (Liu section 3: c_t is the minimum
  // over the slices; here the face edges too).
  const auto min_per_pin = [&](const std::vector<PinContact>& points, const auto& clearance_of) {
    std::vector<double> out(static_cast<std::size_t>(model.pin_count()), std::numeric_limits<double>::infinity());
    for (const PinContact& c : points) {
      double& v = out[static_cast<std::size_t>(c.pin)];
      v = std::min(v, clearance_of(c));
    }
    return out;
  };
  const auto gap = [](const PinContact& c) { return c.clearance; };
  r.clearance = min_per_pin(sections, gap);
  r.theta_c1 = std::numeric_limits<double>::infinity();
  r.theta_c2 = -std::numeric_limits<double>::infinity();
  // A pin whose arm is tiny closes only after a rotation far beyond any other: skip it.
  const double min_arm = 1e-9 * model.pair().pin_circle_radius;
  // Beyond a quarter tooth pitch a closing is a pin jumping teeth, not a contact (RotationWindow):
  // the exact search stops there, and so does the linearised c / L (a degenerate pair's
  // c / L of 3 rad was reported as its backlash).
  const double window = RotationWindow(model);
  const PinContact* best_c1 = nullptr;
  const PinContact* best_c2 = nullptr;
  for (const PinContact& c : sections) {
    if (std::abs(c.arm) < min_arm) continue;
    const double psi = ClosingRotation(model, c, crank, kinematics);
    if (!(std::abs(psi) <= window)) continue;
    if (c.arm > 0.0 && psi < r.theta_c1) r.theta_c1 = psi, r.first_pin_c1 = c.pin, best_c1 = &c;
    if (c.arm < 0.0 && psi > r.theta_c2) r.theta_c2 = psi, r.first_pin_c2 = c.pin, best_c2 = &c;
  }
  if (model.slice_count() > 1 && model.real_pair().errors().VariesAlongWidth()) {
    if (best_c1 != nullptr && std::isfinite(r.theta_c1)) {
      r.theta_c1 = RefineAlongWidth(model, *best_c1, sections, crank, kinematics, 1.0, r.theta_c1);
    }
    if (best_c2 != nullptr && std::isfinite(r.theta_c2)) {
      r.theta_c2 = RefineAlongWidth(model, *best_c2, sections, crank, kinematics, -1.0, r.theta_c2);
    }
  }
  // Overlapping flanks (a preloaded pair): the drive flank's closing lies behind the coast
  // flank's; no free play, and the overlap of the two, as a rotation, is the interference.
  // A rounding-sized overlap (below the model's interference tolerance over the pin-circle
  // radius) is the conjugate pair's zero backlash, kept as computed.
  const double rounding = model.interference_tolerance() / model.pair().pin_circle_radius;
  const bool overlapping = r.theta_c2 - r.theta_c1 > rounding;
  r.backlash = overlapping ? 0.0 : r.theta_c1 - r.theta_c2;
  r.interference = overlapping ? r.theta_c2 - r.theta_c1 : 0.0;
  if (kinematics == ContactKinematics::kExact) {
    const MeshState at_c1 = model.Evaluate(crank, r.theta_c1);
    r.clearance_at_c1 = min_per_pin(FaceSections(model, at_c1), gap);
  } else {
    r.clearance_at_c1 = min_per_pin(sections, [&](const PinContact& c) { return -LinearisedApproach(c, r.theta_c1); });
  }
  return r;
}

UnloadedSweep AnalyseUnloadedSweep(const MeshModel& model, const std::vector<double>& cranks,
                                   ContactKinematics kinematics) {
  UnloadedSweep sweep;
  sweep.closed_period = cranks.size() > 1 && SameMesh(model.Evaluate(cranks.front()), model.Evaluate(cranks.back()));
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0.0;
  for (std::size_t i = 0; i < cranks.size(); ++i) {
    sweep.positions.push_back(AnalyseUnloaded(model, cranks[i], kinematics));
    const double b = sweep.positions.back().backlash;
    if (!(sweep.closed_period && i + 1 == cranks.size())) sum += b;  // a repeated state weighs once
    lo = std::min(lo, b);
    hi = std::max(hi, b);
  }
  sweep.mean_backlash = sum / static_cast<double>(cranks.size() - (sweep.closed_period ? 1 : 0));
  sweep.pp_backlash = hi - lo;
  return sweep;
}

}  // namespace ltca::contact
