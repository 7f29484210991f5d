#pragma once
// The crankshafts of an RV stage (docs/stage.md): `count` crankshafts on the output
// member (the carrier) at radius R_c, crank j at alpha_j = 2 pi j / count + phase in the carrier's
// frame (from +X at crank 0). Each crankshaft's eccentric sits in a crank hole of the disc, through
// a needle bearing (contact/bearing.hpp), with the shaft's own radial compliance at the eccentric
// (its bending and its support bearings) in series: a linear spring, rigid by default.
//
// With the input locked the eccentric keeps its direction in the fixed frame (the eccentric of a
// cycloidal drive does the same); an RV's first stage turns it by `turns_per_output_turn` times the
// output rotation ((1 + z_sun / z_spur) for a sun gear held by the locked input). The eccentric of
// crank j for a disc whose centre the cranks put at D is at E_j = C_j + D, C_j the crank's centre
// on the carrier; the disc's crank hole j sits at H_j = D + R(disc rotation) R_c (cos alpha_j,
// sin alpha_j). At the nominal poses (the carrier turned as the disc) E_j = H_j.
//
// The relative displacement that loads the bearing is u_j = E_j - H_j (of the inner member, the
// eccentric, relative to the outer, the disc's bore); to first order in the disc translation t,
// the disc rotation phi and the carrier rotation psi:
//   du_j = [perp(C_j) + k perp(E_j - C_j)] dpsi - perp(H_j - D) dphi - dt,   k = turns_per_output_turn.
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "ltca/contact/holes.hpp"
#include "ltca/geometry/kinematics.hpp"

namespace ltca::contact {

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
  /// Each crank hole's position deviation in the disc (contact/holes.hpp); empty: none. Every
  /// disc takes the same (discs machined together in a stack).
  HoleDeviations hole_deviation;
  /// Throws std::invalid_argument naming the `[output]` key unless 2 <= count <= kMaxCount, R_c finite and
  /// > 0, the phase and the turns finite, and the shaft stiffness > 0 (infinite allowed).
  void Validate() const;
};

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
