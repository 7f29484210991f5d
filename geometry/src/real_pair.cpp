#include "ltca/geometry/real_pair.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace ltca::geometry {
namespace {

CycloidProfile MakeProfile(const PairParameters& pair, Modification modification, const ManufacturingErrors& errors) {
  errors.Validate(pair.pin_count);
  if (errors.profile_layer == 0.0) return CycloidProfile(pair, modification);
  // A uniform layer t on the profile moves the equidistant by t toward the pins: the same curve
  // as generating it with the pin radius r_rp + dR_rp - t. When the profile is valid without
  // the layer and not with it, the layer is the key to blame, not the pin radius.
  const CycloidProfile without_layer(pair, modification);
  modification.pin_radius -= errors.profile_layer;
  try {
    return CycloidProfile(pair, modification);
  } catch (const std::invalid_argument& e) {
    // The profile's message names the generating radius keys ("[pair] ...: reason"); keep the
    // reason only.
    const std::string what = e.what();
    const auto colon = what.find(": ");
    const std::string reason = colon == std::string::npos ? what : what.substr(colon + 2);
    throw std::invalid_argument(fmt::format(
        "[errors] cycloid_profile_layer_mm = {}: the layer makes the profile invalid; it acts as "
        "the generating pin radius r_rp + dR_rp - layer = {:.6g} mm, and then {}",
        errors.profile_layer, pair.pin_radius + modification.pin_radius, reason));
  }
}

ProfileDeviation MakeProfileDeviation(const ManufacturingErrors& errors, const CycloidProfile& profile) {
  if (profile.tip_cap().active() && errors.HasProfileDeviation()) {
    // The deviated flank is searched over the unrelieved arc [-phi_max, phi_max] (contact/
    // mesh_state.cpp, NearestOnDeviatedFlank); a relieved tip would need the cap deviated too.
    throw std::invalid_argument(fmt::format(
        "[modification] tip_rounding_radius_mm = {}, tip_truncation_mm = {}: a tip relief together with a "
        "profile deviation ([errors] profile_random_* or profile_measured_csv) is not supported yet; expected "
        "one of them",
        profile.tip_cap().relief().rounding_radius, profile.tip_cap().relief().truncation));
  }
  const ProfileDeviation random = ProfileDeviation::Random(errors.profile_random, profile);
  if (!errors.profile_measured) return random;
  return ProfileDeviation::Sum(random, ProfileDeviation::Measured(*errors.profile_measured, profile));
}

}  // namespace

RealPair::RealPair(const PairParameters& pair, const Modification& modification, const ManufacturingErrors& errors,
                   const AssemblyErrors& assembly)
    : modification_(modification),
      errors_(errors),
      assembly_((assembly.Validate(), assembly)),
      profile_(MakeProfile(pair, modification, errors)),
      profile_deviation_(MakeProfileDeviation(errors, profile_)),
      kinematics_(pair),
      pin_circle_radius_(pair.pin_circle_radius + errors.PinCircleRadiusChange()) {
  pin_centres_.reserve(static_cast<std::size_t>(pair.pin_count));
  for (int j = 0; j < pair.pin_count; ++j) pin_centres_.push_back(ComputePinCentre(j));
}

Eigen::Vector2d RealPair::PinCentre(int pin) const {
  // Computed once: every mesh state asks for every pin's centre.
  if (pin >= 0 && static_cast<std::size_t>(pin) < pin_centres_.size()) return pin_centres_[static_cast<std::size_t>(pin)];
  return ComputePinCentre(pin);
}

Eigen::Vector2d RealPair::ComputePinCentre(int pin) const {
  // Liu eq. 5: the cumulative pitch deviation moves the pin along its circle.
  const auto& pitch = errors_.cumulative_pitch_deviation;
  const double shift = pitch.empty() ? 0.0 : pitch[static_cast<std::size_t>(pin)] / pin_circle_radius_;
  const double a = kinematics_.PinAngle(pin) + shift;
  const auto& radial = errors_.pin_radial_deviations;
  const double r = radial.empty() ? pin_circle_radius_ : pin_circle_radius_ + radial[static_cast<std::size_t>(pin)];
  return r * Eigen::Vector2d(std::cos(a), std::sin(a));
}

double RealPair::PinRadius(int pin) const {
  const auto& dev = errors_.pin_radius_deviations;
  return dev.empty() ? nominal().pin_radius : nominal().pin_radius + dev[static_cast<std::size_t>(pin)];
}

Pose RealPair::CycloidPose(double crank) const {
  Pose pose = kinematics_.CycloidPose(crank);
  if (assembly_.eccentricity_deviation != 0.0) {
    pose.centre += assembly_.eccentricity_deviation * Eigen::Vector2d(std::cos(crank), std::sin(crank));
  }
  pose.centre += Eigen::Vector2d(assembly_.centre_dx, assembly_.centre_dy);
  return pose;
}

}  // namespace ltca::geometry
