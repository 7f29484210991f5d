#pragma once
// The holes of a disc's output mechanism (docs/stage.md "Hole position errors"): the
// holes of the output pins, or the crank holes, element j nominally at R (cos alpha_j,
// sin alpha_j) in the disc's body frame. A hole as made is displaced from there by its position
// deviation (radial dr_j along (cos alpha_j, sin alpha_j), tangential dt_j along
// (-sin alpha_j, cos alpha_j), counterclockwise), as [errors] pin_radial_deviations_mm and
// cumulative_pitch_deviation_mm displace the ring pins.
#include <vector>

#include <Eigen/Core>

namespace ltca::contact {

/// Per hole (radial, tangential), mm, in the disc's body frame; empty: the holes as designed.
using HoleDeviations = std::vector<Eigen::Vector2d>;

/// Hole j's centre in the disc's body frame (about the disc centre), mm.
Eigen::Vector2d HoleInDisc(double circle_radius, double alpha, const HoleDeviations& deviations, int j);

/// Every hole's centre in the disc's body frame, element j at alpha_j = 2 pi j / count + phase
/// (the drawings of the disc: DXF, STEP).
std::vector<Eigen::Vector2d> HolesInDisc(double circle_radius, int count, double phase, const HoleDeviations& deviations);

/// Throws std::invalid_argument naming `[output] hole_radial_deviations_mm` (or
/// hole_tangential_deviations_mm) unless empty or one finite pair per hole (count).
void ValidateHoleDeviations(const HoleDeviations& deviations, int count);

}  // namespace ltca::contact
