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
#include "ltca/analysis/backlash.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/units.hpp"
#include "output.hpp"
#include "solve_command.hpp"

namespace ltca::cli {
namespace documents = app::documents;
namespace {

using units::RadToArcsec;
using units::RadToDeg;

nlohmann::json Finite(double v) { return FiniteOrNull(v); }

namespace plots = app::plots;

/// The clearance of every pin around the ring (log scale: it runs from microns in the mesh to
/// millimetres away from it) and its moment arm, at one crank angle.
void WriteMeshFigure(const app::Deck& deck, double crank_deg, const contact::MeshState& state, int pin_count, Output& output) {
  std::vector<double> pin, clearance(static_cast<std::size_t>(pin_count), INFINITY), arm(static_cast<std::size_t>(pin_count), NAN);
  for (const auto& c : state.pins) {  // the slice model: per pin, the slice of least clearance
    const auto j = static_cast<std::size_t>(c.pin);
    if (c.disc != 0 || j >= clearance.size()) continue;
    if (units::MmToUm(c.clearance) < clearance[j]) clearance[j] = units::MmToUm(c.clearance), arm[j] = c.arm;
  }
  // A log axis when the clearances span more than two decades (microns in the mesh, millimetres
  // away from it); a contact (below floor_um) is then drawn at floor_um.
  const double floor_um = 1e-3;
  double least = INFINITY, most = -INFINITY;
  int least_pin = 0;
  for (int j = 0; j < pin_count; ++j) {
    pin.push_back(j + 1);
    const double c = clearance[static_cast<std::size_t>(j)];
    if (c < least) least = c, least_pin = j + 1;
    if (std::isfinite(c)) most = std::max(most, c);
  }
  const bool log = most > 100.0 * std::max(least, floor_um);
  if (log) {
    for (double& c : clearance) c = std::max(c, floor_um);
  }
  plots::Figure figure;
  figure.title = fmt::format("{}: mesh state at crank {:g} deg (unloaded)", deck.info.title, crank_deg);
  figure.caption = FigureCaption(deck, fmt::format("model {}; pins numbered from +x_f counter-clockwise{}{}",
                                                   deck.Model().name,
                                                   log ? fmt::format("; clearance on a log scale, below {:g} um (contact) drawn at {:g} um",
                                                                     floor_um, floor_um)
                                                       : "",
                                                   deck.disc_count() == 2 ? "; [second_disc]: the first disc's mesh" : ""));
  figure.columns = 2;
  figure.width = 1300;
  figure.height = 520;
  plots::Panel c;
  c.title = fmt::format("least clearance {:.4g} um at pin {}", least, least_pin);
  c.x_label = "pin number";
  c.y_label = "clearance (um)";
  c.log_y = log;
  c.series.push_back({"clearance", pin, clearance, plots::Style::kLineMarkers});
  c.x_min = 0.0, c.x_max = pin_count + 1.0;
  figure.panels.push_back(std::move(c));
  plots::Panel a;
  a.title = "moment arm of the contact normal about O_c";
  a.x_label = "pin number";
  a.y_label = "arm L_i (mm)";
  plots::Series arms{"arm", pin, arm, plots::Style::kBars};
  arms.colour = 2;
  a.series.push_back(std::move(arms));
  a.x_min = 0.0, a.x_max = pin_count + 1.0;
  figure.panels.push_back(std::move(a));
  WriteFigure(figure, output);
}

}  // namespace

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
  std::ostream& out = streams.text;
  const contact::MeshModel model = deck.MakeModel();
  const double crank = units::DegToRad(options.crank_deg);
  const contact::MeshState state = model.Evaluate(crank);
  // A table of an interfering pair would show negative clearances as if they were a mesh state.
  contact::RequireNoInterference(state, crank, model.interference_tolerance());
  fmt::print(out, "case      {}\n", deck.info.title);
  fmt::print(out, "mesh state at crank {:g} deg (unloaded pose)\n", options.crank_deg);
  if (deck.disc_count() == 2) fmt::print(out, "note      [second_disc]: the first disc's mesh only\n");
  // The slice model has a row per pin and slice (issue 11): the slice and its z are named.
  const bool sliced = model.slice_count() > 1;
  out << ModelLine(deck);
  fmt::print(out, "{:>4} {}{:>9} {:>12} {:>10} {:>12} {:>8} {:>11} {:>11} {:>5}\n", "pin",
             sliced ? fmt::format("{:>5} {:>7} ", "slice", "z_mm") : std::string(), "angle_deg", "c_um", "L_mm",
             "rho_c_mm", "rho_p_mm", "x_mm", "y_mm", "edge");
  for (const auto& c : state.pins) {
    fmt::print(out, "{:>4} {}{:>9.3f} {:>12.4f} {:>10.4f} {:>12.4f} {:>8.4f} {:>11.5f} {:>11.5f} {:>5}\n", c.pin + 1,
               sliced ? fmt::format("{:>5} {:>7.3f} ", c.slice + 1, c.z) : std::string(), RadToDeg(c.angle),
               units::MmToUm(c.clearance), c.arm,
               c.cycloid_curvature == 0.0 ? INFINITY : 1.0 / c.cycloid_curvature, c.pin_radius,
               c.cycloid_point.x(), c.cycloid_point.y(), c.edge ? "yes" : "");
  }
  if (json.enabled()) {
    {
      std::ostream& os = json.stream();
      nlohmann::json pins = nlohmann::json::array();
      for (const auto& c : state.pins) {
        nlohmann::json row = {{"pin", c.pin + 1},
                        {"pin_angle_deg", RadToDeg(c.angle)},
                        {"clearance_um", units::MmToUm(c.clearance)},
                        {"arm_mm", c.arm},
                        {"cycloid_curvature_radius_mm", Finite(c.cycloid_curvature == 0.0 ? INFINITY : 1.0 / c.cycloid_curvature)},
                        {"pin_radius_mm", c.pin_radius},
                        {"cycloid_point_mm", {c.cycloid_point.x(), c.cycloid_point.y()}},
                        {"pin_point_mm", {c.pin_point.x(), c.pin_point.y()}},
                        {"normal", {c.normal.x(), c.normal.y()}},
                        {"edge_contact", c.edge}};
        if (sliced) {
          row["slice"] = c.slice + 1;
          row["z_mm"] = c.z;
        }
        pins.push_back(std::move(row));
      }
      os << Dump(nlohmann::json{{"case", {{"title", deck.info.title}, {"source", deck.info.source}, {"deck", deck.name}}},
                                {"crank_deg", options.crank_deg},
                                {"model", ModelJson(deck.Model())},
                                {"pins", pins}})
         << '\n';
    }
    json.Commit();
  }
  if (svg.enabled()) WriteMeshFigure(deck, options.crank_deg, state, deck.pair.pin_count, svg);
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
