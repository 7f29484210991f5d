#include "report_command.hpp"

#include "command.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "contact_commands.hpp"
#include "efficiency_command.hpp"
#include "geometry_command.hpp"
#include "ltca/app/plots.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"
#include "solve_command.hpp"
#include "stiffness_command.hpp"
#include "tolerance_command.hpp"

namespace ltca::cli {
namespace {

namespace fs = std::filesystem;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw OutputError(fmt::format("report: cannot read back {}", path.string()));
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string Html(const std::string& text) { return app::plots::XmlEscape(text); }

/// A JSON value as table text: numbers to 6 significant digits, null as n/a.
std::string Cell(const nlohmann::json& v) {
  if (v.is_null()) return "n/a";
  if (v.is_number_float()) return fmt::format("{:.6g}", v.get<double>());
  if (v.is_string()) return Html(v.get<std::string>());
  return Html(v.dump());
}

/// A two-column table of the object's scalar members (nested objects: "key.member").
std::string Table(const nlohmann::json& object, const std::string& prefix = "") {
  std::string rows;
  for (const auto& [key, value] : object.items()) {
    if (value.is_object()) {
      rows += Table(value, prefix + key + ".");
    } else if (!value.is_array()) {
      rows += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", Html(prefix + key), Cell(value));
    }
  }
  return prefix.empty() ? "<table>\n" + rows + "</table>\n" : rows;
}

/// An SVG file inlined into the page: its XML prolog and DOCTYPE dropped, and its element ids
/// (PLplot's "text-clipping<n>") given the figure's prefix, since one page holds several figures
/// and an id must be unique in it (else a later figure's text is clipped by an earlier one's).
std::string InlineSvg(const fs::path& path) {
  std::string svg = ReadFile(path);
  const auto at = svg.find("<svg");
  if (at == std::string::npos) return {};
  svg.erase(0, at);
  const std::string prefix = path.stem().string() + "-";
  for (const std::string from : {"id=\"", "url(#"}) {
    for (auto pos = svg.find(from); pos != std::string::npos; pos = svg.find(from, pos + from.size() + prefix.size())) {
      svg.insert(pos + from.size(), prefix);
    }
  }
  return svg;
}

}  // namespace

int RunReport(const app::Deck& given, const ReportOptions& options, const Streams& streams) {
  // Every analysis of the page runs with --kinematics when given (the deck's otherwise).
  const app::Deck deck = DeckFor(given, options.kinematics);
  if (options.out_dir.empty()) throw std::invalid_argument("report: -o DIR: expected the folder to write index.html into");
  const fs::path dir(options.out_dir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw OutputError(fmt::format("-o {}: cannot create the folder{}", options.out_dir, ec ? ": " + ec.message() : ""));
  const auto file = [&dir](const char* name) { return (dir / name).string(); };
  // Every file the report may write, checked before anything is computed or written: a folder in
  // the way (or a file that cannot be opened) is an error now, not after half the files exist.
  for (const char* name : {"index.html", "geometry.json", "geometry.svg", "solve.json", "solve.svg", "backlash.json",
                           "backlash.svg", "mesh.json", "mesh.svg", "stiffness.json", "stiffness.svg", "efficiency.json",
                           "efficiency.svg", "tolerance.json", "tolerance.svg"}) {
    if (fs::is_directory(dir / name)) {
      throw OutputError(fmt::format("-o {}: {} is a folder; the report writes a file there", options.out_dir, file(name)));
    }
  }
  // The commands write their documents and figures into DIR; their text goes nowhere.
  std::ostringstream sink;
  const Streams quiet{sink, sink, streams.err, streams.progress};
  GeometryOptions geometry;
  geometry.json_path = file("geometry.json");
  geometry.svg_path = file("geometry.svg");
  geometry.crank_deg = 0.0;
  RunGeometry(deck, geometry, quiet);
  SolveOptions solve;
  solve.solver = options.solver;
  solve.json_path = file("solve.json");
  solve.svg_path = file("solve.svg");
  const int code = RunSolve(deck, solve, quiet);
  BacklashOptions backlash;
  backlash.json_path = file("backlash.json");
  backlash.svg_path = file("backlash.svg");
  const int backlash_code = RunBacklash(deck, backlash, quiet);
  MeshOptions mesh;
  mesh.json_path = file("mesh.json");
  mesh.svg_path = file("mesh.svg");
  RunMesh(deck, mesh, quiet);
  // The torque-twist loop at crank 0 (one position of the deck's [stiffness] steps); none at
  // zero torque, where there is no rated torque to run the loop to.
  StiffnessOptions stiffness;
  stiffness.solver = options.solver;
  stiffness.crank_deg = 0.0;
  stiffness.json_path = file("stiffness.json");
  stiffness.svg_path = file("stiffness.svg");
  const bool loop = deck.RequireLoad().torque != 0.0;
  const int loop_code = loop ? RunStiffness(deck, stiffness, quiet) : kExitSuccess;
  // Efficiency (issue 14) when the deck carries [friction] and [operation]; tolerances (issue 15)
  // when it carries [tolerances], with the deck's samples on every hardware thread. Both are one
  // disc's studies: a two-disc deck has neither here (the commands say why).
  const bool efficiency = deck.friction && deck.operation && !deck.second_disc && deck.RequireLoad().torque != 0.0;
  EfficiencyOptions eff;
  eff.solver = options.solver;
  eff.json_path = file("efficiency.json");
  eff.svg_path = file("efficiency.svg");
  const int eff_code = efficiency ? RunEfficiency(deck, eff, quiet) : kExitSuccess;
  const bool tolerance = deck.tolerances.has_value() && !deck.second_disc;
  ToleranceOptions tol;
  tol.solver = options.solver;
  tol.samples = options.samples;
  tol.threads = options.threads;
  tol.no_worst_case = options.no_worst_case;
  tol.json_path = file("tolerance.json");
  tol.svg_path = file("tolerance.svg");
  const int tol_code = tolerance ? RunTolerance(deck, tol, quiet) : kExitSuccess;

  const nlohmann::json g = nlohmann::json::parse(ReadFile(geometry.json_path));
  const nlohmann::json s = nlohmann::json::parse(ReadFile(solve.json_path));
  const nlohmann::json b = nlohmann::json::parse(ReadFile(backlash.json_path));
  const auto& p = deck.pair;
  std::string html = fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>ltca report: {0}</title>\n"
      "<style>body{{font-family:sans-serif;max-width:1500px;margin:1em auto;padding:0 1em;color:#111}}"
      "table{{border-collapse:collapse;margin:0.5em 0 1.5em}}th,td{{border:1px solid #ccc;padding:2px 8px;text-align:left;"
      "font-size:0.9em}}th{{background:#f3f3f3;font-weight:normal}}svg{{max-width:100%;height:auto;display:block;"
      "margin:0.5em 0 2em}}h2{{border-bottom:1px solid #ccc}}.grid{{display:flex;gap:2em;flex-wrap:wrap}}</style>\n"
      "</head>\n<body>\n<h1>{0}</h1>\n",
      Html(deck.info.title));
  html += "<h2>Case</h2>\n<table>\n";
  html += fmt::format("<tr><th>deck</th><td>{}</td></tr>\n<tr><th>source</th><td>{}</td></tr>\n", Html(deck.name), Html(deck.info.source));
  html += fmt::format("<tr><th>model</th><td>{}</td></tr>\n", Html(ModelLine(deck)));
  html += fmt::format("<tr><th>solver</th><td>{}</td></tr>\n", Html(SolverLine(deck, SolverFor(deck, options.solver))));
  html += fmt::format("<tr><th>load</th><td>T = {:g} N*m</td></tr>\n", units::NmmToNm(deck.RequireLoad().torque));
  html += fmt::format("<tr><th>sweep</th><td>{} positions, crank {:g} to {:g} deg</td></tr>\n", deck.sweep.positions,
                      units::RadToDeg(deck.sweep.crank_start), units::RadToDeg(deck.sweep.crank_end));
  html += fmt::format("<tr><th>program</th><td>ltca {}</td></tr>\n</table>\n", LTCA_VERSION);
  html += "<h2>Geometry</h2>\n<div class=\"grid\">\n<div>\n<table>\n";
  html += fmt::format(
      "<tr><th>z_p (pins)</th><td>{}</td></tr><tr><th>z_c (teeth)</th><td>{}</td></tr><tr><th>r_rp (mm)</th><td>{:g}</td></tr>"
      "<tr><th>R_p (mm)</th><td>{:g}</td></tr><tr><th>e (mm)</th><td>{:g}</td></tr><tr><th>B_c (mm)</th><td>{:g}</td></tr>\n</table>\n",
      p.pin_count, p.tooth_count, p.pin_radius, p.pin_circle_radius, p.eccentricity, p.face_width);
  nlohmann::json derived = g;
  derived.erase("case");
  html += Table(derived) + "</div>\n<div>" + InlineSvg(geometry.svg_path) + "</div>\n</div>\n";
  html += "<h2>Loaded tooth contact analysis</h2>\n";
  html += Table(s["summary"]);
  html += InlineSvg(solve.svg_path);
  html += "<h2>Unloaded: backlash and mesh</h2>\n";
  if (deck.reducer) {  // issue 25: the unloaded analysis is the pin ring's; the stage's free play is the loop's
    html += "<p>The pin ring's mesh alone (Liu eq. 17). The stage's free play, which also takes up the output "
            "mechanism's and the bearings' clearances, is the backlash of the torsional stiffness below.</p>\n";
  }
  html += Table(b["summary"]);
  html += InlineSvg(backlash.svg_path);
  html += InlineSvg(mesh.svg_path);
  if (loop) {
    const nlohmann::json l = nlohmann::json::parse(ReadFile(stiffness.json_path));
    html += "<h2>Torsional stiffness: the torque-twist loop at crank 0</h2>\n";
    nlohmann::json summary = l["summary"];
    summary.erase("curve");
    html += Table(summary);
    html += InlineSvg(stiffness.svg_path);
  }
  if (efficiency) {
    const nlohmann::json e = nlohmann::json::parse(ReadFile(eff.json_path));
    html += "<h2>Friction and meshing efficiency</h2>\n";
    html += Table(e["summary"]);
    html += InlineSvg(eff.svg_path);
  }
  if (tolerance) {
    const nlohmann::json t = nlohmann::json::parse(ReadFile(tol.json_path));
    const nlohmann::json& ts = t["summary"];
    html += "<h2>Tolerance analysis (Monte Carlo)</h2>\n";
    nlohmann::json shown = {{"samples", ts["samples"]}, {"seed", ts["seed"]}, {"succeeded", ts["succeeded"]},
                            {"failed", ts["failed"]}, {"rejected", ts["rejected"]}, {"pass_fraction", ts["pass_fraction"]},
                            {"figures", ts["figures"]}};
    html += Table(shown);
    if (options.no_worst_case) html += "<p>The extreme-value (worst-case) runs were skipped (--no-worst-case).</p>\n";
    html += InlineSvg(tol.svg_path);
  }
  html += fmt::format("<p>Built from geometry.json, solve.json, backlash.json, mesh.json{}{}{} in this folder. A static page: "
                      "nothing is fetched when it is viewed.</p>\n</body>\n</html>\n",
                      loop ? ", stiffness.json" : "", efficiency ? ", efficiency.json" : "", tolerance ? ", tolerance.json" : "");
  Output page("-o", file("index.html"), streams.out);
  page.stream() << html;
  page.Commit();
  // The page's status is every part's (issue 26: it said the solve's "success" and exited 1 when the
  // loop failed).
  std::string failed;
  int result = kExitSuccess;
  for (const auto& [part, c] : {std::pair{"solve", code}, std::pair{"backlash", backlash_code}, std::pair{"stiffness", loop_code},
                                std::pair{"efficiency", eff_code}, std::pair{"tolerance", tol_code}}) {
    if (c == kExitSuccess) continue;
    failed += fmt::format("{}{}", failed.empty() ? "" : ", ", part);
    if (result == kExitSuccess) result = c;
  }
  fmt::print(streams.text, "wrote {} (case {}, {})\n", file("index.html"), deck.info.title,
             failed.empty() ? "every part succeeded" : fmt::format("not every part succeeded: {}; see their sections", failed));
  return result;
}

Command ReportCommand() {
  auto st = std::make_shared<DeckState<ReportOptions>>();
  return {"report",
          "One static HTML page, DIR/index.html, that a browser opens from disk (nothing fetched): the case, the model and "
          "solver, the geometry table, the summaries of the loaded sweep and of the backlash, and the figures inlined as "
          "SVG; the JSON documents it is built from are left beside it.",
          [st](CLI::App& c) {
            ReportOptions& o = st->options;
            AddLoadInputs(c, st->deck, o.solver, o.kinematics);
            c.add_option("-o,--out", o.out_dir, "Folder of index.html (created when missing)")->required()->type_name("DIR");
            // The tolerance study's options, as `ltca tolerance` takes them (issue 27).
            AddSamplesOption(c, o.samples);
            c.add_option("--threads", o.threads, "Tolerance study: threads, 1 to 1024 (default 0: every hardware thread)");
            c.add_flag("--no-worst-case", o.no_worst_case, "Tolerance study: skip the extreme-value (worst-case) runs");
          },
          [] { return std::vector<std::string>{}; },
          [st](const Streams& streams) {
            if (!st->options.solver.empty()) solvers::MakeSolver(st->options.solver);  // the name checked first
            return RunReport(st->deck.Read(), st->options, streams);
          }};
}

}  // namespace ltca::cli
