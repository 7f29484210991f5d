#include "cli.hpp"

#include <malloc.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <limits>
#include <stdexcept>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ostream.h>

#include "compare_command.hpp"
#include "report_command.hpp"
#include "contact_commands.hpp"
#include "geometry_command.hpp"
#include "output.hpp"
#include "solve_command.hpp"
#include "stiffness_command.hpp"
#include "tolerance_command.hpp"
#include "efficiency_command.hpp"
#include "validate_command.hpp"
#include "ltca/solvers/registry.hpp"
#include "ltca/app/deck.hpp"

namespace ltca::cli {
namespace {

#ifndef LTCA_VERSION
#define LTCA_VERSION "unknown"
#endif
#ifndef LTCA_BUILD_TYPE
#define LTCA_BUILD_TYPE "unknown"
#endif

app::Deck ReadDeck(const std::string& path, const std::vector<std::string>& overrides) {
  return path.empty() ? app::DefaultDeck(overrides) : app::LoadDeck(path, overrides);
}

constexpr const char* kSetHelp = "Override a deck key: section.key=value (repeatable)";

/// The compiler, from its own macros.
std::string Compiler() {
#if defined(__clang__)
  return "clang " __clang_version__;
#elif defined(__GNUC__)
  return "gcc " __VERSION__;
#else
  return "unknown compiler";
#endif
}

std::string VersionText() {
  return fmt::format("ltca {} ({} build, {}, C++ {})", LTCA_VERSION, LTCA_BUILD_TYPE, Compiler(), __cplusplus);
}

/// --seed and --first: a whole number 0 .. 2^63 - 1, as the deck's integers are (CLI11 would
/// wrap a negative seed into an unsigned one, or clamp one too large, without a word).
const CLI::Validator kIndex(
    [](std::string& text) -> std::string {
      std::int64_t value = 0;
      const char* end = text.data() + text.size();
      const auto [ptr, ec] = std::from_chars(text.data(), end, value);
      if (text.empty() || ptr != end || ec != std::errc() || value < 0) {
        return fmt::format("'{}': expected a whole number from 0 to {}", text, std::numeric_limits<std::int64_t>::max());
      }
      return {};
    },
    "INT >= 0");

constexpr double kMaxCrankDeg = 3600.0;

/// --crank-deg: a finite angle within +-3600 deg (CLI11 names the option in its message).
const CLI::Validator kCrankAngle(
    [](std::string& text) -> std::string {
      double value = 0.0;
      std::size_t used = 0;
      try {
        value = std::stod(text, &used);
      } catch (const std::exception&) {
        return fmt::format("'{}' is not a number of degrees", text);
      }
      if (used != text.size()) return fmt::format("'{}' is not a number of degrees", text);
      if (!std::isfinite(value) || std::abs(value) > kMaxCrankDeg) {
        return fmt::format("{}: expected a finite crank angle within +-{:g} deg", text, kMaxCrankDeg);
      }
      return {};
    },
    "DEG, finite, |DEG| <= 3600");

/// Every command that takes --kinematics follows one rule (issue 26).
constexpr const char* kKinematicsHelp =
    "linearised or exact (default: the deck's [solver] kinematics, which is linearised when the deck does not set it)";

/// The inputs of a command that solves loads: --set, the deck, --solver and --kinematics.
void AddLoadInputs(CLI::App* command, std::vector<std::string>& overrides, std::string& deck_path, std::string& solver,
                   std::string& kinematics) {
  command->add_option("--set", overrides, kSetHelp)->allow_extra_args(false)->type_name("SECTION.KEY=VALUE");
  command->add_option("deck", deck_path, "Case deck (TOML); default: the built-in deck");
  command->add_option("--solver", solver, "Solver name (default: the deck's [solver] name)");
  command->add_option("--kinematics", kinematics, kKinematicsHelp)
      ->check(CLI::IsMember({"exact", "linearised"}));
}

constexpr const char* kFooter =
    "Exit codes:\n"
    "  0  every position of every solver succeeded\n"
    "  1  the run finished but something did not succeed (the outputs are complete, with every\n"
    "     position's status; figures no valid solve produced are null in JSON, n/a in text)\n"
    "  2  bad input or options (the message names the key or the option)\n"
    "  3  an output could not be opened or written (checked before computing; no partial file is left)\n"
    "  4  internal error (a bug: please report it)\n"
    "With an output '-' (standard output), stdout carries only that document and the text goes to stderr.";

}  // namespace

int Run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "ltca: loaded tooth contact analysis of cycloid-pin gear pairs.\n"
      "Without a command, runs `ltca geometry` and `ltca solve` on the built-in default deck (Liu 2021 Table 1).\n"
      "`ltca DECK` runs the same job on DECK.\n"
      "Decks are TOML files whose keys carry their unit; see docs/decks.md and cases/."};
  app.name("ltca");
  app.footer(kFooter);
  app.set_version_flag("--version", VersionText(), "Print the version and the compiler, and exit");

  std::string deck_path;
  std::vector<std::string> overrides;  // --set section.key=value
  GeometryOptions geometry_options;
  CLI::App* geometry = app.add_subcommand(
      "geometry",
      "Derived geometry of the pair: K1, phi_max (Chen eq. 16), contact ratio (eq. 27), "
      "theta_max (eq. 20), alpha_max (Liu eq. 2), minimum radius of curvature, undercut margin, "
      "mesh period; optionally the profile as CSV and a drawing as SVG.");
  geometry->add_option("--set", overrides, kSetHelp)->allow_extra_args(false)->type_name("SECTION.KEY=VALUE");
  geometry->add_option("deck", deck_path, "Case deck (TOML); default: the built-in Liu 2021 Table 1 deck");
  geometry->add_option("--json", geometry_options.json_path,
                       "Write the summary as JSON to FILE ('-' for standard output); keys k1, "
                       "phi_max_deg, contact_ratio, theta_max_deg, alpha_max_deg, "
                       "min_curvature_radius_mm, undercut_margin_mm, mesh_period_deg, "
                       "transmission_ratio")
      ->type_name("FILE|-");
  geometry->add_option("--csv", geometry_options.csv_path,
                       "Write the whole profile to FILE: tooth_space, u_deg, x_mm, y_mm, normal_x, "
                       "normal_y, curvature_radius_mm (body frame)")
      ->type_name("FILE|-");
  geometry->add_option("--svg", geometry_options.svg_path,
                       "Draw the cycloid and the pins at the crank angle --crank-deg to FILE")
      ->type_name("FILE|-");
  geometry->add_option("--crank-deg", geometry_options.crank_deg,
                       "Crank angle of the drawing in degrees (default 0)")
      ->check(kCrankAngle);

  BacklashOptions backlash_options;
  std::string kinematics;
  CLI::App* backlash = app.add_subcommand(
      "backlash",
      "Unloaded tooth contact analysis over the deck's sweep: rotation to first contact both "
      "ways (theta_c1 in the load direction, theta_c2 against it), backlash = theta_c1 - "
      "theta_c2 (Liu eq. 17), first-contact pin; summary keys mean_backlash_arcsec, "
      "pp_backlash_arcsec. Interference is an error naming the pins.");
  backlash->add_option("--set", overrides, kSetHelp)->allow_extra_args(false)->type_name("SECTION.KEY=VALUE");
  backlash->add_option("deck", deck_path, "Case deck (TOML); default: the built-in deck");
  backlash->add_option("--json", backlash_options.json_path, "Write summary and positions as JSON ('-': stdout)")
      ->type_name("FILE|-");
  backlash->add_option("--csv", backlash_options.csv_path, "Write one row per position as CSV")
      ->type_name("FILE|-");
  backlash->add_option("--svg", backlash_options.svg_path,
                       "Draw backlash and the rotations to first contact over crank angle (SVG; .png/.pdf by extension)")
      ->type_name("FILE|-");
  backlash->add_option("--kinematics", kinematics, kKinematicsHelp)->check(CLI::IsMember({"exact", "linearised"}));

  MeshOptions mesh_options;
  CLI::App* mesh = app.add_subcommand(
      "mesh",
      "Mesh state at one crank angle: per pin its angle from the line of centres, clearance c_i "
      "(um), moment arm L_i (mm), radii of curvature, contact point, edge contact.");
  mesh->add_option("--set", overrides, kSetHelp)->allow_extra_args(false)->type_name("SECTION.KEY=VALUE");
  mesh->add_option("deck", deck_path, "Case deck (TOML); default: the built-in deck");
  mesh->add_option("--crank-deg", mesh_options.crank_deg, "Crank angle in degrees (default 0)")->check(kCrankAngle);
  mesh->add_option("--json", mesh_options.json_path, "Write the table as JSON ('-': stdout)")->type_name("FILE|-");
  mesh->add_option("--svg", mesh_options.svg_path, "Draw the clearance and arm of every pin (SVG; .png/.pdf by extension)")
      ->type_name("FILE|-");

  SolveOptions solve_options;
  CLI::App* solve = app.add_subcommand(
      "solve",
      "Loaded tooth contact analysis over the deck's sweep with one solver: loaded TE (Liu eq. 16), "
      "pins in contact, pin forces, contact stresses. JSON, streamed: positions [{crank_deg, te_arcsec, "
      "contacts, pin_force_n, pin_angle_deg, contact_stress_mpa, status, flank, message}], then summary "
      "{mean_te_arcsec, pp_te_arcsec, contacts_min, contacts_max, max_pin_force_n, max_contact_stress_mpa, "
      "wall_seconds, status, positions, succeeded_positions, failed_positions}. A failed position's figures "
      "are null; the summary's are over the successful positions only (null when none succeeded).");
  AddLoadInputs(solve, overrides, deck_path, solve_options.solver, solve_options.kinematics);
  solve->add_option("--json", solve_options.json_path, "Write summary and positions as JSON ('-': stdout)")->type_name("FILE|-");
  solve->add_option("--csv", solve_options.csv_path, "Write one row per position as CSV")->type_name("FILE|-");
  solve->add_option("--svg", solve_options.svg_path, "Draw the TE over the sweep and the load distribution")->type_name("FILE|-");
  solve->add_option("--pattern-csv", solve_options.pattern_csv_path,
                    "Write the contact pattern as CSV: one row per position, pin and slice (force, stress, z)")
      ->type_name("FILE|-");

  StiffnessOptions stiffness_options;
  CLI::App* stiffness = app.add_subcommand(
      "stiffness",
      "Torsional stiffness, lost motion and backlash (docs/stiffness.md): with the crank locked, the "
      "output torque runs from -T to +T and back (T = |[load] torque_nm|, the rated torque) and the twist of the "
      "output (the cycloid about its centre, in the sense of +T from the theoretical position, -TE) is read at each "
      "level, at one crank (--crank-deg) or at every position of the deck's sweep (mean, min, max). Summary keys "
      "torsional_rigidity_nm_per_arcmin, lost_motion_arcmin, backlash_arcmin (for a sweep also _min, _max), "
      "curve [{torque_nm, twist_arcmin, branch}], hysteresis. Options replace the deck's [stiffness] keys.");
  AddLoadInputs(stiffness, overrides, deck_path, stiffness_options.solver, stiffness_options.kinematics);
  stiffness->add_option("--crank-deg", stiffness_options.crank_deg,
                        "One crank angle in degrees ([stiffness] crank_deg; default: the deck's sweep)")
      ->check(kCrankAngle);
  stiffness->add_option("--steps", stiffness_options.steps,
                        "Torque levels per branch from -T to +T, odd ([stiffness] steps_per_branch, default 41)");
  stiffness->add_option("--rigidity", stiffness_options.rigidity,
                        "secant (between 50 % and 100 % of T on each flank, default) or tangent ([stiffness] rigidity)")
      ->check(CLI::IsMember({"secant", "tangent"}));
  stiffness->add_option("--tangent-torque-nm", stiffness_options.tangent_torque_nm,
                        "Torque of the tangent rigidity in N*m, signed ([stiffness] tangent_torque_nm)");
  stiffness->add_option("--lost-motion-fraction", stiffness_options.lost_motion_fraction,
                        "Lost motion at +-this fraction of T ([stiffness] lost_motion_fraction, default 0.03)");
  stiffness->add_option("--json", stiffness_options.json_path, "Write the positions and the summary as JSON ('-': stdout)")
      ->type_name("FILE|-");
  stiffness->add_option("--csv", stiffness_options.csv_path,
                        "Write the curve as CSV: crank_deg, branch, torque_nm, twist_arcmin, status")
      ->type_name("FILE|-");
  stiffness->add_option("--svg", stiffness_options.svg_path, "Draw the loop with the read-off values")->type_name("FILE|-");

  // --- issue 15: ltca tolerance ----------------------------------------------------------------
  ToleranceOptions tolerance_options;
  CLI::App* tolerance = app.add_subcommand(
      "tolerance",
      "Tolerance analysis (docs/tolerance.md): a seeded Monte Carlo over the deck's [tolerances]; every "
      "sample builds its pair and runs the unloaded and the loaded TCA over the sweep (and lost motion when asked). "
      "Percentiles 1/5/50/95/99 of every figure, the fraction within [tolerances] limits, a sensitivity ranking "
      "(standardised regression coefficients), the extreme-value worst case. Sample i depends on (seed, i) only: "
      "any number of threads or MPI ranks (mpirun -np K ltca tolerance ...) gives the same samples.");
  AddLoadInputs(tolerance, overrides, deck_path, tolerance_options.solver, tolerance_options.kinematics);
  tolerance
      ->add_option_function<std::string>(
          "--samples",
          [&tolerance_options](const std::string& text) {
            // Said in the option's own words (CLI11's range check printed "Value 0 not in range 0.000000 to 1.797e308").
            std::int64_t value = 0;
            const char* end = text.data() + text.size();
            const auto [ptr, ec] = std::from_chars(text.data(), end, value);
            if (text.empty() || ptr != end || ec != std::errc() || value < 1 || value > app::ToleranceSettings::kMaxSamples) {
              throw CLI::ValidationError(fmt::format("--samples {}: expected a whole number from 1 to {}", text,
                                                     app::ToleranceSettings::kMaxSamples));
            }
            tolerance_options.samples = value;
          },
          "Number of samples ([tolerances] samples)")
      ->type_name("INT 1..10000000");
  tolerance->add_option("--seed", tolerance_options.seed, "Seed of the counter-based stream ([tolerances] seed)")->check(kIndex);
  tolerance->add_option("--threads", tolerance_options.threads, "Threads, 1 to 1024 (default 0: every hardware thread)");
  tolerance->add_option("--first", tolerance_options.first,
                        "Index of the first sample (re-run sample i of a study: --first i --samples 1)")
      ->check(kIndex);
  tolerance->add_flag("--lost-motion", tolerance_options.lost_motion, "Also lost motion per sample ([tolerances] lost_motion = true)");
  tolerance->add_flag("--no-worst-case", tolerance_options.no_worst_case, "Skip the extreme-value (worst-case) runs");
  tolerance->add_option("--json", tolerance_options.json_path,
                        "Write the summary as JSON ('-': stdout): summary {samples, seed, figures {NAME: {mean, std, p1, p5, p50, "
                        "p95, p99}}, limits, pass_fraction, sensitivity, worst_case}")
      ->type_name("FILE|-");
  tolerance->add_option("--csv", tolerance_options.csv_path, "Write every sample's inputs and figures as CSV")->type_name("FILE|-");
  tolerance->add_option("--svg", tolerance_options.svg_path, "Draw histograms of the figures")->type_name("FILE|-");
  // --- end of ltca tolerance ---------------------------------------------------------------------
  // issue 14: ltca efficiency
  EfficiencyOptions efficiency_options;
  CLI::App* efficiency = app.add_subcommand(
      "efficiency",
      "Friction, power loss and meshing efficiency (docs/efficiency.md): at every position of the deck's "
      "sweep the loaded forces, the sliding and entrainment speed of every contact (crank at [operation] "
      "input_speed_rpm), the friction coefficient ([friction] model coulomb | jiang-mixed), the loss mu F |v_s| and "
      "the efficiency. Summary keys power_loss_w (mean over the sweep), efficiency (full model: sleeve, friction in "
      "the torque balance), efficiency_first_order (pins fixed, no sleeve, frictionless forces), "
      "efficiency_malhotra_parameswaran, efficiency_sensinger.");
  AddLoadInputs(efficiency, overrides, deck_path, efficiency_options.solver, efficiency_options.kinematics);
  efficiency->add_option("--json", efficiency_options.json_path, "Write the positions and the summary as JSON ('-': stdout)")
      ->type_name("FILE|-");
  efficiency->add_option("--csv", efficiency_options.csv_path, "Write one row per position and loaded contact as CSV")
      ->type_name("FILE|-");
  efficiency->add_option("--svg", efficiency_options.svg_path,
                         "Draw efficiency and power loss over crank angle and the friction coefficient per pin")
      ->type_name("FILE|-");

  CompareOptions compare_options;
  CLI::App* compare = app.add_subcommand(
      "compare",
      "Run several solvers (default: all) on the same sweep and print them side by side with the "
      "largest differences from the first in TE, pin force and contact count, and their times.");
  compare->add_option("--set", overrides, kSetHelp)->allow_extra_args(false)->type_name("SECTION.KEY=VALUE");
  compare->add_option("deck", deck_path, "Case deck (TOML); default: the built-in deck");
  compare->add_option("--solvers", compare_options.solvers, "Comma-separated solver names (default: all)")
      ->delimiter(',');
  compare->add_option("--kinematics", compare_options.kinematics, "linearised or exact (default: the deck's)")
      ->check(CLI::IsMember({"exact", "linearised"}));
  compare->add_option("--json", compare_options.json_path, "Write the comparison as JSON ('-': stdout)")
      ->type_name("FILE|-");
  compare->add_option("--svg", compare_options.svg_path,
                      "Draw every solver's TE over crank angle and its difference from the first (SVG; .png/.pdf by extension)")
      ->type_name("FILE|-");

  ValidateOptions validate_options;
  CLI::App* validate = app.add_subcommand(
      "validate",
      "Recompute every checkable number of the four papers from the decks in cases/ and give each a "
      "verdict (reproduced / under a stated convention / not reproducible, and why). --write-doc "
      "regenerates the tables of docs/validation.md.");
  validate->add_option("--cases", validate_options.cases_dir, "The cases/ folder (default: the source tree's)");
  validate->add_option("--markdown", validate_options.markdown_path, "Write the tables as Markdown ('-': stdout)")
      ->type_name("FILE|-");
  validate->add_option("--write-doc", validate_options.doc_path,
                       "Replace the generated block of this document (docs/validation.md)");

  ReportOptions report_options;
  CLI::App* report = app.add_subcommand(
      "report",
      "One static HTML page, DIR/index.html, that a browser opens from disk (nothing fetched): the case, the model "
      "and solver, the geometry table, the summaries of the loaded sweep and of the backlash, and the figures inlined "
      "as SVG; the JSON documents it is built from are left beside it.");
  report->add_option("--set", overrides, kSetHelp)->allow_extra_args(false)->type_name("SECTION.KEY=VALUE");
  report->add_option("deck", deck_path, "Case deck (TOML); default: the built-in deck");
  report->add_option("-o,--out", report_options.out_dir, "Folder of index.html (created when missing)")->required()->type_name("DIR");
  report->add_option("--solver", report_options.solver, "Solver name (default: the deck's [solver] name)");

  // No command: the default job (geometry and solve) on the built-in deck or on DECK.
  SolveOptions default_options;
  app.add_option("deck", deck_path, "Case deck (TOML) for the default job; default: the built-in deck");
  app.add_option("--json", default_options.json_path,
                 "Default job: write {geometry: ..., solve: ...} as JSON ('-': stdout)")
      ->type_name("FILE|-");
  app.add_option("--csv", default_options.csv_path, "Default job: the solve's rows as CSV")->type_name("FILE|-");
  app.add_option("--svg", default_options.svg_path, "Default job: the solve's drawing")->type_name("FILE|-");
  app.add_option("--set", overrides, kSetHelp)->allow_extra_args(false)->type_name("SECTION.KEY=VALUE");

  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::ExtrasError&) {
    // CLI11 lists the extras of a reversed argument list back to front ("0 --crank-deg"); name them
    // in the order given, and the command whose --help lists what it takes (issue 26).
    std::string command = "ltca";
    for (const CLI::App* sub : app.get_subcommands()) command += " " + sub->get_name();
    std::vector<std::string> extras;
    for (const CLI::App* level : [&] {
           std::vector<const CLI::App*> v{&app};
           for (const CLI::App* sub : app.get_subcommands()) v.push_back(sub);
           return v;
         }()) {
      for (const std::string& x : level->remaining()) extras.push_back(x);
    }
    std::string joined;
    for (const std::string& x : extras) joined += (joined.empty() ? "" : " ") + x;
    fmt::print(err, "ltca: error: {}: '{}' {} not an option or argument of this command; `{} --help` lists what it takes\n",
               command, joined, extras.size() == 1 ? "is" : "are", command);
    return kExitBadInput;
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e, out, err);
    return code == 0 ? kExitSuccess : kExitBadInput;  // --help, --version: 0; any parse error: 2
  }

  // Standard output carries one document: with any output '-', the human text goes to err.
  bool to_stdout = false;
  for (const std::string* path :
       {&geometry_options.json_path, &geometry_options.csv_path, &geometry_options.svg_path, &backlash_options.json_path,
        &backlash_options.csv_path, &backlash_options.svg_path, &mesh_options.json_path, &mesh_options.svg_path, &solve_options.json_path, &solve_options.csv_path,
        &solve_options.svg_path, &solve_options.pattern_csv_path, &compare_options.json_path, &compare_options.svg_path, &validate_options.markdown_path,
        &default_options.json_path, &default_options.csv_path, &default_options.svg_path, &stiffness_options.json_path,
        &stiffness_options.csv_path, &stiffness_options.svg_path, &tolerance_options.json_path, &tolerance_options.csv_path,
        &tolerance_options.svg_path, &efficiency_options.json_path,
        &efficiency_options.csv_path, &efficiency_options.svg_path}) {
    to_stdout = to_stdout || *path == "-";
  }
  // The progress line only where a person watches: the process's own stderr, a terminal.
  const bool progress = &err == &std::cerr && isatty(fileno(stderr)) == 1;
  const Streams streams{out, to_stdout ? err : out, err, progress};

  int code = kExitSuccess;
  try {
    if (validate->parsed()) {
      code = RunValidate(validate_options, streams);
    } else if (report->parsed()) {
      if (!report_options.solver.empty()) solvers::MakeSolver(report_options.solver);  // the name checked first
      code = RunReport(ReadDeck(deck_path, overrides), report_options, streams);
    } else if (compare->parsed()) {
      for (const auto& name : compare_options.solvers) solvers::MakeSolver(name);  // names checked first
      code = RunCompare(ReadDeck(deck_path, overrides), compare_options, streams);
    } else if (tolerance->parsed()) {
      code = RunTolerance(ReadDeck(deck_path, overrides), tolerance_options, streams);
    } else if (efficiency->parsed()) {
      code = RunEfficiency(ReadDeck(deck_path, overrides), efficiency_options, streams);
    } else if (stiffness->parsed()) {
      code = RunStiffness(ReadDeck(deck_path, overrides), stiffness_options, streams);
    } else if (solve->parsed()) {
      code = RunSolve(ReadDeck(deck_path, overrides), solve_options, streams);
    } else if (backlash->parsed()) {
      if (!kinematics.empty()) backlash_options.kinematics = ParseKinematics(kinematics);
      code = RunBacklash(ReadDeck(deck_path, overrides), backlash_options, streams);
    } else if (mesh->parsed()) {
      RunMesh(ReadDeck(deck_path, overrides), mesh_options, streams);
    } else if (geometry->parsed()) {
      RunGeometry(ReadDeck(deck_path, overrides), geometry_options, streams);
    } else {
      if (!deck_path.empty() && !std::filesystem::exists(deck_path)) {
        throw std::invalid_argument(fmt::format(
            "'{}' is neither a command (geometry, backlash, mesh, solve, stiffness, tolerance, efficiency, compare, report, validate) nor a deck file",
            deck_path));
      }
      const app::Deck deck = ReadDeck(deck_path, overrides);
      RequireDistinctOutputs({{"--json", default_options.json_path}, {"--csv", default_options.csv_path},
                        {"--svg", default_options.svg_path}});
      RunGeometry(deck, GeometryOptions{}, streams);
      streams.text << '\n';
      JsonEnvelope envelope;
      envelope.before = "{\n\"geometry\": " + Dump(GeometryJson(deck), -1) + ",\n\"solve\": ";
      envelope.after = "\n}";
      code = RunSolve(deck, default_options, streams, envelope);
    }
    out.flush();
    if (!out) throw OutputError("writing standard output failed");
  } catch (const std::invalid_argument& e) {
    fmt::print(err, "ltca: error: {}\n", e.what());
    return kExitBadInput;
  } catch (const OutputError& e) {
    fmt::print(err, "ltca: output error: {}\n", e.what());
    return kExitOutputError;
  } catch (const std::exception& e) {
    fmt::print(err, "ltca: internal error: {}\n", e.what());
    return kExitInternalError;
  }
  return code;
}

void ConfigureProcess() {
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 128 << 20);
#endif
}

}  // namespace ltca::cli
