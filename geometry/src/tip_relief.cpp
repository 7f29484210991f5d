#include "ltca/geometry/tip_relief.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

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

/// The largest u in [0, phi_max) where f changes sign, scanning down from phi_max and refining
/// by bisection to machine precision; NaN when f keeps its sign on the whole flank.
template <class F>
double FirstRootBelowTip(const F& f, double phi_max, double start_sign) {
  constexpr int kScan = 512;
  double hi = phi_max;
  for (int i = 1; i <= kScan; ++i) {
    const double lo = phi_max * (1.0 - static_cast<double>(i) / kScan);
    const double f_lo = f(lo);
    if (f_lo * start_sign <= 0.0) {
      double a = lo, b = hi;  // sign(f(a)) != start_sign, sign(f(b)) == start_sign
      for (int it = 0; it < 200 && b - a > 4.0 * std::numeric_limits<double>::epsilon() * phi_max; ++it) {
        const double mid = 0.5 * (a + b);
        if (f(mid) * start_sign <= 0.0) a = mid; else b = mid;
      }
      return 0.5 * (a + b);
    }
    hi = lo;
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
  junction_ = phi_max;
  pitch_ = profile.tooth_pitch();
  if (relief.IsZero()) return;
  const double sign = profile.tooth_difference() > 0 ? 1.0 : -1.0;
  const double alpha = profile.ToothSpaceRotation(0) + 0.5 * pitch_;
  tip_point_ = profile.Position(phi_max, 0);
  axis_ = sign * Eigen::Vector2d(std::cos(alpha), std::sin(alpha));
  across_ = Eigen::Vector2d(std::sin(alpha), -std::cos(alpha));
  rho_ = relief.rounding_radius;
  const double t = relief.truncation;
  // The flank of space 0 near the tip in the local frame, and the centre of the circle of radius
  // rho tangent to it from inside the material.
  const auto local = [&](double u) {
    const ProfilePoint x = profile.Evaluate(u, 0);
    const Eigen::Vector2d v = x.position - tip_point_;
    return std::pair{Eigen::Vector2d(across_.dot(v), axis_.dot(v)),
                     Eigen::Vector2d(across_.dot(x.normal), axis_.dot(x.normal))};
  };
  const auto centre = [&](double u) {
    const auto [x, n] = local(u);
    return Eigen::Vector2d(x - rho_ * n);
  };
  // Symmetric arc: tangent to both flanks, centre on the axis (s_C = 0). Below the tip s_C > 0
  // once the arc fits; at the tip s_C = -rho n_s <= 0 (n_s = 0 on a smooth tip).
  double u_sym = phi_max;
  if (rho_ > 0.0) {
    const auto f_sym = [&](double u) { return centre(u).x(); };
    const double just_below = phi_max * (1.0 - 1e-9);
    if (f_sym(just_below) < 0.0) u_sym = FirstRootBelowTip(f_sym, phi_max, -1.0);
  }
  double u_j = u_sym;
  truncated_ = false;
  if (t > 0.0) {
    const double apex_sym = centre(u_sym).y() + rho_;  // the symmetric arc's apex (the tip at rho = 0)
    if (apex_sym > -t) {
      // The line cuts below the symmetric arc: the arc is tangent to the flank and to the line.
      const auto f_line = [&](double u) { return centre(u).y() + rho_ + t; };
      u_j = FirstRootBelowTip(f_line, phi_max, 1.0);
      truncated_ = true;
    }
  }
  if (std::isnan(u_j) || u_j <= 0.0) {
    const double height = -local(0.0).first.y();
    throw std::invalid_argument(fmt::format(
        "[modification] tip_truncation_mm = {}, tip_rounding_radius_mm = {}: the tip relief removes the "
        "whole flank; expected a relief well inside the tooth height {:.6g} mm (root to tip, along the axis)",
        t, rho_, height));
  }
  if (u_j >= phi_max * (1.0 - 1e-12)) return;  // a rounding inside a smooth tip's own curvature: no change
  active_ = true;
  junction_ = u_j;
  const auto [xj, nj] = local(u_j);
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
      const double u = phi_max * i / kSamples;
      const double gap = (local(u).first - centre_).norm() - rho_;
      if (gap < -1e-9 * rho_ - 1e-12) {
        const double kappa = profile.Evaluate(u_j, 0).curvature;
        throw std::invalid_argument(fmt::format(
            "[modification] tip_rounding_radius_mm = {}: the rounding arc would add material to the tooth "
            "(the flank at u = {:.6g} deg comes {:.3g} mm inside the arc); expected a radius below the flank's "
            "radius of curvature at the junction, {:.6g} mm",
            rho_, units::RadToDeg(u), -gap, kappa > 0.0 ? 1.0 / kappa : std::numeric_limits<double>::infinity()));
      }
    }
  }
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
  foot.x() *= side;
  normal.x() *= side;
  out.point = ToBody(foot, tip);
  out.normal = DirToBody(normal, tip);
  const int zc = static_cast<int>(std::lround(2.0 * kPi / pitch_));
  out.tooth_space = (((side > 0.0 ? tip : tip + 1) % zc) + zc) % zc;
  return out;
}

double TipCap::length() const {
  if (!active_) return 0.0;
  return 2.0 * (land_ + rho_ * (0.5 * kPi - arc_start_));
}

Eigen::Vector2d TipCap::Point(double w, int tip) const {
  const double half = 0.5 * length();
  const double d = std::clamp(std::abs(w), 0.0, 1.0) * half;  // from the apex on the axis
  Eigen::Vector2d local;
  if (d <= land_ || rho_ == 0.0) {
    local = truncated_ ? Eigen::Vector2d(std::min(d, land_), -relief_.truncation) : centre_;
  } else {
    const double theta = 0.5 * kPi - (d - land_) / rho_;
    local = centre_ + rho_ * Eigen::Vector2d(std::cos(theta), std::sin(theta));
  }
  if (w < 0.0) local.x() = -local.x();
  return ToBody(local, tip);
}

}  // namespace ltca::geometry
