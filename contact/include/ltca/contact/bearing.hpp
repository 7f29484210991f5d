#pragma once
// Rolling bearings of the reducer stage: the eccentric bearing of a cycloidal drive,
// or the needle bearing of an RV crankshaft in the disc's crank hole, as a force element between
// an inner member (the eccentric) and an outer one (the disc's bore).
//
// Rollers (Harris, T. A., Kotzalas, M. N., Rolling Bearing Analysis, 5th ed., CRC 2007: "Contact
// stress and deformation", Palmgren's line contact; "Distribution of internal loading in
// statically loaded bearings"):
// - one roller-raceway contact of effective length l (mm) under Q (N) approaches by
//   delta = 3.84e-5 Q^0.9 / l^0.8 mm (steel on steel, independent of the roller diameter);
// - a roller between both raceways is two such contacts in series: delta = 7.68e-5 Q^0.9 / l^0.8,
//   Q = K_n delta^(10/9), K_n = (7.68e-5)^(-10/9) l^(8/9);
// - roller j sits at psi_j = phase + 2 pi j / Z (rad, in the outer member's frame); for a
//   displacement u of the inner member relative to the outer one its approach is
//   delta_j = u . (cos psi_j, sin psi_j) - c, c the radial clearance (half Harris's diametral
//   P_d), and it carries Q_j = K_n delta_j^(10/9) where delta_j > 0.
// A linear bearing is a radial spring with the same radial clearance: F = k (|u| - c) beyond it.
//
// Rating life (ISO 281:2007, basic rating life; the mean load of a varying load as in the
// bearing makers' handbooks, e.g. the NSK technical catalogue, "mean equivalent load"):
// L10 = (C / P)^p million revolutions, p = 10/3 for roller bearings, 3 for ball bearings;
// L10h = 1e6 L10 / (60 n) hours at n rpm; for loads P_i over equal steps of a revolution,
// P_m = (sum P_i^p / N)^(1/p).
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ltca::contact {

enum class BearingKind {
  kRigid,    ///< "rigid": no compliance, no clearance
  kLinear,   ///< "linear": radial stiffness and radial clearance
  kRollers,  ///< "rollers": every roller a contact point (Palmgren line contact), radial clearance
};
/// "rigid" | "linear" | "rollers"; throws std::invalid_argument naming `[bearing] kind`.
BearingKind ParseBearingKind(const std::string& text);
const char* ToString(BearingKind kind);

/// A bearing's data (the deck's [bearing], in internal units).
struct BearingSettings {
  static constexpr int kMaxRollers = 200;  ///< a full-complement needle bearing has a few dozen
  BearingKind kind = BearingKind::kRigid;
  double radial_stiffness = 0.0;     ///< N/mm, linear (deck: radial_stiffness_n_per_mm)
  double radial_clearance = 0.0;     ///< mm, the radial play, >= 0 (deck: radial_clearance_mm)
  int roller_count = 0;              ///< rollers (deck: roller_count)
  double roller_diameter = 0.0;      ///< mm (deck: roller_diameter_mm)
  double roller_length = 0.0;        ///< mm, effective length l (deck: roller_length_mm)
  double dynamic_load_rating = 0.0;  ///< N, C_r of ISO 281; 0: no life (deck: dynamic_load_rating_n)
  /// Throws std::invalid_argument naming the `[bearing]` key, its value and what is expected:
  /// clearance finite and >= 0; linear: stiffness finite and > 0; rollers: 3 to kMaxRollers rollers,
  /// diameter and length finite and > 0; the rating finite and >= 0.
  void Validate() const;
};

/// Palmgren: the approach of one roller-raceway contact (mm) under `load` (N) over `length` (mm).
double PalmgrenApproach(double load, double length);
/// Its inverse: the load (N) of one contact at `approach` (mm); 0 for approach <= 0.
double PalmgrenLoad(double approach, double length);
/// A roller between both raceways (two contacts in series): Q = K_n delta^(10/9), N; 0 for delta <= 0.
double RollerLoad(double approach, double length);

/// What the bearing does at one displacement u (mm) of the inner member relative to the outer:
/// the force it exerts on the inner member (N, opposing u), its tangent stiffness -dF/du (N/mm,
/// symmetric, positive semidefinite), the elastic energy stored (N*mm) and, for rollers, each
/// roller's load (N, roller j at phase + 2 pi j / Z).
struct BearingResponse {
  Eigen::Vector2d force = Eigen::Vector2d::Zero();
  Eigen::Matrix2d stiffness = Eigen::Matrix2d::Zero();
  double energy = 0.0;
  std::vector<double> roller_load;
};
/// Not for kRigid (throws std::invalid_argument: a rigid bearing is a constraint, not a force).
BearingResponse BearingAt(const BearingSettings& bearing, const Eigen::Vector2d& displacement, double phase = 0.0);
/// The same; without roller_loads, BearingResponse::roller_load stays empty (no allocation: the
/// solvers' inner loop).
BearingResponse BearingAt(const BearingSettings& bearing, const Eigen::Vector2d& displacement, double phase,
                          bool roller_loads);

/// The displacement u of the inner member at which the bearing carries `load` (N, the force the
/// inner member puts on the bearing: BearingAt(u).force = -load), by Newton's method on the convex
/// energy E(u) - load . u with backtracking, to 1e-12 of |load| (+ 1e-9 N). Throws
/// std::invalid_argument for kRigid; std::runtime_error if it does not converge in 200 steps.
Eigen::Vector2d BearingDisplacement(const BearingSettings& bearing, const Eigen::Vector2d& load, double phase = 0.0);

/// ISO 281 life exponents.
inline constexpr double kRollerLifeExponent = 10.0 / 3.0;
inline constexpr double kBallLifeExponent = 3.0;
/// The mean equivalent load of loads over equal steps (N): (sum P_i^p / N)^(1/p); NaN when empty
/// or when a load is not finite.
double MeanEquivalentLoad(const std::vector<double>& loads, double exponent = kRollerLifeExponent);
/// ISO 281 basic rating life L10 in millions of revolutions; infinite for P = 0, NaN without a rating.
double RatingLife(double dynamic_load_rating, double equivalent_load, double exponent = kRollerLifeExponent);
/// L10 (millions of revolutions) in hours at `rpm` revolutions per minute of the bearing.
double RatingLifeHours(double life_million_revolutions, double rpm);

}  // namespace ltca::contact
