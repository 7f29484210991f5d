#include "ltca/geometry/profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::geometry {
namespace {

using units::kPi;

Eigen::Vector2d Rotate(const Eigen::Vector2d& v, double angle) {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

}  // namespace

double ProfilePoint::CurvatureRadius() const {
  if (curvature == 0.0) return std::numeric_limits<double>::infinity();
  return 1.0 / curvature;
}

CycloidProfile::CycloidProfile(const PairParameters& pair, const Modification& modification)
    : pair_(pair), modification_(modification) {
  pair_.Validate();
  modification_.Validate(pair_);
  d_ = pair_.ToothDifference();
  sign_ = d_ > 0 ? 1.0 : -1.0;
  R_ = pair_.pin_circle_radius + modification_.pin_circle_radius;
  r_ = pair_.pin_radius + modification_.pin_radius;
  e_ = pair_.eccentricity;
  ze_ = static_cast<double>(pair_.pin_count) / d_;
  zd_ = static_cast<double>(pair_.tooth_count) / d_;
  k1_ = e_ * ze_ / R_;  // Chen eq. 12, signed (negative for d < 0)
  // cos and sin of every tooth space's rotation, once (Evaluate rotates four vectors).
  space_cos_.resize(static_cast<std::size_t>(pair_.tooth_count));
  space_sin_.resize(static_cast<std::size_t>(pair_.tooth_count));
  for (int k = 0; k < pair_.tooth_count; ++k) {
    const double angle = ToothSpaceRotation(k);
    space_cos_[static_cast<std::size_t>(k)] = std::cos(angle);
    space_sin_[static_cast<std::size_t>(k)] = std::sin(angle);
  }
  ComputePhiMax();
  ComputeCurvatureExtremes();
  tip_cap_ = TipCap(*this, modification_.tip_relief);
}

double CycloidProfile::tooth_pitch() const { return 2.0 * kPi / pair_.tooth_count; }

double CycloidProfile::ToothSpaceRotation(int tooth_space) const {
  return tooth_space * tooth_pitch() + modification_.rotation;
}

double CycloidProfile::contact_ratio() const {
  // Chen eq. 27 (with |d|, so that d = -1 gives z_p / 2 as d = 1 does).
  // In double: z_p z_c overflows an int from about 46,000 pins.
  return static_cast<double>(pair_.pin_count) * static_cast<double>(pair_.tooth_count) * phi_max_ /
         (2.0 * kPi * std::abs(d_));
}

double CycloidProfile::theta_max() const {
  // Chen eq. 20.
  const double k = k1();
  return -std::atan(std::sqrt((1.0 - k * k) / (k * k)));
}

double CycloidProfile::alpha_max() const {
  // Liu eq. 2: alpha = atan(K1 sin phi / (1 - K1 cos phi)) peaks at cos phi = K1.
  return std::asin(k1());
}

Eigen::Vector2d CycloidProfile::PinCentreLocus(double u, int tooth_space) const {
  const Eigen::Vector2d q(R_ * std::cos(u) - e_ * std::cos(ze_ * u),
                          R_ * std::sin(u) - e_ * std::sin(ze_ * u));
  return Rotate(q, ToothSpaceRotation(tooth_space));
}

double CycloidProfile::LocusCurvature(double u) const {
  // Curvature of q toward the material side (s * n_in), Liu eq. 8 generalised to any d:
  //   kappa = s [1 + K1^2 Ze - K1 (1 + Ze) cos(Zd u)] / (R' (1 + K1^2 - 2 K1 cos(Zd u))^(3/2)).
  const double c = std::cos(zd_ * u);
  const double a = 1.0 + k1_ * k1_ * ze_;
  const double b = k1_ * (1.0 + ze_);
  const double s2 = 1.0 + k1_ * k1_ - 2.0 * k1_ * c;
  return sign_ * (a - b * c) / (R_ * s2 * std::sqrt(s2));
}

ProfilePoint CycloidProfile::Evaluate(double u, int tooth_space) const {
  // Locus derivatives.
  const double cu = std::cos(u), su = std::sin(u);
  const double ce = std::cos(ze_ * u), se = std::sin(ze_ * u);
  const Eigen::Vector2d q(R_ * cu - e_ * ce, R_ * su - e_ * se);
  const Eigen::Vector2d q1(-R_ * su + e_ * ze_ * se, R_ * cu - e_ * ze_ * ce);
  const Eigen::Vector2d q2(-R_ * cu + e_ * ze_ * ze_ * ce, -R_ * su + e_ * ze_ * ze_ * se);
  const double speed = q1.norm();  // = R' sqrt(1 + K1^2 - 2 K1 cos(Zd u)) > 0 for |K1| < 1
  const Eigen::Vector2d t = q1 / speed;
  const Eigen::Vector2d n_in(-t.y(), t.x());  // left normal; points to O_c at the root
  // Curvature of the locus toward the material, and its derivative in u.
  const double kappa_m = sign_ * Cross(q1, q2) / (speed * speed * speed);
  // cos and sin of Zd u = (Ze - 1) u from those of u and Ze u (two trig calls fewer).
  const double c = ce * cu + se * su;
  const double s_zd = se * cu - ce * su;
  const double a = 1.0 + k1_ * k1_ * ze_;
  const double b = k1_ * (1.0 + ze_);
  const double dd = 1.0 + k1_ * k1_;
  const double g = 2.0 * k1_;
  const double w = dd - g * c;
  const double dkappa_dc = sign_ * (-b * w + 1.5 * g * (a - b * c)) / (R_ * w * w * std::sqrt(w));
  const double dkappa_du = dkappa_dc * (-zd_ * s_zd);
  // Real profile: equidistant of q at r' toward the material (Chen eq. 13-14: sign of d).
  const double stretch = 1.0 - r_ * kappa_m;  // > 0 on a profile without undercut
  ProfilePoint p;
  p.position = q + sign_ * r_ * n_in;
  p.d1 = stretch * q1;
  p.d2 = stretch * q2 - r_ * dkappa_du * q1;
  p.normal = -sign_ * n_in;
  p.curvature = kappa_m / stretch;  // 1 / (rho_q - r'), Liu eq. 8
  const double rot = ToothSpaceRotation(tooth_space);
  if (rot != 0.0) {
    double c_rot = 0.0, s_rot = 0.0;
    if (tooth_space >= 0 && tooth_space < pair_.tooth_count) {
      c_rot = space_cos_[static_cast<std::size_t>(tooth_space)];
      s_rot = space_sin_[static_cast<std::size_t>(tooth_space)];
    } else {
      c_rot = std::cos(rot), s_rot = std::sin(rot);
    }
    const auto turn = [&](const Eigen::Vector2d& v) -> Eigen::Vector2d {
      return {c_rot * v.x() - s_rot * v.y(), s_rot * v.x() + c_rot * v.y()};
    };
    p.position = turn(p.position);
    p.d1 = turn(p.d1);
    p.d2 = turn(p.d2);
    p.normal = turn(p.normal);
  }
  return p;
}

Eigen::Vector2d CycloidProfile::Position(double u, int tooth_space) const {
  const Eigen::Vector2d q1(-R_ * std::sin(u) + e_ * ze_ * std::sin(ze_ * u),
                           R_ * std::cos(u) - e_ * ze_ * std::cos(ze_ * u));
  const Eigen::Vector2d n_in = Eigen::Vector2d(-q1.y(), q1.x()) / q1.norm();
  const Eigen::Vector2d q(R_ * std::cos(u) - e_ * std::cos(ze_ * u),
                          R_ * std::sin(u) - e_ * std::sin(ze_ * u));
  return Rotate(q + sign_ * r_ * n_in, ToothSpaceRotation(tooth_space));
}

void CycloidProfile::ComputePhiMax() {
  // Chen eq. 16: the profile point on the symmetry axis of the tooth, i.e. at polar angle
  // pi / z_c from the root axis. By symmetry of the lobe, |d| = 1 gives phi_max = pi / z_c exactly.
  const double half_pitch = kPi / pair_.tooth_count;
  if (std::abs(d_) == 1) {
    phi_max_ = half_pitch;
    return;
  }
  // |d| >= 2: bracketed root search over the whole admissible interval (0, |d| pi / z_c]: the
  // polar angle starts at 0 at the root and reaches |d| pi / z_c at the lobe tip of the locus.
  // The first sign change from a uniform scan is refined by bisection to machine precision.
  // Measured from the root axis of space 0, which the rotation modification turns: the tooth's
  // symmetry axis turns with it (the rotation is taken off here: without it a rotated |d| >= 2
  // profile gets the wrong phi_max).
  const auto polar_excess = [&](double u) {
    const Eigen::Vector2d x = Position(u, 0);
    return std::remainder(std::atan2(x.y(), x.x()) - modification_.rotation, 2.0 * kPi) - half_pitch;
  };
  const double upper = std::abs(d_) * half_pitch;
  constexpr int kScan = 256;
  double lo = 0.0;
  double f_lo = polar_excess(lo);
  double hi = upper;
  bool bracketed = false;
  for (int i = 1; i <= kScan; ++i) {
    const double u = upper * i / kScan;
    const double f = polar_excess(u);
    if ((f_lo < 0.0) != (f < 0.0)) {
      hi = u;
      bracketed = true;
      break;
    }
    lo = u;
    f_lo = f;
  }
  if (!bracketed) {
    throw std::invalid_argument(fmt::format(
        "[pair]: the tooth profile never reaches its symmetry axis (Chen eq. 16 has no root in "
        "(0, {:.6g}] rad); the geometry is not a valid cycloid tooth",
        upper));
  }
  for (int it = 0; it < 200 && hi - lo > 4.0 * std::numeric_limits<double>::epsilon() * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    const double f = polar_excess(mid);
    if ((f_lo < 0.0) != (f < 0.0)) {
      hi = mid;
    } else {
      lo = mid;
      f_lo = f;
    }
  }
  phi_max_ = 0.5 * (lo + hi);
}

void CycloidProfile::ComputeCurvatureExtremes() {
  // The locus curvature toward the material is f(c) / R' with c = cos(Zd u) and
  //   f(c) = s (A - B c) / (D - G c)^(3/2),  A = 1 + K1^2 Ze, B = K1 (1 + Ze), D = 1 + K1^2, G = 2 K1,
  // whose derivative is linear in c up to a positive factor: one interior critical point
  // c* = (3 G A - 2 B D) / (G B). The extremes over the real arc are at c*, and the ends.
  const double a = 1.0 + k1_ * k1_ * ze_;
  const double b = k1_ * (1.0 + ze_);
  const double dd = 1.0 + k1_ * k1_;
  const double g = 2.0 * k1_;
  const auto f = [&](double c) {
    const double w = dd - g * c;
    return sign_ * (a - b * c) / (w * std::sqrt(w));
  };
  const double arc = std::abs(zd_) * phi_max_;
  const double c_lo = arc >= kPi ? -1.0 : std::cos(arc);
  double f_max = std::max(f(c_lo), f(1.0));
  double f_min = std::min(f(c_lo), f(1.0));
  double c_at_max = f(c_lo) > f(1.0) ? c_lo : 1.0;
  if (g * b != 0.0) {
    const double c_star = (3.0 * g * a - 2.0 * b * dd) / (g * b);
    if (c_star > c_lo && c_star < 1.0) {
      const double f_star = f(c_star);
      if (f_star > f_max) {
        f_max = f_star;
        c_at_max = c_star;
      }
      f_min = std::min(f_min, f_star);
    }
  }
  const double inf = std::numeric_limits<double>::infinity();
  undercut_margin_ = f_max > 0.0 ? R_ / f_max - r_ : inf;
  const double concave = f_min < 0.0 ? R_ / -f_min + r_ : inf;
  min_curvature_radius_ = std::min(undercut_margin_, concave);
  if (undercut_margin_ <= 0.0) {
    const double u_at = std::acos(std::clamp(c_at_max, -1.0, 1.0)) / std::abs(zd_);
    // Name the key(s) that set the generating radius: the pin radius, and its modification
    // when there is one.
    const std::string keys =
        modification_.pin_radius == 0.0
            ? fmt::format("[pair] pin_radius_mm = {}", pair_.pin_radius)
            : fmt::format("[pair] pin_radius_mm = {} with [modification] pin_radius_mm = {}",
                          pair_.pin_radius, modification_.pin_radius);
    throw std::invalid_argument(fmt::format(
        "{}: the profile is undercut (looped): the generating pin radius "
        "r_rp + dR_rp = {:.6g} mm reaches the smallest convex radius of curvature of the "
        "theoretical profile, {:.6g} mm at u = {:.6g} deg; expected a pin radius below it "
        "(reduce the pin radius or the eccentricity)",
        keys, r_, R_ / f_max, units::RadToDeg(u_at)));
  }
}

}  // namespace ltca::geometry
