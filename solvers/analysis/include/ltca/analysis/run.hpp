#pragma once
// What every analysis reports about its own run (issue 24): one run record, and the spread of a
// figure over the positions.
#include <cstdint>
#include <limits>
#include <string>

namespace ltca::analysis {

/// A figure no valid solve produced: NaN inside, null in the outputs (the output contract).
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Positions (or samples) that succeeded and failed, the first failure, and the wall time.
struct RunRecord {
  std::int64_t succeeded = 0;  ///< positions whose every solve succeeded
  std::int64_t failed = 0;     ///< positions with any other outcome
  std::string first_failure;   ///< where and why the first failure happened; empty when none
  double wall_seconds = 0.0;   ///< construction and solves
  std::int64_t positions() const { return succeeded + failed; }
  bool all_succeeded() const { return failed == 0 && succeeded > 0; }
};

/// Mean, smallest and largest of a figure over the positions where it is finite.
struct Spread {
  double mean = kNaN;
  double min = kNaN;
  double max = kNaN;
  std::int64_t count = 0;          ///< values added
  std::int64_t in_mean_count = 0;  ///< of those, the ones the mean weighs
  /// in_mean false: the value repeats a state already added (the last crank of a closed period,
  /// issue 26); it counts in min and max, not in the mean.
  void Add(double v, bool in_mean = true);
};

}  // namespace ltca::analysis
