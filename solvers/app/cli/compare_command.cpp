#include "compare_command.hpp"

#include "command.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

#include "documents/compare.hpp"
#include "ltca/analysis/compare.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"
#include "solve_command.hpp"

namespace ltca::cli {

int RunCompare(const app::Deck& deck_given, const CompareOptions& options, const Streams& streams) {
  namespace documents = app::documents;
  const app::Deck deck = DeckFor(deck_given, options.kinematics);  // --kinematics, else the deck's
  const std::vector<std::string> asked = options.solvers.empty() ? solvers::SolverNames() : options.solvers;
  RequireDistinctOutputs({{"--json", options.json_path}, {"--svg", options.svg_path}});
  Output json("--json", options.json_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  // Every solver checked (names, options) and the stage (interference) first; one stage for all.
  // A solver that does not solve the deck's model (a reducer stage) is skipped with its reason,
  // named in the text, the JSON and the figure; the exit code judges the solvers that ran.
  deck.RequireMaterial();
  const double torque = deck.RequireLoad().torque;
  const analysis::SolverSelection selection = analysis::SelectSolvers(asked, deck.reducer.has_value(), deck.name);
  const analysis::Stage stage = deck.MakeStage();
  Progress progress(streams.err, streams.progress, "comparing at position", static_cast<std::int64_t>(stage.cranks().size()));
  std::int64_t done = 0;
  // The figure's data: a TE per solver and position, arcsec (NaN where it failed).
  std::vector<double> plot_crank;
  std::vector<std::vector<double>> plot_te(selection.run.size());
  const analysis::CompareResult result = analysis::Compare(
      stage, deck.solver, selection.run, torque, selection.skipped,
      [&](double crank, const std::vector<analysis::PositionResult>& at) {
        if (svg.enabled()) {
          plot_crank.push_back(units::RadToDeg(crank));
          for (std::size_t r = 0; r < at.size(); ++r) plot_te[r].push_back(at[r].succeeded() ? units::RadToArcsec(at[r].result.te) : NAN);
        }
        progress.Update(++done);
      });
  progress.Finish();
  streams.text << documents::Text(deck, result);
  if (json.enabled()) {
    json.stream() << Dump(documents::Json(deck, result)) << '\n';
    json.Commit();
  }
  if (svg.enabled()) WriteFigure(documents::Figure(deck, result, plot_crank, plot_te), svg);
  return result.all_succeeded() ? kExitSuccess : kExitNotSucceeded;
}

Command CompareCommand() {
  auto st = std::make_shared<DeckState<CompareOptions>>();
  return {"compare",
          "Run several solvers (default: all) on the same sweep and print them side by side with the largest differences "
          "from the first in TE, pin force and contact count, and their times.",
          [st](CLI::App& c) {
            CompareOptions& o = st->options;
            AddDeckInputs(c, st->deck);
            c.add_option("--solvers", o.solvers, "Comma-separated solver names (default: all)")->delimiter(',');
            c.add_option("--kinematics", o.kinematics, "linearised or exact (default: the deck's)")
                ->check(CLI::IsMember({"exact", "linearised"}));
            AddOutput(c, "--json", o.json_path, "Write the comparison as JSON ('-': stdout)");
            AddOutput(c, "--svg", o.svg_path,
                      "Draw every solver's TE over crank angle and its difference from the first (SVG; .png/.pdf by extension)");
          },
          [st] { return std::vector<std::string>{st->options.json_path, st->options.svg_path}; },
          [st](const Streams& streams) {
            for (const auto& name : st->options.solvers) solvers::MakeSolver(name);  // names checked first
            return RunCompare(st->deck.Read(), st->options, streams);
          }};
}

}  // namespace ltca::cli
