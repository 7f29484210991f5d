#pragma once
#include <ostream>
#include <string>

namespace ltca::cli {

struct BenchOptions {
  bool smoke = false;       ///< the smallest matrix (ctest)
  std::string out_dir = "bench";  ///< bench.json, bench.csv
  std::string docs_dir;     ///< "" none; else writes performance.md and performance.svg there
  std::string ltca_path;    ///< the ltca executable, for the memory measurement ("" skips it)
  int repeats = 3;
  bool tolerance_only = false;  ///< only the tolerance bar (issue 15), e.g. to re-measure it on a quiet machine
};

/// `ltca bench` / `ltca-bench`: speed against error for every method, and the performance bars.
int RunBenchCommand(const BenchOptions& options, std::ostream& out);

}  // namespace ltca::cli
