// The compiled part of the Python module `ltca` (docs/python.md): decks read by the same reader as
// the command line, the analyses run by the same library, and their documents built by the same
// functions as the command line's JSON, handed to Python as dicts (JSON null as None) with NumPy
// arrays beside them. The Python API (ltca/__init__.py) wraps these functions.
//
// One function per analysis (Bind*: the command's options in; the result's document and arrays
// out, built from the result in this process), and one table of them (kBindings) that the module
// registers, as the command line registers its table of commands (cli/command.hpp, Commands()):
// an analysis reaches Python by its function and its entry.
//
// Errors: bad input (std::invalid_argument, naming the key) becomes ValueError, as pybind11
// translates it; a solve that fails is a status in the result, not an exception. The GIL is
// released while the library computes, so Python threads may run other decks meanwhile.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "documents/analyses.hpp"
#include "documents/backlash.hpp"
#include "documents/compare.hpp"
#include "documents/efficiency.hpp"
#include "documents/geometry.hpp"
#include "documents/mesh.hpp"
#include "documents/optimise.hpp"
#include "documents/solve.hpp"
#include "documents/stiffness.hpp"
#include "documents/tolerance.hpp"
#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/compare.hpp"
#include "ltca/analysis/efficiency.hpp"
#include "ltca/analysis/mesh.hpp"
#include "ltca/analysis/optimise.hpp"
#include "ltca/analysis/spectrum.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/tolerance_run.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/exit_codes.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"

namespace py = pybind11;

namespace {

namespace analysis = ltca::analysis;
namespace documents = ltca::app::documents;
using ltca::app::Deck;
using Strings = std::vector<std::string>;

// --- Shared by the bindings: Python values from the library's, the GIL, the exit code ---

/// A JSON value as Python objects: null None, numbers int or float (a double as it is), arrays
/// lists, objects dicts.
py::object ToPython(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return py::none();
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    case nlohmann::json::value_t::string: return py::str(j.get<std::string>());
    case nlohmann::json::value_t::array: {
      py::list list;
      for (const auto& item : j) list.append(ToPython(item));
      return list;
    }
    case nlohmann::json::value_t::object: {
      py::dict dict;
      for (const auto& [key, item] : j.items()) dict[py::str(key)] = ToPython(item);
      return dict;
    }
    default: return py::none();
  }
}

/// A document kept as JSON until Python asks for it (converting every position's records costs
/// about as much as a short sweep).
struct Document {
  std::function<nlohmann::json()> make;
};

/// A rows x columns array of doubles (row-major), NaN where a row is shorter.
py::array_t<double> Matrix(const std::vector<std::vector<double>>& rows) {
  std::size_t columns = 0;
  for (const auto& r : rows) columns = std::max(columns, r.size());
  py::array_t<double> a({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(columns)});
  auto m = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t k = 0; k < columns; ++k) {
      m(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(k)) = k < rows[i].size() ? rows[i][k] : std::nan("");
    }
  }
  return a;
}

/// A vector of doubles as a 1-D NumPy array, the values as they are.
py::array_t<double> Vector(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

/// A --csv column of numbers: value(row) for each row, NaN where it is not finite (the CSV's empty
/// cell).
template <class Row, class Value>
py::array_t<double> NumberColumn(const std::vector<Row>& rows, const Value& value) {
  std::vector<double> v;
  v.reserve(rows.size());
  for (const Row& row : rows) {
    const double x = value(row);
    v.push_back(std::isfinite(x) ? x : NAN);
  }
  return Vector(v);
}

/// A --csv column of text: text(row) for each row, as a list of str.
template <class Row, class Text>
py::list TextColumn(const std::vector<Row>& rows, const Text& text) {
  py::list list;
  for (const Row& row : rows) list.append(py::str(text(row)));
  return list;
}

/// The --csv message column: the messages as a list of str when any row has one, else an array of
/// NaN (an empty column, as a CSV reader gives it).
py::object MessageColumn(const Strings& messages) {
  if (std::all_of(messages.begin(), messages.end(), [](const std::string& m) { return m.empty(); })) {
    return Vector(std::vector<double>(messages.size(), NAN));
  }
  py::list list;
  for (const std::string& m : messages) list.append(py::str(m));
  return list;
}

/// work() run with the GIL released, its value returned: the library computes while other Python
/// threads run. work touches no Python object (a callback into Python takes the GIL itself).
template <class Work>
auto WithoutGil(Work&& work) {
  py::gil_scoped_release release;
  return work();
}

/// The command's exit code for a result: success when every part of it succeeded.
int ExitCode(bool succeeded) { return succeeded ? ltca::app::kExitSuccess : ltca::app::kExitNotSucceeded; }

/// A result's table (documents::Table) as {column: array}: a 1-D array of a value per record, a
/// records x values array of a list per record (NaN where a list is shorter).
py::dict Arrays(const documents::Table& table) {
  py::dict arrays;
  for (const auto& [name, column] : table.columns) arrays[py::str(name)] = column.lists ? py::object(Matrix(column.rows)) : Vector(column.values);
  return arrays;
}

/// What an analysis other than solve gives Python: (exit code, the --json document as dicts, the
/// --csv columns as {name: array or list of text}, {} for a command without a per-row CSV, and the
/// document's lists of records as {column: array} built from the result: under the list's key
/// for a list at the top of the document, under its path as a tuple (("positions", 0, "curve"))
/// for one further in).
py::tuple Answer(int code, const nlohmann::json& document, const py::dict& columns = py::dict(), const py::dict& tables = py::dict()) {
  return py::make_tuple(code, ToPython(document), columns, tables);
}

/// A list of records of a document as a table: its key or path (Answer), how many records it
/// has (a list without records is left out, as the document's empty lists are) and its columns.
struct NamedTable {
  py::object key;
  std::size_t records;
  documents::Table table;
};

/// {key: the table's arrays}, for Answer.
py::dict Tables(const std::vector<NamedTable>& tables) {
  py::dict out;
  for (const NamedTable& t : tables) {
    if (t.records > 0) out[t.key] = Arrays(t.table);
  }
  return out;
}

/// A path into the document as Python's tuple, e.g. ("positions", 0, "curve").
py::tuple Path(const std::string& list, std::size_t index, const std::string& member) {
  return py::make_tuple(list, index, member);
}

// --- The columns of the per-row tables ---

/// The sweep's arrays, a row per crank position, NaN where the position failed: crank_deg (deg),
/// te_arcsec (arcsec), contacts, pin_force_n (N) and contact_stress_mpa (MPa) as positions x pins,
/// disc_torque_nm (N*m, positions x discs; two discs only), position_status (a list of text).
py::dict SweepArrays(const Deck& deck, const ltca::analysis::SweepResult& sweep) {
  namespace units = ltca::units;
  std::vector<double> crank, te, contacts;
  std::vector<std::vector<double>> force, stress, disc_torque;
  py::list status;
  for (const auto& p : sweep.positions) {
    const bool ok = p.succeeded();
    crank.push_back(units::RadToDeg(p.crank));
    te.push_back(ok ? units::RadToArcsec(p.result.te) : std::nan(""));
    contacts.push_back(ok ? static_cast<double>(p.contacts) : std::nan(""));
    force.push_back(ok ? p.pin_force : std::vector<double>(p.pin_force.size(), std::nan("")));
    stress.push_back(ok ? p.contact_stress : std::vector<double>(p.contact_stress.size(), std::nan("")));
    std::vector<double> torques;
    for (const double t : p.disc_torque) torques.push_back(ok ? units::NmmToNm(t) : std::nan(""));
    disc_torque.push_back(torques);
    status.append(py::str(ltca::solvers::ToString(p.result.status)));
  }
  py::dict arrays;
  arrays["crank_deg"] = Vector(crank);
  arrays["te_arcsec"] = Vector(te);
  arrays["contacts"] = Vector(contacts);
  arrays["pin_force_n"] = Matrix(force);
  arrays["contact_stress_mpa"] = Matrix(stress);
  if (deck.disc_count() == 2) arrays["disc_torque_nm"] = Matrix(disc_torque);
  arrays["position_status"] = status;
  return arrays;
}

/// The profile's --csv columns (tooth_space, u_deg, x_mm, y_mm, normal_x, normal_y,
/// curvature_radius_mm as arrays; part as a list of text).
py::dict ProfileColumns(const documents::ProfileColumns& profile) {
  py::dict columns;
  columns["tooth_space"] = Vector(profile.tooth_space);
  columns["u_deg"] = Vector(profile.u_deg);
  columns["x_mm"] = Vector(profile.x_mm);
  columns["y_mm"] = Vector(profile.y_mm);
  columns["normal_x"] = Vector(profile.normal_x);
  columns["normal_y"] = Vector(profile.normal_y);
  columns["curvature_radius_mm"] = Vector(profile.curvature_radius_mm);
  columns["part"] = py::cast(profile.part);
  return columns;
}

/// The tolerance study's --csv columns, a row per sample: sample, status, every input, every
/// figure the study runs, message (line breaks as spaces, as the CSV carries it).
py::dict ToleranceColumns(const analysis::ToleranceStudy& study, const std::vector<analysis::ToleranceSample>& samples) {
  using Sample = analysis::ToleranceSample;
  py::dict columns;
  columns["sample"] = NumberColumn(samples, [](const Sample& s) { return static_cast<double>(s.index); });
  columns["status"] = TextColumn(samples, [](const Sample& s) { return analysis::ToString(s.status); });
  for (std::size_t i = 0; i < study.inputs().size(); ++i) {
    columns[py::str(study.inputs()[i].name)] = NumberColumn(samples, [i](const Sample& s) { return s.inputs[i]; });
  }
  const auto& names = analysis::ToleranceSettings::FigureNames();
  for (std::size_t f = 0; f < names.size(); ++f) {
    if (study.Runs(f)) columns[py::str(names[f])] = NumberColumn(samples, [f](const Sample& s) { return s.figures[f]; });
  }
  Strings messages;
  for (const Sample& s : samples) {
    std::string message = s.message;
    std::replace_if(message.begin(), message.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
    messages.push_back(message);
  }
  columns["message"] = MessageColumn(messages);
  return columns;
}

/// The search's --csv columns, a row per evaluation: index, phase, the variables, objective,
/// violation, feasible, status, every figure, message (double quotes as single ones, as the CSV
/// carries it).
py::dict OptimiseColumns(const analysis::OptimiseSettings& settings, const std::vector<analysis::DesignEvaluation>& history) {
  using Evaluation = analysis::DesignEvaluation;
  py::dict columns;
  columns["index"] = NumberColumn(history, [](const Evaluation& e) { return static_cast<double>(e.index); });
  columns["phase"] = TextColumn(history, [](const Evaluation& e) { return e.phase; });
  for (std::size_t k = 0; k < settings.variables.size(); ++k) {
    columns[py::str(settings.variables[k].key)] = NumberColumn(history, [k](const Evaluation& e) { return e.x[k]; });
  }
  columns["objective"] = NumberColumn(history, [](const Evaluation& e) { return e.objective; });
  columns["violation"] = NumberColumn(history, [](const Evaluation& e) { return e.violation; });
  columns["feasible"] = TextColumn(history, [](const Evaluation& e) { return e.feasible ? "true" : "false"; });
  columns["status"] = TextColumn(history, [](const Evaluation& e) { return analysis::ToString(e.status); });
  const auto& names = analysis::OptimiseFigureNames();
  for (std::size_t f = 0; f < names.size(); ++f) {
    columns[py::str(names[f])] = NumberColumn(history, [f](const Evaluation& e) { return e.figures[f]; });
  }
  Strings messages;
  for (const Evaluation& e : history) {
    std::string message = e.message;
    std::replace(message.begin(), message.end(), '"', '\'');
    messages.push_back(message);
  }
  columns["message"] = MessageColumn(messages);
  return columns;
}

// --- One binding per analysis: the command's options in, the result's document and arrays out ---
// Each runs the command's checks in the command's order, so that bad input names the same key.

/// `ltca solve`: (the whole --json document, built when Python asks for it; its summary as a
/// dict; the sweep's arrays). progress(done, total), when not None, is called after each position.
py::tuple BindSolve(const Deck& given, const std::string& solver_name, const std::string& kinematics, const py::object& progress) {
  const Deck deck = ltca::app::DeckFor(given, kinematics);
  const ltca::solvers::SolverOptions solver = ltca::app::SolverFor(deck, solver_name);
  deck.RequireMaterial();
  ltca::analysis::SweepCallbacks callbacks;
  if (!progress.is_none()) {  // with the GIL held for the call
    const auto total = static_cast<std::int64_t>(deck.sweep.positions);
    auto done = std::make_shared<std::int64_t>(0);
    callbacks.on_position = [&progress, total, done](const ltca::analysis::PositionResult&) {
      py::gil_scoped_acquire gil;
      progress(++*done, total);
    };
  }
  ltca::analysis::SweepResult sweep = WithoutGil([&] { return ltca::app::SolveDeckSweep(deck, solver, callbacks); });
  // A load spectrum: every bin as `ltca solve` solves it, its block in the document as there.
  std::optional<ltca::analysis::SpectrumResult> spectrum;
  if (!deck.load_spectrum.empty()) spectrum = WithoutGil([&] { return ltca::app::SolveDeckSpectrum(deck, solver); });
  py::object summary = ToPython(documents::Json(deck, sweep.summary));
  py::dict arrays = SweepArrays(deck, sweep);
  auto kept = std::make_shared<const std::tuple<Deck, ltca::solvers::SolverOptions, ltca::analysis::SweepResult,
                                                std::optional<ltca::analysis::SpectrumResult>>>(deck, solver, std::move(sweep),
                                                                                                 std::move(spectrum));
  const bool spectrum_succeeded = !std::get<3>(*kept) || std::get<3>(*kept)->all_succeeded();
  Document document{[kept] {
    nlohmann::json j = documents::Json(std::get<0>(*kept), std::get<1>(*kept), std::get<2>(*kept));
    if (const auto& s = std::get<3>(*kept)) j["spectrum"] = documents::SpectrumJson(std::get<0>(*kept), *s);
    return j;
  }};
  return py::make_tuple(document, summary, arrays, spectrum_succeeded);
}

/// `ltca geometry`: the derived geometry of the pair as made and the profile's columns,
/// samples_per_flank points per flank. (crank_deg, deg, is the drawing's, which Python does not draw.)
py::tuple BindGeometry(const Deck& deck, double /*crank_deg*/, int samples_per_flank) {
  nlohmann::json document;
  documents::ProfileColumns profile;
  WithoutGil([&] {
    const ltca::geometry::RealPair real = deck.MakeRealPair();
    document = documents::Json(deck, real);
    profile = documents::Columns(real.profile(), samples_per_flank);
  });
  return Answer(ltca::app::kExitSuccess, document, ProfileColumns(profile));
}

/// `ltca backlash`: the unloaded backlash over the sweep; kinematics "" is the deck's.
py::tuple BindBacklash(const Deck& deck, const std::string& kinematics) {
  const ltca::contact::ContactKinematics k = kinematics.empty() ? deck.kinematics : ltca::contact::ParseKinematics(kinematics);
  std::vector<analysis::BacklashPosition> positions;
  const analysis::BacklashResult result = WithoutGil([&] {
    const analysis::Stage stage(deck, deck.sweep.CrankAngles());
    return analysis::Backlash(stage, k, [&](const analysis::BacklashPosition& p) { positions.push_back(p); });
  });
  return Answer(ExitCode(result.summary.failed() == 0), documents::Json(deck, positions, result), py::dict(),
                Tables({{py::str("positions"), positions.size(), documents::Columns(positions, result.discs == 2)}}));
}

/// `ltca mesh`: the mesh state of every pin at crank_deg (deg).
py::tuple BindMesh(const Deck& deck, double crank_deg) {
  const analysis::MeshResult mesh = WithoutGil([&] { return analysis::MeshAt(deck.MakeModel(), crank_deg); });
  return Answer(ltca::app::kExitSuccess, documents::Json(deck, mesh), py::dict(), Tables({{py::str("pins"), mesh.state.pins.size(), documents::Columns(mesh)}}));
}

/// `ltca compare`: several solvers on the deck's sweep (every registered solver when `names` is
/// empty). Checks: [material], [load], the solvers, then the stage.
py::tuple BindCompare(const Deck& given, const Strings& names, const std::string& kinematics) {
  const Deck deck = ltca::app::DeckFor(given, kinematics);
  const analysis::CompareResult result = WithoutGil([&] {
    const Strings asked = names.empty() ? ltca::solvers::SolverNames() : names;
    deck.RequireMaterial();
    const double torque = deck.RequireLoad().torque;
    const analysis::SolverSelection selection = analysis::SelectSolvers(asked, deck.reducer.has_value(), deck.name);
    return analysis::Compare(deck.MakeStage(), deck.solver, selection.run, torque, selection.skipped);
  });
  return Answer(ExitCode(result.all_succeeded()), documents::Json(deck, result), py::dict(),
                Tables({{py::str("solvers"), result.solvers.size(), documents::Columns(result)},
                        {py::str("skipped"), result.skipped.size(), {}}}));  // names and reasons: no number
}

/// `ltca stiffness`: the torque-twist loop; crank_deg (deg) and steps replace the deck's
/// [stiffness] crank_deg and steps_per_branch. Checks: the settings, [material], [load], the stage.
py::tuple BindStiffness(const Deck& given, const std::string& solver_name, const std::string& kinematics,
                        std::optional<double> crank_deg, std::optional<int> steps) {
  const Deck deck = ltca::app::DeckFor(given, kinematics);
  const ltca::solvers::SolverOptions solver = ltca::app::SolverFor(deck, solver_name);
  const analysis::StiffnessResult result = WithoutGil([&] {
    analysis::StiffnessSettings settings = deck.stiffness;
    if (crank_deg) settings.crank = ltca::units::DegToRad(*crank_deg);
    if (steps) settings.steps = *steps;
    settings.Validate();
    deck.RequireMaterial();
    const double torque = deck.RequireLoad().torque;
    return analysis::Stiffness(deck.MakeStage(settings.crank ? std::vector<double>{*settings.crank} : deck.sweep.CrankAngles()),
                               solver, settings, torque, deck.friction);
  });
  std::vector<NamedTable> tables{{py::str("positions"), result.positions.size(), documents::Columns(result.positions)}};
  for (std::size_t i = 0; i < result.positions.size(); ++i) {
    tables.push_back({Path("positions", i, "curve"), result.positions[i].curve.size(), documents::Columns(result.positions[i].curve)});
  }
  tables.push_back({py::make_tuple("summary", "curve"), result.summary.curve.size(), documents::SummaryCurveColumns(result)});
  return Answer(ExitCode(result.all_succeeded()), documents::Json(deck, solver, result), py::dict(), Tables(tables));
}

/// `ltca efficiency`: friction, power loss and efficiency over the sweep. Checks: [material],
/// [friction], [operation], [load].
py::tuple BindEfficiency(const Deck& given, const std::string& solver_name, const std::string& kinematics) {
  const Deck deck = ltca::app::DeckFor(given, kinematics);
  const ltca::solvers::SolverOptions solver = ltca::app::SolverFor(deck, solver_name);
  std::vector<analysis::EfficiencyPosition> positions;
  const analysis::EfficiencySummary summary = WithoutGil([&] {
    deck.RequireMaterial();
    const ltca::analysis::FrictionSettings& friction = deck.RequireFriction();
    const ltca::analysis::OperationSettings& operation = deck.RequireOperation();
    const double torque = deck.RequireLoad().torque;
    analysis::EfficiencyRunner runner(deck.MakeStage(), solver, torque, friction, operation);
    for (const double crank : runner.cranks()) positions.push_back(runner.Solve(crank));
    return runner.Summary();
  });
  std::vector<NamedTable> tables{{py::str("positions"), positions.size(), documents::Columns(positions)}};
  for (std::size_t i = 0; i < positions.size(); ++i) {
    tables.push_back({Path("positions", i, "contacts"), positions[i].contacts.size(),
                      documents::ContactColumns(positions[i], deck.second_disc.has_value())});
  }
  return Answer(ExitCode(summary.all_succeeded()), documents::Json(deck, solver, positions, summary), py::dict(), Tables(tables));
}

/// `ltca tolerance`: the Monte Carlo of [tolerances] and the samples' columns; samples and seed
/// replace the deck's, threads 0 is every hardware thread. Checks: [tolerances], threads, the
/// solver, the study's.
py::tuple BindTolerance(const Deck& given, const std::string& solver_name, const std::string& kinematics,
                        std::optional<std::int64_t> samples, std::optional<std::uint64_t> seed, int threads, bool lost_motion,
                        bool no_worst_case) {
  const Deck deck = ltca::app::DeckFor(given, kinematics);
  std::optional<ltca::solvers::SolverOptions> solver;
  std::optional<analysis::ToleranceStudy> study;
  std::vector<analysis::ToleranceSample> kept;
  const analysis::ToleranceResult result = WithoutGil([&] {
    const analysis::ToleranceSettings settings = documents::ToleranceSettingsFor(deck, samples, seed, lost_motion);
    analysis::ToleranceRunPlan plan;
    plan.threads = analysis::ResolveThreads(threads);
    solver = ltca::app::SolverFor(deck, solver_name);
    study.emplace(deck.MakeToleranceCase(), *solver, settings);
    plan.worst_case = !no_worst_case;
    plan.sink = [&kept](const analysis::ToleranceSample& s) { kept.push_back(s); };
    return analysis::RunToleranceStudy(*study, plan);
  });
  const analysis::ToleranceSettings& settings = study->settings();
  std::vector<NamedTable> tables{
      {py::make_tuple("tolerances", "distributions"), settings.distributions.size(), documents::DistributionColumns(settings)},
      {py::make_tuple("summary", "limits"), result.summary.limits.size(), documents::LimitColumns(result.summary)}};
  const auto& names = analysis::ToleranceSettings::FigureNames();
  for (std::size_t f = 0; f < names.size(); ++f) {
    if (!study->Runs(f)) continue;
    const analysis::FigureSensitivity& s = result.summary.sensitivity[f];
    tables.push_back({py::make_tuple("summary", "sensitivity", "figures", names[f], "ranking"), s.keys.size(), documents::RankingColumns(s)});
  }
  return Answer(ExitCode(result.all_succeeded()), documents::Json(deck, *solver, *study, result), ToleranceColumns(*study, kept),
                Tables(tables));
}

/// `ltca optimise`: the search of [optimise] and every evaluation's columns; evaluations replaces
/// the deck's budget, threads 0 is every hardware thread. Checks: [optimise], threads, the
/// solver, the search's.
py::tuple BindOptimise(const Deck& given, const std::string& solver_name, const std::string& kinematics, int threads,
                       std::optional<int> evaluations) {
  const Deck deck = ltca::app::DeckFor(given, kinematics);
  std::optional<ltca::solvers::SolverOptions> solver;
  std::optional<analysis::Optimiser> optimiser;
  std::vector<analysis::DesignEvaluation> history;
  const analysis::OptimiseRun run = WithoutGil([&] {
    const analysis::OptimiseSettings settings = documents::OptimiseSettingsFor(deck, evaluations);
    const int resolved = analysis::ResolveThreads(threads);
    solver = ltca::app::SolverFor(deck, solver_name);
    optimiser.emplace(deck.MakeToleranceCase(), *solver, settings, resolved);
    analysis::OptimiseRunPlan plan;
    plan.sink = [&history](const analysis::DesignEvaluation& e) { history.push_back(e); };
    return analysis::RunOptimisation(*optimiser, plan);
  });
  const analysis::OptimiseSettings& settings = optimiser->settings();
  return Answer(ExitCode(run.best() != nullptr), documents::Json(deck, *solver, settings, run, history),
                OptimiseColumns(settings, history),
                Tables({{py::str("history"), history.size(), documents::Columns(settings, history)},
                        {py::make_tuple("settings", "variables"), settings.variables.size(), documents::VariableColumns(settings)},
                        {py::make_tuple("settings", "constraints"), settings.constraints.size(), documents::ConstraintColumns(settings)},
                        {py::make_tuple("summary", "phases"), run.search.phases.size(), documents::PhaseColumns(run.search)}}));
}

// --- Decks from Python values: the deck writer's TOML, in-memory traces ---

/// numpy.generic, the type of NumPy's scalars (imported once, kept for the module's life).
const py::object& NumpyScalar() {
  static const py::object* generic = new py::object(py::module_::import("numpy").attr("generic"));
  return *generic;
}

/// The ValueError for a value the deck writer cannot write, naming its key `where`.
py::value_error Unwritable(const std::string& where, const py::handle& value, const std::string& expected) {
  return py::value_error(fmt::format("{} = {}: expected {}", where, py::repr(value).cast<std::string>(), expected));
}

/// A str as UTF-8; a ValueError naming `where` for text UTF-8 cannot carry (a lone surrogate).
std::string Utf8(const py::handle& text, const std::string& where) {
  Py_ssize_t size = 0;
  const char* utf8 = PyUnicode_AsUTF8AndSize(text.ptr(), &size);
  if (utf8 == nullptr) {
    PyErr_Clear();
    throw Unwritable(where, text, "text that UTF-8 can carry (no lone surrogates)");
  }
  return {utf8, static_cast<std::size_t>(size)};
}

/// A key of a dict as the deck's key: str(key) in UTF-8.
std::string KeyText(const py::handle& key, const std::string& where) { return Utf8(py::str(key), where); }

/// A Python value as a deck's value (app::TomlValue), `where` its key for messages ("section.key",
/// ".inner" for a table's keys): bool, int (64 bits), float, str, list/tuple/ndarray (an array),
/// dict (an inline table), NumPy scalars and 0-d arrays as their Python values, nested at most
/// DeckLimits::kMaxNesting deep (a list that holds itself is refused, not followed). Anything else
/// (None, a set, a complex number...) is a ValueError naming the key; NaN and inf are written, and
/// the deck reader names the key that refuses them.
ltca::app::TomlValue ToToml(const py::handle& value, const std::string& where, int depth = 0) {
  using ltca::app::TomlValue;
  if (depth > ltca::app::DeckLimits::kMaxNesting) {
    throw Unwritable(where, py::str("..."), fmt::format("lists and tables nested at most {} deep", ltca::app::DeckLimits::kMaxNesting));
  }
  PyObject* o = value.ptr();
  if (PyBool_Check(o)) return {value.cast<bool>()};
  if (PyLong_Check(o)) {
    int overflow = 0;
    const long long i = PyLong_AsLongLongAndOverflow(o, &overflow);
    if (overflow != 0) throw Unwritable(where, value, "an integer from -2**63 to 2**63 - 1 (TOML's 64 bits)");
    if (i == -1 && PyErr_Occurred()) throw py::error_already_set();
    return {static_cast<std::int64_t>(i)};
  }
  if (PyFloat_Check(o)) return {PyFloat_AsDouble(o)};
  if (PyUnicode_Check(o)) return {Utf8(value, where)};
  if (py::isinstance<py::array>(value) && py::reinterpret_borrow<py::array>(value).ndim() == 0) {
    return ToToml(value.attr("item")(), where, depth);
  }
  if (PyList_Check(o) || PyTuple_Check(o) || py::isinstance<py::array>(value)) {
    TomlValue::Array array;
    for (const py::handle item : value) array.push_back(ToToml(item, where, depth + 1));
    return {std::move(array)};
  }
  if (PyDict_Check(o)) {
    TomlValue::Table table;
    for (const auto& [key, item] : py::reinterpret_borrow<py::dict>(value)) {
      const std::string name = KeyText(key, where);
      table.push_back({name, ToToml(item, where + "." + name, depth + 1)});
    }
    return {std::move(table)};
  }
  if (py::isinstance(value, NumpyScalar())) return ToToml(value.attr("item")(), where, depth);
  throw Unwritable(where, value, "a bool, number, string, list or table");
}

/// Deck.from_dict: a deck's text from {"section": {"key": value, ...}, ...} by the deck writer.
std::string TomlDeck(const py::dict& sections) {
  std::vector<std::pair<std::string, ltca::app::TomlValue::Table>> out;
  for (const auto& [section, keys] : sections) {
    const std::string name = KeyText(section, "a section's name");
    if (!PyDict_Check(keys.ptr())) {
      throw py::value_error(fmt::format("[{}]: expected a dict of keys, got {}", name, py::type::of(keys).attr("__name__").cast<std::string>()));
    }
    ltca::app::TomlValue::Table table;
    for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(keys)) {
      const std::string k = KeyText(key, name + ".<a key>");
      table.push_back({k, ToToml(value, name + "." + k)});
    }
    out.emplace_back(name, std::move(table));
  }
  return ltca::app::TomlDeckText(out);
}

/// Deck.set: the override "section.key=value" (the command line's --set) by the deck writer.
std::string TomlSet(const std::string& key, const py::handle& value) { return key + "=" + ltca::app::TomlText(ToToml(value, key)); }

/// Deck.with_measured_profile: the source with the trace as the in-memory file `name`, in the CSV
/// form the deck reader takes (a header abscissa_name, deviation_um; a row per point, the
/// shortest text of each double). abscissa and deviation_um have as many values.
ltca::app::DeckSource WithProfileTrace(const ltca::app::DeckSource& source, const std::string& name, const std::string& abscissa_name,
                                       const std::vector<double>& abscissa, const std::vector<double>& deviation_um) {
  std::string csv = abscissa_name + ", deviation_um\n";
  for (std::size_t i = 0; i < abscissa.size() && i < deviation_um.size(); ++i) {
    csv += fmt::format("{}, {}\n", abscissa[i], deviation_um[i]);
  }
  return source.WithFile(name, std::move(csv));
}

// --- The table ---

/// An analysis's entry: its name in the module, the function that defines its binding there, its
/// docstring.
struct Binding {
  const char* name;
  void (*define)(py::module_& m, const char* name, const char* doc);
  const char* doc;
};

/// Defines Bind as the module's function `name` (pybind11 reads its parameter and return types).
template <auto Bind>
void Define(py::module_& m, const char* name, const char* doc) {
  m.def(name, Bind, doc);
}

/// Every analysis the module binds: one entry each, in the order of the package's functions.
constexpr Binding kBindings[] = {
    {"solve", &Define<&BindSolve>,
     "ltca solve: (the --json document, its summary as a dict, the arrays, whether every [[load_spectrum]] bin succeeded)."},
    {"geometry", &Define<&BindGeometry>, "ltca geometry: (exit code, the --json document, the profile's --csv columns, {})."},
    {"backlash", &Define<&BindBacklash>, "ltca backlash: (exit code, the --json document, {}, the positions' columns)."},
    {"mesh", &Define<&BindMesh>, "ltca mesh: (exit code, the --json document, {}, the pins' columns)."},
    {"compare", &Define<&BindCompare>, "ltca compare: (exit code, the --json document, {}, the solvers' columns)."},
    {"stiffness", &Define<&BindStiffness>, "ltca stiffness: (exit code, the --json document, {}, the positions' columns)."},
    {"efficiency", &Define<&BindEfficiency>, "ltca efficiency: (exit code, the --json document, {}, the positions' columns)."},
    {"tolerance", &Define<&BindTolerance>, "ltca tolerance: (exit code, the --json document, the --csv columns, a row per sample, {})."},
    {"optimise", &Define<&BindOptimise>, "ltca optimise: (exit code, the --json document, the --csv columns, a row per evaluation, the history's columns)."},
};

// --- The generic analyses of the table of analyses (documents/analyses.hpp) ---

/// A keyword argument as an option value: bool, int, float or str (None: not given); TypeError
/// naming the keyword for anything else.
std::optional<documents::OptionValues::Value> OptionValueOf(const std::string& key, const py::handle& value) {
  if (value.is_none()) return std::nullopt;
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value) || (py::hasattr(value, "__index__") && !py::isinstance<py::float_>(value))) {
    const py::int_ whole(py::reinterpret_borrow<py::object>(value));
    try {
      return whole.cast<std::int64_t>();
    } catch (const py::cast_error&) {  // beyond 64 bits: named as every bad value is
      throw std::invalid_argument(key + " = " + std::string(py::repr(whole)) + ": expected a whole number within 64 bits");
    }
  }
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  throw py::type_error(key + " = " + std::string(py::repr(value)) + ": expected a bool, number or string, got " +
                       std::string(py::str(value.get_type().attr("__name__"))));
}

/// A generic analysis: the keyword arguments (Python names, '_' for the option's '-') checked as
/// the command line checks its options, the analysis run without the GIL; (exit code, the --json
/// document, the --csv columns as {name: array}, {} without a per-row table, {}: no nested tables).
py::tuple BindAnalysis(const documents::Analysis& analysis, const Deck& deck, const py::kwargs& kwargs) {
  std::map<std::string, documents::OptionValues::Value> given;
  const std::vector<documents::AnalysisOption> options = documents::AllOptions(analysis);
  for (const auto& [k, v] : kwargs) {
    std::string key = py::str(k);
    std::string name = key;
    std::replace(name.begin(), name.end(), '_', '-');
    const bool known = std::any_of(options.begin(), options.end(), [&](const documents::AnalysisOption& o) { return o.name == name; });
    if (!known) throw py::type_error(analysis.name + "() got an unexpected keyword argument '" + key + "'");
    if (const auto value = OptionValueOf(key, v)) given[name] = *value;
  }
  documents::OptionValues values;
  try {
    values = documents::CompleteOptions(analysis, given);
  } catch (const std::logic_error& e) {
    if (dynamic_cast<const std::invalid_argument*>(&e) != nullptr) throw;
    throw py::type_error(e.what());
  }
  const documents::AnalysisOutput output = WithoutGil([&] { return documents::RunAnalysis(analysis, deck, values); });
  py::dict columns;
  if (output.columns) {
    for (std::size_t k = 0; k < output.columns->header.size(); ++k) {
      columns[py::str(output.columns->header[k])] =
          NumberColumn(output.columns->rows, [k](const std::vector<double>& row) { return k < row.size() ? row[k] : NAN; });
    }
  }
  return Answer(output.exit_code, output.json, columns);
}

/// The table of analyses for the package (ltca/__init__.py makes a function of each generic
/// entry): name, description, whether it is generic, its docstring and its keyword arguments
/// (name, kind, choices, default as text, help).
py::list AnalysesTable() {
  py::list table;
  for (const documents::Analysis& a : documents::Analyses()) {
    py::dict entry;
    entry["name"] = a.name;
    entry["description"] = a.description;
    entry["generic"] = a.generic();
    py::list options;
    for (const documents::AnalysisOption& o : documents::AllOptions(a)) {
      static const char* const kKinds[] = {"real", "integer", "text", "flag", "choice"};
      std::string name = o.name;
      std::replace(name.begin(), name.end(), '-', '_');
      py::dict option;
      option["name"] = name;
      option["kind"] = kKinds[static_cast<int>(o.kind)];
      option["choices"] = o.choices;
      option["default"] = o.default_value;
      option["help"] = o.help;
      options.append(option);
    }
    entry["options"] = options;
    table.append(entry);
  }
  return table;
}

/// The docstring of a generic analysis: the command it mirrors, its description, its keywords.
std::string AnalysisDoc(const documents::Analysis& a) {
  std::string doc = "ltca " + a.name + ": " + a.description + "\n(exit code, the --json document, the --csv columns, {})";
  for (const documents::AnalysisOption& o : a.options) {
    std::string name = o.name;
    std::replace(name.begin(), name.end(), '-', '_');
    doc += "\n  " + name + ": " + o.help + (o.default_value.empty() ? "" : " (default " + o.default_value + ")");
  }
  if (a.load_inputs) doc += "\n  solver, kinematics: as --solver and --kinematics (None: the deck's)";
  return doc;
}

}  // namespace

PYBIND11_MODULE(_ltca, m) {
  m.doc() = "The compiled part of ltca (docs/python.md): use the package's functions, not these.";
  py::class_<Deck>(m, "ParsedDeck", "A deck as the reader of ltca made it (opaque).");
  py::class_<ltca::app::DeckSource>(m, "DeckSource", "A deck's text parsed once (opaque).")
      .def(py::init<std::string, std::string, std::string>())
      .def("read", &ltca::app::DeckSource::Read, "The deck with these overrides; ValueError names the key of bad input.");
  py::class_<Document>(m, "Document", "A JSON document, converted on request.")
      .def("to_python", [](const Document& d) { return ToPython(d.make()); });
  for (const Binding& binding : kBindings) binding.define(m, binding.name, binding.doc);
  // Every generic analysis of the table, a function each; the package wraps them (ltca/__init__.py).
  static std::vector<std::string> docs;  // alive as long as the module
  docs.reserve(documents::Analyses().size());
  for (const documents::Analysis& a : documents::Analyses()) {
    if (!a.generic()) continue;
    docs.push_back(AnalysisDoc(a));
    const documents::Analysis* entry = &a;
    m.def(
        a.name.c_str(), [entry](const Deck& deck, const py::kwargs& kwargs) { return BindAnalysis(*entry, deck, kwargs); },
        docs.back().c_str());
  }
  m.def("_analyses", &AnalysesTable, "The table of analyses: every entry's name, description, kind and options.");
  m.def("_toml_deck", &TomlDeck, "A deck's text from a dict of sections (the deck writer); ValueError names a key it cannot write.");
  m.def("_toml_set", &TomlSet, "The override 'section.key=value' (the deck writer); ValueError names a key it cannot write.");
  m.def("_with_profile_trace", &WithProfileTrace, "A DeckSource with a measured trace as an in-memory file.");
}
