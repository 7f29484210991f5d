#include "ltca/geometry/meshing.hpp"

#include <cmath>

namespace ltca::geometry {

bool IsMeshing(const CycloidProfile& profile, const Kinematics& kinematics, int pin, double crank) {
  return std::abs(kinematics.Seed(pin, crank).u) <= profile.phi_max();
}

Eigen::Vector2d ContactPoint(const CycloidProfile& profile, const Kinematics& kinematics, int pin,
                             double crank) {
  const MeshSeed seed = kinematics.Seed(pin, crank);
  return kinematics.CycloidPose(crank).ToFixed(profile.Position(seed.u, seed.tooth_space));
}

double PinContactAngle(const CycloidProfile& profile, const Kinematics& kinematics, int pin,
                       double crank) {
  const Eigen::Vector2d centre = kinematics.PinCentre(pin);
  // Radial direction from the pin toward the cycloid's material: inward for d > 0, outward for
  // d < 0 (the cycloid is then the outer member).
  const double side = profile.tooth_difference() > 0 ? 1.0 : -1.0;
  const Eigen::Vector2d inward = -side * centre.normalized();
  const Eigen::Vector2d to_contact = ContactPoint(profile, kinematics, pin, crank) - centre;
  return std::atan2(inward.x() * to_contact.y() - inward.y() * to_contact.x(),
                    inward.dot(to_contact));
}

}  // namespace ltca::geometry
