// ltca-bench: the benchmark harness (issue 6): every method on a matrix of cases and settings, time
// per position against error. Not a timed test: it writes figures (bench/, docs/performance.md).
#include <exception>
#include <iostream>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "bench_command.hpp"

int main(int argc, char** argv) {
  CLI::App app("ltca-bench: the benchmark harness: every method on a matrix of cases and settings, time per position "
               "against error, JSON/CSV rows; with --docs, docs/performance.md and the SVG chart with the bars.");
  ltca::bench::BenchOptions options;
  app.add_flag("--smoke", options.smoke, "The smallest matrix (what ctest runs)");
  app.add_option("--out", options.out_dir, "Folder for bench.json and bench.csv (default: bench)");
  app.add_option("--docs", options.docs_dir, "Write performance.md and performance.svg into this folder (docs)");
  app.add_option("--repeats", options.repeats, "Repeats per run (default 3)")->check(CLI::PositiveNumber);
  app.add_flag("--tolerance-only", options.tolerance_only,
               "Only the tolerance bar: 10,000 samples, 1 vs 2 threads, cost against samples; writes tolerance.csv "
               "(with --smoke: 20 samples)");
  app.add_flag("--optimise-only", options.optimise_only,
               "Only the optimisation bars: 2,000 evaluations over 3 variables, 500 robust designs x 64 samples; writes "
               "optimise.csv (with --smoke: 20 evaluations, 12 designs x 45 samples)");
  app.add_option("--profile", options.profile,
                 "Run one row of the matrix, 'case/setting' as the bench prints it (e.g. 'liu2021_table1/compatibility "
                 "linearised tol 1e-10'), --loops times and print its time per position split into the stage (mesh "
                 "states) and the solves: the workload to put under perf");
  app.add_option("--loops", options.loops, "Loops of the --profile row (default 200)")->check(CLI::PositiveNumber);
  app.add_option("--baseline", options.baseline,
                 "With --docs: an older ltca-bench (with --profile) whose issue-29 rows are timed beside this one's "
                 "(benchmarks/side_by_side.py --rows) and written to performance.md");
  CLI11_PARSE(app, argc, argv);
  try {
    return ltca::bench::RunBenchCommand(options, std::cout);
  } catch (const std::invalid_argument& e) {
    std::cerr << "ltca-bench: error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ltca-bench: internal error: " << e.what() << '\n';
    return 4;
  }
}
