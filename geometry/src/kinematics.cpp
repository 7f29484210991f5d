#include "ltca/geometry/kinematics.hpp"

#include <cmath>

#include "ltca/geometry/units.hpp"

namespace ltca::geometry {
namespace {

using units::kPi;

double WrapPi(double angle) {  // into (-pi, pi]
  angle = std::remainder(angle, 2.0 * kPi);
  return angle <= -kPi ? angle + 2.0 * kPi : angle;
}

}  // namespace

PoseFrame Pose::Frame() const { return {centre, std::cos(rotation), std::sin(rotation)}; }

Kinematics::Kinematics(const PairParameters& pair) : pair_(pair) {
  pair_.Validate();
  d_ = pair_.ToothDifference();
}

Pose Kinematics::CycloidPose(double crank) const {
  // Liu eq. 14 (translation with the crank) and eq. 15 (rotation about O_c by theta_c = theta_f / I).
  Pose pose;
  pose.centre = pair_.eccentricity * Eigen::Vector2d(std::cos(crank), std::sin(crank));
  pose.rotation = crank / TransmissionRatio();
  return pose;
}

double Kinematics::PinAngle(int pin) const { return 2.0 * kPi * pin / pair_.pin_count; }

Eigen::Vector2d Kinematics::PinCentre(int pin) const {
  const double a = PinAngle(pin);
  return pair_.pin_circle_radius * Eigen::Vector2d(std::cos(a), std::sin(a));
}

double Kinematics::AngleFromLineOfCentres(int pin, double crank) const {
  return WrapPi(PinAngle(pin) - crank);
}

double Kinematics::TransmissionRatio() const {
  return -static_cast<double>(pair_.tooth_count) / d_;
}

double Kinematics::MeshPeriod() const { return 2.0 * kPi / pair_.pin_count; }

MeshSeed Kinematics::Seed(int pin, double crank) const {
  // In the body frame, pin j lies on tooth space j's locus at u = (theta_f - psi_j) d / z_c
  // (the meshing equation, Chen eq. 3, solved for the given crank angle). The locus repeats
  // after one lobe: q(u + 2 pi d / z_c) = Rot(2 pi d / z_c) q(u), i.e. (k, u) ~ (k + d, u - 2 pi d / z_c).
  const int zc = pair_.tooth_count;
  const double lobe = 2.0 * kPi * d_ / zc;
  const double u = (crank - PinAngle(pin)) * d_ / zc;
  const double m = std::round(u / lobe);
  MeshSeed seed;
  seed.u = u - m * lobe;
  long k = (static_cast<long>(pin) + static_cast<long>(m) * d_) % zc;
  if (k < 0) k += zc;
  seed.tooth_space = static_cast<int>(k);
  return seed;
}

}  // namespace ltca::geometry
