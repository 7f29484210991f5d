#pragma once
// Friction, power loss and meshing efficiency of the cycloid-pin mesh (docs/efficiency.md).
// At every crank position of the deck's sweep the loaded problem is solved (frictionless forces);
// at every loaded contact point the sliding and entrainment speeds (Jiang 2022 eq. 13-14), the
// friction coefficient ([friction] model: Coulomb or Jiang's mixed lubrication, eq. 20-26) and
// the loss mu F |v_s| (eq. 28-29) follow. Figures:
//  - first order (always): pins fixed, no sleeve, frictionless forces,
//    efficiency_first_order = P_out / (P_out + sum mu_i F_i |v_s,i|), P_out = |T| |omega_c|;
//  - full model: the pin sleeve (eq. 34: the sliding moves to the sleeve bore at the ratio of the
//    radii) and the friction moment in the torque balance ([friction] torque_balance: re-solved
//    to a fixed point, or bounded), efficiency = P_out / (P_out + P_loss) = 1 - P_loss / P_in (eq. 30);
//  - the classical estimates with the same mu (Malhotra-Parameswaran's load distribution F_i ~ L_i
//    summed over the pins, and its continuum closed form; see docs/efficiency.md for what they are).
// The crank turns so that the cycloid moves against the load torque (the stage drives the load):
// power flows from the crank to the output.
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "ltca/analysis/friction.hpp"
#include "ltca/analysis/run.hpp"
#include "ltca/analysis/spectrum.hpp"
#include "ltca/analysis/stage.hpp"

namespace ltca::analysis {

constexpr double kEfficiencyNaN = std::numeric_limits<double>::quiet_NaN();

/// One loaded contact point at one position. Speeds in mm/s, forces N, power W.
struct ContactFrictionPoint {
  int disc = 0;  ///< 0 the first disc, 1 the second ([second_disc])
  int pin = 0;
  int slice = 0;
  double force = 0.0;           ///< normal force, N (with the friction moment in the balance, if solved)
  double sliding = 0.0;         ///< v_s, mm/s, signed along t = Rot(+90) n
  double entrainment = 0.0;     ///< U, mm/s
  double coefficient = 0.0;     ///< mu at the cycloid-pin contact (the model's)
  double effective_coefficient = 0.0;  ///< with a sleeve: mu_bore r_bore / r_sleeve; else = coefficient
  double loss = 0.0;            ///< W, full model
  double loss_first_order = 0.0;  ///< W: coefficient F_frictionless |v_s|
  double film_thickness = kEfficiencyNaN;  ///< mm (jiang-mixed)
  double lambda = kEfficiencyNaN;          ///< (jiang-mixed)
  double max_pressure = 0.0;    ///< MPa, of the shape used
  bool point_contact = false;   ///< the ellipse (Jiang eq. 15-19) was used for the pressure
};

/// The power lost at each kind of contact of the stage, W (docs/efficiency.md, "The stage's
/// friction"): mesh, the cycloid flanks against the pins (0 with a rolling pin sleeve); output, the
/// output pins sliding in the disc's holes; bearings, the eccentric bearing or the crank bearings
/// (M = mu F d / 2 at the relative speed of the eccentric and the disc); seats, the pins turning in
/// their sleeves or seats (Jiang eq. 34's bore; 0 with the pins fixed). Their sum is the loss.
struct PowerLossBySource {
  double mesh = 0.0;
  double output = 0.0;
  double bearings = 0.0;
  double seats = 0.0;
  double total() const { return mesh + output + bearings + seats; }
};

struct EfficiencyPosition {
  double crank = 0.0;  ///< rad
  SolverStatus status = SolverStatus::kNotSolved;
  std::string message;
  std::vector<ContactFrictionPoint> contacts;  ///< loaded points only
  std::vector<double> pin_coefficient;  ///< per pin: force-weighted mean mu; NaN when unloaded
  std::vector<double> pin_loss;         ///< per pin, W (full model)
  double output_power = kEfficiencyNaN;          ///< W, |T| |omega_c|
  double power_loss = kEfficiencyNaN;            ///< W, full model: every source's (power_loss_by_source.total())
  /// W, full model, per source; NaN for a failed position.
  PowerLossBySource power_loss_by_source{kEfficiencyNaN, kEfficiencyNaN, kEfficiencyNaN, kEfficiencyNaN};
  /// The stage's friction moments on the discs (bearings and output pins, not in the torque
  /// balance) over |T|: the bound on the relative change of the forces they would cause (0 without
  /// a stage's coefficients; docs/efficiency.md).
  double stage_friction_moment_ratio = kEfficiencyNaN;
  double power_loss_first_order = kEfficiencyNaN;  ///< W
  double efficiency = kEfficiencyNaN;
  double efficiency_first_order = kEfficiencyNaN;
  /// Classical estimates at this position with the same mu (Coulomb's, or the mean of the mixed
  /// coefficients over the loaded contacts): F_i ~ L_i over the pins of the half ring
  /// (Malhotra-Parameswaran), and the continuum closed form.
  double efficiency_malhotra_parameswaran = kEfficiencyNaN;
  double efficiency_sensinger = kEfficiencyNaN;
  double mean_coefficient = kEfficiencyNaN;  ///< force-weighted over the loaded contacts
  /// s = sigma M_f / |T| at the accepted state: the friction moment about the cycloid centre in the
  /// sense of the load torque, over the torque, with the forces the figures use. With
  /// torque_balance = "solve" the forces balanced with friction (the normal forces carry T (1 + s));
  /// with "bound" (or mu = 0) the frictionless forces, the bound on the relative change of the forces.
  double friction_moment_ratio = kEfficiencyNaN;
  /// The same ratio with the frictionless forces (the first-order figure's forces); equals
  /// friction_moment_ratio with "bound".
  double friction_moment_ratio_first_order = kEfficiencyNaN;
  int balance_solves = 0;  ///< extra solves of the torque balance with friction
  /// |ratio(forces) - s| of the accepted state (0 without friction or when bounded): the balance
  /// residual of the forces the figures use. With "solve" the accepted state is a real solve or the
  /// secant step on forces interpolated between two solves (docs/efficiency.md); either way its own
  /// residual, below 1e-10 (a solve) or 1e-8 (interpolated).
  double balance_residual = 0.0;
  std::vector<std::string> warnings;
  bool succeeded() const { return status == SolverStatus::kSuccess; }
};

/// Mean, smallest and largest over the successful positions: the stiffness loop's Spread.
using EfficiencySpread = Spread;

/// The run record counts the successful and failed positions.
struct EfficiencySummary : RunRecord {
  EfficiencySpread power_loss, power_loss_first_order, output_power, friction_moment_ratio, mean_coefficient;
  EfficiencySpread friction_moment_ratio_first_order;  ///< with the frictionless forces
  /// Per source (PowerLossBySource's), W; their means add to power_loss's.
  EfficiencySpread power_loss_mesh, power_loss_output, power_loss_bearings, power_loss_seats;
  EfficiencySpread stage_friction_moment_ratio;
  /// Energy-weighted over the sweep: mean P_out / (mean P_out + mean P_loss).
  double efficiency = kEfficiencyNaN;
  double efficiency_first_order = kEfficiencyNaN;
  double efficiency_malhotra_parameswaran = kEfficiencyNaN;  ///< mean over the positions
  double efficiency_sensinger = kEfficiencyNaN;              ///< closed form, position independent
  double energy_loss_per_revolution = kEfficiencyNaN;        ///< J per crank revolution (mean loss x period)
  std::int64_t solves = 0, balance_solves = 0;
  std::vector<std::string> warnings;  ///< distinct warning names with the first message of each
  double loaded_solve_seconds = 0.0;  ///< of which in the frictionless load solves
  /// The last crank repeats the first's state (contact::SameMesh): the means weigh it once.
  bool closed_period = false;
};

/// Continuum closed form with F ~ L over the half ring of an unmodified pair (docs/efficiency.md):
/// P_loss / P_out = 4 mu (R_p - r_p) / (pi e z_c / |d|).
double SensingerEfficiency(const geometry::PairParameters& pair, double mu);

/// Over the stage's checked cranks at a non-zero torque (N*mm, signed), one disc; validates the
/// options (std::invalid_argument).
class EfficiencyRunner {
 public:
  EfficiencyRunner(const Stage& stage, const SolverOptions& options, double torque, const FrictionSettings& friction,
                   const OperationSettings& operation);
  ~EfficiencyRunner();
  EfficiencyRunner(EfficiencyRunner&&) noexcept;
  EfficiencyRunner& operator=(EfficiencyRunner&&) noexcept;
  EfficiencyPosition Solve(double crank);
  EfficiencySummary Summary() const;
  const std::vector<double>& cranks() const;
  double crank_speed() const;  ///< rad/s, signed: the crank's sense that drives the load

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The efficiency over a load spectrum (docs/efficiency.md, "Over a load spectrum"): each bin's
/// sweep at its torque and crank speed, and the energy over the duty cycle: per hour of operation
/// bin i delivers share_i P_out,i and loses share_i P_loss,i (its means over the crank turn), so
///   efficiency = sum_i share_i P_out,i / sum_i share_i (P_out,i + P_loss,i),
/// the ratio of the energies, not the mean of the bins' efficiencies (a bin at low torque and high
/// loss weighs by its power). The losses are the time-weighted means, W.
struct EfficiencySpectrum {
  struct Bin {
    LoadBin bin;
    EfficiencySummary summary;
  };
  std::vector<Bin> bins;
  double efficiency = kEfficiencyNaN;
  double output_power = kEfficiencyNaN;  ///< W, sum_i share_i P_out,i
  double power_loss = kEfficiencyNaN;    ///< W, sum_i share_i P_loss,i
  /// A stage's loss by source (mesh, output, bearings, seats), W, each sum_i share_i of it (0 for
  /// a source the stage does not have).
  double power_loss_mesh = kEfficiencyNaN, power_loss_output = kEfficiencyNaN,
         power_loss_bearings = kEfficiencyNaN, power_loss_seats = kEfficiencyNaN;
  bool all_succeeded() const;
};
/// Combines the bins' summaries; NaN figures unless every bin succeeded and its figures are finite.
EfficiencySpectrum CombineEfficiency(std::vector<EfficiencySpectrum::Bin> bins);

}  // namespace ltca::analysis
