#pragma once
// The crankshafts of an RV stage (docs/stage.md): `count` crankshafts on the output
// member (the carrier) at radius R_c, crank j at alpha_j = 2 pi j / count + phase in the carrier's
// frame (from +X at crank 0). Each crankshaft's eccentric sits in a crank hole of the disc, through
// a needle bearing (contact/bearing.hpp), with the shaft's own radial compliance at the eccentric
// (its bending and its support bearings) in series: a linear spring, rigid by default.
//
// With the input locked the eccentric keeps its direction in the fixed frame (the eccentric of a
// cycloidal drive does the same), or an RV's first stage turns it by `turns_per_output_turn` times
// the output rotation: FirstStageTurns(z_sun, z_spur) = 1 + z_sun / z_spur for a sun gear held by
// the locked input (docs/stage.md, "The first stage"). The eccentric of
// crank j for a disc whose centre the cranks put at D is at E_j = C_j + D, C_j the crank's centre
// on the carrier; the disc's crank hole j sits at H_j = D + R(disc rotation) R_c (cos alpha_j,
// sin alpha_j). At the nominal poses (the carrier turned as the disc) E_j = H_j.
//
// The relative displacement that loads the bearing is u_j = E_j - H_j (of the inner member, the
// eccentric, relative to the outer, the disc's bore); to first order in the disc translation t,
// the disc rotation phi and the carrier rotation psi:
//   du_j = [perp(C_j) + k perp(E_j - C_j)] dpsi - perp(H_j - D) dphi - dt,   k = turns_per_output_turn.
#include <array>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "ltca/contact/holes.hpp"
#include "ltca/geometry/kinematics.hpp"

namespace ltca::contact {

/// A crankshaft as a beam (issue 49, docs/stage.md "Crankshafts as beams"): a solid circular shaft
/// of diameter d, a Timoshenko beam (Cowper's shear coefficient 6 (1 + nu) / (7 + 6 nu)) simply
/// supported on two support bearings `span` apart, each a radial spring, carrying both discs'
/// eccentrics at a_1 and a_2 from the first support. Its compliance couples the loads of both
/// discs' crank bearings; the same in x and in y (a circular section, isotropic supports).
struct CrankshaftBeam {
  double diameter = 0.0;  ///< d, mm (deck: shaft_diameter_mm; 0: no beam)
  double span = 0.0;      ///< L, mm between the support bearings (deck: shaft_span_mm)
  /// a_1, a_2: the first and the second disc's eccentric from the first support, mm (deck:
  /// eccentric_positions_mm).
  std::array<double, 2> eccentric{0.0, 0.0};
  /// k_s, N/mm: each support bearing's radial stiffness (deck: support_stiffness_n_per_mm; infinite: rigid).
  double support_stiffness = std::numeric_limits<double>::infinity();
  bool given() const { return diameter > 0.0; }
  /// Throws std::invalid_argument naming the `[output]` key unless d, L > 0 and finite, 0 < a_1, a_2 < L
  /// apart from each other, and k_s > 0.
  void Validate() const;
};

/// The 2 x 2 compliance of a crankshaft at its two eccentrics, mm/N per direction: C_ij the
/// deflection at a_i under a unit load at a_j, split into the beam's (bending and shear) and the
/// support bearings' (the rigid-body motion their springs allow).
struct ShaftCompliance {
  Eigen::Matrix2d beam = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d supports = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d total() const { return beam + supports; }
};
/// The closed form (docs/stage.md): with b_j = L - a_j, for a_i <= a_j
///   bending  b_j a_i (L^2 - b_j^2 - a_i^2) / (6 E I L),   shear  b_j a_i / (kappa G A L),
/// (the mirror image for a_i > a_j), supports [(L - a_i)(L - a_j) + a_i a_j] / (k_s L^2);
/// I = pi d^4 / 64, A = pi d^2 / 4, G = E / (2 (1 + nu)), kappa = 6 (1 + nu) / (7 + 6 nu).
ShaftCompliance CrankshaftCompliance(const CrankshaftBeam& beam, double young_modulus, double poisson_ratio);

struct Cranks {
  static constexpr int kMaxCount = 12;  ///< RV stages have 2 or 3
  int count = 0;               ///< crankshafts (deck: [output] count)
  double circle_radius = 0.0;  ///< R_c, mm (deck: circle_radius_mm)
  double phase = 0.0;          ///< rad, of crank 0 from +X at crank 0 (deck: phase_deg)
  /// N/mm, the shaft's radial stiffness at the eccentric; infinite: rigid (deck:
  /// shaft_stiffness_n_per_mm, absent for rigid).
  double shaft_stiffness = std::numeric_limits<double>::infinity();
  /// Turns of the eccentric per turn of the carrier with the input locked (deck:
  /// crank_turns_per_output_turn; 0: the eccentric keeps its direction).
  double turns_per_output_turn = 0.0;
  /// The first stage the turns come from (deck: first_stage_teeth = [z_sun, z_spur]); 0, 0: the
  /// turns were given as such (crank_turns_per_output_turn, or its default 0).
  int sun_teeth = 0, spur_teeth = 0;
  /// Each crankshaft as a beam on its support bearings (two discs); exclusive with shaft_stiffness.
  CrankshaftBeam beam;
  /// The shaft's 2 x 2 compliance given as such (mm/N, per direction; not a deck key): overrides the
  /// beam's, all of it the shaft's group in the budget. The single-spring limit diag(1/k, 1/k) is
  /// shaft_stiffness = k.
  std::optional<Eigen::Matrix2d> shaft_compliance;
  /// Each crank hole's position deviation in the disc (contact/holes.hpp); empty: none. Every
  /// disc takes the same (discs machined together in a stack).
  HoleDeviations hole_deviation;
  /// Throws std::invalid_argument naming the `[output]` key unless 2 <= count <= kMaxCount, R_c finite and
  /// > 0, the phase and the turns finite, and the shaft stiffness > 0 (infinite allowed).
  void Validate() const;
};

/// Turns of a crankshaft (and its eccentric) in the fixed frame per turn of the carrier, with the
/// input locked: the RV's first stage, a sun gear of z_sun teeth on the input shaft meshing with a
/// spur gear of z_spur teeth on each crankshaft, the crankshafts carried by the carrier. Willis:
/// the sun held (omega_s = 0), (omega_s - omega_c) / (omega_p - omega_c) = -z_spur / z_sun gives
/// omega_p = (1 + z_sun / z_spur) omega_c, in the carrier's sense (docs/stage.md). Throws
/// std::invalid_argument naming `[output] first_stage_teeth` unless both counts are >= 1.
double FirstStageTurns(int sun_teeth, int spur_teeth);

/// One crankshaft's eccentric in its crank hole of one disc.
struct CrankContact {
  int crank = 0;
  Eigen::Vector2d crank_centre = Eigen::Vector2d::Zero();      ///< C_j, fixed frame, mm
  Eigen::Vector2d eccentric_centre = Eigen::Vector2d::Zero();  ///< E_j, mm
  Eigen::Vector2d hole_centre = Eigen::Vector2d::Zero();       ///< H_j, mm
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();            ///< u_j = E_j - H_j, mm
  /// du_j / d(carrier rotation) = perp(C_j) + k perp(E_j - C_j), mm/rad (counterclockwise).
  Eigen::Vector2d output_gradient = Eigen::Vector2d::Zero();
  /// du_j / d(disc rotation) = -perp(H_j - D), mm/rad; du_j / d(disc translation) = -I.
  Eigen::Vector2d disc_rotation_gradient = Eigen::Vector2d::Zero();
};

/// Every crank for a disc at `disc` (its centre D is the eccentrics' offset; its rotation places
/// the crank holes) and the carrier turned by `output_rotation` (rad, about the pin-circle centre).
std::vector<CrankContact> EvaluateCranks(const Cranks& cranks, const geometry::Pose& disc, double output_rotation);
/// The same with the eccentrics' offset from their crank centres given apart from the disc's
/// centre (fixed frame, mm): a disc moved off its eccentrics under load (exact
/// kinematics). The output gradient's eccentric term is k perp(eccentric).
std::vector<CrankContact> EvaluateCranks(const Cranks& cranks, const geometry::Pose& disc, double output_rotation,
                                         const Eigen::Vector2d& eccentric);

}  // namespace ltca::contact
