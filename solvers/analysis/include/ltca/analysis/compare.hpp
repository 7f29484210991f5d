#pragma once
// Several load solvers on the same stage and sweep, side by side (`ltca compare`): each solver's
// sweep summary and its largest differences from the first solver (the reference) in TE, pin
// force and contact count, over the positions where both succeeded. The solvers run in lockstep,
// a position at a time, so memory does not grow with the sweep.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/sweep.hpp"

namespace ltca::analysis {

/// The largest differences of one solver from the reference, over the positions where both
/// succeeded (zero over none).
struct SolverDifferences {
  double te = 0.0;     ///< largest |TE - TE of the reference|, rad
  double force = 0.0;  ///< largest |F_i - F_i of the reference| over the pins, N
  int pins = 0;        ///< largest difference of the loaded pin counts
  std::int64_t compared = 0;  ///< positions where both succeeded
  /// Takes position `p` of this solver against `reference`, the reference's at the same crank.
  void Add(const PositionResult& p, const PositionResult& reference);
};

/// One solver of a comparison: its sweep and its differences from the reference.
struct SolverComparison {
  SolverOptions options;  ///< as run (the deck's [solver] with this name)
  SweepSummary summary;   ///< over the sweep, wall_seconds this solver's alone
  SolverDifferences differences;  ///< from the reference; the reference's own are zero
  /// Positions its figures are compared over: the reference's successful positions, another
  /// solver's positions where both succeeded.
  std::int64_t compared(bool reference) const { return reference ? summary.succeeded : differences.compared; }
};

/// A solver asked for that did not run, and why.
struct SkippedSolver {
  std::string name;
  std::string reason;
};

/// The solvers asked for split into those that run on the stage and those skipped with their
/// reason: a solver that does not solve a reducer stage (`reducer`) is skipped. Throws
/// std::invalid_argument for an unknown name (solvers::MakeSolver), and naming the solvers and
/// the deck (`deck`, its name) when none of them runs.
struct SolverSelection {
  std::vector<std::string> run;
  std::vector<SkippedSolver> skipped;
};
SolverSelection SelectSolvers(const std::vector<std::string>& asked, bool reducer, const std::string& deck);

/// What ran and what it found: the solvers in order (the first is the reference), those skipped,
/// the cranks (rad).
struct CompareResult {
  std::vector<SolverComparison> solvers;
  std::vector<SkippedSolver> skipped;
  std::vector<double> cranks;
  bool all_succeeded() const;  ///< every position of every solver
  bool any_failed() const;     ///< some position of some solver failed
};

/// Receives every crank (rad) with each solver's position there, in the solvers' order, as they
/// are solved.
using CompareSink = std::function<void(double crank, const std::vector<PositionResult>& positions)>;

/// Every solver of `names` (options: `base` with the name replaced) over the stage's cranks at
/// `torque` (N*mm), in lockstep. Requires at least one name.
CompareResult Compare(const Stage& stage, const SolverOptions& base, const std::vector<std::string>& names, double torque,
                      const std::vector<SkippedSolver>& skipped = {}, const CompareSink& sink = {});

}  // namespace ltca::analysis
