#include "ltca/geometry/inspection.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::geometry {
namespace {

using units::kPi;

/// The half of a tooth space the roller and the tip see, as one or two parameter intervals: the
/// flank of space 0 from its root to its tip end (u), and the cap of the tip beyond it (w).
struct HalfSpace {
  double root_u = 0.0;  // the flank's root end: 0 (d > 0) or phi_max (a ring)
  double tip_u = 0.0;   // its tip end: the junction or the unrelieved tip
  bool cap = false;     // a relieved tip: the cap of tip 0, w in [-1, 1]
  double axis = 0.0;    // angle of the space's symmetry axis in the body frame, rad
};

HalfSpace HalfOf(const CycloidProfile& profile) {
  HalfSpace h;
  const TipCap& cap = profile.tip_cap();
  const double rotation = profile.modification().rotation;
  if (profile.tooth_difference() > 0) {
    h.root_u = 0.0;
    h.tip_u = cap.active() ? cap.junction() : profile.phi_max();
    h.axis = rotation;  // the root of space 0 at u = 0
  } else {
    h.root_u = profile.phi_max();  // a ring's spaces bottom out on the axis at pi / z_c
    h.tip_u = cap.active() ? cap.junction() : 0.0;
    h.axis = rotation + kPi / profile.pair().tooth_count;
  }
  h.cap = cap.active();
  return h;
}

/// The largest value of f over [lo, hi]: a uniform scan, then golden section about the best sample
/// (f smooth there; -infinity where it is not defined). Returns the argument and the value.
template <class F>
std::pair<double, double> Maximise(const F& f, double lo, double hi) {
  constexpr int kScan = 2000;
  int best = 0;
  double best_value = -std::numeric_limits<double>::infinity();
  for (int i = 0; i <= kScan; ++i) {
    const double v = f(lo + (hi - lo) * i / kScan);
    if (v > best_value) best_value = v, best = i;
  }
  double a = lo + (hi - lo) * std::max(best - 1, 0) / kScan;
  double b = lo + (hi - lo) * std::min(best + 1, kScan) / kScan;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = f(c), fd = f(d);
  for (int it = 0; it < 200 && b - a > 1e-15 * (1.0 + std::abs(a) + std::abs(b)); ++it) {
    if (fc >= fd) {
      b = d, d = c, fd = fc;
      c = b - g * (b - a), fc = f(c);
    } else {
      a = c, c = d, fc = fd;
      d = a + g * (b - a), fd = f(d);
    }
  }
  double arg = fc >= fd ? c : d;
  double value = std::max(fc, fd);
  for (const double t : {lo + (hi - lo) * best / kScan, lo, hi}) {  // the bracket may end on the best
    const double v = f(t);
    if (v > value) value = v, arg = t;
  }
  return {arg, value};
}

Eigen::Vector2d ToAxis(const Eigen::Vector2d& p, double axis) {
  const double c = std::cos(axis), s = std::sin(axis);
  return {c * p.x() + s * p.y(), -s * p.x() + c * p.y()};
}

}  // namespace

const char* RollerContactName(RollerContact contact) {
  switch (contact) {
    case RollerContact::kFlanks: return "flanks";
    case RollerContact::kRoot: return "root";
    case RollerContact::kTips: return "tips";
  }
  return "?";
}

double RootDiameter(const CycloidProfile& profile) {
  // The bottom of a space lies on its symmetry axis: u = 0 (d > 0) or u = phi_max (a ring).
  return 2.0 * profile.Position(HalfOf(profile).root_u, 0).norm();
}

double TipDiameter(const CycloidProfile& profile) {
  const HalfSpace h = HalfOf(profile);
  if (!h.cap) return 2.0 * profile.Position(profile.tooth_difference() > 0 ? profile.phi_max() : 0.0, 0).norm();
  // The cap's extreme radius: the largest for a disc, the least for a ring (its teeth point inward).
  const double sign = profile.tooth_difference() > 0 ? 1.0 : -1.0;
  const TipCap& cap = profile.tip_cap();
  const auto radius = [&](double w) { return sign * cap.Point(w, 0).point.norm(); };
  return 2.0 * sign * Maximise(radius, -1.0, 1.0).second;
}

RollerMeasurement MeasureOverRollers(const CycloidProfile& profile, double roller_diameter) {
  if (!std::isfinite(roller_diameter) || roller_diameter <= 0.0) {
    throw std::invalid_argument(
        fmt::format("[inspection] roller_diameter_mm = {}: expected a positive roller diameter in mm", roller_diameter));
  }
  const HalfSpace h = HalfOf(profile);
  const double sign = profile.tooth_difference() > 0 ? 1.0 : -1.0;
  const double r = 0.5 * roller_diameter;
  // The roller's travel along the axis a profile point allows (the header's equation), signed so
  // that the seat is its largest value.
  const auto travel = [&](const Eigen::Vector2d& body) {
    const Eigen::Vector2d p = ToAxis(body, h.axis);
    if (std::abs(p.y()) > r) return -std::numeric_limits<double>::infinity();
    return sign * p.x() + std::sqrt(r * r - p.y() * p.y());
  };
  const auto on_flank = [&](double u) { return travel(profile.Position(u, 0)); };
  auto [u, flank_value] = Maximise(on_flank, std::min(h.root_u, h.tip_u), std::max(h.root_u, h.tip_u));
  RollerMeasurement m;
  m.roller_diameter = roller_diameter;
  double value = flank_value;
  Eigen::Vector2d contact = profile.Position(u, 0);
  constexpr double kAtEnd = 1e-7;  // rad: a maximum this near an end of the flank is that end
  if (std::abs(u - h.root_u) < kAtEnd) {
    m.contact = RollerContact::kRoot;
    m.contact_u = h.root_u;
    contact = profile.Position(h.root_u, 0);
    value = travel(contact);
  } else if (std::abs(u - h.tip_u) < kAtEnd) {
    m.contact = RollerContact::kTips;
    m.contact_u = h.tip_u;
  } else {
    m.contact = RollerContact::kFlanks;
    m.contact_u = std::abs(u);
  }
  if (h.cap) {
    const TipCap& cap = profile.tip_cap();
    const auto [w, cap_value] = Maximise([&](double w) { return travel(cap.Point(w, 0).point); }, -1.0, 1.0);
    if (cap_value > value) {
      value = cap_value;
      contact = cap.Point(w, 0).point;
      m.contact = RollerContact::kTips;
      m.contact_u = std::numeric_limits<double>::quiet_NaN();
    }
  }
  m.centre_radius = sign * value;
  m.contact_diameter = 2.0 * contact.norm();
  const int z = profile.pair().tooth_count;
  const double chord = z % 2 == 0 ? 2.0 * m.centre_radius : 2.0 * m.centre_radius * std::cos(kPi / (2.0 * z));
  m.dimension = chord + sign * roller_diameter;
  return m;
}

}  // namespace ltca::geometry
