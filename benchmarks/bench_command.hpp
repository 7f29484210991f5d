#pragma once
#include <ostream>
#include <string>
#include <vector>

namespace ltca::bench {

struct BenchOptions {
  bool smoke = false;       ///< the smallest matrix (ctest)
  std::string out_dir = "bench";  ///< bench.json, bench.csv
  std::string docs_dir;     ///< "" none; else writes performance.md and performance.svg there
  std::string ltca_path;    ///< the ltca executable, for the memory measurement ("" skips it)
  int repeats = 3;
  bool tolerance_only = false;  ///< only the tolerance bar (issue 15), e.g. to re-measure it on a quiet machine
  bool optimise_only = false;   ///< only the optimisation bars (issue 28)
  std::string profile;          ///< "case/setting": run that row `loops` times, for perf (issue 29)
  int loops = 200;
  std::string baseline;         ///< an older ltca-bench: issue 29's rows side by side with it (--docs)
};

/// Peak resident memory of one run of a program (args[0] a path, the rest its arguments), MB, as
/// measured by the ltca-peak-rss program at peak_rss_exe (a small process that forks it and reads
/// its rusage); -1 when it could not run or did not exit 0. Its standard output is discarded.
double PeakRssMb(const std::string& peak_rss_exe, const std::vector<std::string>& args);

/// `ltca-bench`: speed against error for every method, and the performance bars.
int RunBenchCommand(const BenchOptions& options, std::ostream& out);

}  // namespace ltca::bench
