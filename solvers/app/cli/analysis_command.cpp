// The command of a generic entry of the table of analyses (documents/analyses.hpp): its options
// from the entry (--NAME, the load inputs as every command takes them), --json, and --csv and
// --svg where the entry writes them; run: the deck, the options checked, the outputs opened
// before computing, the analysis, its text and documents.
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "command.hpp"
#include "documents/analyses.hpp"
#include "output.hpp"

namespace ltca::cli {
namespace documents = app::documents;

Command AnalysisCommand(const documents::Analysis& analysis) {
  struct State {
    DeckInput deck;
    std::string solver, kinematics;
    std::map<std::string, std::string> text;  // the options given, as text
    std::map<std::string, bool> flags;
    std::string json_path, csv_path, svg_path;
  };
  auto st = std::make_shared<State>();
  const documents::Analysis* a = &analysis;  // the table lives as long as the process
  return {a->name, a->description,
          [st, a](CLI::App& c) {
            if (a->load_inputs) {
              AddLoadInputs(c, st->deck, st->solver, st->kinematics);
            } else {
              AddDeckInputs(c, st->deck);
            }
            for (const documents::AnalysisOption& o : a->options) {
              const std::string flag = "--" + o.name;
              const std::string help = o.default_value.empty() ? o.help : fmt::format("{} (default {})", o.help, o.default_value);
              if (o.kind == documents::AnalysisOption::Kind::kFlag) {
                c.add_flag(flag, st->flags[o.name], o.help);
                continue;
              }
              CLI::Option* option = c.add_option(flag, st->text[o.name], help);
              if (o.kind == documents::AnalysisOption::Kind::kChoice) option->check(CLI::IsMember(o.choices));
              option->type_name(o.kind == documents::AnalysisOption::Kind::kReal      ? "REAL"
                                : o.kind == documents::AnalysisOption::Kind::kInteger ? "INT"
                                                                                      : "TEXT");
            }
            AddOutput(c, "--json", st->json_path, "Write the document as JSON ('-': stdout)");
            if (!a->csv_help.empty()) AddOutput(c, "--csv", st->csv_path, a->csv_help.c_str());
            if (!a->svg_help.empty()) AddOutput(c, "--svg", st->svg_path, a->svg_help.c_str());
          },
          [st] { return std::vector<std::string>{st->json_path, st->csv_path, st->svg_path}; },
          [st, a](const Streams& streams) {
            // The options as given (an option left out takes the entry's default).
            std::map<std::string, std::string> given;
            for (const auto& [name, text] : st->text) {
              if (!text.empty()) given[name] = text;
            }
            for (const auto& [name, on] : st->flags) {
              if (on) given[name] = "true";  // a flag given; else the entry's default
            }
            if (!st->solver.empty()) given["solver"] = st->solver;
            if (!st->kinematics.empty()) given["kinematics"] = st->kinematics;
            const documents::OptionValues values = documents::ParseOptions(*a, given);
            const app::Deck deck = st->deck.Read();
            RequireDistinctOutputs({{"--json", st->json_path}, {"--csv", st->csv_path}, {"--svg", st->svg_path}});
            Output json("--json", st->json_path, streams.out);  // checked before computing
            Output csv("--csv", st->csv_path, streams.out);
            Output svg("--svg", st->svg_path, streams.out);
            const documents::AnalysisOutput result = documents::RunAnalysis(*a, deck, values);
            streams.text << result.text;
            if (json.enabled()) {
              json.stream() << Dump(result.json) << '\n';
              json.Commit();
            }
            if (csv.enabled()) {
              if (!result.columns) throw std::logic_error(fmt::format("{}: --csv without a per-row table", a->name));
              csv.stream() << documents::Csv(*result.columns);
              csv.Commit();
            }
            if (svg.enabled()) {
              if (!result.figure) throw std::logic_error(fmt::format("{}: --svg without a figure", a->name));
              WriteFigure(*result.figure, svg);
            }
            return result.exit_code;
          }};
}

}  // namespace ltca::cli
