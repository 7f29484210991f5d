#include "ltca/analysis/run.hpp"

#include <algorithm>
#include <cmath>

namespace ltca::analysis {

const char* ToString(RunStatus status) {
  switch (status) {
    case RunStatus::kSuccess: return "success";
    case RunStatus::kFailed: return "failed";
    case RunStatus::kRejected: return "rejected";
    case RunStatus::kCannotAssemble: return "cannot-assemble";
    case RunStatus::kNotRun: return "not run";
  }
  return "unknown";
}

void Spread::Add(double v, bool in_mean) {
  if (!std::isfinite(v)) return;
  if (count == 0) {
    min = max = v;
  } else {
    min = std::min(min, v);
    max = std::max(max, v);
  }
  if (in_mean) {
    mean = in_mean_count == 0 ? v : mean + (v - mean) / static_cast<double>(in_mean_count + 1);
    ++in_mean_count;
  } else if (in_mean_count == 0) {
    mean = v;  // only the repeated state so far: it is the mean
  }
  ++count;
}

}  // namespace ltca::analysis
