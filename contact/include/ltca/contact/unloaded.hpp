#pragma once
// Unloaded tooth contact analysis (Liu 2021 section 3, eq. 17; Li Fig. 4): rotate the cycloid
// about its own centre both ways from the theoretical meshing position to first contact.
#include <string>
#include <vector>

#include "ltca/contact/mesh_state.hpp"

namespace ltca::contact {

/// How the contact geometry follows a rotation of the cycloid.
enum class ContactKinematics {
  kLinearised,  ///< c_i and L_i frozen at the unrotated pose: approach = L_i psi - c_i
  kExact,       ///< the contact geometry re-evaluated at the rotated pose
};
/// "linearised" | "exact": the one spelling of the kinematics in decks, options and outputs.
const char* ToString(ContactKinematics kinematics);
/// The inverse; throws std::invalid_argument naming [solver] kinematics and the valid values.
ContactKinematics ParseKinematics(const std::string& text);

struct UnloadedContact {
  double crank = 0.0;      ///< rad
  /// Rotation to first contact in the load direction, rad (>= 0 when there is clearance):
  /// Liu's theta_c1 measured in the load direction.
  double theta_c1 = 0.0;
  /// Rotation to first contact against the load direction, rad (<= 0).
  double theta_c2 = 0.0;
  /// theta_c1 - theta_c2, rad (Liu eq. 17): the free play; 0 for a preloaded pair (its flanks
  /// overlap by more than the model's interference tolerance over R_p; a rounding-sized overlap
  /// is kept as computed, the conjugate pair's zero).
  double backlash = 0.0;
  /// max(0, theta_c2 - theta_c1), rad: a preloaded pair's flanks overlap (the drive flank closes
  /// before the coast flank opens, theta_c1 < theta_c2); the rotation by which they overlap, > 0
  /// exactly when the backlash is 0 by overlap. 0 for a pair with free play.
  double interference = 0.0;
  int first_pin_c1 = -1;   ///< 0-based pin that touches first in the load direction
  int first_pin_c2 = -1;   ///< and against it
  /// Clearance of every pin at the theoretical position, mm (in the slice model the smallest over
  /// the pin's slices, as Liu section 3 takes it).
  std::vector<double> clearance;
  /// Clearance of every pin after rotating to first contact in the load direction, mm (Li Fig. 4;
  /// the smallest over its slices).
  std::vector<double> clearance_at_c1;
};

/// The pair jams at this pose: pins overlap the cycloid by more than tolerance_mm and no rotation of
/// the cycloid about its centre frees them all (linearised about the pose; a pin whose arm
/// vanishes cannot be freed). Returns the overlapping pins (InterferenceReport), or empty when
/// the pair fits. A pin that overlaps at the theoretical position while a rotation frees it (a
/// pitch or position error of that pin) is no interference: the unloaded cycloid just
/// sits elsewhere, and the load solves start from its first contact.
std::string JamReport(const MeshState& state, double tolerance_mm);

/// Throws std::invalid_argument naming the crank, the pins and their overlap in um when the pair
/// jams at the theoretical meshing position of that crank (rad), JamReport with tolerance
/// model.interference_tolerance(). Every command that solves or tabulates a mesh calls it first.
void RequireNoInterference(const MeshModel& model, double crank);
/// The same on an evaluated state (loaded rotation 0) of that crank.
void RequireNoInterference(const MeshState& state, double crank, double tolerance_mm = 1e-9);

/// Rotates both ways to first contact (ClosingRotation: an overlapping pin's closing lies on the
/// opening side). A preloaded pair (both flanks overlapping) has theta_c1 < theta_c2: backlash 0
/// and interference theta_c2 - theta_c1. interference_tolerance_mm is not used (kept for callers).
UnloadedContact AnalyseUnloaded(const MeshModel& model, double crank,
                                ContactKinematics kinematics = ContactKinematics::kExact,
                                double interference_tolerance_mm = 1e-9);

/// The unloaded TCA over a sweep of crank angles, with the mean and peak-to-peak backlash (rad).
/// A sweep whose last crank repeats the state of its first (SameMesh: a closed period) weights
/// that state once in the mean.
struct UnloadedSweep {
  std::vector<UnloadedContact> positions;
  double mean_backlash = 0.0;
  double pp_backlash = 0.0;
  bool closed_period = false;  ///< the last crank's state is the first's: left out of the mean
};
UnloadedSweep AnalyseUnloadedSweep(const MeshModel& model, const std::vector<double>& cranks,
                                   ContactKinematics kinematics = ContactKinematics::kExact);

/// The largest rotation of the cycloid about its centre (from the theoretical position) that the
/// contact model describes: a quarter of a cycloid tooth pitch, rad. The exact geometry repeats
/// every pitch; a closing or loaded rotation beyond this is a pin jumping teeth, not a contact.
double RotationWindow(const MeshModel& model);

/// The pins that overlap the cycloid by more than tolerance_mm in this state, with their overlap
/// ("pin 3 by 2.5 um, pin 4 by 1.2 um"); empty when there is no interference.
std::string InterferenceReport(const MeshState& state, double tolerance_mm = 1e-9);

/// Rotation (rad, signed, in the load direction) at which pin's gap closes, starting from its
/// state at psi = 0: c/L linearised, or Newton on c(psi) = 0 with dc/dpsi = -L(psi) (exact).
double ClosingRotation(const MeshModel& model, const PinContact& at_zero, double crank,
                       ContactKinematics kinematics);

}  // namespace ltca::contact
