#pragma once
// The relieved tooth tip: what replaces the sharp tip corner of a |d| >= 2 profile
// (Chen 2008 section 2.2 leaves the addendum open) or cuts back the smooth tip of a |d| = 1 one.
//
// Local frame of tip k, for d > 0 between tooth space k at u = +phi_max and space k + 1 at
// u = -phi_max; for d < 0 (a ring, whose teeth point to the centre) at u = 0 of space k. Origin at
// the unrelieved tip point on the tooth's symmetry axis:
//   y along the axis, out of the material (toward the pins),
//   s across it, > 0 toward tooth space k's u < phi_max (d > 0) or u > 0 (d < 0).
// The tip is symmetric about the axis (x(-u) mirrors x(u) in the space's own axis), so one half
// is built, for s >= 0, and mirrored:
//   - the truncation line y = -t (t = tip_truncation_mm), perpendicular to the axis;
//   - the rounding arc of radius rho (tip_rounding_radius_mm), centre C = x(u_j) - rho n(u_j),
//     tangent to the flank at the junction u_j and to the line (y_C + rho = -t, s_C >= 0); when
//     the line does not reach that far (the arc tangent to both flanks, centred on the axis, lies
//     below the line) the arc is tangent to both flanks and the line cuts nothing;
//   - the flank of each tooth space runs over |u| <= u_j.
// The cap (arc, segment, mirrored arc) is tangent-continuous with both flanks when rho > 0; with
// rho = 0 and t > 0 the line meets each flank in a corner (an edge, as the sharp tip is).
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ltca/geometry/pair.hpp"

namespace ltca::geometry {

class CycloidProfile;

/// Which piece of the relieved profile a point lies on.
enum class SurfacePart : unsigned char {
  kFlank,          ///< the working flank (Chen eq. 13-14)
  kTipRounding,    ///< the rounding arc (convex, curvature 1 / rho)
  kTipTruncation,  ///< the truncation line (curvature 0)
  kTipCorner,      ///< a sharp corner (no rounding): edge contact
};
/// "flank", "tip-rounding", "tip-truncation", "tip-corner".
const char* SurfacePartName(SurfacePart part);

/// Nearest point of a tip cap to a body-frame point.
struct CapFoot {
  Eigen::Vector2d point;        ///< body frame, mm
  Eigen::Vector2d normal;       ///< unit, from the point toward the query point (out of the material)
  double distance = 0.0;        ///< signed: > 0 outside the material, mm
  double curvature = 0.0;       ///< 1/mm: 1 / rho on the arc, 0 on the line, +infinity at a corner
  SurfacePart part = SurfacePart::kFlank;
  int tooth_space = 0;          ///< the tooth space whose flank this half of the cap continues
  double u = 0.0;               ///< that flank's junction parameter (the nearest flank point)
  /// Where on the cap, as TipCap::Point's w: in [-1, 1], uniformly in arc length from the junction
  /// on space k + 1's side (-1) over the tip to the junction on space k's side (+1).
  double w = 0.0;
};

/// The relieved tip of a profile, built once by CycloidProfile from its Modification::tip_relief.
class TipCap {
 public:
  TipCap() = default;  ///< no relief
  /// Throws std::invalid_argument naming the key when the relief does not fit the tooth: it would
  /// remove the whole flank, or the arc would add material (rho above the flank's radius of
  /// curvature at the junction).
  TipCap(const CycloidProfile& profile, const TipRelief& relief);

  /// A relief that changes the profile (the sharp tip of |d| >= 2 and the smooth tip of |d| = 1
  /// are kept when the relief is zero, or when only a rounding is asked of a smooth tip).
  bool active() const { return active_; }
  const TipRelief& relief() const { return relief_; }
  /// The flank of a tooth space ends at u = +-junction() (rad): for d > 0 it runs over
  /// |u| <= junction() (phi_max without relief), for d < 0 over junction() <= |u| <= phi_max (0
  /// without relief: a ring's tips are at u = 0 of its spaces).
  double junction() const { return junction_; }
  /// The u-intervals of a tooth space's flank (one for d > 0, two for d < 0).
  std::vector<std::pair<double, double>> FlankArcs() const;
  /// The truncation line cuts the tooth (false: the arc alone, tangent to both flanks).
  bool truncated() const { return truncated_; }
  /// Half-length of the truncation segment, mm (0 without one).
  double land_half_width() const { return land_; }
  /// Depth of material removed on the tooth axis, from the unrelieved tip point, mm.
  double depth() const { return depth_; }

  /// Nearest point of the cap of tip k to the body-frame point p.
  CapFoot Nearest(const Eigen::Vector2d& p, int tip) const;
  /// A point of the cap of tip k, body frame, with its outward normal, curvature and piece
  /// (distance 0): w in [-1, 1] runs from the junction on space k + 1's side (w = -1) over the tip
  /// to the junction on space k's side (w = 1), uniformly in arc length (for drawings and tables).
  CapFoot Point(double w, int tip) const;
  /// Length of one cap from junction to junction, mm.
  double length() const;

 private:
  Eigen::Vector2d ToLocal(const Eigen::Vector2d& p, int tip) const;
  Eigen::Vector2d ToBody(const Eigen::Vector2d& local, int tip) const;
  Eigen::Vector2d DirToBody(const Eigen::Vector2d& local, int tip) const;
  int SpaceOf(int tip, double side) const;
  double JunctionOf(double side) const;

  TipRelief relief_;
  bool active_ = false;
  bool ring_ = false;              // d < 0: tips at u = 0
  double phi_max_ = 0.0;
  bool truncated_ = false;
  double junction_ = 0.0;
  double land_ = 0.0;
  double depth_ = 0.0;
  double pitch_ = 0.0;             // tooth pitch, rad
  Eigen::Vector2d tip_point_{0.0, 0.0};  // reference tip (k = 0), body frame
  Eigen::Vector2d axis_{0.0, 1.0};       // y: out of the material along the axis
  Eigen::Vector2d across_{1.0, 0.0};     // s: toward tooth space 0
  Eigen::Vector2d centre_{0.0, 0.0};     // arc centre (s >= 0 half), local
  double rho_ = 0.0;
  double arc_start_ = 0.0;  // angle of the flank normal at the junction, local; the arc runs to pi/2
};

}  // namespace ltca::geometry
