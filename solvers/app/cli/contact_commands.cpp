#include "contact_commands.hpp"

#include "command.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "ltca/analysis/backlash.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/units.hpp"
#include "output.hpp"
#include "solve_command.hpp"

namespace ltca::cli {
namespace {

using units::RadToArcsec;
using units::RadToDeg;

nlohmann::json Finite(double v) { return FiniteOrNull(v); }

namespace plots = app::plots;

/// Backlash over crank angle with its mean and peak-to-peak (left); the rotations to first contact
/// both ways (right).
void WriteBacklashFigure(const app::Deck& deck, const BacklashOptions& options, const std::vector<double>& crank_deg,
                         const std::vector<double>& c1, const std::vector<double>& c2, const std::vector<double>& backlash,
                         bool two_discs, Output& output) {
  plots::Figure figure;
  figure.title = fmt::format("{}: unloaded backlash over crank {:.4g} to {:.4g} deg", deck.info.title,
                             crank_deg.empty() ? 0.0 : crank_deg.front(), crank_deg.empty() ? 0.0 : crank_deg.back());
  figure.caption = FigureCaption(deck, fmt::format("unloaded TCA, {} kinematics, {} positions; backlash = theta_c1 - theta_c2 "
                                                   "(Liu eq. 17), the first contacts on the drive and coast flanks{}",
                                                   contact::ToString(*options.kinematics),
                                                   crank_deg.size(), two_discs ? "; two discs: the nearer of either disc's" : ""));
  figure.columns = 2;
  figure.width = 1400;
  figure.height = 520;
  plots::Panel b;
  b.title = "backlash";
  b.x_label = "crank angle (deg)";
  b.y_label = "backlash (arcsec)";
  b.series.push_back({"backlash", crank_deg, backlash, plots::Style::kLineMarkers});
  MarkMeanAndPeakToPeak(b, backlash, "arcsec");
  figure.panels.push_back(std::move(b));
  plots::Panel r;
  r.title = "rotation of the output to first contact";
  r.x_label = "crank angle (deg)";
  r.y_label = "rotation to first contact (arcsec)";
  r.legend = plots::LegendPlace::kOutsideRight;
  r.series.push_back({"theta_c1 (drive)", crank_deg, c1, plots::Style::kLineMarkers});
  r.series.push_back({"theta_c2 (coast)", crank_deg, c2, plots::Style::kLineMarkers});
  r.marks.push_back({plots::Mark::Axis::kHorizontal, 0.0, "", false});
  figure.panels.push_back(std::move(r));
  WriteFigure(figure, output);
}

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
  // One rule for every command (issue 26): --kinematics, else the deck's [solver] kinematics.
  BacklashOptions run = options;
  if (!run.kinematics) run.kinematics = deck.kinematics;
  const contact::ContactKinematics kinematics = *run.kinematics;
  std::vector<double> plot_crank, plot_c1, plot_c2, plot_backlash;  // for the figure (a double each per position)
  std::ostream& out = streams.text;
  // The stage checks every crank for interference before anything is computed or written.
  const analysis::Stage stage(deck, deck.sweep.CrankAngles());
  const contact::MeshModel& model = stage.model();
  const contact::MeshModel* second = stage.disc_count() == 2 ? &stage.model(1) : nullptr;  // [second_disc] (issue 13)
  const std::vector<double>& cranks = stage.cranks();
  // A sweep whose last state repeats its first (a closed period) weights it once in the mean.
  const bool closed = stage.closed_period();
  fmt::print(out, "case      {}\n", deck.info.title);
  out << ModelLine(deck);
  fmt::print(out, "unloaded TCA, {} kinematics, {} positions from {:g} to {:g} deg crank\n", contact::ToString(kinematics),
             cranks.size(), RadToDeg(deck.sweep.crank_start), RadToDeg(deck.sweep.crank_end));
  if (model.slice_count() > 1) {
    fmt::print(out, "first contact sought at both face edges and the {} slice centres\n", model.slice_count());
  }
  if (second) {
    fmt::print(out, "two discs: the stage's free play, on each flank the nearer first contact of either disc "
                    "(pin column: disc:pin)\n");
  }
  fmt::print(out, "{:>10} {:>14} {:>14} {:>14} {:>6}\n", "crank_deg", "theta_c1_as", "theta_c2_as",
             "backlash_as", "pin");
  // Streamed, one position at a time, so memory does not grow with the sweep (issue 10): the JSON
  // holds the positions, then the summary.
  if (json.enabled()) {
    json.stream() << "{\n\"case\": "
                  << Dump({{"title", deck.info.title}, {"source", deck.info.source}, {"deck", deck.name}}, -1)
                  << ",\n\"model\": " << Dump(ModelJson(deck.Model()), -1)
                  << ",\n\"kinematics\": " << Dump(contact::ToString(kinematics), -1) << ",\n\"positions\": [";
  }
  if (csv.enabled()) {
    csv.stream() << "crank_deg,theta_c1_arcsec,theta_c2_arcsec,backlash_arcsec,first_contact_disc,first_contact_pin,status\n";
  }
  const std::size_t step = std::max<std::size_t>(1, cranks.size() / 10);
  analysis::BacklashSummary tally;  // the rule of every backlash figure (analysis/backlash.hpp)
  for (std::size_t i = 0; i < cranks.size(); ++i) {
    const analysis::BacklashPosition at = analysis::UnloadedBacklashAt(stage, cranks[i], kinematics);
    tally.Add(at, closed && i + 1 == cranks.size());  // a repeated state weighs once
    const contact::UnloadedContact& r = at.contact;
    const bool ok = at.ok;
    const std::string& failure = at.failure;
    const int disc_c1 = at.disc_c1, disc_c2 = at.disc_c2;
    const std::vector<double>& second_clearance = at.second_clearance;
    const double c1 = ok ? r.theta_c1 : NAN, c2 = ok ? r.theta_c2 : NAN, b = ok ? r.backlash : NAN;
    const std::string pin_label = !ok ? "n/a" : second ? fmt::format("{}:{}", disc_c1, r.first_pin_c1 + 1)
                                                       : fmt::format("{}", r.first_pin_c1 + 1);
    if (svg.enabled()) {
      plot_crank.push_back(RadToDeg(r.crank)), plot_c1.push_back(RadToArcsec(c1));
      plot_c2.push_back(RadToArcsec(c2)), plot_backlash.push_back(RadToArcsec(b));
    }
    if (i % step == 0 || !ok) {
      fmt::print(out, "{:>10.4f} {:>14} {:>14} {:>14} {:>6}\n", RadToDeg(r.crank), FormatOrNa(RadToArcsec(c1), 4),
                 FormatOrNa(RadToArcsec(c2), 4), FormatOrNa(RadToArcsec(b), 4), pin_label);
    }
    if (json.enabled()) {
      nlohmann::json clearance = nlohmann::json::array(), after = nlohmann::json::array();
      for (const double c : r.clearance) clearance.push_back(Finite(units::MmToUm(c)));
      for (const double c : r.clearance_at_c1) after.push_back(ok ? Finite(units::MmToUm(c)) : nlohmann::json(nullptr));
      const auto pin_or_null = [&](int pin) { return ok ? nlohmann::json(pin + 1) : nlohmann::json(nullptr); };
      nlohmann::json position = {{"crank_deg", RadToDeg(r.crank)},
                                 {"status", ToString(ok ? analysis::RunStatus::kSuccess : analysis::RunStatus::kFailed)},
                                 {"theta_c1_arcsec", Finite(RadToArcsec(c1))},
                                 {"theta_c2_arcsec", Finite(RadToArcsec(c2))},
                                 {"backlash_arcsec", Finite(RadToArcsec(b))},
                                 {"first_contact_pin", pin_or_null(r.first_pin_c1)},
                                 {"first_contact_pin_reverse", pin_or_null(r.first_pin_c2)},
                                 {"clearance_um", clearance},
                                 {"clearance_at_first_contact_um", after}};
      if (!ok) position["message"] = failure;
      if (second) {
        position["first_contact_disc"] = ok ? nlohmann::json(disc_c1) : nlohmann::json(nullptr);
        position["first_contact_disc_reverse"] = ok ? nlohmann::json(disc_c2) : nlohmann::json(nullptr);
        nlohmann::json c2j = nlohmann::json::array();
        for (const double c : second_clearance) c2j.push_back(Finite(units::MmToUm(c)));
        position["second_disc_clearance_um"] = c2j;
        // Each disc's own first contact is not the stage's: no figure rather than a misleading one.
        position["clearance_at_first_contact_um"] = nullptr;
      }
      json.stream() << (i == 0 ? "\n" : ",\n") << Dump(position, -1);
    }
    if (csv.enabled()) {
      if (ok) {
        fmt::print(csv.stream(), "{:.9g},{:.9g},{:.9g},{:.9g},{},{},success\n", RadToDeg(r.crank), RadToArcsec(c1),
                   RadToArcsec(c2), RadToArcsec(b), disc_c1, r.first_pin_c1 + 1);
      } else {
        fmt::print(csv.stream(), "{:.9g},,,,,,failed\n", RadToDeg(r.crank));
      }
    }
  }
  // Over the successful positions.
  const double mean = tally.mean(), pp = tally.pp();
  const std::size_t succeeded = tally.succeeded(), failed = tally.failed();
  const std::string& first_failure = tally.first_failure();
  if (failed > 0) fmt::print(out, "failed                  {} of {} positions, first at {}\n", failed, cranks.size(), first_failure);
  fmt::print(out, "mean backlash           {} arcsec   (Liu eq. 17){}\n", FormatOrNa(RadToArcsec(mean), 4),
             closed ? "; the last position repeats the first: counted once" : "");
  if (deck.reducer) {  // issue 25
    fmt::print(out, "note                    the pin ring's mesh alone; the stage's free play (holes, bearings too) is the "
                    "backlash of ltca stiffness\n");
  }
  fmt::print(out, "peak-to-peak backlash   {} arcsec\n", FormatOrNa(RadToArcsec(pp), 4));
  if (json.enabled()) {
    nlohmann::json summary = {{"mean_backlash_arcsec", Finite(RadToArcsec(mean))},
                              {"pp_backlash_arcsec", Finite(RadToArcsec(pp))},
                              {"status", ToString(failed == 0 ? analysis::RunStatus::kSuccess : analysis::RunStatus::kFailed)},
                              {"positions", cranks.size()},
                              {"succeeded_positions", succeeded},
                              {"failed_positions", failed},
                              {"closed_period", closed}};
    if (deck.reducer) summary["scope"] = "the pin ring's mesh alone; the stage's free play is the backlash of ltca stiffness";
    if (failed > 0) summary["first_failure"] = first_failure;
    json.stream() << "\n],\n\"summary\": " << Dump(summary, -1) << "\n}\n";
    json.Commit();
  }
  if (csv.enabled()) csv.Commit();
  if (svg.enabled()) WriteBacklashFigure(deck, run, plot_crank, plot_c1, plot_c2, plot_backlash, second != nullptr, svg);
  return failed == 0 ? kExitSuccess : kExitNotSucceeded;
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
