#pragma once
// The pair as made: the nominal pair with its profile modification and its manufacturing and
// assembly errors applied, once, here (issue 9). Every consumer (the contact layer, `ltca
// geometry` and its drawing, validation) builds this one object, so that none of them sees a
// different pair. Liu 2021 eq. 1 (modification), eq. 4-5 (errors).
#include <vector>

#include <Eigen/Core>

#include "ltca/geometry/errors.hpp"
#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/pair.hpp"
#include "ltca/geometry/profile.hpp"

namespace ltca::geometry {

class RealPair {
 public:
  /// Validates the errors (std::invalid_argument naming the key). A uniform profile layer t
  /// moves the equidistant by t toward the pins: the profile is generated with the pin radius
  /// r_rp + dR_rp - t; when that makes the profile invalid, the message blames the layer.
  RealPair(const PairParameters& pair, const Modification& modification, const ManufacturingErrors& errors = {});

  const PairParameters& nominal() const { return profile_.pair(); }
  const Modification& modification() const { return modification_; }
  const ManufacturingErrors& errors() const { return errors_; }
  /// The cycloid as made: modification and profile layer applied.
  const CycloidProfile& profile() const { return profile_; }
  const Kinematics& kinematics() const { return kinematics_; }
  /// Radius of the pin circle as assembled, mm: R_p plus the pin-circle deviation.
  double pin_circle_radius() const { return pin_circle_radius_; }
  /// Centre of pin j as assembled (pin-circle deviation, cumulative pitch deviation), fixed frame, mm.
  Eigen::Vector2d PinCentre(int pin) const;

 private:
  Modification modification_;
  ManufacturingErrors errors_;
  CycloidProfile profile_;
  Kinematics kinematics_;
  double pin_circle_radius_;
};

}  // namespace ltca::geometry
