#include "documents/optimise.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "documents/solve.hpp"

namespace ltca::app::documents {
namespace {

/// A number in the CSV: every bit (17 significant digits), empty when not finite.
std::string Cell(double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : std::string(); }

/// The deck of a design: every key the deck gave (after --set), the variables' keys set to the
/// design's values, also where [second_disc] gives its own value of that key (the discs of one
/// part share their design), without [optimise]; `ltca solve` runs it as it is.
std::string DesignDeck(const Deck& deck, const analysis::OptimiseSettings& s, const std::vector<double>& x, const std::string& header) {
  std::vector<DeckEdit> edits;
  for (std::size_t k = 0; k < s.variables.size(); ++k) {
    const std::string& key = s.variables[k].key;
    const std::string section = key.substr(0, key.find('.')), name = key.substr(key.find('.') + 1);
    const std::string value = fmt::format("{}", x[k]);
    edits.push_back({section, name, value, "the optimum"});
    const bool own = std::any_of(deck.given.begin(), deck.given.end(),
                                 [&](const Deck::GivenKey& g) { return g.section == "second_disc" && g.key == name; });
    if (deck.second_disc && own) edits.push_back({"second_disc", name, value, "the optimum"});
  }
  return WriteDeck(deck, edits, {"optimise"}, header);
}

}  // namespace

analysis::OptimiseSettings OptimiseSettingsFor(const Deck& deck, std::optional<int> evaluations) {
  if (!deck.optimise) {
    throw std::invalid_argument(fmt::format(
        "deck '{}': missing section [optimise] for ltca optimise; expected e.g. [optimise] variables = {{ "
        "\"modification.pin_radius_mm\" = [-0.03, 0.0] }}, objective = \"pp_te_arcsec\", constraints = {{ "
        "mean_backlash_arcsec = {{ min = 20, max = 40 }} }} (docs/optimise.md)",
        deck.name));
  }
  analysis::OptimiseSettings settings = *deck.optimise;
  if (evaluations) settings.evaluations = *evaluations;
  return settings;
}

std::string RobustRule(const analysis::OptimiseSettings& s) {
  if (s.confidence <= 0.0) return fmt::format("p{:g} (point estimate)", s.percentile);
  const std::int64_t k = analysis::ConfidenceRank(s.robust_samples, s.percentile / 100.0, s.confidence);
  return fmt::format("p{:g} bounded at confidence {:g} (upper: the {}th smallest, lower: the {}th largest of the {})", s.percentile,
                     s.confidence, k, k, s.robust_samples);
}

nlohmann::json Json(const analysis::OptimiseSettings& s, const analysis::DesignEvaluation& e) {
  nlohmann::json j;
  j["index"] = e.index;
  j["phase"] = e.phase;
  nlohmann::json x = nlohmann::json::object();
  for (std::size_t k = 0; k < s.variables.size() && k < e.x.size(); ++k) x[s.variables[k].key] = e.x[k];
  j["variables"] = x;
  j["objective"] = FiniteOrNull(e.objective);
  j["violation"] = FiniteOrNull(e.violation);
  j["feasible"] = e.feasible;
  j["status"] = analysis::ToString(e.status);
  j["message"] = e.message;
  nlohmann::json f = nlohmann::json::object();
  const auto& names = analysis::OptimiseFigureNames();
  for (std::size_t k = 0; k < names.size(); ++k) f[names[k]] = FiniteOrNull(e.figures[k]);
  j["figures"] = f;
  if (s.robust) j["samples_failed"] = e.samples_failed;
  return j;
}

Table Columns(const analysis::OptimiseSettings& s, const std::vector<analysis::DesignEvaluation>& history) {
  Table t;
  for (const analysis::DesignEvaluation& e : history) {
    t.Add("index", static_cast<double>(e.index));
    t.Add("objective", e.objective);
    t.Add("violation", e.violation);
    if (s.robust) t.Add("samples_failed", static_cast<double>(e.samples_failed));
  }
  return t;
}

Table VariableColumns(const analysis::OptimiseSettings& s) {
  Table t;
  for (const auto& v : s.variables) {
    t.Add("lower", v.lower);
    t.Add("upper", v.upper);
  }
  return t;
}

Table ConstraintColumns(const analysis::OptimiseSettings& s) {
  Table t;
  for (const auto& l : s.constraints) {
    t.Add("min", l.min);
    t.Add("max", l.max);
  }
  return t;
}

Table PhaseColumns(const analysis::OptimiseResult& search) {
  Table t;
  for (const auto& p : search.phases) t.Add("evaluations", static_cast<double>(p.evaluations));
  return t;
}

nlohmann::json OptimiseJsonHead(const Deck& deck, const SolverOptions& solver, const analysis::OptimiseSettings& s,
                                const analysis::OptimiseRun& run) {
  const analysis::OptimiseResult& r = run.search;
  const analysis::DesignEvaluation* best = run.best();
  nlohmann::json j;
  j["case"] = {{"title", deck.info.title}, {"deck", deck.name}};
  if (!deck.source.overrides.empty()) j["case"]["overrides"] = OverrideArguments(deck);
  j["model"] = ModelJson(deck.Model());  // every output names the model that ran
  j["solver"] = SolverJson(deck, solver);
  nlohmann::json vars = nlohmann::json::array();
  for (const auto& v : s.variables) vars.push_back({{"key", v.key}, {"lower", v.lower}, {"upper", v.upper}});
  nlohmann::json cons = nlohmann::json::array();
  for (const auto& l : s.constraints) cons.push_back({{"figure", l.figure}, {"min", FiniteOrNull(l.min)}, {"max", FiniteOrNull(l.max)}});
  j["settings"] = {{"variables", vars}, {"objective", s.objective}, {"maximise", s.maximise}, {"constraints", cons},
                   {"global", analysis::ToString(s.global)}, {"local", analysis::ToString(s.local)}, {"evaluations", s.evaluations},
                   {"global_share", s.global_share}, {"tolerance", s.tolerance}, {"seed", s.seed}, {"robust", s.robust},
                   {"robust_samples", s.robust ? nlohmann::json(s.robust_samples) : nlohmann::json(nullptr)},
                   {"percentile", s.robust ? nlohmann::json(s.percentile) : nlohmann::json(nullptr)},
                   {"confidence", s.robust ? nlohmann::json(s.confidence) : nlohmann::json(nullptr)},
                   {"order_statistic", s.robust && s.confidence > 0.0
                                           ? nlohmann::json(analysis::ConfidenceRank(s.robust_samples, s.percentile / 100.0, s.confidence))
                                           : nlohmann::json(nullptr)},
                   {"penalty_weight", analysis::OptimiseSettings::kPenaltyWeight}, {"threads", run.threads}, {"mpi_ranks", run.ranks}};
  nlohmann::json phases = nlohmann::json::array();
  for (const auto& p : r.phases) phases.push_back({{"method", p.method}, {"evaluations", p.evaluations}, {"stop", p.stop}});
  j["summary"] = {{"status", best != nullptr ? "success" : "failed"},
                  {"evaluations", r.evaluations},
                  {"failed", r.failed},
                  {"rejected", r.rejected},
                  {"first_failure", r.first_failure},
                  {"phases", phases},
                  {"best", best != nullptr ? Json(s, *best) : nlohmann::json(nullptr)},
                  {"wall_seconds", r.wall_seconds}};
  return j;
}

std::string HistoryItem(const analysis::OptimiseSettings& settings, const analysis::DesignEvaluation& e) {
  return (e.index == 0 ? "\n    " : ",\n    ") + Dump(Json(settings, e), -1);
}

namespace {
/// A step of the Pareto front: the second figure, its bound, the step's best design (null: none).
nlohmann::json ParetoJson(const analysis::OptimiseSettings& s, const std::string& figure, const analysis::ParetoPoint& p) {
  return nlohmann::json{{"figure", figure}, {"bound", p.epsilon}, {"design", p.best >= 0 ? Json(s, p.design) : nlohmann::json(nullptr)}};
}
}  // namespace

void WriteOptimiseJson(std::ostream& os, const nlohmann::json& head, const std::function<void(std::ostream&)>& history,
                       const analysis::OptimiseSettings& s, const analysis::OptimiseRun& run) {
  // The history, the map and the front are streamed one evaluation at a time after the rest of
  // the document: the whole document as one JSON value took about 9 KB an evaluation.
  os << OpenObject(head);
  const auto stream_array = [&os](const char* key, std::size_t n, const auto& item) {
    os << ",\n  \"" << key << "\": [";
    for (std::size_t i = 0; i < n; ++i) os << (i == 0 ? "\n    " : ",\n    ") << Dump(item(i), -1);
    os << (n == 0 ? "]" : "\n  ]");
  };
  os << ",\n  \"history\": [";
  history(os);
  os << (run.search.evaluations == 0 ? "]" : "\n  ]");
  if (!run.grid.empty()) stream_array("map", run.grid.size(), [&](std::size_t i) { return Json(s, run.grid[i]); });
  if (!run.front.empty()) stream_array("pareto", run.front.size(), [&](std::size_t i) { return ParetoJson(s, run.pareto, run.front[i]); });
  os << "\n}\n";
}

nlohmann::json Json(const Deck& deck, const SolverOptions& solver, const analysis::OptimiseSettings& s, const analysis::OptimiseRun& run,
                    const std::vector<analysis::DesignEvaluation>& history) {
  nlohmann::json doc = OptimiseJsonHead(deck, solver, s, run);
  nlohmann::json items = nlohmann::json::array();
  for (const auto& e : history) items.push_back(Json(s, e));
  doc["history"] = std::move(items);
  if (!run.grid.empty()) {
    nlohmann::json map = nlohmann::json::array();
    for (const auto& e : run.grid) map.push_back(Json(s, e));
    doc["map"] = std::move(map);
  }
  if (!run.front.empty()) {
    nlohmann::json front = nlohmann::json::array();
    for (const auto& p : run.front) front.push_back(ParetoJson(s, run.pareto, p));
    doc["pareto"] = std::move(front);
  }
  return doc;
}

std::string OptimiseTextHead(const Deck& deck, const SolverOptions& solver, const analysis::OptimiseSettings& s, int threads, int ranks) {
  std::string text = CaseLines(deck, 12);
  text += ModelLine(deck);
  text += SolverLine(deck, solver);
  text += fmt::format("objective   {} {}{}\n", s.maximise ? "maximise" : "minimise", s.objective,
                      s.robust ? fmt::format(" (robust: {} over {} samples of [tolerances], seed {})", RobustRule(s), s.robust_samples,
                                             s.tolerances.seed)
                               : "");
  for (const auto& v : s.variables) text += fmt::format("variable    {} in [{:g}, {:g}]\n", v.key, v.lower, v.upper);
  for (const auto& l : s.constraints) text += fmt::format("constraint  {:g} <= {} <= {:g}\n", l.min, l.figure, l.max);
  text += fmt::format("method      {} then {}, {} evaluations, {} thread(s){}\n", analysis::ToString(s.global), analysis::ToString(s.local),
                      s.evaluations, threads, ranks > 1 ? fmt::format(" on each of {} MPI ranks", ranks) : "");
  return text;
}

std::string Text(const analysis::OptimiseSettings& s, const analysis::OptimiseRun& run) {
  const analysis::OptimiseResult& r = run.search;
  std::string text;
  for (const auto& p : r.phases) text += fmt::format("phase       {}: {} evaluations, stopped: {}\n", p.method, p.evaluations, p.stop);
  text += fmt::format("evaluations {} ({} failed, {} rejected){}\n", r.evaluations, r.failed, r.rejected,
                      r.first_failure.empty() ? "" : "; first: " + r.first_failure);
  if (const analysis::DesignEvaluation* best = run.best()) {
    text += fmt::format("best        evaluation {} ({}): {} = {:.10g}\n", best->index, best->phase, s.objective, best->objective);
    for (std::size_t k = 0; k < s.variables.size(); ++k) text += fmt::format("            {} = {:.10g}\n", s.variables[k].key, best->x[k]);
  } else {
    text += "best        none: no evaluation met the constraints\n";
  }
  for (const auto& p : run.front) {
    text += fmt::format("pareto      {} <= {:g}: {}\n", run.pareto, p.epsilon,
                        p.best >= 0 ? fmt::format("{} = {:.6g}", s.objective, p.design.objective) : std::string("nothing feasible"));
  }
  return text;
}

std::string OptimiseCsvHead(const analysis::OptimiseSettings& s) {
  std::string c = "index,phase";
  for (const auto& v : s.variables) c += ',' + v.key;
  c += ",objective,violation,feasible,status";
  for (const auto& f : analysis::OptimiseFigureNames()) c += ',' + f;
  return c + ",message\n";
}

std::string Csv(const analysis::DesignEvaluation& e) {
  std::string c = fmt::format("{},{}", e.index, e.phase);
  for (const double v : e.x) c += ',' + Cell(v);
  c += ',' + Cell(e.objective) + ',' + Cell(e.violation) + ',' + (e.feasible ? "true" : "false") + ',' + analysis::ToString(e.status);
  for (const double v : e.figures) c += ',' + Cell(v);
  std::string m = e.message;
  std::replace(m.begin(), m.end(), '"', '\'');
  return c + ",\"" + m + "\"\n";
}

OptimiseSeries::OptimiseSeries(const analysis::OptimiseSettings& settings, bool path)
    : maximise_(settings.maximise), path_(path), feasible_(settings.evaluations), infeasible_(settings.evaluations),
      best_(settings.evaluations), drawn_path_(settings.evaluations), best_so_far_(std::numeric_limits<double>::quiet_NaN()) {}

void OptimiseSeries::Add(const analysis::DesignEvaluation& e) {
  // The path over the first two variables (with a map): every evaluation, failed ones too,
  // judged by the objective.
  if (path_) drawn_path_.Add(e.index, e.x[0], e.x[1], e.status == analysis::RunStatus::kSuccess ? e.objective : NAN);
  if (e.status != analysis::RunStatus::kSuccess) return;  // failed evaluations are not drawn
  const auto at = static_cast<double>(e.index);
  (e.feasible ? feasible_ : infeasible_).Add(e.index, at, e.objective);
  if (e.feasible && (std::isnan(best_so_far_) || (maximise_ ? e.objective > best_so_far_ : e.objective < best_so_far_))) best_so_far_ = e.objective;
  if (std::isfinite(best_so_far_)) best_.Add(e.index, at, best_so_far_);
}

plots::Figure Figure(const Deck& deck, const analysis::OptimiseSettings& s, const analysis::OptimiseRun& run, OptimiseSeries& series) {
  const analysis::OptimiseResult& r = run.search;
  const analysis::DesignEvaluation* best = run.best();
  const std::vector<analysis::DesignEvaluation>& grid = run.grid;
  plots::Figure figure;
  figure.title = fmt::format("{}: {} {} over {} evaluations ({} then {})", CaseTitle(deck), s.maximise ? "maximise" : "minimise",
                             s.objective, r.evaluations, analysis::ToString(s.global), analysis::ToString(s.local));
  const std::int64_t stride = series.feasible_.stride();
  figure.caption = FigureCaption(deck, fmt::format("{}; infeasible: a constraint not met; failed evaluations are not drawn{}{}",
                                                   s.robust ? fmt::format("robust: {} of {} samples", RobustRule(s), s.robust_samples) : "nominal pair",
                                                   grid.empty() ? "" : "; map: blank cells are infeasible",
                                                   stride > 1 ? fmt::format("; drawn: the least and largest objective of every {} evaluations", stride)
                                                              : std::string()));
  plots::Panel c;
  c.title = "convergence";
  c.x_label = "evaluation";
  c.y_label = s.objective;
  plots::Series feasible{"feasible", series.feasible_.x(), series.feasible_.y(), plots::Style::kMarkers},
      infeasible{"infeasible", series.infeasible_.x(), series.infeasible_.y(), plots::Style::kMarkers},
      best_line{"best feasible so far", series.best_.x(), series.best_.y(), plots::Style::kLine};
  infeasible.marker_size = 0.6;
  c.series = {feasible, infeasible, best_line};
  c.legend = plots::LegendPlace::kOutsideRight;
  figure.panels.push_back(c);
  if (!grid.empty()) {
    plots::Panel m;
    m.title = "objective over the two variables";
    m.x_label = s.variables[0].key;
    m.y_label = s.variables[1].key;
    plots::Map map;
    map.z_label = s.objective;
    const auto n = static_cast<std::size_t>(run.map);
    for (std::size_t i = 0; i < n; ++i) map.x.push_back(grid[i].x[0]);
    for (std::size_t k = 0; k < n; ++k) map.y.push_back(grid[k * n].x[1]);
    map.z.assign(n, std::vector<double>(n, std::numeric_limits<double>::quiet_NaN()));
    for (std::size_t k = 0; k < n; ++k) {
      for (std::size_t i = 0; i < n; ++i) {
        const auto& e = grid[k * n + i];
        if (e.feasible) map.z[i][k] = e.objective;
      }
    }
    m.map = map;
    plots::Series path{"evaluations", series.drawn_path_.x(), series.drawn_path_.y(), plots::Style::kMarkers};
    path.marker_size = 0.4;
    path.colour = 7;
    m.series.push_back(path);
    if (best != nullptr) {
      plots::Series opt{"optimum", {best->x[0]}, {best->x[1]}, plots::Style::kMarkers};
      opt.colour = 1;
      opt.marker_size = 1.6;
      m.series.push_back(opt);
    }
    m.legend = plots::LegendPlace::kBottomRight;  // the colour bar is on the right
    figure.panels.push_back(m);
  }
  if (!run.front.empty()) {
    plots::Panel p;
    p.title = "Pareto front (epsilon constraints)";
    p.x_label = run.pareto;
    p.y_label = s.objective;
    plots::Series pts{"front", {}, {}, plots::Style::kLineMarkers};
    const int fi = analysis::FigureIndex(run.pareto);
    for (const auto& q : run.front) {
      if (q.best < 0) continue;
      pts.x.push_back(q.design.figures[static_cast<std::size_t>(fi)]);
      pts.y.push_back(q.design.objective);
    }
    p.series.push_back(pts);
    figure.panels.push_back(p);
  }
  figure.columns = static_cast<int>(figure.panels.size());
  figure.width = figure.columns == 1 ? 1000 : 700 * figure.columns;  // one panel: room for the legend beside it
  figure.height = 600;
  return figure;
}

std::string BestDesignDeck(const Deck& deck, const analysis::OptimiseSettings& s, const analysis::OptimiseRun& run) {
  const analysis::DesignEvaluation& best = *run.best();
  const std::string header = fmt::format("# Written by ltca optimise from {}: the best of {} evaluations, {} = {:.10g}.\n"
                                         "# ltca solve runs it as it is; [optimise] is left out.\n",
                                         deck.name, run.search.evaluations, s.objective, best.objective);
  return DesignDeck(deck, s, best.x, header);
}

}  // namespace ltca::app::documents
