#include "analyses.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace ltca::app::documents {

// --- the values -------------------------------------------------------------------------------

const OptionValues::Value& OptionValues::At(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) throw std::logic_error(fmt::format("analysis option '{}': not an option of the entry", name));
  return it->second;
}

namespace {
template <class T>
const T& Typed(const OptionValues::Value& v, const std::string& name, const char* kind) {
  if (const T* x = std::get_if<T>(&v)) return *x;
  throw std::logic_error(fmt::format("analysis option '{}': not {} option", name, kind));
}
}  // namespace

double OptionValues::Real(const std::string& name) const { return Typed<double>(At(name), name, "a real"); }
std::int64_t OptionValues::Integer(const std::string& name) const { return Typed<std::int64_t>(At(name), name, "an integer"); }
const std::string& OptionValues::Text(const std::string& name) const { return Typed<std::string>(At(name), name, "a text"); }
bool OptionValues::Flag(const std::string& name) const { return Typed<bool>(At(name), name, "a flag"); }

solvers::SolverOptions OptionValues::Solver(const Deck& deck) const {
  return SolverFor(deck, Has("solver") ? Text("solver") : std::string());
}

// --- the CSV ----------------------------------------------------------------------------------

std::string Csv(const AnalysisColumns& columns) {
  std::string text = fmt::format("{}\n", fmt::join(columns.header, ","));
  for (const std::vector<double>& row : columns.rows) {
    for (std::size_t k = 0; k < row.size(); ++k) {
      if (k > 0) text += ',';
      if (std::isfinite(row[k])) text += fmt::format("{}", row[k]);
    }
    text += '\n';
  }
  return text;
}

// --- the options from text and from typed values ------------------------------------------------

namespace {

using Kind = AnalysisOption::Kind;

/// The option's value from its text, checked; std::invalid_argument names --NAME and the value.
OptionValues::Value FromText(const AnalysisOption& o, const std::string& text) {
  const auto bad = [&](const std::string& expected) {
    return std::invalid_argument(fmt::format("--{} {}: expected {}", o.name, text, expected));
  };
  switch (o.kind) {
    case Kind::kReal: {
      char* end = nullptr;
      const double v = text.empty() ? NAN : std::strtod(text.c_str(), &end);
      if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v) || v < o.min || v > o.max) {
        throw bad(fmt::format("a finite number from {:g} to {:g}", o.min, o.max));
      }
      return v;
    }
    case Kind::kInteger: {
      std::int64_t v = 0;
      const char* end = text.data() + text.size();
      const auto [ptr, ec] = std::from_chars(text.data(), end, v);
      if (text.empty() || ptr != end || ec != std::errc() || static_cast<double>(v) < o.min || static_cast<double>(v) > o.max) {
        // The bounds the option sets; a whole number in the 64-bit range when it sets none.
        const bool bounded = o.min > -9.2e18 && o.max < 9.2e18;
        throw bad(bounded ? fmt::format("a whole number from {:.0f} to {:.0f}", o.min, o.max)
                          : std::string("a whole number from -9223372036854775808 to 9223372036854775807"));
      }
      return v;
    }
    case Kind::kFlag:
      if (text == "true") return true;
      if (text == "false") return false;
      throw bad("true or false");
    case Kind::kChoice:
      if (!text.empty() && std::find(o.choices.begin(), o.choices.end(), text) == o.choices.end()) {
        throw bad(fmt::format("one of {}", fmt::join(o.choices, ", ")));
      }
      return text;
    case Kind::kText: return text;
  }
  return text;
}

/// The load inputs as options: --solver (text) and --kinematics (a choice), "" the deck's.
const std::vector<AnalysisOption>& LoadInputOptions() {
  static const std::vector<AnalysisOption> options = {
      {"solver", "Solver name (default: the deck's [solver] name)", Kind::kText, {}, ""},
      {"kinematics", "linearised or exact (default: the deck's [solver] kinematics)", Kind::kChoice, {"exact", "linearised"}, ""}};
  return options;
}

}  // namespace

std::vector<AnalysisOption> AllOptions(const Analysis& analysis) {
  std::vector<AnalysisOption> all = analysis.options;
  if (analysis.load_inputs) all.insert(all.end(), LoadInputOptions().begin(), LoadInputOptions().end());
  return all;
}

OptionValues ParseOptions(const Analysis& analysis, const std::map<std::string, std::string>& given) {
  OptionValues values;
  for (const AnalysisOption& o : AllOptions(analysis)) {
    const auto it = given.find(o.name);
    values.Set(o.name, FromText(o, it != given.end() ? it->second : o.default_value));
  }
  return values;
}

OptionValues CompleteOptions(const Analysis& analysis, const std::map<std::string, OptionValues::Value>& given) {
  OptionValues values;
  for (const AnalysisOption& o : AllOptions(analysis)) {
    const auto it = given.find(o.name);
    if (it == given.end()) {
      values.Set(o.name, FromText(o, o.default_value));
      continue;
    }
    const OptionValues::Value& v = it->second;
    const bool fits = (o.kind == Kind::kReal && (std::holds_alternative<double>(v) || std::holds_alternative<std::int64_t>(v))) ||
                      (o.kind == Kind::kInteger && std::holds_alternative<std::int64_t>(v)) ||
                      (o.kind == Kind::kFlag && std::holds_alternative<bool>(v)) ||
                      ((o.kind == Kind::kText || o.kind == Kind::kChoice) && std::holds_alternative<std::string>(v));
    if (!fits) throw std::logic_error(fmt::format("{}: not the kind of value the option '{}' takes", analysis.name, o.name));
    // Checked by the command line's rule, from the value's exact text.
    const std::string text = std::visit(
        [](const auto& x) -> std::string {
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, bool>) return x ? "true" : "false";
          else if constexpr (std::is_same_v<T, std::string>) return x;
          else return fmt::format("{}", x);
        },
        v);
    values.Set(o.name, FromText(o, text));
  }
  return values;
}

AnalysisOutput RunAnalysis(const Analysis& analysis, const Deck& given, const OptionValues& values) {
  if (!analysis.generic()) throw std::logic_error(fmt::format("analysis '{}' has front-ends of its own", analysis.name));
  if (!analysis.load_inputs) return analysis.run(given, values);
  return analysis.run(DeckFor(given, values.Text("kinematics")), values);
}

// --- the table --------------------------------------------------------------------------------

namespace {

/// An analysis whose command, report section and Python binding are written by hand.
Analysis Bespoke(std::string name, std::string description, std::string anchor, std::string title, bool load_inputs) {
  Analysis a;
  a.name = std::move(name);
  a.description = std::move(description);
  a.report_anchor = std::move(anchor);
  a.report_title = std::move(title);
  a.load_inputs = load_inputs;
  return a;
}

}  // namespace

// The generic analyses' entries, one factory each in the analysis's documents source.

const std::vector<Analysis>& Analyses() {
  static const std::vector<Analysis> table = [] {
    std::vector<Analysis> t = {
        Bespoke("geometry", "Derived geometry of the pair as made, its profile and drawing", "geometry", "Geometry", false),
        Bespoke("backlash", "Unloaded tooth contact analysis over the sweep: the backlash (Liu eq. 17)", "unloaded",
                "Unloaded: backlash and mesh", false),
        Bespoke("mesh", "The mesh state of every pin at one crank angle", "unloaded", "Unloaded: backlash and mesh", false),
        Bespoke("solve", "Loaded tooth contact analysis over the sweep with one solver", "loaded",
                "Loaded tooth contact analysis", true),
        Bespoke("stiffness", "The torque-twist loop: torsional stiffness, lost motion, hysteresis", "stiffness",
                "Torsional stiffness", true),
        Bespoke("tolerance", "The Monte Carlo of [tolerances], its worst case and sensitivities", "tolerance",
                "Tolerance analysis (Monte Carlo)", true),
        Bespoke("optimise", "The design search of [optimise]", "optimise", "Design optimisation", true),
        Bespoke("efficiency", "Friction, power loss and meshing efficiency over the sweep", "efficiency",
                "Friction and meshing efficiency", true),
        Bespoke("compare", "Several solvers on the same sweep, side by side", "", "", true),
    };
    t.back().not_in_report = "the page is of the deck's solver; ltca compare runs several solvers side by side";
    // The generic analyses, one line each.
    return t;
  }();
  return table;
}

const Analysis* FindAnalysis(const std::string& name) {
  for (const Analysis& a : Analyses()) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

}  // namespace ltca::app::documents
