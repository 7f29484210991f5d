#include "efficiency_command.hpp"

#include "command.hpp"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

#include "documents/efficiency.hpp"
#include "ltca/analysis/efficiency.hpp"
#include "solve_command.hpp"

namespace ltca::cli {

int RunEfficiency(const app::Deck& deck_given, const EfficiencyOptions& options, const Streams& streams) {
  namespace documents = app::documents;
  const app::Deck deck = DeckFor(deck_given, options.kinematics);  // --kinematics, else the deck's
  const solvers::SolverOptions solver = SolverFor(deck, options.solver);
  RequireDistinctOutputs({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path}});
  Output json("--json", options.json_path, streams.out);
  Output csv("--csv", options.csv_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  // Old order of the checks: [material], [friction], [operation], [load]; the stage checks interference.
  deck.RequireMaterial();
  const analysis::FrictionSettings& friction = deck.RequireFriction();
  const analysis::OperationSettings& operation = deck.RequireOperation();
  const double torque = deck.RequireLoad().torque;
  analysis::EfficiencyRunner runner(deck.MakeStage(), solver, torque, friction, operation);
  const std::vector<double>& cranks = runner.cranks();

  std::ostream& text = streams.text;
  text << documents::EfficiencyTextHead(deck, solver);
  // Two discs: every contact names its disc (a last CSV column, a JSON key).
  const bool two_discs = deck.second_disc.has_value();
  std::optional<documents::EfficiencyJsonWriter> writer;
  if (json.enabled()) writer.emplace(json.stream(), deck, solver, two_discs);
  if (csv.enabled()) csv.stream() << documents::EfficiencyCsvHead(two_discs, deck.reducer.has_value());
  Progress progress(streams.err, streams.progress, "efficiency at position", static_cast<std::int64_t>(cranks.size()));
  const std::size_t every = std::max<std::size_t>(1, cranks.size() / 10);
  std::vector<analysis::EfficiencyPosition> kept;  // for the figure
  for (std::size_t i = 0; i < cranks.size(); ++i) {
    analysis::EfficiencyPosition p = runner.Solve(cranks[i]);
    if (i % every == 0) text << documents::Text(p);
    if (writer) writer->Add(p);
    if (csv.enabled()) csv.stream() << documents::Csv(p, two_discs, deck.reducer.has_value());
    if (svg.enabled()) {
      p.contacts.clear();  // the figure needs the per-pin figures only
      kept.push_back(std::move(p));
    }
    progress.Update(static_cast<std::int64_t>(i + 1));
  }
  progress.Finish();
  const analysis::EfficiencySummary s = runner.Summary();
  // A load spectrum: each bin's efficiency over the sweep at its torque and speed.
  std::optional<analysis::EfficiencySpectrum> spectrum;
  if (!deck.load_spectrum.empty()) spectrum = app::EfficiencyDeckSpectrum(deck, solver);
  if (writer) {
    writer->Finish(s, spectrum ? &*spectrum : nullptr);
    json.Commit();
  }
  if (csv.enabled()) csv.Commit();
  if (svg.enabled()) WriteFigure(documents::Figure(deck, solver, kept, s), svg);
  text << documents::Text(s);
  if (spectrum) text << documents::Text(*spectrum);
  return s.all_succeeded() && (!spectrum || spectrum->all_succeeded()) ? kExitSuccess : kExitNotSucceeded;
}

Command EfficiencyCommand() {
  auto st = std::make_shared<DeckState<EfficiencyOptions>>();
  return {"efficiency",
          "Friction, power loss and meshing efficiency (docs/efficiency.md): at every position of the deck's sweep the "
          "loaded forces, the sliding and entrainment speed of every contact (crank at [operation] input_speed_rpm), the "
          "friction coefficient ([friction] model coulomb | jiang-mixed), the loss mu F |v_s| and the efficiency. Summary "
          "keys power_loss_w (mean over the sweep), efficiency (full model: sleeve, friction in the torque balance), "
          "efficiency_first_order (pins fixed, no sleeve, frictionless forces), efficiency_malhotra_parameswaran, "
          "efficiency_sensinger.",
          [st](CLI::App& c) {
            EfficiencyOptions& o = st->options;
            AddLoadInputs(c, st->deck, o.solver, o.kinematics);
            AddOutput(c, "--json", o.json_path, "Write the positions and the summary as JSON ('-': stdout)");
            AddOutput(c, "--csv", o.csv_path, "Write one row per position and loaded contact as CSV");
            AddOutput(c, "--svg", o.svg_path,
                      "Draw efficiency and power loss over crank angle and the friction coefficient per pin");
          },
          [st] { return std::vector<std::string>{st->options.json_path, st->options.csv_path, st->options.svg_path}; },
          [st](const Streams& streams) { return RunEfficiency(st->deck.Read(), st->options, streams); }};
}

}  // namespace ltca::cli
