#include "stiffness_command.hpp"

#include "command.hpp"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "documents/stiffness.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/geometry/units.hpp"
#include "solve_command.hpp"

namespace ltca::cli {

analysis::StiffnessSettings StiffnessSettingsFor(const app::Deck& deck, const StiffnessOptions& options) {
  analysis::StiffnessSettings s = deck.stiffness;
  if (options.crank_deg) s.crank = units::DegToRad(*options.crank_deg);
  if (options.steps) s.steps = *options.steps;
  if (!options.rigidity.empty()) {
    if (options.rigidity == "secant") s.rigidity = analysis::StiffnessSettings::Rigidity::kSecant;
    else if (options.rigidity == "tangent") s.rigidity = analysis::StiffnessSettings::Rigidity::kTangent;
    else throw std::invalid_argument(fmt::format("--rigidity {}: expected secant or tangent", options.rigidity));
  }
  if (options.tangent_torque_nm) s.tangent_torque = units::NmToNmm(*options.tangent_torque_nm);
  if (options.lost_motion_fraction) s.lost_motion_fraction = *options.lost_motion_fraction;
  s.Validate();
  return s;
}

int RunStiffness(const app::Deck& deck_given, const StiffnessOptions& options, const Streams& streams) {
  namespace documents = app::documents;
  const app::Deck deck = DeckFor(deck_given, options.kinematics);  // --kinematics, else the deck's
  const solvers::SolverOptions solver = SolverFor(deck, options.solver);
  const analysis::StiffnessSettings settings = StiffnessSettingsFor(deck, options);
  RequireDistinctOutputs({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path}});
  // Outputs first: an unwritable path is an error before anything is computed.
  Output json("--json", options.json_path, streams.out);
  Output csv("--csv", options.csv_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  deck.RequireMaterial();
  const double torque = deck.RequireLoad().torque;
  // The stage checks interference at the loop's cranks; the runner checks the options and the torque.
  analysis::StiffnessRunner runner(deck.MakeStage(settings.crank ? std::vector<double>{*settings.crank} : deck.sweep.CrankAngles()),
                                   solver, settings, torque, deck.friction);
  const std::size_t positions = runner.cranks().size();

  std::ostream& text = streams.text;
  text << documents::StiffnessTextHead(deck, solver, settings, runner.rated_torque(), positions);
  std::optional<documents::StiffnessJsonWriter> writer;
  if (json.enabled()) writer.emplace(json.stream(), deck, solver, settings, runner.rated_torque());
  if (csv.enabled()) csv.stream() << documents::StiffnessCsvHead();
  Progress progress(streams.err, streams.progress, "stiffness loop at position", static_cast<std::int64_t>(positions),
                    streams.progress_delay_seconds);
  const std::size_t every = std::max<std::size_t>(1, positions / 10);
  std::size_t i = 0;
  const analysis::StiffnessResult result = runner.Run([&](const analysis::StiffnessPosition& p) {
    if (i % every == 0) {
      progress.Clear();  // a row of the table never lands on the progress line
      text << documents::Text(p);
    }
    if (writer) writer->Add(p);
    if (csv.enabled()) csv.stream() << documents::Csv(p);
    progress.Update(static_cast<std::int64_t>(++i));
  });
  progress.Finish();
  if (writer) {
    writer->Finish(result);
    json.Commit();
  }
  if (csv.enabled()) csv.Commit();
  if (svg.enabled()) WriteFigure(documents::Figure(deck, solver, result), svg);
  text << documents::Text(result);
  return result.all_succeeded() ? kExitSuccess : kExitNotSucceeded;
}

Command StiffnessCommand() {
  auto st = std::make_shared<DeckState<StiffnessOptions>>();
  return {"stiffness",
          "Torsional stiffness, lost motion and backlash (docs/stiffness.md): with the crank locked, the output torque "
          "runs from -T to +T and back (T = |[load] torque_nm|, the rated torque) and the twist of the output (the "
          "cycloid about its centre, in the sense of +T from the theoretical position, -TE) is read at each level, at "
          "one crank (--crank-deg) or at every position of the deck's sweep (mean, min, max). Summary keys "
          "torsional_rigidity_nm_per_arcmin, lost_motion_arcmin, backlash_arcmin (for a sweep also _min, _max), curve "
          "[{torque_nm, twist_arcmin, branch}], hysteresis. Options replace the deck's [stiffness] keys.",
          [st](CLI::App& c) {
            StiffnessOptions& o = st->options;
            AddLoadInputs(c, st->deck, o.solver, o.kinematics);
            c.add_option("--crank-deg", o.crank_deg, "One crank angle in degrees ([stiffness] crank_deg; default: the deck's sweep)")
                ->check(CrankAngle());
            c.add_option("--steps", o.steps, "Torque levels per branch from -T to +T, odd ([stiffness] steps_per_branch, default 41)");
            c.add_option("--rigidity", o.rigidity,
                         "secant (between 50 % and 100 % of T on each flank, default) or tangent ([stiffness] rigidity)")
                ->check(CLI::IsMember({"secant", "tangent"}));
            c.add_option("--tangent-torque-nm", o.tangent_torque_nm,
                         "Torque of the tangent rigidity in N*m, signed ([stiffness] tangent_torque_nm)");
            c.add_option("--lost-motion-fraction", o.lost_motion_fraction,
                         "Lost motion at +-this fraction of T ([stiffness] lost_motion_fraction, default 0.03)");
            AddOutput(c, "--json", o.json_path, "Write the positions and the summary as JSON ('-': stdout)");
            AddOutput(c, "--csv", o.csv_path,
                      "Write the curve as CSV: crank_deg, branch, torque_nm, twist_arcmin, status");
            AddOutput(c, "--svg", o.svg_path, "Draw the loop with the read-off values");
          },
          [st] { return std::vector<std::string>{st->options.json_path, st->options.csv_path, st->options.svg_path}; },
          [st](const Streams& streams) { return RunStiffness(st->deck.Read(), st->options, streams); }};
}

}  // namespace ltca::cli
