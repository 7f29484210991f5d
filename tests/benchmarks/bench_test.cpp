// The benchmark harness (benchmarks/): its chart and its memory measurement. The harness itself is
// smoke-run by ctest (ltca-bench --smoke); no timing is asserted anywhere.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <doctest/doctest.h>

#include "bench_command.hpp"
#include "harness.hpp"
#include "helpers.hpp"

namespace {

namespace fs = std::filesystem;

using ltca::test::CheckSvg;

}  // namespace

TEST_CASE("bench: the chart has a panel per case and every method in each, one colour and marker per method") {
  ltca::bench::BenchReport report;
  report.header = {"2026-11-23", "abc1234", "Release", "gcc", "test"};
  for (const char* c : {"case_a", "case_b"}) {
    for (const char* solver : {"bisection", "compatibility", "energy-qp"}) {
      ltca::bench::BenchRow row;
      row.case_name = c;
      row.setting.solver = solver;
      row.seconds_per_position_median = solver[0] == 'b' ? 1e-4 : 1e-3;
      row.errors.mean_te_arcsec = solver[0] == 'e' ? 1e-3 : 0.0;  // 0 is drawn at the floor, 1e-12
      report.rows.push_back(row);
    }
  }
  const fs::path svg = fs::temp_directory_path() / "ltca_plots_test_bench.svg";
  ltca::bench::WriteBenchSvg(report, svg);
  CHECK(CheckSvg(svg, 2, 3) == 0);
  fs::remove(svg);
}

TEST_CASE("bench: the peak memory of a run is that process's, not the largest child's so far, issue 26 item 10") {
  // A first child that touches 200 MB, then a tiny one: getrusage(RUSAGE_CHILDREN) reports the
  // 200 MB for both, and a child exec'd straight from this (40 MB) test process would carry its size.
  const double big = ltca::bench::PeakRssMb(LTCA_PEAK_RSS_EXE, {"/usr/bin/python3", "-c", "b = bytearray(200 * 2**20)"});
  CHECK(big > 200.0);
  CHECK(big < 260.0);
  const double small = ltca::bench::PeakRssMb(LTCA_PEAK_RSS_EXE, {"/bin/true"});
  CHECK(small > 0.0);
  CHECK(small < 5.0);
  CHECK(ltca::bench::PeakRssMb(LTCA_PEAK_RSS_EXE, {"/bin/false"}) == -1.0);
}

TEST_CASE("bench: an output that is the --baseline binary (a link or a hard link to it included) is refused before any work") {
  // Issue 46 item 1: every file a run reads is protected from its outputs, --baseline included.
  const fs::path dir = fs::temp_directory_path() / "ltca_bench_baseline_test";
  fs::remove_all(dir);
  fs::create_directories(dir / "docs");
  const fs::path binary = dir / "old-ltca-bench";
  {
    std::ofstream f(binary);
    f << "#!/bin/sh\n";
  }
  const auto refused = [&](const ltca::bench::BenchOptions& options) {
    std::ostringstream out;
    CHECK_THROWS_AS(ltca::bench::RunBenchCommand(options, out), std::invalid_argument);
    CHECK(out.str().empty());  // nothing ran
  };
  ltca::bench::BenchOptions options;
  options.smoke = true;
  options.out_dir = dir.string();
  fs::rename(binary, dir / "bench.csv");  // the baseline where the CSV goes
  options.baseline = (dir / "bench.csv").string();
  refused(options);
  fs::create_hard_link(dir / "bench.csv", dir / "docs" / "performance.md");  // a hard link the docs would replace
  options.baseline = (dir / "docs" / "performance.md").string();
  options.out_dir = (dir / "elsewhere").string();
  options.docs_dir = (dir / "docs" / "..").string() + "/docs";
  refused(options);
  fs::create_symlink(dir / "bench.csv", dir / "link");  // through a symbolic link
  options.baseline = (dir / "link").string();
  options.out_dir = dir.string();
  options.docs_dir.clear();
  refused(options);
  CHECK(ltca::test::ReadText(dir / "bench.csv") == "#!/bin/sh\n");
  fs::remove_all(dir);
}
