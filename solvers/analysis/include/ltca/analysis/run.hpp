#pragma once
// What every analysis reports about its own run: one run record, and the spread of a
// figure over the positions.
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

namespace ltca::analysis {

/// A figure no valid solve produced: NaN inside, null in the outputs (the output contract).
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// How a run of an analysis ended (a sample of the tolerance study, a deterministic run, a
/// summary): printed by ToString as "success", "failed", "rejected", "not run".
enum class RunStatus : std::uint8_t {
  kSuccess = 0,  ///< every solve succeeded
  kFailed = 1,   ///< some position did not succeed (the figures are over the ones that did)
  kRejected = 2, ///< the pair as drawn interferes or cannot be built: no figure
  kNotRun = 3,   ///< not attempted (e.g. a worst-case corner whose stack is unknown)
  /// A preloaded pair that cannot be assembled (solvers::SolverStatus::kCannotAssemble at some
  /// position: no preload balance within the laws, or its stress beyond the material's limit)
  kCannotAssemble = 4,
};
const char* ToString(RunStatus status);

/// Positions (or samples) that succeeded and failed, the first failure, and the wall time.
struct RunRecord {
  std::int64_t succeeded = 0;  ///< positions whose every solve succeeded
  std::int64_t failed = 0;     ///< positions with any other outcome
  std::string first_failure;   ///< where and why the first failure happened; empty when none
  double wall_seconds = 0.0;   ///< construction and solves
  std::int64_t positions() const { return succeeded + failed; }
  bool all_succeeded() const { return failed == 0 && succeeded > 0; }
  RunStatus status() const { return all_succeeded() ? RunStatus::kSuccess : RunStatus::kFailed; }
  /// Counts a failed position; the first one's `what` becomes first_failure.
  void Fail(std::string what) {
    ++failed;
    if (first_failure.empty()) first_failure = std::move(what);
  }
};

/// Mean, smallest and largest of a figure over the positions where it is finite.
struct Spread {
  double mean = kNaN;
  double min = kNaN;
  double max = kNaN;
  std::int64_t count = 0;          ///< values added
  std::int64_t in_mean_count = 0;  ///< of those, the ones the mean weighs
  /// in_mean false: the value repeats a state already added (the last crank of a closed period);
  /// it counts in min and max, not in the mean.
  void Add(double v, bool in_mean = true);
};

}  // namespace ltca::analysis
