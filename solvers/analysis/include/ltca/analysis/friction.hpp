#pragma once
// Friction (docs/efficiency.md): the operating point and the friction model of a deck
// ([operation], [friction]), and the quasi-static torque balance of the torque-twist loop with
// Coulomb friction, which both `ltca stiffness` and `ltca tolerance` (lost motion) run.
#include <functional>
#include <limits>
#include <optional>

#include "ltca/analysis/stage.hpp"

namespace ltca::analysis {

/// [operation]: how the stage runs, for `ltca efficiency`. Internal units: rad/s, MPa*s, 1/MPa, mm.
struct OperationSettings {
  double input_speed = 0.0;          ///< crank speed, rad/s (deck: input_speed_rpm, required, > 0)
  double viscosity = 30e-9;          ///< eta_0, MPa*s (deck: oil_viscosity_pa_s, default 0.03, Jiang)
  double pressure_viscosity = 0.01;  ///< alpha, 1/MPa (deck: pressure_viscosity_per_gpa, default 10, Jiang)
  double roughness_cycloid = 0.3e-3; ///< Ra, mm (deck: roughness_ra_cycloid_um, default 0.3, Jiang)
  double roughness_pin = 0.3e-3;     ///< Ra, mm (deck: roughness_ra_pin_um, default 0.3)
  /// nu, mm^2/s: the kinematic viscosity of the bearings' oil at operating temperature (deck:
  /// oil_kinematic_viscosity_mm2_per_s), ISO 281's viscosity ratio kappa = nu / nu_1 of the modified
  /// rating life. Not given (the default): no modified life. The same oil as oil_viscosity_pa_s
  /// (nu = eta / rho), given apart because ISO 281 asks for the kinematic one and eta's default is
  /// the friction model's, not a statement of the oil.
  std::optional<double> kinematic_viscosity;
  static constexpr double kMaxSpeedRpm = 100'000.0;
  /// Throws std::invalid_argument naming the key, the value and what is expected.
  void Validate() const;
};

/// [friction]: the friction coefficient model, the pin sleeve and the torque balance.
struct FrictionSettings {
  enum class Model {
    kCoulomb,     ///< constant mu = coefficient (deck: model = "coulomb", the default)
    kJiangMixed,  ///< Jiang 2022 eq. 20-26 (deck: "jiang-mixed"); needs [operation]
  };
  Model model = Model::kCoulomb;
  /// mu (deck: coefficient): Coulomb's constant; with jiang-mixed the coefficient of the first-order
  /// figure is the mixed one, and this key is not used (it may be absent). In [0, 1].
  double coefficient = std::numeric_limits<double>::quiet_NaN();
  double boundary_coefficient = 0.1;    ///< f_b of eq. 20 (deck: boundary_coefficient), in [0, 1]
  double limiting_shear_modulus = 1.0;  ///< G of eq. 23, MPa (deck: limiting_shear_modulus_mpa)
  double power_law_exponent = 0.5;      ///< n of eq. 22-23 (deck: power_law_exponent), in (0, 1]
  /// The lubricant's limiting shear stress tau_L = tau_L0 + gamma p (Bair and Winer 1979, Evans
  /// and Johnson 1986), capping eq. 23's shear stress point by point (contact/sliding.hpp): gamma
  /// (deck: limiting_shear_stress_coefficient, in (0, 1]; NaN, the default: no cap, Jiang as
  /// printed) and tau_L0 in MPa (deck: limiting_shear_stress_mpa, >= 0, default 0; only with gamma).
  double limiting_shear_coefficient = std::numeric_limits<double>::quiet_NaN();
  double limiting_shear_stress = 0.0;
  /// Pin sleeve (Jiang eq. 34, deck: sleeve_bore_radius_mm): the radius of the pin inside a sleeve
  /// whose outer radius is [pair] pin_radius_mm. Empty: no sleeve.
  std::optional<double> sleeve_bore_radius;
  /// mu at the sleeve's bore (deck: sleeve_coefficient); NaN (the default): the coefficient of the
  /// contact it replaces (Coulomb's mu, or the mixed one there), Jiang eq. 34 read literally.
  double sleeve_coefficient = std::numeric_limits<double>::quiet_NaN();
  /// The reducer stage's contacts (docs/efficiency.md, "The stage's friction"): Coulomb's mu of an
  /// output pin sliding in its hole (deck: output_pin_coefficient, [output] kind = "pins"), and the
  /// bearings' constant coefficient of M = mu F d / 2 (deck: bearing_coefficient; SKF's simplified
  /// friction moment), d the bearing's diameter (deck: bearing_diameter_mm; NaN, the default: [bearing]
  /// pitch_diameter_mm). Both in [0, 1], 0 by default (no loss there).
  double output_pin_coefficient = 0.0;
  double bearing_coefficient = 0.0;
  double bearing_diameter = std::numeric_limits<double>::quiet_NaN();  ///< mm
  /// Palmgren's viscous friction moment of each rolling bearing (Harris and Kotzalas, Essential
  /// Concepts of Bearing Technology, 5th ed., 2007, sec. 10.3; Palmgren 1959): M_0 = 1e-7 f_0
  /// (nu n)^(2/3) d^3 N*mm for nu n >= 2000, 160e-7 f_0 d^3 below (nu in mm^2/s, [operation]
  /// oil_kinematic_viscosity_mm2_per_s; n the bearing's relative speed in rpm; d as above), beside
  /// the load term mu F d / 2. f_0 (deck: bearing_viscous_factor, in [0, 100], 0 by default: none;
  /// needle and cylindrical roller bearings about 2 to 12 by their lubrication). A running loss:
  /// ltca efficiency only, not the quasi-static loop.
  double bearing_viscous_factor = 0.0;
  bool stage_friction() const {
    return output_pin_coefficient > 0.0 || bearing_coefficient > 0.0 || bearing_viscous_factor > 0.0;
  }
  enum class TorqueBalance {
    kSolve,  ///< re-solve with the friction moment in the balance, to a fixed point (default)
    kBound,  ///< frictionless forces; the friction moment's ratio to T reported as a bound
  };
  TorqueBalance torque_balance = TorqueBalance::kSolve;  ///< deck: torque_balance = "solve" | "bound"
  /// Throws std::invalid_argument naming the key, the value and what is expected.
  void Validate(const geometry::PairParameters& pair) const;
};
const char* ToString(FrictionSettings::Model model);
/// d of the stage's bearings' friction moment, mm: [friction] bearing_diameter_mm, else [bearing]
/// pitch_diameter_mm (`pitch`). Throws std::invalid_argument naming the keys when neither gives one
/// and a bearing coefficient (load or viscous) is above 0; 0 when neither coefficient is.
double BearingFrictionDiameter(const FrictionSettings& friction, double pitch);
/// Palmgren's viscous friction moment of a rolling bearing, N*mm (FrictionSettings::
/// bearing_viscous_factor): 1e-7 f_0 (nu n)^(2/3) d^3 for nu n >= 2000, 160e-7 f_0 d^3 below; nu
/// mm^2/s, n rpm (the rings' relative speed), d mm. 0 when f_0 is 0.
double PalmgrenViscousMoment(double f0, double nu, double n_rpm, double d);
// --- the stiffness loop with friction --------------------------------------------------------
/// The signed torque the normal forces carry at a quasi-static step of the torque-twist loop with
/// Coulomb friction (the crank locked, the cycloid turning about its centre): the friction at each
/// loaded contact resists the turning, so the normal forces carry T - sense mu sum F_i |a_t,i|
/// (a_t: the tangential arm about the cycloid centre), sense = +1 while the twist grows in +T's
/// sense (the increasing branch), -1 on the way back. problem(t) is the frictionless problem at
/// signed torque t, solve(p) solves one. mu: [friction]'s static coefficient (Coulomb's, or f_b for
/// jiang-mixed: no entrainment, boundary friction). Returns the last result; *solves counts.
/// second: the second disc of a two-disc stage, whose points in state turn about its own
/// centre, half a crank turn on; nullptr for one disc.
///
/// Issue 27: the balance sum_i F_i (L_i + d sense mu a_i) = |T| (d the flank's sign) is the
/// frictionless balance of laws scaled by w_i = 1 + d sense mu a_i / L_i (ContactLaw::Scaled):
/// where the problem's laws are its own (LoadProblem::scalable_laws: linearised, uncoupled, no
/// stage), it is solved once, and the result's forces are the normal forces F_i = (w_i F_i) / w_i
/// (its energy theirs, its residuals the judge's on the balance with friction). A pin of arm
/// L_i <= 0, or whose w_i would be <= 0 (its friction arm outgrows its normal arm on the way back),
/// keeps w_i = 1, and the answer stands only if their friction moment in it is below 1e-12 of T.
/// Otherwise (exact kinematics, a coupling, a stage, or such a pin pressed) a fixed point in t,
/// each step the frictionless problem at t, by the secant method. Both find the same balance.
///
/// Where the last balance of the same kind ended (the same torque and sense at the
/// neighbouring crank angle): the ratio t / T it converged to and the slope of its residual
/// g(t) = T - sense M_f(t) - t. The first solve is then at ratio T and the first step uses that
/// slope; the balance is the same fixed point to the same tolerance, found in fewer solves. NaN:
/// no warm start (the first solve at T, the first slope -(1 + sense M_f / t)). Updated on success.
struct LoopFrictionWarmStart {
  double ratio = std::numeric_limits<double>::quiet_NaN();
  double slope = std::numeric_limits<double>::quiet_NaN();
};
/// What a solved balance tells beyond its result.
struct LoopFrictionBalance {
  /// The friction moment mu sum F_i a_i, N*mm (>= 0): the normal forces carry |T| - d sense of it.
  double moment = std::numeric_limits<double>::quiet_NaN();
  /// Solved once with scaled laws (linearised, uncoupled, no reducer), else by the secant iteration.
  /// With direct, every force of an arm L_i > 0 grows with the rotation, and so with the torque t
  /// the normal forces carry; behind bounds the friction moment of the pins of arm <= 0 (which
  /// open as the rotation grows) at any rotation a torque of this flank gives, N*mm (0 when they
  /// are open there; NaN without direct). SolveLostMotion's use: M(t) <= M_+(t) + behind, M_+
  /// non-decreasing in t.
  bool direct = false;
  double behind = std::numeric_limits<double>::quiet_NaN();
};
using LoadProblemAt = std::function<solvers::LoadProblem(double)>;
using SolveProblem = std::function<LoadResult(const solvers::LoadProblem&)>;
LoadResult SolveWithLoopFriction(const contact::MeshModel& model, const contact::MeshState& state, double torque,
                                 double sense, double mu, const LoadProblemAt& problem, const SolveProblem& solve,
                                 int* solves, const contact::MeshModel* second = nullptr,
                                 LoopFrictionWarmStart* warm = nullptr, LoopFrictionBalance* balance = nullptr);
/// The stage's torque-twist loop with friction (docs/stiffness.md, "The stage's loop with friction"):
/// with the input locked the discs move with the output against the pins and their bearings. The
/// stage's motion along the branch is the frictionless stage's between T and a step of 1e-4 |T|
/// behind it on the branch; each loaded pin-cycloid contact's friction, mu F against the tangential
/// part of its disc's motion there (translation and turn), acts on the disc (force and moment), and
/// each bearing's friction moment M_b = mu_b |F_b| d / 2 (SKF's constant-coefficient form, as `ltca
/// efficiency` takes it) against the bearing's relative rotation: the disc against its locked
/// eccentric (output pins), or a crankshaft turning k psi against its disc (cranks, k =
/// turns_per_output_turn), whose friction the output member supplies through the locked first stage
/// (virtual work: -sign(k dpsi - dphi) M_b k on psi, +sign(k dpsi - dphi) M_b on the disc). The
/// output pins move with their disc (their slide is the elements' deflection, not the twist) and the
/// pins sit in their seats: no friction there in the loop. These loads enter the stage's balance
/// apart from the output torque (LoadProblem::WithStageLoads): a fixed point, each step the stage at
/// T with the loads of the last answer's forces, accelerated by Anderson's method of depth 1;
/// converged when the answer's loads equal those it was solved with to 1e-10 |T|.
struct StageLoopFriction {
  double mesh = 0.0;              ///< mu at the pin-cycloid contacts (LoopFrictionCoefficient)
  double bearing = 0.0;           ///< mu_b ([friction] bearing_coefficient)
  double bearing_diameter = 0.0;  ///< d of M_b, mm (bearing_diameter_mm, else [bearing] pitch_diameter_mm)
  bool any() const { return mesh > 0.0 || bearing > 0.0; }
};
/// The loads friction puts on the stage at a solved state `result` (its forces) moving as the stage
/// moves from `from` to `to` (the sliding senses; see StageLoopFriction; problem: the stage at
/// result's torque, whose frame from and to share).
solvers::StageLoads StageFrictionLoads(const solvers::LoadProblem& problem, const contact::MeshModel& model,
                                       const contact::MeshModel* second, const contact::MeshState& state,
                                       const LoadResult& result, const LoadResult& from, const LoadResult& to,
                                       const StageLoopFriction& friction);
LoadResult SolveStageWithLoopFriction(const contact::MeshModel& model, const contact::MeshState& state,
                                      double torque, double sense, const StageLoopFriction& friction,
                                      const LoadProblemAt& problem, const SolveProblem& solve, int* solves,
                                      const contact::MeshModel* second = nullptr,
                                      LoopFrictionBalance* balance = nullptr);
/// The static coefficient of the loop: Coulomb's mu, or f_b for jiang-mixed; 0 without [friction].
double LoopFrictionCoefficient(const std::optional<FrictionSettings>& friction);

}  // namespace ltca::analysis
