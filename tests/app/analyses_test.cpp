// The table of analyses (documents::Analyses()) against the three front-ends that iterate it: every
// analysis has a command of the command line and a section of the report (or says why the page has
// none), every command that runs an analysis is in the table, and a generic analysis's JSON builder
// runs on a stock deck. The Python bindings are held to the table by tests/python/test_bindings.py.
// The generic command's machinery (options from the entry, outputs, exit code) is checked on an
// entry made here.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "command.hpp"
#include "documents/analyses.hpp"
#include "report_command.hpp"

namespace {

namespace documents = ltca::app::documents;

/// The commands that run no analysis of the table: the validation cases, the report page of them
/// all, the key table.
const std::set<std::string> kNotAnalyses = {"validate", "report", "keys"};

std::set<std::string> CommandNames() {
  std::set<std::string> names;
  for (const ltca::cli::Command& c : ltca::cli::Commands()) names.insert(c.name);
  return names;
}

}  // namespace

TEST_CASE("app: every analysis of the table is a command, and every command that runs an analysis is in the table") {
  const std::set<std::string> commands = CommandNames();
  std::set<std::string> table;
  for (const documents::Analysis& a : documents::Analyses()) {
    CHECK_MESSAGE(commands.count(a.name) == 1, a.name);
    CHECK_MESSAGE(table.insert(a.name).second, "listed twice: " << a.name);
    CHECK(!a.description.empty());
    CHECK(documents::FindAnalysis(a.name) == &a);
  }
  for (const std::string& c : commands) {
    if (kNotAnalyses.count(c) == 0) CHECK_MESSAGE(table.count(c) == 1, "the command '" << c << "' is not in the table of analyses");
  }
  CHECK(table.size() >= 9);  // geometry, backlash, mesh, solve, stiffness, tolerance, optimise, efficiency, compare
}

TEST_CASE("app: every analysis of the table has a section of the report, under its title, or says why the page has none") {
  const std::vector<std::pair<std::string, std::string>> sections = ltca::cli::ReportSectionTitles();
  for (const documents::Analysis& a : documents::Analyses()) {
    if (a.report_anchor.empty()) {
      CHECK_MESSAGE(a.not_in_report != nullptr, a.name << ": no report section and no reason");
      CHECK(!a.generic());  // a generic analysis always has its section
      continue;
    }
    const auto it = std::find_if(sections.begin(), sections.end(), [&](const auto& s) { return s.first == a.report_anchor; });
    REQUIRE_MESSAGE(it != sections.end(), a.name << ": no report section '" << a.report_anchor << "'");
    CHECK(it->second == a.report_title);
  }
  // One section per anchor.
  std::set<std::string> anchors;
  for (const auto& s : sections) CHECK_MESSAGE(anchors.insert(s.first).second, "two sections '" << s.first << "'");
}

namespace {
/// A document without the members that time the run (wall_seconds, ...), which differ between runs.
nlohmann::json WithoutTimes(nlohmann::json j) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end();) {
      if (it.key().find("seconds") != std::string::npos) {
        it = j.erase(it);
      } else {
        *it = WithoutTimes(*it);
        ++it;
      }
    }
  } else if (j.is_array()) {
    for (auto& item : j) item = WithoutTimes(item);
  }
  return j;
}
}  // namespace

TEST_CASE("app: every generic analysis's JSON builder runs on the built-in deck, and its command writes that document") {
  const ltca::app::Deck deck = ltca::app::DefaultDeck({});
  for (const documents::Analysis& a : documents::Analyses()) {
    if (!a.generic()) continue;
    CAPTURE(a.name);
    const documents::AnalysisOutput output = documents::RunAnalysis(a, deck, documents::ParseOptions(a, {}));
    CHECK(output.exit_code == 0);
    REQUIRE(output.json.is_object());
    CHECK(!output.json.empty());
    CHECK(!output.text.empty());
    CHECK(output.figure.has_value() == !a.svg_help.empty());
    CHECK(output.columns.has_value() == !a.csv_help.empty());
    const ltca::test::Outcome run = ltca::test::RunCli({a.name, "--json", "-"});
    CHECK(run.code == 0);
    CHECK(WithoutTimes(nlohmann::json::parse(run.out)) == WithoutTimes(output.json));
  }
}

namespace {

/// A generic entry made here: options of every kind, a per-row table and no figure.
documents::Analysis Probe() {
  using Kind = documents::AnalysisOption::Kind;
  documents::Analysis a;
  a.name = "probe";
  a.description = "A test's analysis";
  a.report_anchor = "probe";
  a.report_title = "Probe";
  a.load_inputs = true;
  a.csv_help = "rows";
  a.options = {{"scale", "a factor", Kind::kReal, {}, "1.5", 0.0, 10.0},
               {"count", "rows", Kind::kInteger, {}, "2", 1.0, 5.0},
               {"mode", "a choice", Kind::kChoice, {"up", "down"}, "up"},
               {"loud", "a flag", Kind::kFlag, {}, "false"}};
  a.run = [](const ltca::app::Deck&, const documents::OptionValues& v) {
    documents::AnalysisOutput out;
    out.json = {{"scale", v.Real("scale")}, {"count", v.Integer("count")}, {"mode", v.Text("mode")}, {"loud", v.Flag("loud")},
                {"solver", v.Text("solver")}, {"kinematics", v.Text("kinematics")}};
    out.text = "probe ran\n";
    out.columns = documents::AnalysisColumns{{"i", "x"}, {}};
    for (std::int64_t i = 0; i < v.Integer("count"); ++i) {
      out.columns->rows.push_back({static_cast<double>(i), i == 0 ? std::numeric_limits<double>::quiet_NaN() : v.Real("scale") * i});
    }
    out.exit_code = v.Flag("loud") ? 1 : 0;
    return out;
  };
  return a;
}

/// Runs the probe's command with `args` as the command line would; (exit code, stdout).
std::pair<int, std::string> RunProbe(const documents::Analysis& probe, std::vector<std::string> args) {
  const ltca::cli::Command command = ltca::cli::AnalysisCommand(probe);
  CLI::App app;
  command.options(*app.add_subcommand(command.name, command.description));
  args.insert(args.begin(), "probe");
  std::reverse(args.begin(), args.end());
  app.parse(args);
  std::ostringstream out, err;
  const int code = command.run(ltca::cli::Streams{out, err, err});
  return {code, out.str()};
}

}  // namespace

TEST_CASE("app: a generic analysis's options take their defaults, are checked in the command line's words and typed from Python") {
  const documents::Analysis probe = Probe();
  const documents::OptionValues d = documents::ParseOptions(probe, {});
  CHECK(d.Real("scale") == 1.5);
  CHECK(d.Integer("count") == 2);
  CHECK(d.Text("mode") == "up");
  CHECK(d.Flag("loud") == false);
  CHECK(d.Text("solver").empty());
  CHECK_THROWS_WITH_AS(documents::ParseOptions(probe, {{"scale", "11"}}), "--scale 11: expected a finite number from 0 to 10",
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(documents::ParseOptions(probe, {{"count", "2.5"}}), "--count 2.5: expected a whole number from 1 to 5",
                       std::invalid_argument);
  CHECK_THROWS_AS(documents::ParseOptions(probe, {{"mode", "sideways"}}), std::invalid_argument);
  CHECK_THROWS_AS(documents::ParseOptions(probe, {{"kinematics", "wobbly"}}), std::invalid_argument);
  CHECK_THROWS_AS(d.Real("count"), std::logic_error);  // the kind the entry declares, no other
  const documents::OptionValues t = documents::CompleteOptions(probe, {{"scale", std::int64_t{3}}, {"loud", true}});
  CHECK(t.Real("scale") == 3.0);
  CHECK(t.Flag("loud"));
  CHECK_THROWS_AS(documents::CompleteOptions(probe, {{"scale", std::int64_t{30}}}), std::invalid_argument);
  CHECK_THROWS_AS(documents::CompleteOptions(probe, {{"count", 2.0}}), std::logic_error);
}

TEST_CASE("app: a generic analysis's command takes its entry's options and writes its JSON, CSV and exit code") {
  const documents::Analysis probe = Probe();
  const auto [code, out] = RunProbe(probe, {"--scale", "2", "--count", "3", "--mode", "down", "--loud", "--kinematics", "exact",
                                            "--json", "-"});
  CHECK(code == 1);  // the run's own exit code
  const nlohmann::json doc = nlohmann::json::parse(out);
  CHECK(doc["scale"] == 2.0);
  CHECK(doc["count"] == 3);
  CHECK(doc["mode"] == "down");
  CHECK(doc["loud"] == true);
  CHECK(doc["kinematics"] == "exact");
  const auto [csv_code, csv] = RunProbe(probe, {"--csv", "-"});
  CHECK(csv_code == 0);
  CHECK(csv == "i,x\n0,\n1,1.5\n");
  CHECK_THROWS_AS(RunProbe(probe, {"--svg", "-"}), CLI::ParseError);  // no figure: no --svg
  CHECK_THROWS_AS(RunProbe(probe, {"--mode", "sideways"}), CLI::ParseError);
}
