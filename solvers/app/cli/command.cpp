#include "command.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace ltca::cli {

app::Deck DeckInput::Read() const {
  // app::ParseDeck tells a removal by its leading '-': neither option may pass for the other.
  std::vector<std::string> all;
  for (const std::string& removal : removals) {
    if (removal.empty() || removal.front() == '-' || removal.find('=') != std::string::npos) {
      throw std::invalid_argument(fmt::format("--unset '{}': expected section or section.key, e.g. --unset friction; a value "
                                              "is set with --set section.key=value", removal));
    }
    all.push_back("-" + removal);
  }
  for (const std::string& set : overrides) {
    if (!set.empty() && set.front() == '-') {
      throw std::invalid_argument(fmt::format("--set '{}': expected section.key=value, e.g. --set load.torque_nm=100; a "
                                              "section or key is removed with --unset section[.key]", set));
    }
    all.push_back(set);
  }
  app::Deck deck = path.empty() ? app::DefaultDeck(all) : app::LoadDeck(path, all);
  // No output of this run may be the deck or a file it reads (a trace).
  if (OutputTransaction* run = OutputTransaction::Current()) {
    for (std::size_t i = 0; i < deck.source.files.size(); ++i) {
      run->ProtectInput(i == 0 && !path.empty() ? "the deck" : "a file the deck reads", deck.source.files[i]);
    }
  }
  return deck;
}

// The factories, one in each command's source.
Command GeometryCommand();
Command BacklashCommand();
Command MeshCommand();
Command SolveCommand();
Command StiffnessCommand();
Command ToleranceCommand();
Command OptimiseCommand();
Command EfficiencyCommand();
Command CompareCommand();
Command ValidateCommand();
Command ReportCommand();
Command KeysCommand();

std::vector<Command> Commands() {
  std::vector<Command> commands = {GeometryCommand(),  BacklashCommand(),  MeshCommand(),       SolveCommand(),
                                   StiffnessCommand(), ToleranceCommand(), OptimiseCommand(),   EfficiencyCommand(),
                                   CompareCommand()};
  // Every generic analysis of the table (documents/analyses.hpp), a command each, built from its entry.
  for (const app::documents::Analysis& analysis : app::documents::Analyses()) {
    if (analysis.generic()) commands.push_back(AnalysisCommand(analysis));
  }
  commands.push_back(ValidateCommand());
  commands.push_back(ReportCommand());
  commands.push_back(KeysCommand());
  return commands;
}

void AddDeckInputs(CLI::App& command, DeckInput& deck, const char* deck_help) {
  command.add_option("--set", deck.overrides, kSetHelp)->allow_extra_args(false)->type_name("SECTION.KEY=VALUE");
  command.add_option("--unset", deck.removals, kUnsetHelp)->allow_extra_args(false)->type_name("SECTION[.KEY]");
  command.add_option("deck", deck.path, deck_help);
}

void AddLoadInputs(CLI::App& command, DeckInput& deck, std::string& solver, std::string& kinematics) {
  AddDeckInputs(command, deck);
  command.add_option("--solver", solver, "Solver name (default: the deck's [solver] name)");
  command.add_option("--kinematics", kinematics, kKinematicsHelp)->check(CLI::IsMember({"exact", "linearised"}));
}

void AddSamplesOption(CLI::App& command, std::optional<std::int64_t>& samples) {
  command
      .add_option_function<std::string>(
          "--samples",
          [&samples](const std::string& text) {
            // Said in the option's own words (CLI11's range check printed "Value 0 not in range 0.000000 to 1.797e308").
            std::int64_t value = 0;
            const char* end = text.data() + text.size();
            const auto [ptr, ec] = std::from_chars(text.data(), end, value);
            if (text.empty() || ptr != end || ec != std::errc() || value < 1 || value > analysis::ToleranceSettings::kMaxSamples) {
              throw CLI::ValidationError(fmt::format("--samples {}: expected a whole number from 1 to {}", text,
                                                     analysis::ToleranceSettings::kMaxSamples));
            }
            samples = value;
          },
          "Number of tolerance samples ([tolerances] samples)")
      ->type_name("INT 1..10000000");
}

void AddOutput(CLI::App& command, const char* option, std::string& path, const char* help) {
  command.add_option(option, path, help)->type_name("FILE|-");
}

const CLI::Validator& CrankAngle() {
  static const CLI::Validator validator(
      [](std::string& text) -> std::string {
        double value = 0.0;
        std::size_t used = 0;
        try {
          value = std::stod(text, &used);
        } catch (const std::exception&) {
          return fmt::format("'{}' is not a number of degrees", text);
        }
        if (used != text.size()) return fmt::format("'{}' is not a number of degrees", text);
        if (!std::isfinite(value) || std::abs(value) > analysis::kMaxCrankDeg) {
          return fmt::format("{}: expected a finite crank angle within +-{:g} deg", text, analysis::kMaxCrankDeg);
        }
        return {};
      },
      fmt::format("DEG, finite, |DEG| <= {:g}", analysis::kMaxCrankDeg));
  return validator;
}

const CLI::Validator& Index() {
  // CLI11 would wrap a negative seed into an unsigned one, or clamp one too large, without a word.
  static const CLI::Validator validator(
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
  return validator;
}

}  // namespace ltca::cli
