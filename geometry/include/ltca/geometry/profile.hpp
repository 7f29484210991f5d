#pragma once
#include <vector>
// The cycloid tooth profile of Chen 2008 (universal profile, eq. 10-14) for any nonzero tooth
// difference, written in Liu 2021's body frame (eq. 1-2) with Liu's modifications (dR_p, dR_rp).
//
// Body frame of the cycloid: origin at the cycloid centre O_c; the root of the reference tooth
// space (k = 0) lies on the +x axis. Parameter u is Chen's phi_b' (= Liu's phi_p / z_c):
//   q(u) = R'(cos u, sin u) - e (cos Ze u, sin Ze u),   Ze = z_p / d,  R' = R_p + dR_p
// is the pin-centre locus (the theoretical profile, Chen's r_Z = 0), and the real profile is its
// equidistant at r' = r_rp + dR_rp, on the inner side for d > 0 and the outer side for d < 0
// (the sign of Chen eq. 14). Chen's eq. 10 is the same curve mirrored into his frame:
//   Chen(phi) = Rot(+90 deg) * Position(-phi)          (tested in tests/geometry).
// Tooth space k is the reference space rotated by 2 pi k / z_c (plus the rotation modification).
// The reference space is the arc u in [-phi_max, phi_max]; for |d| = 1 consecutive spaces join
// smoothly at the tips, for |d| >= 2 they meet in sharp tip corners (Chen section 2.2).
#include <cmath>

#include <Eigen/Core>

#include "ltca/geometry/pair.hpp"
#include "ltca/geometry/tip_relief.hpp"

namespace ltca::geometry {

/// A point of the real (modified) cycloid profile, in the body frame.
struct ProfilePoint {
  Eigen::Vector2d position;  ///< mm.
  Eigen::Vector2d normal;    ///< unit normal out of the cycloid material, toward the pin.
  Eigen::Vector2d d1;        ///< dx/du, mm/rad.
  Eigen::Vector2d d2;        ///< d2x/du2, mm/rad^2.
  double curvature = 0.0;    ///< 1/mm, signed: > 0 convex (centre of curvature inside the
                             ///< material), < 0 concave; 0 at the inflection point. Finite.
  /// Signed radius of curvature (Liu eq. 8 sign convention), mm; +-infinity at the inflection.
  double CurvatureRadius() const;
};

class CycloidProfile {
 public:
  /// Validates the pair and the modification and rejects an undercut (looped) profile:
  /// throws std::invalid_argument naming the key, the value and what is expected.
  explicit CycloidProfile(const PairParameters& pair, const Modification& modification = {});

  const PairParameters& pair() const { return pair_; }
  const Modification& modification() const { return modification_; }
  int tooth_difference() const { return d_; }

  /// |K1| of the generating (modified) profile, e z_p / ((R_p + dR_p) |d|) (Chen eq. 12).
  double k1() const { return std::abs(k1_); }
  /// Half-width in u of a tooth space, Chen eq. 16 (root of the symmetry-axis equation), rad.
  double phi_max() const { return phi_max_; }
  /// Chen eq. 27: z_p z_c phi_max / (2 pi |d|).
  double contact_ratio() const;
  /// Chen eq. 20: the pin's maximum contact angle, -arctan(sqrt((1 - K1^2) / K1^2)), rad (< 0).
  double theta_max() const;
  /// Liu eq. 2 at its maximum: alpha_max = arcsin(K1) = pi/2 - |theta_max|, rad.
  double alpha_max() const;
  /// Smallest |radius of curvature| of the real profile over the tooth arc, mm (tip corners of
  /// |d| >= 2 profiles are corners, not curvature, and are not counted).
  double min_curvature_radius() const { return min_curvature_radius_; }
  /// Undercut margin: smallest convex radius of the pin-centre locus on the side the profile is
  /// offset to, minus r', mm. Positive for a valid profile; +infinity if that side has no
  /// convex part.
  double undercut_margin() const { return undercut_margin_; }
  /// Angular pitch of the teeth, 2 pi / z_c.
  double tooth_pitch() const;
  /// True when consecutive tooth spaces meet in sharp corners (|d| >= 2 without a tip relief, or
  /// a truncation without rounding).
  bool has_tip_corners() const {
    return tip_cap_.active() ? tip_cap_.relief().rounding_radius == 0.0 : std::abs(d_) >= 2;
  }
  /// The relieved tips ([modification] tip_truncation_mm, tip_rounding_radius_mm):
  /// inactive without a relief. With one, the flank of every space runs over
  /// |u| <= tip_cap().junction() and the cap replaces the rest. phi_max, the contact ratio and the
  /// curvature extremes stay those of the flank (Chen's checks).
  const TipCap& tip_cap() const { return tip_cap_; }

  /// The real profile of tooth space k at parameter u (any u: the generating curve; the real
  /// profile is u in [-phi_max, phi_max]). Analytic position, normal, derivatives, curvature.
  ProfilePoint Evaluate(double u, int tooth_space = 0) const;
  /// Position only (cheaper).
  Eigen::Vector2d Position(double u, int tooth_space = 0) const;
  /// The pin-centre locus q(u) (theoretical profile), rotated into tooth space k.
  Eigen::Vector2d PinCentreLocus(double u, int tooth_space = 0) const;
  /// Signed curvature of the pin-centre locus toward the material, 1/mm (Liu eq. 8 without r').
  double LocusCurvature(double u) const;
  /// Rotation (rad) that maps the reference tooth space onto space k, incl. the modification.
  double ToothSpaceRotation(int tooth_space) const;

 private:
  void ComputePhiMax();
  void ComputeCurvatureExtremes();  // undercut margin and min |rho|; throws on undercut

  PairParameters pair_;
  Modification modification_;
  int d_ = 0;
  double sign_ = 1.0;    // s = sign(d): side of the equidistant (Chen eq. 14)
  double R_ = 0.0;       // R' = R_p + dR_p, mm
  double r_ = 0.0;       // r' = r_rp + dR_rp, mm
  double e_ = 0.0;       // mm
  double ze_ = 0.0;      // Ze = z_p / d
  double zd_ = 0.0;      // Zd = z_c / d
  double k1_ = 0.0;      // signed K1 = e Ze / R'
  double phi_max_ = 0.0;
  double undercut_margin_ = 0.0;
  double min_curvature_radius_ = 0.0;
  TipCap tip_cap_;
  std::vector<double> space_cos_, space_sin_;  // of ToothSpaceRotation(k), k = 0 .. z_c - 1
};

}  // namespace ltca::geometry
