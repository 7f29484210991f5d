// The compiled part of the Python module `ltca` (issue 30, docs/python.md): decks read by the same
// reader as the command line, the analyses run by the same library, and their documents built by
// the same functions as the command line's JSON, handed to Python as dicts (JSON null as None) with
// NumPy arrays beside them. The Python API (ltca/__init__.py) wraps these functions.
//
// Errors: bad input (std::invalid_argument, naming the key) becomes ValueError, as pybind11
// translates it; a solve that fails is a status in the result, not an exception. The GIL is
// released while the library computes, so Python threads may run other decks meanwhile.
#include <algorithm>
#include <memory>
#include <cmath>
#include <cstdint>
#include <functional>
#include <tuple>
#include <type_traits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "documents/backlash.hpp"
#include "documents/compare.hpp"
#include "documents/efficiency.hpp"
#include "documents/optimise.hpp"
#include "documents/geometry.hpp"
#include "documents/mesh.hpp"
#include "documents/solve.hpp"
#include "documents/stiffness.hpp"
#include "documents/tolerance.hpp"
#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/compare.hpp"
#include "ltca/analysis/efficiency.hpp"
#include "ltca/analysis/mesh.hpp"
#include "ltca/analysis/optimise.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/tolerance_run.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/exit_codes.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"

namespace py = pybind11;

namespace {

using ltca::app::Deck;

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

py::array_t<double> Vector(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

/// `ltca solve`: the document its --json writes and the arrays of the sweep. A failed position's
/// row of an array is NaN (its JSON figures are null).
py::tuple Solve(const Deck& given, const std::string& solver_name, const std::string& kinematics, const py::object& progress) {
  const Deck deck = ltca::app::DeckFor(given, kinematics);
  const ltca::solvers::SolverOptions solver = ltca::app::SolverFor(deck, solver_name);
  deck.RequireMaterial();
  ltca::app::SweepResult sweep;
  ltca::app::SweepCallbacks callbacks;
  if (!progress.is_none()) {  // progress(done, total) after each position, with the GIL held for it
    const auto total = static_cast<std::int64_t>(deck.sweep.positions);
    auto done = std::make_shared<std::int64_t>(0);
    callbacks.on_position = [&progress, total, done](const ltca::app::PositionResult&) {
      py::gil_scoped_acquire gil;
      progress(++*done, total);
    };
  }
  {
    py::gil_scoped_release release;
    sweep = ltca::app::SolveDeckSweep(deck, solver, callbacks);
  }
  py::object summary = ToPython(ltca::app::documents::Json(deck, sweep.summary));
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
  // The whole document is built when Python asks for it, from the sweep kept for it.
  auto kept = std::make_shared<const std::tuple<Deck, ltca::solvers::SolverOptions, ltca::app::SweepResult>>(deck, solver, std::move(sweep));
  Document document{[kept] { return ltca::app::documents::Json(std::get<0>(*kept), std::get<1>(*kept), std::get<2>(*kept)); }};
  return py::make_tuple(document, summary, arrays);
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
  m.def("solve", &Solve, "ltca solve: (the --json document, its summary as a dict, the arrays).");
  // The other analyses: (exit code, the --json document, the --csv columns as {name: array} or {}).
  using Strings = std::vector<std::string>;
  // The derived geometry of the pair as made, in this process: its document and the profile's columns
  // by the command's builders. (The crank is the drawing's, which Python does not draw.)
  m.def("geometry", [](const Deck& deck, double /*crank_deg*/, int samples_per_flank) {
    nlohmann::json doc;
    ltca::app::documents::ProfileColumns profile;
    {
      py::gil_scoped_release release;
      const ltca::geometry::RealPair real = deck.MakeRealPair();
      doc = ltca::app::documents::Json(deck, real);
      profile = ltca::app::documents::Columns(real.profile(), samples_per_flank);
    }
    py::dict columns;  // the --csv columns, numbers as arrays
    columns["tooth_space"] = Vector(profile.tooth_space);
    columns["u_deg"] = Vector(profile.u_deg);
    columns["x_mm"] = Vector(profile.x_mm);
    columns["y_mm"] = Vector(profile.y_mm);
    columns["normal_x"] = Vector(profile.normal_x);
    columns["normal_y"] = Vector(profile.normal_y);
    columns["curvature_radius_mm"] = Vector(profile.curvature_radius_mm);
    columns["part"] = py::cast(profile.part);
    return py::make_tuple(ltca::app::kExitSuccess, ToPython(doc), columns);
  });
  // The unloaded backlash from its result in this process, its document by the command's builder.
  m.def("backlash", [](const Deck& deck, const std::string& kinematics) {
    const ltca::contact::ContactKinematics k = kinematics.empty() ? deck.kinematics : ltca::contact::ParseKinematics(kinematics);
    std::vector<ltca::analysis::BacklashPosition> positions;
    std::optional<ltca::analysis::BacklashResult> result;
    {
      py::gil_scoped_release release;
      const ltca::analysis::Stage stage(deck, deck.sweep.CrankAngles());
      result = ltca::analysis::Backlash(stage, k, [&](const ltca::analysis::BacklashPosition& p) { positions.push_back(p); });
    }
    const int code = result->summary.failed() == 0 ? ltca::app::kExitSuccess : ltca::app::kExitNotSucceeded;
    return py::make_tuple(code, ToPython(ltca::app::documents::Json(deck, positions, *result)), py::dict());
  });
  // The mesh state at one crank from its result in this process, its document by the command's builder.
  m.def("mesh", [](const Deck& deck, double crank_deg) {
    std::optional<ltca::analysis::MeshResult> mesh;
    {
      py::gil_scoped_release release;
      mesh = ltca::analysis::MeshAt(deck.MakeModel(), crank_deg);
    }
    return py::make_tuple(ltca::app::kExitSuccess, ToPython(ltca::app::documents::Json(deck, *mesh)), py::dict());
  });
  // Several solvers on the deck's sweep from their result in this process, its document by the
  // command's builder (every registered solver when `solvers` is empty).
  m.def("compare", [](const Deck& given, const Strings& names, const std::string& kinematics) {
    std::optional<ltca::app::Deck> deck;
    std::optional<ltca::analysis::CompareResult> result;
    {
      py::gil_scoped_release release;
      deck = ltca::app::DeckFor(given, kinematics);
      const Strings asked = names.empty() ? ltca::solvers::SolverNames() : names;
      // The command's order of the checks: [material], [load], the solvers, then the stage.
      deck->RequireMaterial();
      const double torque = deck->RequireLoad().torque;
      const ltca::analysis::SolverSelection selection = ltca::analysis::SelectSolvers(asked, deck->reducer.has_value(), deck->name);
      result = ltca::analysis::Compare(deck->MakeStage(), deck->solver, selection.run, torque, selection.skipped);
    }
    const int code = result->all_succeeded() ? ltca::app::kExitSuccess : ltca::app::kExitNotSucceeded;
    return py::make_tuple(code, ToPython(ltca::app::documents::Json(*deck, *result)), py::dict());
  });
  // The torque-twist loop from its result in this process, its document by the command's builder.
  // crank_deg (deg) and steps replace the deck's [stiffness] crank_deg and steps_per_branch.
  m.def("stiffness", [](const Deck& given, const std::string& solver_name, const std::string& kinematics,
                        std::optional<double> crank_deg, std::optional<int> steps) {
    std::optional<ltca::app::Deck> deck;
    std::optional<ltca::solvers::SolverOptions> solver;
    std::optional<ltca::analysis::StiffnessResult> result;
    {
      py::gil_scoped_release release;
      deck = ltca::app::DeckFor(given, kinematics);
      solver = ltca::app::SolverFor(*deck, solver_name);
      ltca::analysis::StiffnessSettings settings = deck->stiffness;
      if (crank_deg) settings.crank = ltca::units::DegToRad(*crank_deg);
      if (steps) settings.steps = *steps;
      settings.Validate();
      // The command's order of the checks: [material], [load], then the stage and the runner.
      deck->RequireMaterial();
      const double torque = deck->RequireLoad().torque;
      result = ltca::analysis::Stiffness(
          deck->MakeStage(settings.crank ? std::vector<double>{*settings.crank} : deck->sweep.CrankAngles()), *solver, settings,
          torque, deck->friction);
    }
    const int code = result->all_succeeded() ? ltca::app::kExitSuccess : ltca::app::kExitNotSucceeded;
    return py::make_tuple(code, ToPython(ltca::app::documents::Json(*deck, *solver, *result)), py::dict());
  });
  // Friction, power loss and efficiency over the sweep from its result in this process, its
  // document by the command's builder.
  m.def("efficiency", [](const Deck& given, const std::string& solver_name, const std::string& kinematics) {
    std::optional<ltca::app::Deck> deck;
    std::optional<ltca::solvers::SolverOptions> solver;
    std::vector<ltca::analysis::EfficiencyPosition> positions;
    std::optional<ltca::analysis::EfficiencySummary> summary;
    {
      py::gil_scoped_release release;
      deck = ltca::app::DeckFor(given, kinematics);
      solver = ltca::app::SolverFor(*deck, solver_name);
      // The command's order of the checks: [material], [friction], [operation], [load].
      deck->RequireMaterial();
      const ltca::app::FrictionSettings& friction = deck->RequireFriction();
      const ltca::app::OperationSettings& operation = deck->RequireOperation();
      const double torque = deck->RequireLoad().torque;
      ltca::analysis::EfficiencyRunner runner(deck->MakeStage(), *solver, torque, friction, operation);
      for (const double crank : runner.cranks()) positions.push_back(runner.Solve(crank));
      summary = runner.Summary();
    }
    const int code = summary->all_succeeded() ? ltca::app::kExitSuccess : ltca::app::kExitNotSucceeded;
    return py::make_tuple(code, ToPython(ltca::app::documents::Json(*deck, *solver, positions, *summary)), py::dict());
  });
  // The tolerance study from its result in this process: its document by the command's builder,
  // and the samples as the --csv columns (sample, status, every input, every figure the study
  // runs, message): NumPy arrays of numbers (NaN where not finite), status and messages as lists
  // of text (the messages an array of NaN when every sample succeeded).
  m.def("tolerance", [](const Deck& given, const std::string& solver_name, const std::string& kinematics,
                        std::optional<std::int64_t> samples, std::optional<std::uint64_t> seed, int threads, bool lost_motion,
                        bool no_worst_case) {
    namespace analysis = ltca::analysis;
    std::optional<ltca::app::Deck> deck;
    std::optional<ltca::solvers::SolverOptions> solver;
    std::optional<analysis::ToleranceStudy> study;
    std::optional<analysis::ToleranceResult> result;
    std::vector<analysis::ToleranceSample> kept;
    {
      py::gil_scoped_release release;
      deck = ltca::app::DeckFor(given, kinematics);
      // The command's order of the checks: [tolerances], --threads, the solver, the study's.
      const analysis::ToleranceSettings settings = ltca::app::documents::ToleranceSettingsFor(*deck, samples, seed, lost_motion);
      analysis::ToleranceRunPlan plan;
      plan.threads = analysis::ResolveThreads(threads);
      solver = ltca::app::SolverFor(*deck, solver_name);
      study.emplace(deck->MakeToleranceCase(), *solver, settings);
      plan.worst_case = !no_worst_case;
      plan.sink = [&kept](const analysis::ToleranceSample& s) { kept.push_back(s); };
      result = analysis::RunToleranceStudy(*study, plan);
    }
    const auto finite = [](double v) { return std::isfinite(v) ? v : NAN; };
    py::dict columns;
    std::vector<double> index;
    py::list status, messages;
    bool any_message = false;
    for (const auto& s : kept) {
      index.push_back(static_cast<double>(s.index));
      status.append(py::str(analysis::ToString(s.status)));
      std::string message = s.message;  // as the CSV carries it: line breaks as spaces
      for (char& c : message) c = (c == '\n' || c == '\r') ? ' ' : c;
      any_message = any_message || !message.empty();
      messages.append(py::str(message));
    }
    columns["sample"] = Vector(index);
    columns["status"] = status;
    for (std::size_t i = 0; i < study->inputs().size(); ++i) {
      std::vector<double> v;
      for (const auto& s : kept) v.push_back(finite(s.inputs[i]));
      columns[py::str(study->inputs()[i].name)] = Vector(v);
    }
    const auto& names = analysis::ToleranceSettings::FigureNames();
    for (std::size_t f = 0; f < names.size(); ++f) {
      if (!study->Runs(f)) continue;
      std::vector<double> v;
      for (const auto& s : kept) v.push_back(finite(s.figures[f]));
      columns[py::str(names[f])] = Vector(v);
    }
    if (any_message) {
      columns["message"] = messages;
    } else {
      columns["message"] = Vector(std::vector<double>(kept.size(), NAN));
    }
    const int code = result->all_succeeded() ? ltca::app::kExitSuccess : ltca::app::kExitNotSucceeded;
    return py::make_tuple(code, ToPython(ltca::app::documents::Json(*deck, *solver, *study, *result)), columns);
  });
  // The search of [optimise] from its result in this process: its document by the command's
  // builder (the history kept from the sink), and every evaluation as the --csv columns (index,
  // phase, the variables, objective, violation, feasible, status, every figure, message): NumPy
  // arrays of numbers (NaN where not finite), the others lists of text (the messages an array of
  // NaN when none has one).
  m.def("optimise", [](const Deck& given, const std::string& solver_name, const std::string& kinematics, int threads,
                       std::optional<int> evaluations) {
    namespace analysis = ltca::analysis;
    std::optional<ltca::app::Deck> deck;
    std::optional<ltca::solvers::SolverOptions> solver;
    std::optional<analysis::Optimiser> optimiser;
    std::optional<analysis::OptimiseRun> run;
    std::vector<analysis::DesignEvaluation> history;
    {
      py::gil_scoped_release release;
      deck = ltca::app::DeckFor(given, kinematics);
      // The command's order of the checks: [optimise], --threads, the solver, the search's.
      const analysis::OptimiseSettings settings = ltca::app::documents::OptimiseSettingsFor(*deck, evaluations);
      const int resolved = analysis::ResolveThreads(threads);
      solver = ltca::app::SolverFor(*deck, solver_name);
      optimiser.emplace(deck->MakeToleranceCase(), *solver, settings, resolved);
      analysis::OptimiseRunPlan plan;
      plan.sink = [&history](const analysis::DesignEvaluation& e) { history.push_back(e); };
      run = analysis::RunOptimisation(*optimiser, plan);
    }
    const analysis::OptimiseSettings& s = optimiser->settings();
    const auto finite = [](double v) { return std::isfinite(v) ? v : NAN; };
    const auto numbers = [&](const auto& value) {
      std::vector<double> v;
      for (const auto& e : history) v.push_back(finite(value(e)));
      return Vector(v);
    };
    py::dict columns;
    py::list phase, feasible, status, messages;
    bool any_message = false;
    for (const auto& e : history) {
      phase.append(py::str(e.phase));
      feasible.append(py::str(e.feasible ? "true" : "false"));
      status.append(py::str(analysis::ToString(e.status)));
      std::string message = e.message;  // as the CSV carries it: double quotes as single ones
      std::replace(message.begin(), message.end(), '"', '\'');
      any_message = any_message || !message.empty();
      messages.append(py::str(message));
    }
    columns["index"] = numbers([](const analysis::DesignEvaluation& e) { return static_cast<double>(e.index); });
    columns["phase"] = phase;
    for (std::size_t k = 0; k < s.variables.size(); ++k) {
      columns[py::str(s.variables[k].key)] = numbers([k](const analysis::DesignEvaluation& e) { return e.x[k]; });
    }
    columns["objective"] = numbers([](const analysis::DesignEvaluation& e) { return e.objective; });
    columns["violation"] = numbers([](const analysis::DesignEvaluation& e) { return e.violation; });
    columns["feasible"] = feasible;
    columns["status"] = status;
    const auto& names = analysis::OptimiseFigureNames();
    for (std::size_t f = 0; f < names.size(); ++f) {
      columns[py::str(names[f])] = numbers([f](const analysis::DesignEvaluation& e) { return e.figures[f]; });
    }
    if (any_message) {
      columns["message"] = messages;
    } else {
      columns["message"] = Vector(std::vector<double>(history.size(), NAN));
    }
    const int code = run->best() != nullptr ? ltca::app::kExitSuccess : ltca::app::kExitNotSucceeded;
    return py::make_tuple(code, ToPython(ltca::app::documents::Json(*deck, *solver, s, *run, history)), columns);
  });
}
