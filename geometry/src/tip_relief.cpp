#include "ltca/geometry/tip_relief.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::geometry {
namespace {

using units::kPi;

Eigen::Vector2d Rotate(const Eigen::Vector2d& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

/// The smallest v in (0, span] where f changes sign from start_sign, scanning up from the tip
/// (v = 0) and refining by bisection to machine precision; NaN when f keeps its sign.
template <class F>
double FirstRootFromTip(const F& f, double span, double start_sign) {
  constexpr int kScan = 512;
  double lo = 0.0;
  for (int i = 1; i <= kScan; ++i) {
    const double hi = span * static_cast<double>(i) / kScan;
    if (f(hi) * start_sign <= 0.0) {
      double a = lo, b = hi;  // sign(f(a)) == start_sign, sign(f(b)) != start_sign
      for (int it = 0; it < 200 && b - a > 4.0 * std::numeric_limits<double>::epsilon() * span; ++it) {
        const double mid = 0.5 * (a + b);
        if (f(mid) * start_sign <= 0.0) b = mid; else a = mid;
      }
      return 0.5 * (a + b);
    }
    lo = hi;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

const char* SurfacePartName(SurfacePart part) {
  switch (part) {
    case SurfacePart::kFlank: return "flank";
    case SurfacePart::kTipRounding: return "tip-rounding";
    case SurfacePart::kTipTruncation: return "tip-truncation";
    case SurfacePart::kTipCorner: return "tip-corner";
  }
  return "flank";
}

TipCap::TipCap(const CycloidProfile& profile, const TipRelief& relief) : relief_(relief) {
  const double phi_max = profile.phi_max();
  ring_ = profile.tooth_difference() < 0;
  phi_max_ = phi_max;
  junction_ = ring_ ? 0.0 : phi_max;
  pitch_ = profile.tooth_pitch();
  if (relief.IsZero()) return;
  // The tip and its axis: for d > 0 the tip between spaces 0 and 1 (u = phi_max of space 0), the
  // axis radial and outward; for d < 0 (a ring: its teeth point to the centre) the tip at u = 0 of
  // space 0, the axis toward the centre. s > 0 is the side of space 0's u < phi_max (d > 0) or of
  // u > 0 (d < 0): the flank there is u = phi_max - v or u = v, v >= 0 from the tip.
  const double alpha = profile.ToothSpaceRotation(0) + (ring_ ? 0.0 : 0.5 * pitch_);
  const Eigen::Vector2d radial(std::cos(alpha), std::sin(alpha));
  tip_point_ = profile.Position(ring_ ? 0.0 : phi_max, 0);
  axis_ = ring_ ? Eigen::Vector2d(-radial) : radial;
  across_ = ring_ ? Eigen::Vector2d(-radial.y(), radial.x()) : Eigen::Vector2d(radial.y(), -radial.x());
  rho_ = relief.rounding_radius;
  const double t = relief.truncation;
  const auto u_of = [&](double v) { return ring_ ? v : phi_max - v; };
  // The flank near the tip in the local frame, and the centre of the circle of radius rho tangent
  // to it from inside the material.
  const auto local = [&](double v) {
    const ProfilePoint x = profile.Evaluate(u_of(v), 0);
    const Eigen::Vector2d d = x.position - tip_point_;
    return std::pair{Eigen::Vector2d(across_.dot(d), axis_.dot(d)),
                     Eigen::Vector2d(across_.dot(x.normal), axis_.dot(x.normal))};
  };
  const auto centre = [&](double v) {
    const auto [x, n] = local(v);
    return Eigen::Vector2d(x - rho_ * n);
  };
  // Symmetric arc: tangent to both flanks, centre on the axis (s_C = 0). Below the tip s_C > 0
  // once the arc fits; at the tip s_C = -rho n_s <= 0 (n_s = 0 on a smooth tip).
  double v_sym = 0.0;
  if (rho_ > 0.0) {
    const auto f_sym = [&](double v) { return centre(v).x(); };
    if (f_sym(1e-9 * phi_max) < 0.0) v_sym = FirstRootFromTip(f_sym, phi_max, -1.0);
  }
  double v_j = v_sym;
  truncated_ = false;
  if (t > 0.0) {
    const double apex_sym = centre(v_sym).y() + rho_;  // the symmetric arc's apex (the tip at rho = 0)
    if (!(apex_sym <= -t)) {
      // The line cuts below the symmetric arc: the arc is tangent to the flank and to the line.
      const auto f_line = [&](double v) { return centre(v).y() + rho_ + t; };
      v_j = FirstRootFromTip(f_line, phi_max, 1.0);
      truncated_ = true;
    }
  }
  if (std::isnan(v_j) || v_j >= phi_max) {
    const double height = -local(phi_max).first.y();
    throw std::invalid_argument(fmt::format(
        "[modification] tip_truncation_mm = {}, tip_rounding_radius_mm = {}: the tip relief removes the "
        "whole flank; expected a relief well inside the tooth height {:.6g} mm (root to tip, along the axis)",
        t, rho_, height));
  }
  if (v_j <= phi_max * 1e-12) return;  // a rounding inside a smooth tip's own curvature: no change
  active_ = true;
  junction_ = u_of(v_j);
  const auto [xj, nj] = local(v_j);
  centre_ = xj - rho_ * nj;
  if (!truncated_) centre_.x() = 0.0;  // on the axis (the root is found to rounding)
  land_ = truncated_ ? std::max(centre_.x(), 0.0) : 0.0;
  depth_ = truncated_ ? t : -(centre_.y() + rho_);
  arc_start_ = std::atan2(nj.y(), nj.x());
  // The arc must lie in the material: every point of the flank (the part kept and the part cut
  // away) is at least rho from its centre. Fails when rho exceeds the flank's convex radius of
  // curvature at the junction.
  if (rho_ > 0.0) {
    constexpr int kSamples = 512;
    for (int i = 0; i <= kSamples; ++i) {
      const double v = phi_max * i / kSamples;
      const double gap = (local(v).first - centre_).norm() - rho_;
      if (gap < -1e-9 * rho_ - 1e-12) {
        const double kappa = profile.Evaluate(junction_, 0).curvature;
        throw std::invalid_argument(fmt::format(
            "[modification] tip_rounding_radius_mm = {}: the rounding arc would add material to the tooth "
            "(the flank at u = {:.6g} deg comes {:.3g} mm inside the arc); expected a radius below the flank's "
            "radius of curvature at the junction, {:.6g} mm",
            rho_, units::RadToDeg(u_of(v)), -gap, kappa > 0.0 ? 1.0 / kappa : std::numeric_limits<double>::infinity()));
      }
    }
  }
}

std::vector<std::pair<double, double>> TipCap::FlankArcs() const {
  if (!ring_) return {{-junction_, junction_}};
  return {{-phi_max_, -junction_}, {junction_, phi_max_}};
}

int TipCap::SpaceOf(int tip, double side) const {
  const int zc = static_cast<int>(std::lround(2.0 * kPi / pitch_));
  const int k = ring_ || side > 0.0 ? tip : tip + 1;
  return ((k % zc) + zc) % zc;
}

double TipCap::JunctionOf(double side) const {
  // d > 0: space k ends at +u_j, space k + 1 starts at -u_j; d < 0: space k's flank starts at
  // u_j on the s > 0 side and ends at -u_j on the other.
  return side > 0.0 ? junction_ : -junction_;
}

Eigen::Vector2d TipCap::ToLocal(const Eigen::Vector2d& p, int tip) const {
  const Eigen::Vector2d v = Rotate(p, -tip * pitch_) - tip_point_;
  return {across_.dot(v), axis_.dot(v)};
}

Eigen::Vector2d TipCap::ToBody(const Eigen::Vector2d& local, int tip) const {
  return Rotate(tip_point_ + local.x() * across_ + local.y() * axis_, tip * pitch_);
}

Eigen::Vector2d TipCap::DirToBody(const Eigen::Vector2d& local, int tip) const {
  return Rotate(local.x() * across_ + local.y() * axis_, tip * pitch_);
}

CapFoot TipCap::Nearest(const Eigen::Vector2d& p, int tip) const {
  const Eigen::Vector2d v = ToLocal(p, tip);
  const double side = v.x() >= 0.0 ? 1.0 : -1.0;
  const Eigen::Vector2d q(std::abs(v.x()), v.y());
  // Candidates on the half cap s >= 0: the arc (or the corner when rho = 0) and the segment.
  Eigen::Vector2d foot, piece_normal;
  SurfacePart part;
  if (rho_ > 0.0) {
    const Eigen::Vector2d w = q - centre_;
    const double theta = std::clamp(std::atan2(w.y(), w.x()), arc_start_, 0.5 * kPi);
    piece_normal = Eigen::Vector2d(std::cos(theta), std::sin(theta));
    foot = centre_ + rho_ * piece_normal;
    part = SurfacePart::kTipRounding;
  } else {
    foot = centre_;
    piece_normal = (q - centre_).normalized();
    part = SurfacePart::kTipCorner;
  }
  if (truncated_) {
    const double s = std::min(q.x(), land_);
    const Eigen::Vector2d on_line(s, -relief_.truncation);
    if ((q - on_line).norm() < (q - foot).norm() && !(rho_ == 0.0 && s == land_)) {
      foot = on_line;
      piece_normal = Eigen::Vector2d(0.0, 1.0);
      part = SurfacePart::kTipTruncation;
    }
  }
  CapFoot out;
  const Eigen::Vector2d r = q - foot;
  const double dist = r.norm();
  Eigen::Vector2d normal = dist > 0.0 ? Eigen::Vector2d(r / dist) : piece_normal;
  out.distance = r.dot(piece_normal) >= 0.0 ? dist : -dist;
  if (out.distance < 0.0) normal = -normal;  // inside the material: the outward normal
  out.curvature = part == SurfacePart::kTipRounding ? 1.0 / rho_
                  : part == SurfacePart::kTipCorner ? std::numeric_limits<double>::infinity()
                                                     : 0.0;
  out.part = part;
  // w: the foot's arc length from the apex (the segment's s, then the arc's angle from pi/2) over
  // the half cap's.
  const double half = 0.5 * length();
  double from_apex = land_;
  if (part == SurfacePart::kTipTruncation) {
    from_apex = std::min(foot.x(), land_);
  } else if (part == SurfacePart::kTipRounding) {
    const Eigen::Vector2d arm = foot - centre_;
    from_apex = land_ + rho_ * (0.5 * kPi - std::atan2(arm.y(), arm.x()));
  }
  out.w = half > 0.0 ? side * std::clamp(from_apex / half, 0.0, 1.0) : side;
  foot.x() *= side;
  normal.x() *= side;
  out.point = ToBody(foot, tip);
  out.normal = DirToBody(normal, tip);
  out.tooth_space = SpaceOf(tip, side);
  out.u = JunctionOf(side);
  return out;
}

double TipCap::length() const {
  if (!active_) return 0.0;
  return 2.0 * (land_ + rho_ * (0.5 * kPi - arc_start_));
}

CapFoot TipCap::Point(double w, int tip) const {
  const double half = 0.5 * length();
  const double d = std::clamp(std::abs(w), 0.0, 1.0) * half;  // from the apex on the axis
  Eigen::Vector2d local, normal(0.0, 1.0);
  CapFoot out;
  if (rho_ == 0.0 || (truncated_ && d <= land_)) {
    local = truncated_ ? Eigen::Vector2d(std::min(d, land_), -relief_.truncation) : centre_;
    out.part = rho_ == 0.0 && d >= land_ ? SurfacePart::kTipCorner : SurfacePart::kTipTruncation;
    out.curvature = out.part == SurfacePart::kTipCorner ? std::numeric_limits<double>::infinity() : 0.0;
  } else {
    const double theta = 0.5 * kPi - (d - land_) / rho_;
    normal = Eigen::Vector2d(std::cos(theta), std::sin(theta));
    local = centre_ + rho_ * normal;
    out.part = SurfacePart::kTipRounding;
    out.curvature = 1.0 / rho_;
  }
  if (w < 0.0) local.x() = -local.x(), normal.x() = -normal.x();
  out.w = std::clamp(w, -1.0, 1.0);
  out.point = ToBody(local, tip);
  out.normal = DirToBody(normal, tip);
  out.tooth_space = SpaceOf(tip, w >= 0.0 ? 1.0 : -1.0);
  out.u = JunctionOf(w >= 0.0 ? 1.0 : -1.0);
  return out;
}

}  // namespace ltca::geometry
