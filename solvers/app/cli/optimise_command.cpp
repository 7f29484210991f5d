// `ltca optimise` (docs/optimise.md): the design that meets the deck's [optimise] constraints with
// the best objective, by NLopt's global search and local polish over a few keys of [modification]
// and [errors]; the history of evaluations, a convergence figure (with the objective's map over
// two variables), the best design written as a deck, a Pareto front. Options -> run plan ->
// analysis::RunOptimisation -> documents (documents/optimise.hpp).
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "optimise_command.hpp"

#include "command.hpp"
#include "documents/optimise.hpp"
#include "ltca/analysis/optimise.hpp"
#include "ltca/analysis/tolerance_run.hpp"
#include "output.hpp"
#include "solve_command.hpp"
#include "tolerance_command.hpp"
#include "ltca/app/deck.hpp"

namespace ltca::cli {

analysis::RankGroup RankGroupOf(SampleFarm* farm) {
  analysis::RankGroup ranks;
  if (farm != nullptr) {
    ranks.rank = farm->rank();
    ranks.size = farm->size();
    ranks.all_gather = [farm](const std::string& mine) { return farm->AllGather(mine); };
  }
  return ranks;
}

int RunOptimise(const app::Deck& deck_given, const OptimiseOptions& o, const Streams& streams) {
  namespace documents = app::documents;
  const app::Deck deck = DeckFor(deck_given, o.kinematics);
  const analysis::OptimiseSettings settings = documents::OptimiseSettingsFor(deck, o.evaluations);
  const int threads = analysis::ResolveThreads(o.threads);  // the rule of every command with threads
  if (o.map != 0 && (o.map < 2 || o.map > 201)) throw std::invalid_argument(fmt::format("--map {}: expected 2 to 201 points a variable", o.map));
  if (o.map != 0 && settings.variables.size() != 2) {
    throw std::invalid_argument(fmt::format("--map {}: the map is drawn over two variables; [optimise] has {}", o.map, settings.variables.size()));
  }
  // Under mpirun every rank runs the search in lockstep and shares what divides (a robust design's
  // samples, the map's points, the Pareto steps); rank 0 alone writes.
  std::unique_ptr<SampleFarm> farm = MakeSampleFarm();
  const analysis::RankGroup ranks = RankGroupOf(farm.get());
  return FailTogether(farm.get(), streams.err, [&]() -> int {
    const bool root = ranks.rank == 0;
    const solvers::SolverOptions solver = SolverFor(deck, o.solver);
    const analysis::Optimiser optimiser(deck.MakeToleranceCase(), solver, settings, threads, ranks);
    if (!o.pareto.empty() && !(std::isfinite(o.pareto_from) && std::isfinite(o.pareto_to))) {
      throw std::invalid_argument("--pareto FIGURE: expected --pareto-from and --pareto-to, the range of its bound");
    }
    RequireDistinctOutputs({{"--json", o.json_path}, {"--csv", o.csv_path}, {"--svg", o.svg_path}, {"--write-deck", o.deck_path}});
    Output json("--json", root ? o.json_path : "", streams.out);
    Output csv("--csv", root ? o.csv_path : "", streams.out);
    Output svg("--svg", root ? o.svg_path : "", streams.out);
    Output best_deck("--write-deck", root ? o.deck_path : "", streams.out);
    std::ostringstream quiet;
    std::ostream& text = root ? streams.text : quiet;
    const analysis::OptimiseSettings& s = optimiser.settings();
    text << documents::OptimiseTextHead(deck, solver, s, threads, ranks.size);

    // The history goes out as the evaluations are made: the search keeps none of them. The CSV's
    // rows into the output's own (staged) file; the JSON's items into a spool, copied after the
    // summary, which comes first in the document and is known only at the end; the figure's
    // series decimated (documents::OptimiseSeries).
    std::unique_ptr<Spool> history;
    if (json.enabled()) history = std::make_unique<Spool>("--json", o.json_path);
    if (csv.enabled()) csv.stream() << documents::OptimiseCsvHead(s);
    documents::OptimiseSeries series(s, o.map > 0);
    analysis::OptimiseRunPlan plan;
    plan.map = o.map;
    plan.pareto = o.pareto;
    plan.pareto_from = o.pareto_from;
    plan.pareto_to = o.pareto_to;
    plan.pareto_steps = o.pareto_steps;
    plan.sink = [&](const analysis::DesignEvaluation& e) {
      if (history) {
        history->stream() << documents::HistoryItem(s, e);
        history->Check();
      }
      if (csv.enabled()) {
        csv.stream() << documents::Csv(e);
        csv.Check();  // a full disk ends the search now, not at its end
      }
      if (svg.enabled()) series.Add(e);
    };
    const analysis::OptimiseRun run = analysis::RunOptimisation(optimiser, plan);
    text << documents::Text(s, run);
    if (json.enabled()) {
      documents::WriteOptimiseJson(json.stream(), documents::OptimiseJsonHead(deck, solver, s, run),
                                   [&](std::ostream& os) { history->CopyTo(os); }, s, run);
      history.reset();  // removed now, not with the run's end
      json.Commit();
    }
    if (csv.enabled()) {
      for (const auto& e : run.grid) csv.stream() << documents::Csv(e);
      csv.Commit();
    }
    if (svg.enabled()) WriteFigure(documents::Figure(deck, s, run, series), svg);
    // The search's documents are kept whatever becomes of the deck: a deck that cannot be written
    // (no design met the constraints, or the deck's text does not take the edit) is said, is not
    // written, and the run is one that did not wholly succeed (exit 1), not an input error that
    // would discard the search.
    bool deck_written = !best_deck.enabled();
    if (best_deck.enabled() && run.best() == nullptr) {
      fmt::print(streams.err, "ltca: --write-deck {}: no evaluation met the constraints, so there is no design to write\n", o.deck_path);
    } else if (best_deck.enabled()) {
      try {
        best_deck.stream() << documents::BestDesignDeck(deck, s, run);
        best_deck.Commit();
        deck_written = true;
      } catch (const std::invalid_argument& e) {
        fmt::print(streams.err, "ltca: --write-deck {}: not written: {}\n", o.deck_path, e.what());
      }
    }
    // Failed and rejected evaluations are designs the search ruled out (counted in the summary);
    // the run succeeds when it found a design that meets the constraints.
    return run.best() != nullptr && deck_written ? kExitSuccess : kExitNotSucceeded;
  });
}

Command OptimiseCommand() {
  auto st = std::make_shared<DeckState<OptimiseOptions>>();
  return {"optimise",
          "Design optimisation (docs/optimise.md): the values of the deck's [optimise] variables (keys of [modification] "
          "and [errors], or a reducer stage's clearances) that meet its constraints with the best objective, by NLopt's global search then a local "
          "polish; robust over the samples of [tolerances] when asked. Deterministic: the same result on any number of "
          "threads.",
          [st](CLI::App& c) {
            OptimiseOptions& o = st->options;
            AddLoadInputs(c, st->deck, o.solver, o.kinematics);
            c.add_option("--threads", o.threads, "Threads, 1 to 1024 (default 0: every hardware thread): a robust design's samples, the map's points, the Pareto steps");
            c.add_option("--evaluations", o.evaluations, "The budget ([optimise] evaluations)");
            c.add_option("--map", o.map, "With two variables: the objective on an N x N grid (drawn with --svg, listed in --json and --csv)");
            c.add_option("--pareto", o.pareto, "A second figure: the Pareto front of the objective against it (epsilon constraints)");
            c.add_option("--pareto-from", o.pareto_from, "The first bound on the --pareto figure");
            c.add_option("--pareto-to", o.pareto_to, "The last bound on the --pareto figure");
            c.add_option("--pareto-steps", o.pareto_steps, "Bounds from --pareto-from to --pareto-to (default 11)");
            AddOutput(c, "--json", o.json_path, "Write the settings, the best design, the phases, the history (and map, front) as JSON");
            AddOutput(c, "--csv", o.csv_path, "Write every evaluation as CSV (the map's after the search's)");
            AddOutput(c, "--svg", o.svg_path, "Draw the convergence (and the map, the front)");
            AddOutput(c, "--write-deck", o.deck_path, "Write the best design as a deck that ltca solve runs as it is");
          },
          [st] {
            return std::vector<std::string>{st->options.json_path, st->options.csv_path, st->options.svg_path, st->options.deck_path};
          },
          [st](const Streams& streams) { return RunOptimise(st->deck.Read(), st->options, streams); }};
}

}  // namespace ltca::cli
