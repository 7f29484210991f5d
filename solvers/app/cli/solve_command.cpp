#include "solve_command.hpp"

#include "command.hpp"

#include <cstdint>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "documents/solve.hpp"

namespace ltca::cli {

int RunSolve(const app::Deck& deck_given, const SolveOptions& options, const Streams& streams, const JsonEnvelope& envelope) {
  const app::Deck deck = DeckFor(deck_given, options.kinematics);  // --kinematics, else the deck's
  const solvers::SolverOptions solver = SolverFor(deck, options.solver);
  RequireDistinctOutputs({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path},
                    {"--pattern-csv", options.pattern_csv_path}});
  // Outputs first: an unwritable path is an error before anything is computed.
  Output json("--json", options.json_path, streams.out);
  Output csv("--csv", options.csv_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  Output pattern("--pattern-csv", options.pattern_csv_path, streams.out);

  // Streamed, one position at a time, so memory does not grow with the sweep; the headers are
  // written once the sweep is accepted (no partial document on bad input).
  std::optional<documents::SolveJsonWriter> writer;
  if (json.enabled()) writer.emplace(json.stream(), deck, solver, envelope.before, envelope.after);
  documents::SolveSeries series(deck.sweep.positions);
  bool started = false;
  std::int64_t done = 0;
  Progress progress(streams.err, streams.progress, "solving position", deck.sweep.positions);
  const auto start = [&] {
    started = true;
    if (csv.enabled()) csv.stream() << documents::SolveCsvHead(deck);
    if (pattern.enabled()) pattern.stream() << documents::PatternCsvHead();
  };
  analysis::SweepCallbacks callbacks;
  callbacks.keep_positions = false;
  callbacks.on_position = [&](const analysis::PositionResult& p) {
    if (!started) start();
    if (writer) writer->Add(p);
    if (csv.enabled()) csv.stream() << documents::Csv(p);
    if (svg.enabled()) series.Add(p);
    if (pattern.enabled()) pattern.stream() << documents::PatternCsv(deck, p);
    progress.Update(++done);
  };
  const analysis::SweepResult sweep = app::SolveDeckSweep(deck, solver, callbacks);
  progress.Finish();
  if (!started) start();
  const analysis::SweepSummary& s = sweep.summary;
  // A load spectrum: each bin solved as the deck's sweep at its torque and speed (issue 50).
  std::optional<analysis::SpectrumResult> spectrum;
  if (!deck.load_spectrum.empty()) spectrum = app::SolveDeckSpectrum(deck, solver);
  if (writer) {
    writer->Finish(deck, s, spectrum ? &*spectrum : nullptr);
    json.Commit();
  }
  if (csv.enabled()) csv.Commit();
  if (pattern.enabled()) pattern.Commit();
  if (svg.enabled()) WriteFigure(documents::Figure(deck, solver, series, s), svg);
  streams.text << documents::Text(deck, solver, s);
  if (spectrum) streams.text << documents::SpectrumText(deck, *spectrum);
  const bool succeeded = s.all_succeeded() && (!spectrum || spectrum->all_succeeded());
  return succeeded ? kExitSuccess : kExitNotSucceeded;
}

Command SolveCommand() {
  auto st = std::make_shared<DeckState<SolveOptions>>();
  return {"solve",
          "Loaded tooth contact analysis over the deck's sweep with one solver: loaded TE (Liu eq. 16), pins in contact, "
          "pin forces, contact stresses. JSON, streamed: positions [{crank_deg, te_arcsec, contacts, pin_force_n, "
          "pin_angle_deg, contact_stress_mpa, status, flank, message}], then summary {mean_te_arcsec, pp_te_arcsec, "
          "contacts_min, contacts_max, max_pin_force_n, max_contact_stress_mpa, wall_seconds, status, positions, "
          "succeeded_positions, failed_positions}. A failed position's figures are null; the summary's are over the "
          "successful positions only (null when none succeeded).",
          [st](CLI::App& c) {
            AddLoadInputs(c, st->deck, st->options.solver, st->options.kinematics);
            AddOutput(c, "--json", st->options.json_path, "Write summary and positions as JSON ('-': stdout)");
            AddOutput(c, "--csv", st->options.csv_path, "Write one row per position as CSV");
            AddOutput(c, "--svg", st->options.svg_path, "Draw the TE over the sweep and the load distribution");
            AddOutput(c, "--pattern-csv", st->options.pattern_csv_path,
                      "Write the contact pattern as CSV: one row per position, pin and slice (force, stress, z)");
          },
          [st] {
            return std::vector<std::string>{st->options.json_path, st->options.csv_path, st->options.svg_path,
                                            st->options.pattern_csv_path};
          },
          [st](const Streams& streams) { return RunSolve(st->deck.Read(), st->options, streams); }};
}

}  // namespace ltca::cli
