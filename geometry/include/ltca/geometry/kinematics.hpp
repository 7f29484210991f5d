#pragma once
// Rigid-body kinematics of the pair (Liu 2021 eq. 14-15) and the meshing equation in the form
// the contact layer needs. Conventions (docs/conventions.md):
//  - Fixed frame O_f: origin at the pin-circle centre, pins fixed.
//  - Pin j (0-based; printed as number j + 1) sits at angle psi_j = 2 pi j / z_p from +X_f.
//  - The crank angle theta_f turns counterclockwise; the cycloid centre is at e (cos, sin)(theta_f).
//  - The cycloid turns about its own centre by theta_c = -theta_f d / z_c (clockwise for d > 0):
//    the transmission ratio crank/cycloid is I = -z_c / d.
#include <Eigen/Core>

#include "ltca/geometry/pair.hpp"

namespace ltca::geometry {

/// v turned by +90 deg: (-v_y, v_x). The velocity of a point at v from a centre turning at 1 rad/s,
/// and the lever of a force in the plane (a . Perp(b) = a x b).
inline Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }

/// Placement of the cycloid body frame in the fixed frame: x_f = centre + Rot(rotation) x_b.
/// A pose with the cosine and sine of its rotation taken once: the maps of a Pose, for a caller
/// that applies several of them (a pin's closest-point search maps the pin centre into the body
/// and the foot point and normal back). Pose's own maps go through it, so the two agree bit for bit.
struct PoseFrame {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< mm.
  double cos_rotation = 1.0, sin_rotation = 0.0;

  Eigen::Vector2d ToFixed(const Eigen::Vector2d& body) const { return centre + DirectionToFixed(body); }
  Eigen::Vector2d ToBody(const Eigen::Vector2d& fixed) const {
    const Eigen::Vector2d v = fixed - centre;
    return {cos_rotation * v.x() + sin_rotation * v.y(), -sin_rotation * v.x() + cos_rotation * v.y()};
  }
  Eigen::Vector2d DirectionToFixed(const Eigen::Vector2d& body) const {
    return {cos_rotation * body.x() - sin_rotation * body.y(), sin_rotation * body.x() + cos_rotation * body.y()};
  }
};

struct Pose {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< mm.
  double rotation = 0.0;                             ///< rad, counterclockwise.

  Eigen::Vector2d ToFixed(const Eigen::Vector2d& body) const { return Frame().ToFixed(body); }
  Eigen::Vector2d ToBody(const Eigen::Vector2d& fixed) const { return Frame().ToBody(fixed); }
  Eigen::Vector2d DirectionToFixed(const Eigen::Vector2d& body) const { return Frame().DirectionToFixed(body); }
  /// The cosine and sine of the rotation, taken once.
  PoseFrame Frame() const;
  /// The same pose rotated further about the cycloid's own centre by angle (Liu eq. 15).
  Pose RotatedAboutCentre(double angle) const { return {centre, rotation + angle}; }
};

/// Where pin j meshes on the generating curve: tooth space and profile parameter.
struct MeshSeed {
  int tooth_space = 0;  ///< k in [0, z_c).
  double u = 0.0;       ///< rad, wrapped into the lobe [-|d| pi / z_c, |d| pi / z_c).
};

class Kinematics {
 public:
  explicit Kinematics(const PairParameters& pair);

  /// Nominal (unloaded, error-free) pose of the cycloid at crank angle theta_f, Liu eq. 14-15.
  Pose CycloidPose(double crank) const;
  /// Centre of pin j in the fixed frame (nominal, Liu eq. 5 without errors), mm.
  Eigen::Vector2d PinCentre(int pin) const;
  /// psi_j = 2 pi j / z_p.
  double PinAngle(int pin) const;
  /// Angle of pin j from the line of centres O_f -> O_c, wrapped into (-pi, pi].
  double AngleFromLineOfCentres(int pin, double crank) const;
  /// Crank rotation per cycloid rotation, I = -z_c / d (negative: opposite senses for d > 0).
  double TransmissionRatio() const;
  /// Crank angle after which the mesh repeats up to a rigid rotation and a relabelling of
  /// pins and teeth: 2 pi / z_p (docs/conventions.md derives it).
  double MeshPeriod() const;
  /// The meshing equation solved for pin j: on the unmodified pair the pin centre at crank
  /// theta_f is exactly PinCentreLocus(seed.u, seed.tooth_space) in the body frame.
  MeshSeed Seed(int pin, double crank) const;

 private:
  PairParameters pair_;
  int d_ = 0;
};

}  // namespace ltca::geometry
