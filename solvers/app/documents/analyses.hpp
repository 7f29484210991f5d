#pragma once
// The table of analyses: the one list of what ltca analyses, which the command line (a command
// each), the report (a section each) and the Python module (a function each) iterate. An entry
// says what the analysis is called, what it takes and why it does not run for a deck; an entry
// with generic hooks (run) reaches all three front-ends by itself: its options become the
// command's options and the function's keyword arguments, its output the command's --json, --csv
// and --svg, the report's section and the function's (exit code, document, columns). The first
// nine analyses keep front-ends of their own (streaming, MPI, sinks) and are listed without run.
// The table knows neither CLI11 nor pybind11.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"

namespace ltca::app::documents {

/// An option of an analysis, described for every front-end: `name` is the command line's
/// (--NAME; words joined by '-') and, with '_' for '-', the Python keyword's.
struct AnalysisOption {
  enum class Kind { kReal, kInteger, kText, kFlag, kChoice };
  std::string name;
  std::string help;
  Kind kind = Kind::kReal;
  std::vector<std::string> choices;  ///< kChoice: the values it takes
  /// The value when not given, as text in the option's kind ("0", "3", "true"; "" for a text or
  /// choice: none given, the analysis's own rule applies).
  std::string default_value;
  /// kReal: finite and within [min, max]; kInteger: within [min, max].
  double min = -1e300, max = 1e300;
};

/// The values of an analysis's options, every one present (its default when not given); the
/// common load inputs, when the analysis takes them, as "solver" and "kinematics" (text, "" the
/// deck's). Typed access; std::logic_error for a name or kind the entry does not declare.
class OptionValues {
 public:
  using Value = std::variant<bool, std::int64_t, double, std::string>;
  double Real(const std::string& name) const;
  std::int64_t Integer(const std::string& name) const;
  const std::string& Text(const std::string& name) const;  ///< a text or choice option
  bool Flag(const std::string& name) const;
  /// The solver of a run with the common load inputs: --solver, else the deck's (app::SolverFor).
  solvers::SolverOptions Solver(const Deck& deck) const;
  void Set(const std::string& name, Value value) { values_[name] = std::move(value); }
  bool Has(const std::string& name) const { return values_.count(name) != 0; }

 private:
  const Value& At(const std::string& name) const;
  std::map<std::string, Value> values_;
};

/// A per-row table of an analysis (its --csv, its Python columns): a header and rows of numbers
/// (NaN: an empty cell, None/NaN in Python).
struct AnalysisColumns {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
};
/// The CSV text of a table: the header, then a line per row, numbers in their shortest exact text,
/// an empty cell for NaN.
std::string Csv(const AnalysisColumns& columns);

/// What every front-end needs of one run of an analysis.
struct AnalysisOutput {
  int exit_code = 0;             ///< kExitSuccess, or kExitNotSucceeded when a part did not succeed
  nlohmann::json json;           ///< the --json document (NAME.json beside the report)
  std::string text;              ///< the text on standard output
  std::optional<AnalysisColumns> columns;  ///< the --csv rows, when the analysis has a per-row table
  std::optional<plots::Figure> figure;     ///< the --svg figure (NAME.svg, inlined in the report)
  /// The report section's key figures, from the typed result: (key as the documents name it, its
  /// value in the key's unit; NaN: n/a). Tabled like the other sections' summaries.
  std::vector<std::pair<std::string, double>> key_figures;
  /// The report section's HTML body before its figure; "" for the key figures' table alone.
  std::string report_html;
};

/// One analysis. Generic (run set): every front-end is built from the entry. Bespoke (run empty):
/// its command, report section and Python binding are written by hand, and the entry lists them.
struct Analysis {
  std::string name;         ///< the command's and the Python function's
  std::string description;  ///< the command's help and the function's docstring
  /// The report's section that shows it (its anchor and title); "" with `not_in_report` saying why
  /// the page has none.
  std::string report_anchor, report_title;
  const char* not_in_report = nullptr;
  std::vector<AnalysisOption> options;  ///< generic entries: every option besides the load inputs
  bool load_inputs = false;  ///< takes --solver and --kinematics (the deck's when not given)
  /// What its --csv and --svg write ("": the analysis has no per-row table, or no figure).
  std::string csv_help, svg_help;
  /// Why it does not run for a deck (the report's note), nullptr when it runs.
  const char* (*skipped)(const Deck&) = nullptr;
  /// The analysis and its documents; bad input throws std::invalid_argument naming the key.
  std::function<AnalysisOutput(const Deck&, const OptionValues&)> run;
  bool generic() const { return static_cast<bool>(run); }
};

/// Every analysis, in the order `ltca --help` lists their commands.
const std::vector<Analysis>& Analyses();
/// The entry named `name`, or nullptr.
const Analysis* FindAnalysis(const std::string& name);

/// Every option of the entry: its own, then, when it takes the load inputs, "solver" (text) and
/// "kinematics" (a choice of exact and linearised), both "" (the deck's) by default.
std::vector<AnalysisOption> AllOptions(const Analysis& analysis);

/// The option values from text as the command line gives them (name -> text; an option not given
/// is absent and takes its default). std::invalid_argument names the option, the value and what it
/// expects.
OptionValues ParseOptions(const Analysis& analysis, const std::map<std::string, std::string>& given);

/// The entry's options checked and filled with defaults, from values already typed (Python):
/// std::invalid_argument (a bad value) or std::logic_error (a kind the option does not take).
OptionValues CompleteOptions(const Analysis& analysis, const std::map<std::string, OptionValues::Value>& given);

/// Runs a generic entry with the common rules: the deck with --kinematics when given
/// (app::DeckFor), then the entry's run.
AnalysisOutput RunAnalysis(const Analysis& analysis, const Deck& deck, const OptionValues& values);

}  // namespace ltca::app::documents
