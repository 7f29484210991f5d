#pragma once
// A loaded sweep over the deck's crank positions with one solver: per-position results and the
// summary users ask for (mean / peak-to-peak TE, contact counts, largest force and stress).
// The summary is taken over the positions that succeeded only: a failed position has no valid
// TE, force or stress to average. Long sweeps can stream: a callback sees every position as it
// is solved, and the positions need not be kept.
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include <algorithm>
#include <cmath>

#include "ltca/contact/bearing.hpp"
#include "ltca/analysis/run.hpp"
#include "ltca/analysis/contact_fatigue.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/solvers/load_solver.hpp"

namespace ltca::analysis {

/// A sweep may span this many output revolutions (a per-tooth error repeats after one; issue 54).
inline constexpr int kMaxOutputTurns = 2;
/// The largest crank angle of a sweep of a disc of `tooth_count` teeth, deg: kMaxOutputTurns turns of
/// the disc relative to the eccentric (tooth_count crank turns each: at least kMaxOutputTurns output
/// revolutions, whose ratio is tooth_count / d), and never less than 10 crank turns (docs/decks.md,
/// Limits).
inline double MaxCrankDeg(int tooth_count) {
  return std::max(3600.0, 360.0 * kMaxOutputTurns * std::abs(static_cast<double>(tooth_count)));
}
/// The largest crank angle any command names, deg: two output turns of the largest pair a deck may
/// give (10,001 teeth); a sweep's own bound is MaxCrankDeg of its pair.
inline constexpr double kMaxCrankDeg = 360.0 * kMaxOutputTurns * 10'001;

/// [load]: the output torque of the stage: the one disc's, or with a second disc both discs' together.
struct LoadCase {
  double torque = 0.0;  ///< N*mm (deck: torque_nm), finite, signed: the sign picks the flank.
  /// Throws std::invalid_argument "[load] torque_nm = ...: expected a finite torque" otherwise.
  void Validate() const;
};

/// The crank positions of a sweep (a deck's [sweep]); default one mesh period in 91 positions
/// (Liu's 0.1 deg step at z_p = 40).
struct Sweep {
  static constexpr int kMaxPositions = 1'000'000;
  double crank_start = 0.0;  ///< rad (deck: crank_start_deg).
  double crank_end = 0.0;    ///< rad (deck: crank_end_deg), inclusive.
  int positions = 91;        ///< 1 .. kMaxPositions.
  /// Throws std::invalid_argument naming the key: positions out of range, angles not finite or
  /// beyond MaxCrankDeg(tooth_count), an empty range with several positions.
  void Validate(int tooth_count) const;
  /// The crank angles, rad: positions values from start to end inclusive.
  std::vector<double> CrankAngles() const;
};

/// A pin counts as in contact when its force exceeds this fraction of the largest pin force:
/// pins whose arm is zero to rounding (a pin exactly on the line of centres, at the root or the
/// tip) carry ~1e-12 of it, which is numerical zero (docs/validation.md).
inline constexpr double kContactForceFraction = 1e-6;

/// One crank position. The solver's result is per contact point (pin-major: one per pin in the
/// plane model, pin x slice in the slice model); the per-pin figures gather a pin's slices.
struct PositionResult {
  double crank = 0.0;                   ///< rad
  LoadResult result;                    ///< forces per contact point, N
  int slices = 1;                       ///< face-width slices of the model that ran
  std::vector<double> angle;            ///< pin angle from the line of centres, rad
  std::vector<double> pin_force;        ///< per pin: the total over its slices, N
  std::vector<double> contact_stress;   ///< per pin: the largest Hertz pressure over its slices, MPa (0 if unloaded)
  std::vector<double> point_stress;     ///< per contact point: Hertz maximum pressure, MPa (0 if unloaded)
  /// per pin: the axial centroid of its load from face B, mm (NaN when the pin is unloaded)
  std::vector<double> load_centroid;
  int contacts = 0;                     ///< pins above kContactForceFraction of the largest pin force
  /// Two discs ([second_disc]): the torque each disc carries, N*mm, signed as T (NaN for
  /// a failed position); empty for one disc. The per-pin figures above then run over disc 1's pins,
  /// then disc 2's (2 z_p entries).
  std::vector<double> disc_torque;
  /// The solve is valid (status success); a failed position's te, forces and stresses are not
  /// answers and take no part in the summary.
  bool succeeded() const { return result.status == SolverStatus::kSuccess; }
};

/// Figures over the successful positions only; NaN (and contacts -1) when none succeeded. The run
/// record counts positions with status success and with any other status.
/// A reducer stage's figures over the successful positions: the largest output-pin
/// force, bearing load and roller load, and each bearing's mean equivalent load over the positions
/// in the mean (ISO 281's averaging of a load that varies over equal steps, exponent 10/3;
/// contact/bearing.hpp). Bearings run disc-major: one per disc for output pins (the eccentric
/// bearing), one per crank and disc for cranks.
struct ReducerSummary {
  double max_output_force = std::numeric_limits<double>::quiet_NaN();   ///< N
  double max_bearing_load = std::numeric_limits<double>::quiet_NaN();   ///< N
  double max_roller_load = std::numeric_limits<double>::quiet_NaN();    ///< N (NaN without rollers)
  std::vector<double> mean_equivalent_load;                             ///< N, per bearing
  /// Per bearing, its largest load and its largest roller's load over the successful positions
  /// (N; the roller's NaN without rollers): ISO 76's P_0 and the static stress.
  std::vector<double> bearing_max_load;
  std::vector<double> bearing_max_roller_load;
  /// Rollers: per bearing, per position in the mean, its roller loads' moments as the raceways see
  /// them (contact::LoadMoments): the load-zone life's load states. Empty without rollers.
  std::vector<std::vector<contact::RollerLoadMoments>> roller_moments;
  /// Mean share of the strain energy per element group (solvers::StageGroup order).
  std::vector<double> energy_share;
};

/// ISO 281 basic rating life of each of a stage's bearings (contact::RatingLife, exponent 10/3)
/// from its mean equivalent load over a sweep (ReducerSummary), in millions of revolutions of the
/// bearing's rings relative to each other and in hours at the crank speed: the eccentric turns
/// against the disc at |1 - 1/I| times the crank speed (I the transmission ratio,
/// geometry::Kinematics; the disc turns 1/I of a crank turn), for a cycloidal drive's eccentric
/// bearing and an RV's crank bearings alike. NaN without a rating ([bearing]
/// dynamic_load_rating_n) or, for hours, without a speed. `basis` says what the mean is over: a
/// whole crank turn, a mesh period that repeats over the turn (SweepSummary::closed_period), or
/// only the swept positions.
///
/// The load-zone life (rollers with [bearing] pitch_diameter_mm and a rating): the reference
/// rating life of ISO/TS 16281 in its Lundberg-Palmgren form from each position's roller loads
/// (contact/bearing.hpp), Palmgren-Miner over the positions in the mean, calibrated on ISO 281 by
/// the load-zone equivalent load P_lz: L = (C / P_lz)^(10/3). The raceway that turns against the
/// load follows from the element (turning_basis says why): the outer one for the eccentric
/// bearing of a cycloidal drive (its load turns with the eccentric), the inner one for a crank's
/// needle bearing (its load stands on the carrier, as the translating disc's bore does).
/// Static safety (ISO 76:2006): s_0 = C_0 / P_0,max, P_0 = the radial load of a radial roller
/// bearing (alpha = 0), the largest over the successful positions; and the largest roller's Hertz
/// stress on the inner raceway against ISO 76's 4,000 MPa.
struct BearingLife {
  std::vector<double> million_revolutions;
  std::vector<double> hours;
  std::string basis;
  std::vector<contact::Raceway> turning_raceway;        ///< per bearing: the raceway turning against the load
  std::string turning_basis;                             ///< why, from the element's kinematics
  std::vector<double> load_zone_equivalent_load;         ///< N, P_lz per bearing (NaN: not computed)
  std::vector<double> load_zone_million_revolutions;     ///< per bearing (NaN: not computed)
  std::vector<double> load_zone_hours;                   ///< per bearing (NaN: not computed)
  std::vector<double> static_safety;                     ///< s_0 per bearing (NaN without C_0)
  std::vector<double> max_roller_stress;                 ///< MPa per bearing (NaN without rollers and d_m)
  /// ISO 281:2007's modified rating life L_10m = a_ISO L_10 (9.3; a_1 = 1, 90 % reliability; radial
  /// roller bearings, contact::LifeModificationFactor), rated when [operation]
  /// oil_kinematic_viscosity_mm2_per_s is given (`modified`). kappa = nu / nu_1, nu_1 at the
  /// bearing's speed (|1 - 1/I| times the crank's) and d_m (contact::ReferenceViscosity), one for
  /// all the stage's bearings (one [bearing], one speed). a_ISO is rated per bearing twice: on the
  /// basic life with P its mean equivalent load (as ISO 281 defines L_10m), and on the load-zone
  /// life with P = P_lz (the load that gives the load-zone life by ISO 281's formula). NaN without
  /// a speed.
  bool modified = false;
  double kinematic_viscosity = std::numeric_limits<double>::quiet_NaN();  ///< nu, mm^2/s as given
  double reference_viscosity = std::numeric_limits<double>::quiet_NaN();  ///< nu_1, mm^2/s
  double viscosity_ratio = std::numeric_limits<double>::quiet_NaN();      ///< kappa = nu / nu_1, before ISO's clamp to [0.1, 4]
  double contamination_factor = std::numeric_limits<double>::quiet_NaN(); ///< e_C ([bearing] contamination_factor)
  double fatigue_load_limit = std::numeric_limits<double>::quiet_NaN();   ///< C_u, N
  std::string fatigue_load_limit_basis;  ///< "given" or ISO 281 Annex B's estimate
  std::vector<double> load_ratio;                  ///< e_C C_u / P per bearing, P the mean equivalent load
  std::vector<double> life_modification;           ///< a_ISO per bearing on the basic life
  std::vector<double> modified_hours;              ///< a_ISO L_10 in hours per bearing
  std::vector<double> load_zone_load_ratio;        ///< e_C C_u / P_lz per bearing
  std::vector<double> load_zone_life_modification; ///< a_ISO per bearing on the load-zone life
  std::vector<double> load_zone_modified_hours;    ///< a_ISO L_lz in hours per bearing
  /// The shortest life in hours of the bearings that have one; NaN when none has (no rating, no speed).
  double ShortestHours() const;
  /// The same for the load-zone lives.
  double ShortestLoadZoneHours() const;
  /// The smallest s_0 of the bearings that have one; NaN when none has.
  double SmallestStaticSafety() const;
  /// The largest roller contact stress, MPa; NaN when none is computed.
  double LargestRollerStress() const;
  /// The shortest modified lives (a_ISO times the basic and the load-zone life), h; NaN when none.
  double ShortestModifiedHours() const;
  double ShortestLoadZoneModifiedHours() const;
};

struct SweepSummary : RunRecord {
  double mean_te = std::numeric_limits<double>::quiet_NaN();        ///< rad
  double pp_te = std::numeric_limits<double>::quiet_NaN();          ///< rad
  int contacts_min = -1;
  int contacts_max = -1;
  double max_pin_force = std::numeric_limits<double>::quiet_NaN();  ///< N, a pin's total over its slices
  double max_contact_stress = std::numeric_limits<double>::quiet_NaN();  ///< MPa
  /// Successful positions whose result carries warnings (stress beyond the material limit, a
  /// half-width beyond the law: LoadResult::warnings), and the first of those warnings.
  std::int64_t warned = 0;
  std::string first_warning;
  /// Two discs: the share of the torque the first disc carries, T_1 / T, over the successful
  /// positions (NaN for one disc or none).
  double first_disc_share_mean = std::numeric_limits<double>::quiet_NaN();
  double first_disc_share_min = std::numeric_limits<double>::quiet_NaN();
  double first_disc_share_max = std::numeric_limits<double>::quiet_NaN();
  SolverStatus status = SolverStatus::kNotSolved;  ///< the worst status over the sweep
  /// A preloaded pair (LoadResult::preload): the positions whose result carries a preload state,
  /// its largest point force (N) and contact stress (MPa) at zero torque over them (NaN: none),
  /// and the positions whose status is cannot-assemble.
  std::int64_t preloaded = 0;
  double max_preload_force = std::numeric_limits<double>::quiet_NaN();
  double max_preload_stress = std::numeric_limits<double>::quiet_NaN();
  std::int64_t cannot_assemble = 0;
  /// The sweep's last crank repeats the state of its first (contact::SameMesh: a whole crank turn,
  /// or a mesh period of a pair that keeps that symmetry), so the means weight that state once;
  /// the extremes and counts see every position.
  bool closed_period = false;
  std::optional<ReducerSummary> reducer;  ///< the reducer's elements' figures; none for the mesh alone
  /// Notes for the user about the sweep itself (Stage::SamplingNote: too few positions a mesh period).
  std::vector<std::string> notes;
  /// A reducer stage's bearing lives (ISO 281, BearingLives) from `reducer`'s mean equivalent loads,
  /// computed once by app::SolveDeckSweep, which knows the deck's bearings and crank speed; none
  /// for the mesh alone and from a SweepRunner alone.
  std::optional<BearingLife> bearing_life;
  /// The pin-cycloid contact's load cycles over the sweep (contact_fatigue.hpp), counted by the
  /// accumulator from every position's per-pin pressure.
  ContactCycles contact_cycles;
  /// Their pitting rating (RateContactFatigue), computed once by app::SolveDeckSweep, which knows
  /// the material, the crank speed and the required life; none from a SweepRunner alone.
  std::optional<ContactFatigue> contact_fatigue;
};

struct StageDesign;
/// input_speed: the crank speed, rad/s ([operation] input_speed_rpm), NaN when none is given.
/// kinematic_viscosity: the oil's nu, mm^2/s ([operation] oil_kinematic_viscosity_mm2_per_s), NaN
/// when none is given (no modified life).
BearingLife BearingLives(const StageDesign& design, const ReducerSummary& summary, const Sweep& sweep, bool closed_period,
                         double input_speed, double kinematic_viscosity = std::numeric_limits<double>::quiet_NaN());

/// Accumulates the summary position by position (the rule of SweepSummary).
class SummaryAccumulator {
 public:
  /// in_mean false: the position repeats one already added (the last of a closed period), and
  /// counts everywhere but in the means.
  void Add(const PositionResult& position, bool in_mean = true);
  /// Sets SweepSummary::closed_period (the caller decides it, SweepRunner from the states).
  bool closed_period = false;
  /// The summary so far (wall_seconds left to the caller).
  SweepSummary Summary() const;

 private:
  SweepSummary s_;
  double te_sum_ = 0.0, te_lo_ = std::numeric_limits<double>::infinity(),
         te_hi_ = -std::numeric_limits<double>::infinity();
  std::int64_t te_count_ = 0;
  double share_sum_ = 0.0;
  std::int64_t shares_ = 0, share_count_ = 0;
  std::vector<double> bearing_power_sum_;  // sum of P^(10/3) per bearing over the positions in the mean
  std::vector<double> share_sums_;         // per group
  std::int64_t stage_count_ = 0;
  ContactCycleCounter cycles_;
  double first_crank_ = 0.0, last_crank_ = 0.0;  // rad, of the positions added (failed ones too)
  std::int64_t added_ = 0;
  std::size_t discs_ = 1;
};

/// One solver over the crank positions of a stage at one torque (N*mm, signed), a position at a
/// time, so that callers can stream or run several solvers in lockstep. The constructor validates
/// the options; the stage has checked its cranks for interference.
class SweepRunner {
 public:
  SweepRunner(const Stage& stage, const SolverOptions& options, double torque);
  ~SweepRunner();
  SweepRunner(SweepRunner&&) noexcept;
  SweepRunner& operator=(SweepRunner&&) noexcept;

  /// Solves one crank angle (rad) and adds it to the summary.
  PositionResult Solve(double crank);
  /// The summary of the positions solved so far; wall_seconds counts construction and solves.
  SweepSummary Summary() const;
  const SolverOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct SweepResult {
  std::string solver;
  SolverOptions options;
  std::vector<PositionResult> positions;  ///< empty when the sweep was run without keeping them
  SweepSummary summary;
};

struct SweepCallbacks {
  /// Called with every position as soon as it is solved, in crank order.
  std::function<void(const PositionResult&)> on_position;
  /// false: SweepResult::positions stays empty, so memory does not grow with the sweep.
  bool keep_positions = true;
};

/// Solves every checked crank of the stage at the torque (N*mm). Throws std::invalid_argument for
/// bad options, before solving anything.
SweepResult SolveSweep(const Stage& stage, const SolverOptions& options, double torque,
                       const SweepCallbacks& callbacks = {});

}  // namespace ltca::analysis
