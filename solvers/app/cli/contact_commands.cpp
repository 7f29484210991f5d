#include "contact_commands.hpp"

#include "command.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "documents/backlash.hpp"
#include "documents/mesh.hpp"
#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/mesh.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/units.hpp"
#include "output.hpp"
#include "solve_command.hpp"

namespace ltca::cli {
namespace documents = app::documents;
int RunBacklash(const app::Deck& deck, const BacklashOptions& options, const Streams& streams) {
  RequireDistinctOutputs({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path}});
  Output json("--json", options.json_path, streams.out);  // checked before computing
  Output csv("--csv", options.csv_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  // --kinematics, else the deck's [solver] kinematics (the rule of every command).
  const contact::ContactKinematics kinematics = options.kinematics.value_or(deck.kinematics);
  // The stage checks every crank for interference before anything is computed or written.
  const analysis::Stage stage(deck, deck.sweep.CrankAngles());
  const bool two_discs = stage.disc_count() == 2;
  std::ostream& out = streams.text;
  out << documents::BacklashTextHead(deck, stage, kinematics);
  // Streamed, one position at a time, so memory does not grow with the sweep: the JSON holds the
  // positions, then the summary; the text a row for every tenth position and every failed one.
  std::optional<documents::BacklashJsonWriter> writer;
  if (json.enabled()) writer.emplace(json.stream(), deck, kinematics, two_discs);
  if (csv.enabled()) csv.stream() << documents::BacklashCsvHead();
  const std::size_t step = std::max<std::size_t>(1, stage.cranks().size() / 10);
  std::size_t i = 0;
  documents::BacklashSeries series(stage.cranks().size());
  const analysis::BacklashResult result = analysis::Backlash(stage, kinematics, [&](const analysis::BacklashPosition& p) {
    if (svg.enabled()) series.Add(p);
    if (i % step == 0 || !p.ok) out << documents::Text(p, two_discs);
    if (writer) writer->Add(p);
    if (csv.enabled()) csv.stream() << documents::Csv(p);
    ++i;
  });
  out << documents::Text(deck, result);
  if (writer) {
    writer->Finish(deck, result);
    json.Commit();
  }
  if (csv.enabled()) csv.Commit();
  if (svg.enabled()) WriteFigure(documents::Figure(deck, series, result), svg);
  return result.summary.failed() == 0 ? kExitSuccess : kExitNotSucceeded;
}

void RunMesh(const app::Deck& deck, const MeshOptions& options, const Streams& streams) {
  RequireDistinctOutputs({{"--json", options.json_path}, {"--svg", options.svg_path}});
  Output json("--json", options.json_path, streams.out);  // checked before computing
  Output svg("--svg", options.svg_path, streams.out);
  const analysis::MeshResult mesh = analysis::MeshAt(deck.MakeModel(), options.crank_deg);
  streams.text << documents::Text(deck, mesh);
  if (json.enabled()) {
    json.stream() << Dump(documents::Json(deck, mesh)) << '\n';
    json.Commit();
  }
  if (svg.enabled()) WriteFigure(documents::Figure(deck, mesh), svg);
}

Command BacklashCommand() {
  struct State {
    DeckInput deck;
    BacklashOptions options;
    std::string kinematics;
  };
  auto st = std::make_shared<State>();
  return {"backlash",
          "Unloaded tooth contact analysis over the deck's sweep: rotation to first contact both ways (theta_c1 in the "
          "load direction, theta_c2 against it), backlash = theta_c1 - theta_c2 (Liu eq. 17), first-contact pin; summary "
          "keys mean_backlash_arcsec, pp_backlash_arcsec. Interference is an error naming the pins.",
          [st](CLI::App& c) {
            AddDeckInputs(c, st->deck);
            AddOutput(c, "--json", st->options.json_path, "Write summary and positions as JSON ('-': stdout)");
            AddOutput(c, "--csv", st->options.csv_path, "Write one row per position as CSV");
            AddOutput(c, "--svg", st->options.svg_path,
                      "Draw backlash and the rotations to first contact over crank angle (SVG; .png/.pdf by extension)");
            c.add_option("--kinematics", st->kinematics, kKinematicsHelp)->check(CLI::IsMember({"exact", "linearised"}));
          },
          [st] { return std::vector<std::string>{st->options.json_path, st->options.csv_path, st->options.svg_path}; },
          [st](const Streams& streams) {
            BacklashOptions options = st->options;
            if (!st->kinematics.empty()) options.kinematics = contact::ParseKinematics(st->kinematics);
            return RunBacklash(st->deck.Read(), options, streams);
          }};
}

Command MeshCommand() {
  auto st = std::make_shared<DeckState<MeshOptions>>();
  return {"mesh",
          "Mesh state at one crank angle: per pin its angle from the line of centres, clearance c_i (um), moment arm L_i "
          "(mm), radii of curvature, contact point, edge contact.",
          [st](CLI::App& c) {
            AddDeckInputs(c, st->deck);
            c.add_option("--crank-deg", st->options.crank_deg, "Crank angle in degrees (default 0)")->check(CrankAngle());
            AddOutput(c, "--json", st->options.json_path, "Write the table as JSON ('-': stdout)");
            AddOutput(c, "--svg", st->options.svg_path,
                      "Draw the clearance and arm of every pin (SVG; .png/.pdf by extension)");
          },
          [st] { return std::vector<std::string>{st->options.json_path, st->options.svg_path}; },
          [st](const Streams& streams) {
            RunMesh(st->deck.Read(), st->options, streams);
            return kExitSuccess;
          }};
}

}  // namespace ltca::cli
