#include "cli.hpp"

#include <malloc.h>
#include <unistd.h>

#include <algorithm>
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
#include <fmt/ranges.h>

#include "command.hpp"
#include "documents/geometry.hpp"
#include "geometry_command.hpp"
#include "output.hpp"
#include "solve_command.hpp"
#include "ltca/app/deck.hpp"

namespace ltca::cli {
namespace {

#ifndef LTCA_VERSION
#define LTCA_VERSION "unknown"
#endif
#ifndef LTCA_BUILD_TYPE
#define LTCA_BUILD_TYPE "unknown"
#endif

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

  // The table of commands: each adds its own options to its sub-command.
  const std::vector<Command> commands = Commands();
  std::vector<CLI::App*> subcommands;
  for (const Command& command : commands) {
    CLI::App* sub = app.add_subcommand(command.name, command.description);
    command.options(*sub);
    subcommands.push_back(sub);
  }

  // No command: the default job (geometry and solve) on the built-in deck or on DECK.
  DeckInput default_deck;
  SolveOptions default_options;
  app.add_option("deck", default_deck.path, "Case deck (TOML) for the default job; default: the built-in deck");
  app.add_option("--json", default_options.json_path,
                 "Default job: write {geometry: ..., solve: ...} as JSON ('-': stdout)")
      ->type_name("FILE|-");
  app.add_option("--csv", default_options.csv_path, "Default job: the solve's rows as CSV")->type_name("FILE|-");
  app.add_option("--svg", default_options.svg_path, "Default job: the solve's drawing")->type_name("FILE|-");
  app.add_option("--set", default_deck.overrides, kSetHelp)->allow_extra_args(false)->type_name("SECTION.KEY=VALUE");
  app.add_option("--unset", default_deck.removals, kUnsetHelp)->allow_extra_args(false)->type_name("SECTION[.KEY]");

  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::ExtrasError&) {
    // CLI11 lists the extras of a reversed argument list back to front ("0 --crank-deg"); name them
    // in the order given, and the command whose --help lists what it takes.
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
    fmt::print(err, "ltca: error: {}: '{}' {} of this command; `{} --help` lists what it takes\n", command, joined,
               extras.size() == 1 ? "is not an option or argument" : "are not options or arguments", command);
    return kExitBadInput;
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e, out, err);
    return code == 0 ? kExitSuccess : kExitBadInput;  // --help, --version: 0; any parse error: 2
  }

  // The command given (nullptr: the default job), and its outputs.
  const Command* given = nullptr;
  std::vector<std::string> outputs = {default_options.json_path, default_options.csv_path, default_options.svg_path};
  for (std::size_t i = 0; i < commands.size(); ++i) {
    if (subcommands[i]->parsed()) given = &commands[i], outputs = commands[i].outputs();
  }
  // Standard output carries one document: with any output '-', the human text goes to err.
  const bool to_stdout = std::find(outputs.begin(), outputs.end(), "-") != outputs.end();
  // The progress line only where a person watches: the process's own stderr, a terminal.
  const bool progress = &err == &std::cerr && isatty(fileno(stderr)) == 1;
  const Streams streams{out, to_stdout ? err : out, err, progress};

  int code = kExitSuccess;
  OutputTransaction files;  // every output of the run is put in place at its end, or none is
  try {
    if (given != nullptr) {
      code = given->run(streams);
    } else {
      if (!default_deck.path.empty() && !std::filesystem::exists(default_deck.path)) {
        std::vector<std::string> names;
        for (const Command& command : commands) names.push_back(command.name);
        throw std::invalid_argument(
            fmt::format("'{}' is neither a command ({}) nor a deck file", default_deck.path, fmt::join(names, ", ")));
      }
      const app::Deck deck = default_deck.Read();
      RequireDistinctOutputs({{"--json", default_options.json_path}, {"--csv", default_options.csv_path},
                        {"--svg", default_options.svg_path}});
      RunGeometry(deck, GeometryOptions{}, streams);
      streams.text << '\n';
      JsonEnvelope envelope;
      envelope.before = "{\n\"geometry\": " + Dump(app::documents::Json(deck, deck.MakeRealPair()), -1) + ",\n\"solve\": ";
      envelope.after = "\n}";
      code = RunSolve(deck, default_options, streams, envelope);
    }
    out.flush();
    if (!out) throw OutputError("writing standard output failed");
    files.CommitAll();
  } catch (...) {
    return ReportError(std::current_exception(), err);
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
