#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ltca/analysis/tolerance_run.hpp"
#include "ltca/app/deck.hpp"
#include "output.hpp"
#include "sample_farm.hpp"

namespace ltca::cli {

/// The command line of `ltca tolerance` (docs/tolerance.md): each option given replaces
/// the deck's [tolerances] key.
struct ToleranceOptions {
  std::string solver;      ///< "" = the deck's [solver] name
  std::string kinematics;  ///< "" = the deck's
  std::string json_path, csv_path, svg_path;
  std::optional<std::int64_t> samples;  ///< [tolerances] samples
  std::optional<std::uint64_t> seed;    ///< [tolerances] seed
  std::int64_t first = 0;               ///< the first sample index (re-run sample i: --first i --samples 1)
  int threads = 0;                      ///< 0: every hardware thread
  bool lost_motion = false;             ///< also lost motion (as [tolerances] lost_motion = true)
  bool no_worst_case = false;           ///< skip the extreme-value counterpart
  /// The progress lines (samples, then worst-case runs) appear once a phase has run this long, s
  /// (when Streams::progress); a test sets 0.
  double progress_after_seconds = 2.0;
};

/// A tolerance study's account as `ltca tolerance` gives it: a progress line on `streams.err` for
/// each phase ("tolerance sample", then "tolerance worst-case run") when `shown`, once a phase has
/// run `after_seconds` (s), and the estimate from the first samples written to `text`.
class ToleranceProgressLines final : public analysis::ToleranceProgress {
 public:
  ToleranceProgressLines(const Streams& streams, bool shown, std::ostream& text, double after_seconds, int threads, bool several_ranks,
                         bool worst_case);
  void Start(analysis::TolerancePhase phase, std::int64_t total) override;
  void Update(analysis::TolerancePhase phase, std::int64_t done) override;
  void Finish(analysis::TolerancePhase phase) override;
  void Estimate(double seconds, std::int64_t done, std::int64_t count, double worst_case_seconds,
                std::int64_t worst_case_runs) override;

 private:
  const Streams& streams_;
  bool shown_;
  std::ostream& text_;
  double after_seconds_;
  int threads_;
  bool several_ranks_, worst_case_;
  std::optional<Progress> line_;
};

/// False on the ranks other than the first of an mpirun job (OpenMPI's or PMIx's rank in the
/// environment): the ranks that compute but do not write.
bool IsFirstRank();

/// Runs `body`, the part of a command after its farm is made. When it throws on a rank of a job of
/// several, the message is printed as `ltca` prints it, the run's temporaries are removed and
/// every rank ends with the exit code (SampleFarm::Abort); alone, the exception goes on.
int FailTogether(SampleFarm* farm, std::ostream& err, const std::function<int()>& body);
/// The MPI job this process is a rank of (started by mpirun), or nullptr: not started by mpirun (a
/// plain run is one process with threads). Under mpirun it loads the module ltca_mpi.so (MPI stays
/// out of every other run's start-up); a build without MPI throws std::runtime_error there.
std::unique_ptr<SampleFarm> MakeSampleFarm();

/// `ltca tolerance`: the Monte Carlo of [tolerances] over threads (and MPI ranks), its summary
/// (percentiles, limits, sensitivity), the extreme-value worst case, per-sample CSV, SVG
/// histograms. Returns kExitSuccess when every sample succeeded, kExitNotSucceeded otherwise.
int RunTolerance(const app::Deck& deck, const ToleranceOptions& options, const Streams& streams);

}  // namespace ltca::cli
