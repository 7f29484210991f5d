#pragma once
// Theoretical meshing of the unmodified pair: the contact line (Chen 2008 eq. 21-25) and the
// pin's contact angle (Liu 2021 eq. 2). The modified pair's real contacts are the contact
// layer's business; these functions describe the conjugate (zero-clearance) mesh.
#include <Eigen/Core>

#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/profile.hpp"

namespace ltca::geometry {

/// True when pin j faces a flank of the real profile at crank theta_f (|u| <= phi_max); false
/// when it faces a tip corner, which only happens for |d| >= 2 (contact ratio < z_p / 2).
bool IsMeshing(const CycloidProfile& profile, const Kinematics& kinematics, int pin, double crank);

/// The conjugate contact point of pin j at crank theta_f, in the fixed frame (Chen eq. 21-23).
/// Its locus over the crank angle, seen from the crank, is Chen's contact line.
Eigen::Vector2d ContactPoint(const CycloidProfile& profile, const Kinematics& kinematics, int pin,
                             double crank);

/// Liu eq. 2: signed angle on pin j between its radial direction toward the cycloid (toward O_f
/// for d > 0, away from it for d < 0) and the conjugate contact point, rad; tan(alpha) = K1 sin(phi) / (1 - K1 cos(phi)) with phi the pin's angle from
/// the line of centres, so |alpha| <= alpha_max = arcsin K1. Chen's eq. 24-25 angle is
/// theta = alpha - pi / 2 (mirrored frame).
double PinContactAngle(const CycloidProfile& profile, const Kinematics& kinematics, int pin,
                       double crank);

}  // namespace ltca::geometry
