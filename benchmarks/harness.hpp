#pragma once
// The benchmark harness (issue 6): speed against error for every method. Not a timed test: it
// writes figures (JSON, CSV, docs/performance.md, an SVG chart); ctest only smoke-runs it.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "ltca/app/deck.hpp"
#include "ltca/solvers/load_solver.hpp"

namespace ltca::bench {

using app::Deck;
using solvers::SolverOptions;

struct BenchSetting {
  std::string solver = "bisection";
  contact::ContactKinematics kinematics = contact::ContactKinematics::kLinearised;
  double torque_tolerance = 1e-10;
  std::string preset;  ///< "" or "liu2021"
  geometry::GeometrySettings geometry;  ///< analytic (default) or Liu's elements
  std::string only_case;                ///< "" all cases; else run on this case only (slow settings)
  std::string Label() const;
  std::string GeometryLabel() const;
  /// The deck and solver options of this setting on a case's deck (geometry, kinematics, preset,
  /// solver, tolerance).
  std::pair<Deck, SolverOptions> Apply(const Deck& deck) const;
};

struct BenchCase {
  std::string name;  ///< e.g. "liu2021_table1"
  Deck deck;
};

struct BenchMatrix {
  std::vector<BenchCase> cases;
  std::vector<BenchSetting> settings;
  int repeats = 3;
  int positions = 0;  ///< 0: the deck's sweep; otherwise this many positions over one mesh period
};

/// Errors of one run against the reference of the same physics (same deck: law, convention).
struct BenchErrors {
  double mean_te_arcsec = 0, pp_te_arcsec = 0, max_force_n = 0, max_stress_mpa = 0;
  int contacts = 0;  ///< largest difference in the contact count at any position
};

struct BenchRow {
  std::string case_name;
  BenchSetting setting;
  std::string status;
  int positions = 0;
  double seconds_per_position_median = 0, seconds_per_position_min = 0, seconds_per_position_max = 0;
  double evaluations_per_position = 0;  ///< torque evaluations (bisection, compatibility) or iterations
  BenchErrors errors;
  double residual = 0;  ///< the largest shared residual over the sweep
  double mean_te_arcsec = 0;
};

struct BenchHeader {
  std::string date, commit, build_type, compiler, machine;
};

struct BenchReference {
  std::string case_name;
  double mean_te_arcsec = 0;
  double agreement_arcsec = 0;  ///< |bisection - compatibility| of the reference, exact kinematics, 1e-12
};

struct BenchReport {
  BenchHeader header;
  std::vector<BenchReference> references;
  std::vector<BenchRow> rows;
  double peak_rss_mb = 0;  ///< of this process after the runs
};

/// The deck with its sweep over one mesh period at `positions` positions (0: the deck's own sweep).
Deck WithPositions(Deck deck, int positions);

/// Runs the matrix. The reference of each case is the analytic geometry with exact kinematics
/// solved to 1e-12 by bisection, confirmed by compatibility.
BenchReport RunBench(const BenchMatrix& matrix, const BenchHeader& header);

void WriteBenchJson(const BenchReport& report, const std::filesystem::path& path);
void WriteBenchCsv(const BenchReport& report, const std::filesystem::path& path);
/// Log-log chart of the mean-TE error against the time per position, one series per method.
void WriteBenchSvg(const BenchReport& report, const std::filesystem::path& path);

}  // namespace ltca::bench
