#pragma once
// The mesh state of the pair at one crank angle: for every pin its clearance, contact points,
// common normal, moment arm and curvatures. Computed exactly from the analytic profile (closest
// point by a safeguarded Newton iteration seeded from the meshing equation), once, and shared by
// every load solver. Liu 2021 section 3 (eq. 14-15, 19, 27), Li eq. 1-2 and Fig. 4,
// Jiang 2022 eq. 10.
//
// Loaded rotation psi: the cycloid's extra rotation about its own centre, in the load direction
// (counterclockwise for d > 0, clockwise for d < 0; docs/conventions.md). A pin's approach is
//   exact:       delta_i(psi) = -c_i(psi), the geometry re-evaluated at the rotated pose;
//   linearised:  delta_i(psi) = L_i psi - c_i, with c_i and L_i of the unrotated pose.
// The exact clearance has derivative dc_i/dpsi = -L_i(psi) (the contact normal's lever arm),
// so the two agree to first order in psi.
#include <vector>

#include <Eigen/Core>

#include <memory>

#include "ltca/geometry/discrete_profile.hpp"
#include "ltca/geometry/errors.hpp"
#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/pair.hpp"
#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/real_pair.hpp"

namespace ltca::contact {

/// One contact point at one pose: a pin in one face-width slice. The plane model has one slice
/// over the whole face width, so there is one point per pin and the point index is the pin
/// index; the slice model has a point per pin and slice, pin-major: point index
/// pin * slice_count + slice.
struct PinContact {
  int pin = 0;                    ///< 0-based index (printed + 1).
  int slice = 0;                  ///< 0-based face-width slice (0: the plane model's only one).
  /// 0-based cycloid disc of the stage: 0 for a single disc and for the first of two;
  /// 1 for the second disc of an RV stage, half a crank turn behind (EvaluateTwoDiscs).
  int disc = 0;
  double length = 0.0;            ///< contact length of this point along the face width, mm.
  double z = 0.0;                 ///< axial position of the slice centre from face B, mm.
  double angle = 0.0;             ///< phi: angle from the line of centres, rad, (-pi, pi].
  double clearance = 0.0;         ///< c_i: normal gap, mm; < 0 is overlap.
  double arm = 0.0;               ///< L_i: lever arm of the contact normal about O_c, mm; > 0 when
                                  ///< a rotation in the load direction closes the gap.
  Eigen::Vector2d cycloid_point;  ///< contact point on the cycloid, fixed frame, mm.
  Eigen::Vector2d pin_point;      ///< contact point on the pin, fixed frame, mm.
  Eigen::Vector2d normal;         ///< unit common normal from the cycloid toward the pin, fixed frame.
  double cycloid_curvature = 0.0; ///< 1/mm, signed: > 0 convex, < 0 concave (Liu eq. 8).
  double pin_radius = 0.0;        ///< rho_p of Liu eq. 9, mm.
  int tooth_space = 0;            ///< where on the cycloid
  double u = 0.0;                 ///< profile parameter, rad, in [-phi_max, phi_max]
  bool edge = false;              ///< the closest point is a tip corner (|d| >= 2): edge contact,
                                  ///< to which the line-contact laws do not apply.
  /// Which piece of the profile the closest point is on: the flank, or with a tip relief (issue
  /// 12) its rounding arc or truncation line; kTipCorner exactly when `edge`. On the cap, u is the
  /// junction +-TipCap::junction() of `tooth_space` (the nearest flank point, a search seed).
  geometry::SurfacePart part = geometry::SurfacePart::kFlank;
  /// On the cap (part kTipRounding, kTipTruncation or kTipCorner): where, as geometry::CapFoot's w
  /// (TipCap::Point's parameter, -1 at the junction with tooth_space + 1 ... +1 at tooth_space's for
  /// d > 0; its sign is that of u). 0 on the flank.
  double cap_w = 0.0;
};

/// All pins at one pose.
struct MeshState {
  double crank = 0.0;             ///< theta_f, rad.
  double loaded_rotation = 0.0;   ///< psi, rad, in the load direction.
  /// Every contact point, pin-major (one per pin in the plane model, in pin order).
  std::vector<PinContact> pins;
};

/// The pair as the contact layer sees it: profile (with modifications and the profile layer),
/// pins (with their errors), kinematics (with the assembly errors), and the face-width slices.
///
/// Model only what the scene needs: the slice model (width_slices slices of width
/// B / n, slice k a plane state at z_k = (k + 1/2) B / n from face B) runs when something varies
/// along the width (misalignment, lead crowning or slope) or when something couples the slices
/// (pin bending: `coupled_along_width`); otherwise the plane model runs, one slice over the whole
/// face width, whatever width_slices says.
class MeshModel {
 public:
  MeshModel(const geometry::PairParameters& pair, const geometry::Modification& modification,
            const geometry::ManufacturingErrors& errors = {}, const geometry::GeometrySettings& geometry = {});
  /// The pair as made (modification and errors applied once, in geometry::RealPair).
  explicit MeshModel(geometry::RealPair real, const geometry::GeometrySettings& geometry = {},
                     bool coupled_along_width = false);

  const geometry::RealPair& real_pair() const { return real_; }

  /// Elements mode (Liu 2021 section 2-3): the discrete surface, or nullptr in the analytic mode.
  const geometry::DiscreteProfile* discrete() const { return discrete_.get(); }

  const geometry::CycloidProfile& profile() const { return real_.profile(); }
  const geometry::Kinematics& kinematics() const { return real_.kinematics(); }
  const geometry::PairParameters& pair() const { return real_.nominal(); }
  int pin_count() const { return real_.nominal().pin_count; }
  /// Face-width slices of the model that runs (1: the plane model).
  int slice_count() const { return slices_; }
  /// Contact points per pose: pins x slices.
  int point_count() const { return pin_count() * slices_; }
  /// Axial position of the centre of slice k from face B, mm.
  double SliceZ(int slice) const { return (slice + 0.5) * pair().face_width / slices_; }
  /// Clearance below which a pin counts as overlapping the cycloid, mm: 1e-9 on the analytic
  /// surface; on the element surface (Liu section 2-3) its discretisation error, estimated at
  /// construction as twice the largest difference between the element and the analytic clearance
  /// over the pins at 16 crank angles of a mesh period (at least 1e-9). Without it the element surface of a pair with zero
  /// clearance "interferes" by its own rounding (1.6e-8 mm at 800 elements on Liu Table 1).
  double interference_tolerance() const { return interference_tolerance_; }
  /// +1 when the load turns the cycloid counterclockwise (d > 0), -1 otherwise.
  double load_direction() const { return load_direction_; }

  /// Centre of pin j with the pin-circle deviation, fixed frame, mm.
  Eigen::Vector2d PinCentre(int pin) const;
  /// Pose of the cycloid at crank theta_f turned by psi in the load direction (Liu eq. 14-15, with
  /// the assembly errors of geometry::RealPair::CycloidPose), in the slice at axial position z.
  geometry::Pose CyclePose(double crank, double loaded_rotation, double z) const;

  /// Exact state of every contact point at crank theta_f and loaded rotation psi.
  MeshState Evaluate(double crank, double loaded_rotation = 0.0) const;
  /// Exact state of one contact point (pin, slice).
  PinContact EvaluatePoint(int pin, int slice, double crank, double loaded_rotation = 0.0) const;
  /// The same, searched from a nearby earlier foot point (tooth space and u of a PinContact of the
  /// same point at a nearby pose) instead of the meshing equation: fewer Newton steps.
  PinContact EvaluatePoint(const PinContact& near, double crank, double loaded_rotation) const;
  /// The same with the disc's centre moved by `centre_shift` (fixed frame, mm) from its pose at the
  /// crank: a reducer stage's floating disc under load (exact kinematics). The arm is
  /// about the moved centre.
  PinContact EvaluatePoint(const PinContact& near, double crank, double loaded_rotation,
                           const Eigen::Vector2d& centre_shift) const;
  /// The same in a pose the caller has taken once for many pins, with the pin's angle it keeps:
  /// `frame` is the Frame() of CyclePose(crank, loaded_rotation, near.z) (its centre moved by any
  /// shift) and `angle` is geometry::Kinematics::AngleFromLineOfCentres(near.pin, crank). The
  /// contact is the one the overloads above give, bit for bit.
  PinContact EvaluatePointInFrame(const PinContact& near, const geometry::PoseFrame& frame, double angle) const;
  /// Exact state of a pin in the face section at axial position z from face B (mm, in [0, B]),
  /// which need not be a slice centre: the unloaded analysis looks at the face edges too, where
  /// a gap that varies linearly along the width (misalignment) is smallest. The point
  /// is labelled with the slice that contains z (its length is that slice's).
  PinContact EvaluateSection(int pin, double z, double crank, double loaded_rotation = 0.0) const;
  /// The same with the slice label given (EvaluatePoint is the section at the slice's centre).
  PinContact EvaluateSection(int pin, int slice, double z, double crank, double loaded_rotation) const;

 private:
  PinContact EvaluatePointFrom(int pin, int slice, double crank, double loaded_rotation, int tooth_space,
                               double u) const;
  // angle: the pin's angle from the line of centres at the crank (AngleFromLineOfCentres).
  PinContact EvaluatePointAt(int pin, int slice, double z, double angle, const geometry::PoseFrame& frame,
                             int tooth_space, double u) const;
  PinContact EvaluatePointElements(int pin, int slice, double z, double angle, const geometry::PoseFrame& frame) const;
  /// The point's slice data (at axial position z) and the lead layer (normal offset of the flank)
  /// applied to a foot point.
  void FinishPoint(int slice, double z, PinContact* c) const;

  geometry::RealPair real_;
  std::shared_ptr<const geometry::DiscreteProfile> discrete_;  // elements mode only
  int slices_ = 1;
  bool lead_layer_ = false;  // crowning or slope: a normal offset per slice
  double load_direction_ = 1.0;
  double interference_tolerance_ = 1e-9;  // mm
};

/// The second disc of an RV stage sits on the crank half a turn from the first.
inline constexpr double kSecondDiscCrankOffset = 3.14159265358979323846;

/// The two discs of an RV stage on one pin ring at crank theta_f: every contact point
/// of `first` at theta_f, then every point of `second` at theta_f + kSecondDiscCrankOffset with
/// disc = 1, both at loaded rotation psi (the one output rotation they share). Throws
/// std::invalid_argument unless both models have the same pin ring (pin count, pin-circle radius,
/// pin radius, tooth count, eccentricity).
MeshState EvaluateTwoDiscs(const MeshModel& first, const MeshModel& second, double crank,
                           double loaded_rotation = 0.0);
/// The check of EvaluateTwoDiscs alone.
void RequireSamePinRing(const MeshModel& first, const MeshModel& second);
/// EvaluateTwoDiscs from each disc's own state: `behind` (the second disc's model at
/// theta_f + kSecondDiscCrankOffset) appended to `first` with disc = 1.
MeshState CombineTwoDiscs(MeshState first, MeshState behind);

/// Whether two states are one mesh up to the numbering of the pins: the same contact points
/// (matched by disc, slice and angle from the line of centres) with the same clearance, arm,
/// curvature, pin radius and length, to 1e-9 (mm, rad, relative for the curvature). The states
/// of a sweep's first and last crank are one mesh when the sweep closes a period: a whole crank
/// turn, or a mesh period of a pair whose errors keep that symmetry. A mean over such a sweep
/// weights that state once.
bool SameMesh(const MeshState& a, const MeshState& b);

/// Linearised approach of a pin at loaded rotation psi: L_i psi - c_i (mm).
inline double LinearisedApproach(const PinContact& pin, double loaded_rotation) {
  return pin.arm * loaded_rotation - pin.clearance;
}

}  // namespace ltca::contact
