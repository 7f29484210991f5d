#pragma once
// A loaded sweep over the deck's crank positions with one solver: per-position results and the
// summary users ask for (mean / peak-to-peak TE, contact counts, largest force and stress).
#include <string>
#include <vector>

#include "ltca/solvers/deck.hpp"
#include "ltca/solvers/load_solver.hpp"

namespace ltca::solvers {

/// A pin counts as in contact when its force exceeds this fraction of the largest pin force:
/// pins whose arm is zero to rounding (a pin exactly on the line of centres, at the root or the
/// tip) carry ~1e-12 of it, which is numerical zero (docs/validation.md).
inline constexpr double kContactForceFraction = 1e-6;

struct PositionResult {
  double crank = 0.0;                   ///< rad
  LoadResult result;
  std::vector<double> angle;            ///< pin angle from the line of centres, rad
  std::vector<double> contact_stress;   ///< Hertz maximum pressure per pin, MPa (0 if unloaded)
  int contacts = 0;                     ///< pins above kContactForceFraction of the largest force
};

struct SweepSummary {
  double mean_te = 0.0;        ///< rad
  double pp_te = 0.0;          ///< rad
  int contacts_min = 0;
  int contacts_max = 0;
  double max_pin_force = 0.0;  ///< N
  double max_contact_stress = 0.0;  ///< MPa
  double wall_seconds = 0.0;
  SolverStatus status = SolverStatus::kNotSolved;  ///< the worst status over the sweep
};

struct SweepResult {
  std::string solver;
  SolverOptions options;
  std::vector<PositionResult> positions;
  SweepSummary summary;
};

/// Solves every crank position of the deck (requires [material] and [load]).
SweepResult SolveSweep(const Deck& deck, const SolverOptions& options);

}  // namespace ltca::solvers
