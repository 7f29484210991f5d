#pragma once
// The reducer stage (docs/stage.md): each disc floats on its eccentric bearing (a
// cycloidal drive) or on the needle bearings of its crankshafts (an RV stage), and drives the
// output member through output pins in holes or through the crankshafts. A load problem with a
// stage (LoadProblem::WithReducer) has these unknowns besides the pin-ring forces: per disc the
// translation t = (x, y) of its centre from the theoretical pose and its rotation phi; the output
// member's rotation psi, whose moment balance carries T; per crank and disc the shaft's deflection
// when both the needle bearing and the shaft are compliant. The input is locked at the crank
// angle, as in a catalogue test.
//
// Every element is a contact point whose gap is affine in these unknowns (linearised kinematics)
// with a convex energy, so the balance is the minimum of the total potential energy
//   Pi(q) = sum_elements E_e(q) - T psi,
// whose stationarity is each disc's force and moment balance and the output member's torque
// balance (Li's minimum-energy principle extended from the pin ring to the stage).
//
// Rotations are in the problem's frame (LoadProblem: positive in the direction of the torque,
// the physical counterclockwise angle is load_direction() * direction() times it); translations
// and forces are in the fixed frame.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ltca/contact/bearing.hpp"
#include "ltca/contact/cranks.hpp"
#include "ltca/contact/output_pins.hpp"

namespace ltca::solvers {

/// How the discs drive the output member.
enum class OutputKind {
  kPins,    ///< "pins": output pins in holes of the disc (cycloidal drive, W mechanism)
  kCranks,  ///< "cranks": crankshafts in crank holes, through needle bearings (RV)
};
/// "pins" | "cranks"; throws std::invalid_argument naming `[output] kind`.
OutputKind ParseOutputKind(const std::string& text);
const char* ToString(OutputKind kind);

/// The stage's elements besides the pin ring, as data (the deck's [output] and [bearing]).
struct ReducerSettings {
  OutputKind kind = OutputKind::kPins;
  contact::OutputPins pins;      ///< kPins: the output pins (their law is [contact] law, over the face width)
  contact::Cranks cranks;        ///< kCranks
  /// kPins: the eccentric bearing between the locked eccentric and the disc's bore; kCranks: the
  /// needle bearing of each crank hole. Rollers: roller 0 on the eccentric's direction.
  contact::BearingSettings bearing;
  /// N*mm/rad: the carrier, the output flange and the housing as one torsional spring in series
  /// between the output member's elements (its pins or cranks) and the output where T acts (deck:
  /// carrier_torsional_stiffness_nm_per_arcmin; infinite: rigid). The output member carries T
  /// through it whatever the stage does, so the output turns T / k beyond the stage's rotation
  /// and the spring stores T^2 / (2 k) (docs/stage.md, "The carrier in series").
  double carrier_stiffness = std::numeric_limits<double>::infinity();
  /// The second disc's own holes and bearing play where the deck gives them per disc ([second_disc]
  /// hole_radial_deviations_mm, hole_tangential_deviations_mm, bearing_radial_clearance_mm: discs
  /// are machined one by one); none: the first disc's (`pins.hole_deviation` or
  /// `cranks.hole_deviation`, `bearing.radial_clearance`). Ignored with one disc.
  std::optional<contact::HoleDeviations> second_disc_holes;
  std::optional<double> second_disc_bearing_clearance;
  /// The holes of disc 0 or 1 (the second disc's own, else the common ones).
  const contact::HoleDeviations& Holes(int disc) const;
  /// The element settings of disc 0 or 1 with that disc's holes (and, Bearing, its play).
  contact::OutputPins PinsOf(int disc) const;
  contact::Cranks CranksOf(int disc) const;
  contact::BearingSettings BearingOf(int disc) const;
  /// Throws std::invalid_argument naming the key (see OutputPins, Cranks, BearingSettings).
  void Validate(double eccentricity) const;
};

/// Loads on the stage besides T: a force and a moment on each disc and a moment on the output
/// member, constant over the solve. The stage's total potential energy gains their work,
///   Pi(q) = sum_e E_e(q) - T psi - sum_d (F_d . t_d + M_d phi_d) - M_out psi,
/// so each balance (ReducerSystem::Judge) carries them. What the quasi-static loop with friction
/// puts on the stage (analysis::SolveStageWithLoopFriction: the mesh's friction forces on each disc,
/// the bearings' friction moments). Forces N (fixed frame), moments N*mm (problem frame, as the
/// rotations).
struct StageLoads {
  struct Disc {
    Eigen::Vector2d force = Eigen::Vector2d::Zero();
    double moment = 0.0;
  };
  std::vector<Disc> discs;  ///< at most the problem's disc count; a missing disc carries none
  double output_moment = 0.0;
};

/// The element groups of the compliance budget.
/// kMesh: the pin-cycloid contacts; kSeats: the pins' seats in series with them ([pins] seat);
/// kPinBending: the pins' bending between their supports ([pins] span_mm, the coupling);
/// kCarrier: the carrier, output flange and housing in series (ReducerSettings::carrier_stiffness);
/// kSupports: the crankshafts' support bearings (crankshafts as beams; kShafts holds the beams);
/// kDiscBody: the elastic disc body's complementary energy f^T C f / 2 ([disc] body = "elastic",
/// C its condensed compliance over the ring-pin and hole contacts), reported only with that body.
enum class StageGroup { kMesh, kOutput, kBearings, kShafts, kSeats, kPinBending, kCarrier, kSupports, kDiscBody };
/// The groups every stage reports; an elastic disc body's solution holds kDiscBody too (one more).
inline constexpr int kStageGroups = 8;
inline constexpr int kStageGroupsWithBody = 9;
const char* ToString(StageGroup group);

/// What a stage solve found besides the pin-ring forces (LoadResult::force) and the output
/// rotation (LoadResult::rotation).
struct ReducerSolution {
  struct Disc {
    Eigen::Vector2d translation = Eigen::Vector2d::Zero();  ///< mm, fixed frame
    double rotation = 0.0;  ///< rad, problem frame (the disc's own rotation under load)
    /// kPins: per output pin, the force the pin puts on the disc (N, magnitude) and its direction
    /// (unit, fixed frame: from the hole's centre towards the pin's).
    std::vector<double> output_force;
    std::vector<Eigen::Vector2d> output_direction;
    /// Per bearing (kPins: one, the eccentric bearing; kCranks: one per crank), the force the
    /// eccentric puts on the disc through it (N, fixed frame) and, for rollers, each roller's load.
    std::vector<Eigen::Vector2d> bearing_force;
    std::vector<std::vector<double>> roller_load;
    /// kCranks with a compliant shaft: each shaft's deflection at the eccentric, mm.
    std::vector<Eigen::Vector2d> shaft_deflection;
  };
  std::vector<Disc> discs;
  /// Strain energy per group (StageGroup order), N*mm: the compliance budget's shares.
  std::vector<double> group_energy = std::vector<double>(kStageGroups, 0.0);
  /// The balance the shared judge measured: the largest force imbalance of a disc over the
  /// largest element force, and the largest moment imbalance (discs and output member) over T.
  double force_balance_relative = 0.0;
  double moment_balance_relative = 0.0;
};

}  // namespace ltca::solvers
