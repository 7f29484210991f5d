#pragma once
// The pair as made: the nominal pair with its profile modification and its manufacturing and
// assembly errors applied, once, here. Every consumer (the contact layer, `ltca
// geometry` and its drawing, validation) builds this one object, so that none of them sees a
// different pair. Liu 2021 eq. 1 (modification), eq. 4-5 (manufacturing errors), eq. 6-7
// (assembly errors: per-pin radius and position, lead crowning and slope, centre offset,
// eccentricity deviation, misalignment).
#include <vector>

#include <Eigen/Core>

#include "ltca/geometry/errors.hpp"
#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/pair.hpp"
#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/profile_deviation.hpp"

namespace ltca::geometry {

class RealPair {
 public:
  /// Validates the errors (std::invalid_argument naming the key). A uniform profile layer t
  /// moves the equidistant by t toward the pins: the profile is generated with the pin radius
  /// r_rp + dR_rp - t; when that makes the profile invalid, the message blames the layer.
  RealPair(const PairParameters& pair, const Modification& modification, const ManufacturingErrors& errors = {},
           const AssemblyErrors& assembly = {});

  const PairParameters& nominal() const { return profile_.pair(); }
  const Modification& modification() const { return modification_; }
  const ManufacturingErrors& errors() const { return errors_; }
  const AssemblyErrors& assembly() const { return assembly_; }
  /// The cycloid as made: modification and profile layer applied.
  const CycloidProfile& profile() const { return profile_; }
  /// The profile deviation along the profile of the cycloid as made (errors().profile_random plus
  /// errors().profile_measured), built once against profile(); IsZero() without one. Constant
  /// along the face width: it leaves the plane model valid.
  const ProfileDeviation& profile_deviation() const { return profile_deviation_; }
  const Kinematics& kinematics() const { return kinematics_; }
  /// Radius of the pin circle as assembled, mm: R_p plus the pin-circle deviation.
  double pin_circle_radius() const { return pin_circle_radius_; }
  /// Centre of pin j as assembled (pin-circle deviation, the pin's radial deviation, cumulative
  /// pitch deviation), fixed frame, mm.
  Eigen::Vector2d PinCentre(int pin) const;
  /// Radius of pin j as made: r_rp plus its radius deviation, mm.
  double PinRadius(int pin) const;
  /// Pose of the cycloid at crank theta_f as assembled, before any loaded rotation: the crank
  /// throws the centre by e + the eccentricity deviation (turning with the crank, Liu eq. 14),
  /// the bore offset (dx, dy) is fixed in the frame (Liu eq. 7), the rotation is Liu eq. 15's.
  /// This is the pose at face B (pivot face) or at the mid-plane (pivot mid); the slice at z adds
  /// SliceShift(z).
  Pose CycloidPose(double crank) const;
  /// Misalignment's shift of the cycloid centre in the slice at axial position z (from face B), mm.
  Eigen::Vector2d SliceShift(double z) const { return assembly_.SliceShift(z, nominal().face_width); }
  /// Material the lead modifications (crowning, slope) add at axial position z, mm.
  double LeadLayer(double z) const { return errors_.LeadLayer(z, nominal().face_width); }
  /// Something varies along the face width (misalignment, crowning, slope): the plane model
  /// cannot represent the pair.
  bool VariesAlongWidth() const { return errors_.VariesAlongWidth() || assembly_.VariesAlongWidth(); }

 private:
  Modification modification_;
  ManufacturingErrors errors_;
  AssemblyErrors assembly_;
  CycloidProfile profile_;
  ProfileDeviation profile_deviation_;  // after profile_: built against it
  Kinematics kinematics_;
  double pin_circle_radius_;
  std::vector<Eigen::Vector2d> pin_centres_;  // PinCentre of every pin, computed once
  Eigen::Vector2d ComputePinCentre(int pin) const;
};

}  // namespace ltca::geometry
