#pragma once
// The table of commands: each command is {name, description, options, outputs, run};
// cli.cpp adds every entry to the command line and runs the one that was given. A new command is
// one factory in its *_command.cpp, declared and listed in command.cpp (Commands()).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "documents/analyses.hpp"
#include "ltca/app/deck.hpp"
#include "output.hpp"

namespace ltca::cli {

/// The deck a command reads: DECK (default: the built-in deck) with its --set overrides.
struct DeckInput {
  std::string path;
  std::vector<std::string> overrides;
  std::vector<std::string> removals;  ///< --unset section[.key], applied before the --set overrides
  app::Deck Read() const;
};

/// The state of a command that reads a deck: the deck and the command's options (bound by `options`).
template <class Options>
struct DeckState {
  DeckInput deck;
  Options options;
};

struct Command {
  std::string name;
  std::string description;
  /// Adds the command's arguments and options to its sub-command, bound to the entry's own state.
  std::function<void(CLI::App&)> options;
  /// The output paths its options name after parsing ('-': standard output, "" none).
  std::function<std::vector<std::string>()> outputs;
  /// Runs it; returns the exit code (kExitSuccess or kExitNotSucceeded), throws for bad input.
  std::function<int(const Streams&)> run;
};

/// Every command, in the order `ltca --help` lists them: the bespoke analyses', a command for
/// every generic analysis of the table (documents::Analyses()), then validate, report and keys.
std::vector<Command> Commands();
/// The command of a generic analysis of the table, built from its entry (cli/analysis_command.cpp).
Command AnalysisCommand(const app::documents::Analysis& analysis);

// --- the options several commands share ------------------------------------------------------------
inline constexpr const char* kSetHelp = "Override a deck key: section.key=value (repeatable)";
inline constexpr const char* kUnsetHelp =
    "Remove a deck section or key: section or section.key (repeatable; before every --set, so --unset S --set S.k=v replaces S)";
/// Every command that takes --kinematics follows one rule.
inline constexpr const char* kKinematicsHelp =
    "linearised or exact (default: the deck's [solver] kinematics, which is linearised when the deck does not set it)";
/// --set and DECK.
void AddDeckInputs(CLI::App& command, DeckInput& deck, const char* deck_help = "Case deck (TOML); default: the built-in deck");
/// --samples N of a tolerance study (`ltca tolerance`, `ltca report`): 1 to
/// analysis::ToleranceSettings::kMaxSamples, said in the option's own words when not.
void AddSamplesOption(CLI::App& command, std::optional<std::int64_t>& samples);

/// --set, DECK, --solver and --kinematics: the inputs of a command that solves loads.
void AddLoadInputs(CLI::App& command, DeckInput& deck, std::string& solver, std::string& kinematics);
/// An output option (--json, --csv, --svg, ...): a FILE, or '-' for standard output.
void AddOutput(CLI::App& command, const char* option, std::string& path, const char* help);
/// --crank-deg: a finite angle within +-analysis::kMaxCrankDeg (CLI11 names the option in its message).
const CLI::Validator& CrankAngle();
/// --seed and --first: a whole number 0 .. 2^63 - 1, as the deck's integers are.
const CLI::Validator& Index();

}  // namespace ltca::cli
