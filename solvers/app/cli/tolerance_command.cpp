// `ltca tolerance` (docs/tolerance.md): options -> run plan -> analysis::RunToleranceStudy ->
// documents (documents/tolerance.hpp); the ranks of an MPI job failing together, and the progress lines.
#include "tolerance_command.hpp"

#include "command.hpp"

#include <cstdlib>
#include <functional>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "documents/tolerance.hpp"
#include "ltca/analysis/tolerance.hpp"
#include "ltca/analysis/tolerance_run.hpp"
#include "ltca/app/modules.hpp"
#include "solve_command.hpp"

namespace ltca::cli {

ToleranceProgressLines::ToleranceProgressLines(const Streams& streams, bool shown, std::ostream& text, double after_seconds, int threads,
                                               bool several_ranks, bool worst_case)
    : streams_(streams), shown_(shown), text_(text), after_seconds_(after_seconds), threads_(threads), several_ranks_(several_ranks),
      worst_case_(worst_case) {}

void ToleranceProgressLines::Start(analysis::TolerancePhase phase, std::int64_t total) {
  line_.emplace(streams_.err, shown_, phase == analysis::TolerancePhase::kSamples ? "tolerance sample" : "tolerance worst-case run", total,
                after_seconds_);
}

void ToleranceProgressLines::Update(analysis::TolerancePhase, std::int64_t done) { line_->Update(done); }

void ToleranceProgressLines::Finish(analysis::TolerancePhase) {
  line_->Finish();
  line_.reset();
}

void ToleranceProgressLines::Estimate(double seconds, std::int64_t done, std::int64_t count, double worst_case_seconds,
                                      std::int64_t worst_case_runs) {
  text_ << app::documents::ToleranceEstimateText(seconds, done, count, threads_, several_ranks_, worst_case_seconds,
                                                 worst_case_runs);
  text_.flush();
}

bool IsFirstRank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"}) {
    if (const char* rank = std::getenv(name)) return std::string(rank) == "0";
  }
  return true;
}

std::unique_ptr<SampleFarm> MakeSampleFarm() {
  if (std::getenv("OMPI_COMM_WORLD_SIZE") == nullptr && std::getenv("PMIX_RANK") == nullptr && std::getenv("PMI_RANK") == nullptr) {
    return nullptr;
  }
#ifdef LTCA_HAVE_MPI
  return std::unique_ptr<SampleFarm>(app::ModuleFunction<SampleFarm* (*)()>("mpi", "ltca_mpi_sample_farm")());
#else
  // Each rank would run the whole study alone and write the same outputs at once.
  throw std::runtime_error("started by mpirun, but this ltca was built without MPI (no ltca_mpi.so): run it without mpirun");
#endif
}

int FailTogether(SampleFarm* farm, std::ostream& err, const std::function<int()>& body) {
  try {
    return body();
  } catch (...) {
    if (farm == nullptr || farm->size() < 2) throw;
    const int code = ReportError(std::current_exception(), err);
    err.flush();
    {
      auto lock = app::LockTemporaries();  // every temporary: the staged outputs, a report's folder
      app::RemoveTemporariesLocked();
    }
    farm->Abort(code);  // ends the process
    throw;              // not reached
  }
}

int RunTolerance(const app::Deck& deck_given, const ToleranceOptions& options, const Streams& streams) {
  namespace documents = app::documents;
  const app::Deck deck = DeckFor(deck_given, options.kinematics);  // --kinematics, else the deck's
  const analysis::ToleranceSettings settings = documents::ToleranceSettingsFor(deck, options.samples, options.seed, options.lost_motion);
  if (options.first < 0) throw std::invalid_argument(fmt::format("--first {}: expected a sample index >= 0", options.first));
  const int threads = analysis::ResolveThreads(options.threads);
  const solvers::SolverOptions solver = SolverFor(deck, options.solver);
  const analysis::ToleranceStudy study(deck.MakeToleranceCase(), solver, settings);  // validates everything

  std::unique_ptr<SampleFarm> farm = MakeSampleFarm();
  return FailTogether(farm.get(), streams.err, [&]() -> int {
    const int ranks = farm ? farm->size() : 1;
    const bool root = !farm || farm->rank() == 0;
    RequireDistinctOutputs({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path}});
    // Outputs first (rank 0 only): an unwritable path is an error before anything is computed.
    Output json("--json", root ? options.json_path : "", streams.out);
    Output csv("--csv", root ? options.csv_path : "", streams.out);
    Output svg("--svg", root ? options.svg_path : "", streams.out);
    std::ostringstream quiet;
    std::ostream& text = root ? streams.text : quiet;

    analysis::ToleranceRunPlan plan;
    plan.first = options.first;
    plan.threads = threads;
    plan.ranks = farm.get();
    plan.worst_case = !options.no_worst_case;
    plan.Validate(settings);
    text << documents::ToleranceTextHead(deck, solver, study, options.first, threads, ranks);
    // The CSV is written as the samples come, in sample order: every sample's inputs and figures,
    // so that any one can be re-run (--first i --samples 1).
    if (csv.enabled()) {
      csv.stream() << documents::ToleranceCsvHead(study);
      plan.sink = [&](const analysis::ToleranceSample& s) { csv.stream() << documents::Csv(study, s); };
    }
    ToleranceProgressLines progress(streams, streams.progress && root, text, options.progress_after_seconds, threads, ranks > 1, plan.worst_case);
    plan.progress = &progress;
    const analysis::ToleranceResult result = analysis::RunToleranceStudy(study, plan);
    // A rank other than the first: its exit code is whether its own samples succeeded.
    if (!root) return result.all_succeeded() ? kExitSuccess : kExitNotSucceeded;
    if (csv.enabled()) csv.Commit();
    if (svg.enabled()) WriteFigure(documents::Figure(deck, study, result), svg);
    if (json.enabled()) {
      json.stream() << documents::Dump(documents::Json(deck, solver, study, result)) << '\n';
      json.Commit();
    }
    text << documents::Text(study, result);
    return result.all_succeeded() ? kExitSuccess : kExitNotSucceeded;
  });
}

Command ToleranceCommand() {
  auto st = std::make_shared<DeckState<ToleranceOptions>>();
  return {"tolerance",
          "Tolerance analysis (docs/tolerance.md): a seeded Monte Carlo over the deck's [tolerances]; every sample builds "
          "its pair and runs the unloaded and the loaded TCA over the sweep (and lost motion when asked). Percentiles "
          "1/5/50/95/99 of every figure, the fraction within [tolerances] limits, a sensitivity ranking (standardised "
          "regression coefficients), the extreme-value worst case. Sample i depends on (seed, i) only: any number of "
          "threads or MPI ranks (mpirun -np K ltca tolerance ...) gives the same samples.",
          [st](CLI::App& c) {
            ToleranceOptions& o = st->options;
            AddLoadInputs(c, st->deck, o.solver, o.kinematics);
            AddSamplesOption(c, o.samples);
            c.add_option("--seed", o.seed, "Seed of the counter-based stream ([tolerances] seed)")->check(Index());
            c.add_option("--threads", o.threads, "Threads, 1 to 1024 (default 0: every hardware thread)");
            c.add_option("--first", o.first, "Index of the first sample (re-run sample i of a study: --first i --samples 1)")
                ->check(Index());
            c.add_flag("--lost-motion", o.lost_motion, "Also lost motion per sample ([tolerances] lost_motion = true)");
            c.add_flag("--no-worst-case", o.no_worst_case, "Skip the extreme-value (worst-case) runs");
            AddOutput(c, "--json", o.json_path,
                      "Write the summary as JSON ('-': stdout): summary {samples, seed, figures {NAME: {mean, std, p1, p5, "
                      "p50, p95, p99}}, limits, pass_fraction, sensitivity, worst_case}");
            AddOutput(c, "--csv", o.csv_path, "Write every sample's inputs and figures as CSV");
            AddOutput(c, "--svg", o.svg_path, "Draw histograms of the figures");
          },
          [st] { return std::vector<std::string>{st->options.json_path, st->options.csv_path, st->options.svg_path}; },
          [st](const Streams& streams) { return RunTolerance(st->deck.Read(), st->options, streams); }};
}

}  // namespace ltca::cli
