#pragma once
// The torque-twist loop of a stage (docs/stiffness.md): with the input (crank) locked,
// the output torque runs from -T to +T and back, T the rated torque (|[load] torque_nm|), and the
// twist of the output is read at every level. Twist: the cycloid's rotation about its centre in
// the sense of +T, measured from the theoretical position (= -TE, docs/conventions.md), the
// unloaded free play included. From the loop, as reducer catalogues state them (Nabtesco RV
// catalogue, "torsional rigidity, lost motion and backlash"):
//  - torsional rigidity: b / a, the torque step b = T / 2 between 50 % and 100 % of T over the
//    twist a it causes, on each flank; the stage's figure takes both flanks, T / (a_drive + a_coast)
//    (or, as an option, the tangent at a given torque);
//  - lost motion: the twist between the midpoints of the loop at +-3 % of T;
//  - backlash: the width of the loop at zero torque.
// At exactly zero torque the output rests at the first contact of the flank it comes from, so
// the loop's width there is the backlash of the unloaded analysis (Liu 2021 eq. 17). Without
// [friction] the loading and unloading branches coincide (no hysteresis), and the result says so
// with the largest difference found between them. With Coulomb friction the loop is
// path dependent: after each reversal (+T, -T) the output sticks at the twist it
// reached while the torque falls back, until the branch of the other sense (friction resisting
// that motion) reaches the same twist; only then does the twist move along that branch. The loop
// closes at -T, and its area (the work friction dissipates per cycle) is the hysteresis.
// Everything here is the pin-ring mesh alone: bearings, crankshafts and the output mechanism are
// not modelled.
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <optional>

#include "ltca/analysis/friction.hpp"
#include "ltca/analysis/run.hpp"
#include "ltca/analysis/stage.hpp"

namespace ltca::analysis {

/// [stiffness]: the torque-twist loop of `ltca stiffness` (docs/stiffness.md). The torque
/// runs from -T to +T and back, T = |[load] torque_nm| (the rated torque).
struct StiffnessSettings {
  static constexpr int kMaxSteps = 10'001;
  /// Torque levels per branch from -T to +T inclusive (deck: steps_per_branch): odd, so that zero
  /// and the levels +-T / 2 of an (n - 1) / 4 grid are on it; 3 .. kMaxSteps.
  int steps = 41;
  enum class Rigidity {
    kSecant,   ///< between 50 % and 100 % of T on each flank (catalogue definition, the default)
    kTangent,  ///< the slope at tangent_torque
  };
  Rigidity rigidity = Rigidity::kSecant;  ///< deck: rigidity = "secant" | "tangent"
  /// N*mm, signed (deck: tangent_torque_nm): where the tangent rigidity is taken; finite, not zero
  /// (the free play has no slope). Required when rigidity is tangent.
  double tangent_torque = std::numeric_limits<double>::quiet_NaN();
  /// Lost motion is read at +-fraction T (deck: lost_motion_fraction, default 3 %), in (0, 1).
  double lost_motion_fraction = 0.03;
  /// One crank angle, rad (deck: crank_deg); empty: every position of [sweep].
  std::optional<double> crank;
  /// Throws std::invalid_argument naming the key, the value and what is expected.
  void Validate() const;
};


/// Which way the torque runs on a branch of the loop.
enum class Branch {
  kIncreasing,  ///< from -T to +T
  kDecreasing,  ///< from +T back to -T
};
const char* ToString(Branch branch);  ///< "increasing" | "decreasing"

struct CurvePoint {
  double torque = 0.0;  ///< N*mm, signed
  /// Output rotation in the sense of +T from the theoretical position, rad (-TE); NaN when the
  /// solve at this torque did not succeed.
  double twist = std::numeric_limits<double>::quiet_NaN();
  Branch branch = Branch::kIncreasing;
  SolverStatus status = SolverStatus::kNotSolved;  ///< the solve's (zero torque: the first contact's)
  /// With friction: where the stick after a reversal ends (the torque at which the branch of the
  /// other sense reaches the held twist), a point off the torque levels.
  bool stick_end = false;
};

/// The loop at one crank angle. A figure that no valid solve produced is NaN.
struct StiffnessPosition {
  double crank = 0.0;  ///< rad
  /// Both branches: increasing then decreasing. Each has the steps torque levels; at zero torque
  /// two points, the first contact of the flank it comes from, then that of the flank it goes to
  /// (the free play crossed at zero torque). With friction each branch starts at its reversal
  /// (-T, +T) with the twist the other branch ended with, holds it (stick) over the levels up to its
  /// stick_end point, inserted in torque order, and the decreasing branch ends at -T where the
  /// increasing one began (the loop closes).
  std::vector<CurvePoint> curve;
  double first_contact_drive = std::numeric_limits<double>::quiet_NaN();  ///< rad, >= 0 with clearance
  double first_contact_coast = std::numeric_limits<double>::quiet_NaN();  ///< rad, in the coast direction
  double backlash = std::numeric_limits<double>::quiet_NaN();             ///< rad: drive + coast first contact
  double rigidity = std::numeric_limits<double>::quiet_NaN();        ///< N*mm/rad, by the chosen definition
  double rigidity_drive = std::numeric_limits<double>::quiet_NaN();  ///< N*mm/rad, secant on the drive flank
  double rigidity_coast = std::numeric_limits<double>::quiet_NaN();  ///< N*mm/rad, secant on the coast flank
  double lost_motion = std::numeric_limits<double>::quiet_NaN();     ///< rad
  /// Two discs ([second_disc]): the share of the torque the first disc carries at +T
  /// (drive) and at -T (coast), T_1 / T; NaN for one disc or a failed solve.
  double first_disc_share_drive = std::numeric_limits<double>::quiet_NaN();
  double first_disc_share_coast = std::numeric_limits<double>::quiet_NaN();
  /// A reducer stage: the compliance budget at +T, each element group's share of the
  /// strain energy (solvers::StageGroup order: mesh, output, bearings, shafts); for linear
  /// elements the share of the twist T psi / 2 = sum of the energies. Empty for the mesh alone,
  /// NaN entries when the solve at +T failed.
  std::vector<double> compliance_share;
  /// The read-off points, each solved at its own torque: secant +T, +T / 2, -T / 2, -T (or the
  /// tangent's two torques), then lost motion +f T, -f T. Branch: increasing without friction;
  /// with friction the rigidity's are on the loading pass (increasing for T > 0, decreasing for
  /// T < 0) and the lost motion's the midpoints of the loop's width (labelled increasing).
  std::vector<CurvePoint> readoffs;
  /// The largest |twist(increasing) - twist(decreasing)| at the same torque level, rad: zero up to
  /// the solver's tolerance without friction.
  double branch_difference = std::numeric_limits<double>::quiet_NaN();
  /// The loop's area, the integral of T d(twist) once round the curve (trapezoids between its
  /// points), N*mm*rad = 1e-3 J per cycle: the work friction dissipates. Without friction zero up
  /// to the solver's tolerance. NaN when a point of the curve was not solved.
  double hysteresis = std::numeric_limits<double>::quiet_NaN();
  /// With friction, N*mm: the torque at which the stick after the reversal at +T ends (drive) and
  /// after the reversal at -T (coast); NaN without friction.
  double stick_end_drive = std::numeric_limits<double>::quiet_NaN();
  double stick_end_coast = std::numeric_limits<double>::quiet_NaN();
  int solves = 0;  ///< load solves (the curve and the read-off torques)
  int failed = 0;  ///< of those, not successful
  std::string first_failure;  ///< "torque x N*m: status: message" of the first failed solve
  bool succeeded() const { return failed == 0; }
};


/// The run record counts positions whose every solve succeeded; first_failure is "crank x deg,
/// torque y N*m: ..." of the first failed solve.
struct StiffnessSummary : RunRecord {
  Spread rigidity, rigidity_drive, rigidity_coast, lost_motion, backlash, branch_difference;
  Spread first_disc_share_drive, first_disc_share_coast;  ///< two discs only
  std::vector<Spread> compliance_share;  ///< a reducer stage only, per group
  Spread hysteresis;                        ///< N*mm*rad per cycle
  Spread stick_end_drive, stick_end_coast;  ///< N*mm, friction only
  /// The loop over the positions: per curve point (the layout of StiffnessPosition::curve), the
  /// twist's mean, smallest and largest over the positions where it was solved. With friction the
  /// stick_end points (whose torque differs by position) are the means of their torques and twists,
  /// inserted in torque order.
  std::vector<CurvePoint> curve;  ///< twist: the mean
  std::vector<double> curve_min, curve_max;
  std::vector<CurvePoint> readoffs;  ///< twist: the mean over the positions
  std::int64_t solves = 0;
  /// The last crank repeats the first's state (contact::SameMesh): the means weigh it once.
  bool closed_period = false;
};

/// The torque-twist loop of a stage: what ran and what it found (one result for `ltca stiffness`,
/// the report and the Python module).
struct StiffnessResult {
  StiffnessSettings settings;  ///< as run: settings.crank one crank, empty the stage's sweep
  double rated_torque = 0.0;   ///< T, N*mm (> 0): the loop runs from -T to +T and back
  /// The loop's Coulomb coefficient (LoopFrictionCoefficient): 0 without [friction], where the
  /// branches coincide and the hysteresis is zero up to the solver's tolerance.
  double friction_coefficient = 0.0;
  /// A stage's bearings' coefficient in the loop (StageLoopFriction: M_b = mu_b |F| d / 2; [friction]
  /// bearing_coefficient), 0 without; the loop has friction when either coefficient is above 0.
  double bearing_friction_coefficient = 0.0;
  bool with_friction() const { return friction_coefficient > 0.0 || bearing_friction_coefficient > 0.0; }
  std::vector<double> cranks;  ///< rad, in the order solved
  /// Every position in crank order; empty when they went to a sink instead (bounded memory).
  std::vector<StiffnessPosition> positions;
  /// The spreads over the positions, the mean loop, the run record (positions, failures, the
  /// first failure, wall_seconds of the whole run) and the solve count.
  StiffnessSummary summary;
  bool sweep() const { return !settings.crank.has_value(); }  ///< over the stage's cranks
  bool all_succeeded() const { return summary.all_succeeded(); }
};
/// Receives every position in crank order as it is solved.
using StiffnessSink = std::function<void(const StiffnessPosition&)>;

/// The loop position by position with one solver and one workspace: every torque step starts from
/// what the previous one left in the workspace (warm starts). The constructor validates the
/// options and the settings and requires a non-zero rated torque T (N*mm; its sign is not used),
/// before anything is solved (std::invalid_argument). friction:
/// the loop's Coulomb friction (LoopFrictionCoefficient), none without.
class StiffnessRunner {
 public:
  StiffnessRunner(const Stage& stage, const SolverOptions& options, const StiffnessSettings& settings, double torque,
                  const std::optional<FrictionSettings>& friction = std::nullopt);
  ~StiffnessRunner();
  StiffnessRunner(StiffnessRunner&&) noexcept;
  StiffnessRunner& operator=(StiffnessRunner&&) noexcept;

  /// The cranks of the run, rad: settings.crank, or the stage's checked cranks.
  const std::vector<double>& cranks() const;
  /// The torque levels of a branch, N*mm, from -T to +T.
  std::vector<double> Levels() const;
  double rated_torque() const;  ///< T, N*mm (> 0)
  /// The loop at one crank (rad), added to the summary.
  StiffnessPosition Solve(double crank);
  /// Only the lost motion at one crank (rad), added to the summary's lost_motion (and its run
  /// record): what a tolerance sample needs. Without friction the twists at +-f T, two
  /// solves. With friction the loop's width at +-f T on both passes and the twists held after the
  /// reversals at -T and +T: the rising pass at -f T is max(branch, held at -T) (the stick after
  /// the reversal holds the twist until the branch of the new sense reaches it, and the branch
  /// rises with the torque), the falling pass at +f T is min(branch, held at +T); no stick can
  /// outlast zero torque. The same lost motion as Solve's, without its curve, free play, rigidity
  /// and stick-end searches. Fills crank, lost_motion, readoffs (+f T, -f T), solves, failed.
  StiffnessPosition SolveLostMotion(double crank);
  /// Only the free play at one crank (rad), added to the summary's backlash (and its run record):
  /// the unloaded analysis of a tolerance sample of a reducer stage, whose free play
  /// takes up the clearances of every element, not the pin ring's alone. The same first contacts
  /// as Solve's (two solves at +-1e-7 T for a stage, the first-contact rotations for the mesh
  /// alone). Fills crank, first_contact_drive, first_contact_coast, backlash, solves, failed,
  /// first_failure.
  StiffnessPosition SolveFreePlay(double crank);
  StiffnessSummary Summary() const;
  /// The loop at every crank of cranks(), in order (Solve each), then the summary: each position
  /// to `sink` when given, else kept in the result's positions. Once per runner (the summary
  /// accumulates).
  StiffnessResult Run(const StiffnessSink& sink = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The loop of a stage at once (StiffnessRunner(...).Run()): every position kept in the result.
StiffnessResult Stiffness(const Stage& stage, const SolverOptions& options, const StiffnessSettings& settings, double torque,
                          const std::optional<FrictionSettings>& friction = std::nullopt);

}  // namespace ltca::analysis
