// `ltca optimise` (issue 28, docs/optimise.md): the design that meets the deck's [optimise]
// constraints with the best objective, by NLopt's global search and local polish over a few keys
// of [modification] and [errors]; the history of evaluations, a convergence figure (with the
// objective's map over two variables), the best design written as a deck, a Pareto front.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "optimise_command.hpp"

#include "command.hpp"
#include "output.hpp"
#include "solve_command.hpp"
#include "tolerance_command.hpp"
#include "ltca/analysis/tolerance_run.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"

namespace ltca::cli {
namespace {

nlohmann::json EvaluationJson(const app::OptimiseSettings& s, const app::DesignEvaluation& e) {
  nlohmann::json j;
  j["index"] = e.index;
  j["phase"] = e.phase;
  nlohmann::json x = nlohmann::json::object();
  for (std::size_t k = 0; k < s.variables.size() && k < e.x.size(); ++k) x[s.variables[k].key] = e.x[k];
  j["variables"] = x;
  j["objective"] = FiniteOrNull(e.objective);
  j["violation"] = FiniteOrNull(e.violation);
  j["feasible"] = e.feasible;
  j["status"] = app::ToString(e.status);
  j["message"] = e.message;
  nlohmann::json f = nlohmann::json::object();
  const auto& names = app::OptimiseFigureNames();
  for (std::size_t k = 0; k < names.size(); ++k) f[names[k]] = FiniteOrNull(e.figures[k]);
  j["figures"] = f;
  if (s.robust) j["samples_failed"] = e.samples_failed;
  return j;
}

/// How a robust design's figures are taken: "p95 at confidence 0.9 (the 64th of 64 samples)".
std::string RobustRule(const app::OptimiseSettings& s) {
  if (s.confidence <= 0.0) return fmt::format("p{:g} (point estimate)", s.percentile);
  const std::int64_t k = app::ConfidenceRank(s.robust_samples, s.percentile / 100.0, s.confidence);
  return fmt::format("p{:g} bounded at confidence {:g} (upper: the {}th smallest, lower: the {}th largest of the {})", s.percentile,
                     s.confidence, k, k, s.robust_samples);
}

/// The deck of a design: every key the deck gave (after --set), the variables' keys set to the
/// design's values, without [optimise]; `ltca solve` runs it as it is.
/// The best design as a deck: the deck's own text (comments and empty sections kept) with the
/// optimum of every variable, also where [second_disc] gives its own value of that key (the
/// discs of one part share their design), and without [optimise].
std::string DesignDeck(const app::Deck& deck, const app::OptimiseSettings& s, const std::vector<double>& x,
                       const std::string& header) {
  std::vector<app::DeckEdit> edits;
  for (std::size_t k = 0; k < s.variables.size(); ++k) {
    const std::string& key = s.variables[k].key;
    const std::string section = key.substr(0, key.find('.')), name = key.substr(key.find('.') + 1);
    const std::string value = fmt::format("{}", x[k]);
    edits.push_back({section, name, value, "the optimum"});
    const bool own = std::any_of(deck.given.begin(), deck.given.end(),
                                 [&](const app::Deck::GivenKey& g) { return g.section == "second_disc" && g.key == name; });
    if (deck.second_disc && own) edits.push_back({"second_disc", name, value, "the optimum"});
  }
  return app::WriteDeck(deck, edits, {"optimise"}, header);
}

}  // namespace

int RunOptimise(const app::Deck& deck_given, const OptimiseOptions& o, const Streams& streams) {
  const app::Deck deck = DeckFor(deck_given, o.kinematics);
  if (!deck.optimise) {
    throw std::invalid_argument(fmt::format(
        "deck '{}': missing section [optimise] for ltca optimise; expected e.g. [optimise] variables = {{ "
        "\"modification.pin_radius_mm\" = [-0.03, 0.0] }}, objective = \"pp_te_arcsec\", constraints = {{ "
        "mean_backlash_arcsec = {{ min = 20, max = 40 }} }} (docs/optimise.md)",
        deck.name));
  }
  app::OptimiseSettings settings = *deck.optimise;
  if (o.evaluations) settings.evaluations = *o.evaluations;
  const int threads = analysis::ResolveThreads(o.threads);  // the rule of every command with threads
  if (o.map != 0 && (o.map < 2 || o.map > 201)) throw std::invalid_argument(fmt::format("--map {}: expected 2 to 201 points a variable", o.map));
  if (o.map != 0 && settings.variables.size() != 2) {
    throw std::invalid_argument(fmt::format("--map {}: the map is drawn over two variables; [optimise] has {}", o.map, settings.variables.size()));
  }
  // Under mpirun every rank runs the search in lockstep and shares what divides (a robust design's
  // samples, the map's points, the Pareto steps); rank 0 alone writes.
  std::unique_ptr<SampleFarm> farm = MakeSampleFarm();
  app::RankGroup ranks;
  if (farm) {
    ranks.rank = farm->rank();
    ranks.size = farm->size();
    ranks.all_gather = [f = farm.get()](const std::string& mine) { return f->AllGather(mine); };
  }
  return FailTogether(farm.get(), streams.err, [&]() -> int {
    const bool root = ranks.rank == 0;
    const solvers::SolverOptions solver = SolverFor(deck, o.solver);
    const app::Optimiser optimiser(deck.MakeToleranceCase(), solver, settings, threads, ranks);
    if (!o.pareto.empty() && !(std::isfinite(o.pareto_from) && std::isfinite(o.pareto_to))) {
      throw std::invalid_argument("--pareto FIGURE: expected --pareto-from and --pareto-to, the range of its bound");
    }
    RequireDistinctOutputs({{"--json", o.json_path}, {"--csv", o.csv_path}, {"--svg", o.svg_path}, {"--write-deck", o.deck_path}});
    Output json("--json", root ? o.json_path : "", streams.out);
    Output csv("--csv", root ? o.csv_path : "", streams.out);
    Output svg("--svg", root ? o.svg_path : "", streams.out);
    Output best_deck("--write-deck", root ? o.deck_path : "", streams.out);
    std::ostringstream quiet;
    std::ostream& text = root ? streams.text : quiet;
    const auto& s = optimiser.settings();
    fmt::print(text, "case        {}\n", deck.info.title);
    fmt::print(text, "{}", ModelLine(deck));
    text << SolverLine(deck, solver);
    fmt::print(text, "objective   {} {}{}\n", s.maximise ? "maximise" : "minimise", s.objective,
               s.robust ? fmt::format(" (robust: {} over {} samples of [tolerances], seed {})", RobustRule(s), s.robust_samples, s.tolerances.seed) : "");
    for (const auto& v : s.variables) fmt::print(text, "variable    {} in [{:g}, {:g}]\n", v.key, v.lower, v.upper);
    for (const auto& l : s.constraints) fmt::print(text, "constraint  {:g} <= {} <= {:g}\n", l.min, l.figure, l.max);
    fmt::print(text, "method      {} then {}, {} evaluations, {} thread(s){}\n", app::ToString(s.global), app::ToString(s.local), s.evaluations,
               threads, ranks.size > 1 ? fmt::format(" on each of {} MPI ranks", ranks.size) : "");

    // The history goes out as the evaluations are made (issue 46): the search keeps none of them.
    // The CSV's rows into the output's own (staged) file; the JSON's items into a spool, copied
    // after the summary, which comes first in the document and is known only at the end; the
    // figure's series decimated (DecimatedSeries: at most about 2,000 runs of evaluations).
    std::unique_ptr<Spool> history;
    if (json.enabled()) history = std::make_unique<Spool>("--json", o.json_path);
    const auto cell = [](double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : std::string(); };
    const auto row = [&](const app::DesignEvaluation& e) {
      std::ostream& c = csv.stream();
      c << e.index << ',' << e.phase;
      for (const double v : e.x) c << ',' << cell(v);
      c << ',' << cell(e.objective) << ',' << cell(e.violation) << ',' << (e.feasible ? "true" : "false") << ',' << app::ToString(e.status);
      for (const double v : e.figures) c << ',' << cell(v);
      std::string m = e.message;
      std::replace(m.begin(), m.end(), '"', '\'');
      c << ",\"" << m << "\"\n";
    };
    if (csv.enabled()) {
      std::ostream& c = csv.stream();
      c << "index,phase";
      for (const auto& v : s.variables) c << ',' << v.key;
      c << ",objective,violation,feasible,status";
      for (const auto& f : app::OptimiseFigureNames()) c << ',' << f;
      c << ",message\n";
    }
    const std::int64_t expected = s.evaluations;
    DecimatedSeries drawn_feasible(expected), drawn_infeasible(expected), drawn_best(expected), drawn_path(expected);
    double best_so_far = std::numeric_limits<double>::quiet_NaN();
    const app::EvaluationSink sink = [&](const app::DesignEvaluation& e) {
      if (history) {
        history->stream() << (e.index == 0 ? "\n    " : ",\n    ") << Dump(EvaluationJson(s, e), -1);
        history->Check();
      }
      if (csv.enabled()) {
        row(e);
        csv.Check();  // a full disk ends the search now, not at its end
      }
      if (!svg.enabled()) return;
      // The path over the first two variables (with --map): every evaluation, failed ones too,
      // judged by the objective.
      if (o.map > 0) drawn_path.Add(e.index, e.x[0], e.x[1], e.status == app::RunStatus::kSuccess ? e.objective : NAN);
      if (e.status != app::RunStatus::kSuccess) return;  // failed evaluations are not drawn
      const auto at = static_cast<double>(e.index);
      (e.feasible ? drawn_feasible : drawn_infeasible).Add(e.index, at, e.objective);
      if (e.feasible && (std::isnan(best_so_far) || (s.maximise ? e.objective > best_so_far : e.objective < best_so_far))) best_so_far = e.objective;
      if (std::isfinite(best_so_far)) drawn_best.Add(e.index, at, best_so_far);
    };
    const app::OptimiseResult r = optimiser.Run(sink);
    for (const auto& p : r.phases) fmt::print(text, "phase       {}: {} evaluations, stopped: {}\n", p.method, p.evaluations, p.stop);
    fmt::print(text, "evaluations {} ({} failed, {} rejected){}\n", r.evaluations, r.failed, r.rejected,
               r.first_failure.empty() ? "" : "; first: " + r.first_failure);
    const app::DesignEvaluation* best = r.best >= 0 ? &r.best_design : nullptr;
    if (best != nullptr) {
      fmt::print(text, "best        evaluation {} ({}): {} = {:.10g}\n", best->index, best->phase, s.objective, best->objective);
      for (std::size_t k = 0; k < s.variables.size(); ++k) fmt::print(text, "            {} = {:.10g}\n", s.variables[k].key, best->x[k]);
    } else {
      fmt::print(text, "best        none: no evaluation met the constraints\n");
    }
    std::vector<app::DesignEvaluation> grid;
    if (o.map > 0) grid = optimiser.Grid(o.map);
    std::vector<app::ParetoPoint> front;
    if (!o.pareto.empty()) {
      front = optimiser.Pareto(o.pareto, o.pareto_from, o.pareto_to, o.pareto_steps);
      for (const auto& p : front) {
        fmt::print(text, "pareto      {} <= {:g}: {}\n", o.pareto, p.epsilon,
                   p.best >= 0 ? fmt::format("{} = {:.6g}", s.objective, p.design.objective) : std::string("nothing feasible"));
      }
    }

    if (json.enabled()) {
      nlohmann::json j;
      j["case"] = {{"title", deck.info.title}, {"deck", deck.name}};
      j["model"] = ModelJson(deck.Model());  // every output names the model that ran
      j["solver"] = SolverJson(deck, solver);
      nlohmann::json vars = nlohmann::json::array();
      for (const auto& v : s.variables) vars.push_back({{"key", v.key}, {"lower", v.lower}, {"upper", v.upper}});
      nlohmann::json cons = nlohmann::json::array();
      for (const auto& l : s.constraints) cons.push_back({{"figure", l.figure}, {"min", FiniteOrNull(l.min)}, {"max", FiniteOrNull(l.max)}});
      j["settings"] = {{"variables", vars}, {"objective", s.objective}, {"maximise", s.maximise}, {"constraints", cons},
                       {"global", app::ToString(s.global)}, {"local", app::ToString(s.local)}, {"evaluations", s.evaluations},
                       {"global_share", s.global_share}, {"tolerance", s.tolerance}, {"seed", s.seed}, {"robust", s.robust},
                       {"robust_samples", s.robust ? nlohmann::json(s.robust_samples) : nlohmann::json(nullptr)},
                       {"percentile", s.robust ? nlohmann::json(s.percentile) : nlohmann::json(nullptr)},
                       {"confidence", s.robust ? nlohmann::json(s.confidence) : nlohmann::json(nullptr)},
                       {"order_statistic", s.robust && s.confidence > 0.0
                                               ? nlohmann::json(app::ConfidenceRank(s.robust_samples, s.percentile / 100.0, s.confidence))
                                               : nlohmann::json(nullptr)},
                       {"penalty_weight", app::OptimiseSettings::kPenaltyWeight}, {"threads", threads}, {"mpi_ranks", ranks.size}};
      nlohmann::json phases = nlohmann::json::array();
      for (const auto& p : r.phases) phases.push_back({{"method", p.method}, {"evaluations", p.evaluations}, {"stop", p.stop}});
      j["summary"] = {{"status", best != nullptr ? "success" : "failed"},
                      {"evaluations", r.evaluations},
                      {"failed", r.failed},
                      {"rejected", r.rejected},
                      {"first_failure", r.first_failure},
                      {"phases", phases},
                      {"best", best != nullptr ? EvaluationJson(s, *best) : nlohmann::json(nullptr)},
                      {"wall_seconds", r.wall_seconds}};
      // The history (spooled as the search made it), the map and the front are streamed one
      // evaluation at a time after the rest of the document: the whole document as one JSON value
      // took about 9 KB an evaluation.
      std::ostream& os = json.stream();
      os << OpenObject(j);
      const auto stream_array = [&os](const char* key, std::size_t n, const auto& item) {
        os << ",\n  \"" << key << "\": [";
        for (std::size_t i = 0; i < n; ++i) os << (i == 0 ? "\n    " : ",\n    ") << Dump(item(i), -1);
        os << (n == 0 ? "]" : "\n  ]");
      };
      os << ",\n  \"history\": [";
      history->CopyTo(os);
      os << (r.evaluations == 0 ? "]" : "\n  ]");
      history.reset();  // removed now, not with the run's end
      if (!grid.empty()) stream_array("map", grid.size(), [&](std::size_t i) { return EvaluationJson(s, grid[i]); });
      if (!front.empty()) {
        stream_array("pareto", front.size(), [&](std::size_t i) {
          const auto& p = front[i];
          return nlohmann::json{{"figure", o.pareto}, {"bound", p.epsilon}, {"design", p.best >= 0 ? EvaluationJson(s, p.design) : nlohmann::json(nullptr)}};
        });
      }
      os << "\n}\n";
      json.Commit();
    }
    if (csv.enabled()) {
      for (const auto& e : grid) row(e);
      csv.Commit();
    }
    if (svg.enabled()) {
      namespace plots = app::plots;
      plots::Figure figure;
      figure.title = fmt::format("{}: {} {} over {} evaluations ({} then {})", deck.info.title, s.maximise ? "maximise" : "minimise",
                                 s.objective, r.evaluations, app::ToString(s.global), app::ToString(s.local));
      const std::int64_t stride = drawn_feasible.stride();
      figure.caption = FigureCaption(deck, fmt::format("{}; infeasible: a constraint not met; failed evaluations are not drawn{}{}",
                                                       s.robust ? fmt::format("robust: {} of {} samples", RobustRule(s), s.robust_samples) : "nominal pair",
                                                       grid.empty() ? "" : "; map: blank cells are infeasible",
                                                       stride > 1 ? fmt::format("; drawn: the least and largest objective of every {} evaluations", stride)
                                                                  : std::string()));
      plots::Panel c;
      c.title = "convergence";
      c.x_label = "evaluation";
      c.y_label = s.objective;
      plots::Series feasible{"feasible", drawn_feasible.x(), drawn_feasible.y(), plots::Style::kMarkers},
          infeasible{"infeasible", drawn_infeasible.x(), drawn_infeasible.y(), plots::Style::kMarkers},
          best_line{"best feasible so far", drawn_best.x(), drawn_best.y(), plots::Style::kLine};
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
        const auto n = static_cast<std::size_t>(o.map);
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
        plots::Series path{"evaluations", drawn_path.x(), drawn_path.y(), plots::Style::kMarkers};
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
      if (!front.empty()) {
        plots::Panel p;
        p.title = "Pareto front (epsilon constraints)";
        p.x_label = o.pareto;
        p.y_label = s.objective;
        plots::Series pts{"front", {}, {}, plots::Style::kLineMarkers};
        const int fi = app::FigureIndex(o.pareto);
        for (const auto& q : front) {
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
      WriteFigure(figure, svg);
    }
    // The search's documents are kept whatever becomes of the deck: a deck that cannot be written
    // (no design met the constraints, or the deck's text does not take the edit) is said, is not
    // written, and the run is one that did not wholly succeed (exit 1), not an input error that
    // would discard the search.
    bool deck_written = !best_deck.enabled();
    if (best_deck.enabled() && best == nullptr) {
      fmt::print(streams.err, "ltca: --write-deck {}: no evaluation met the constraints, so there is no design to write\n", o.deck_path);
    } else if (best_deck.enabled()) {
      const std::string header = fmt::format("# Written by ltca optimise from {}: the best of {} evaluations, {} = {:.10g}.\n"
                                             "# ltca solve runs it as it is; [optimise] is left out.\n",
                                             deck.name, r.evaluations, s.objective, best->objective);
      try {
        best_deck.stream() << DesignDeck(deck, s, best->x, header);
        best_deck.Commit();
        deck_written = true;
      } catch (const std::invalid_argument& e) {
        fmt::print(streams.err, "ltca: --write-deck {}: not written: {}\n", o.deck_path, e.what());
      }
    }
    // Failed and rejected evaluations are designs the search ruled out (counted in the summary);
    // the run succeeds when it found a design that meets the constraints.
    return best != nullptr && deck_written ? kExitSuccess : kExitNotSucceeded;
  });
}

Command OptimiseCommand() {
  auto st = std::make_shared<DeckState<OptimiseOptions>>();
  return {"optimise",
          "Design optimisation (docs/optimise.md): the values of the deck's [optimise] variables (keys of [modification] "
          "and [errors], or a reducer stage's clearances) that meet its constraints with the best objective, by NLopt's global search then a local "
          "polish; robust over the samples of [tolerances] when asked. Deterministic: the same result on any number of "
          "threads.",
          [st](CLI::App& c) {
            OptimiseOptions& o = st->options;
            AddLoadInputs(c, st->deck, o.solver, o.kinematics);
            c.add_option("--threads", o.threads, "Threads, 1 to 1024 (default 0: every hardware thread): a robust design's samples, the map's points, the Pareto steps");
            c.add_option("--evaluations", o.evaluations, "The budget ([optimise] evaluations)");
            c.add_option("--map", o.map, "With two variables: the objective on an N x N grid (drawn with --svg, listed in --json and --csv)");
            c.add_option("--pareto", o.pareto, "A second figure: the Pareto front of the objective against it (epsilon constraints)");
            c.add_option("--pareto-from", o.pareto_from, "The first bound on the --pareto figure");
            c.add_option("--pareto-to", o.pareto_to, "The last bound on the --pareto figure");
            c.add_option("--pareto-steps", o.pareto_steps, "Bounds from --pareto-from to --pareto-to (default 11)");
            AddOutput(c, "--json", o.json_path, "Write the settings, the best design, the phases, the history (and map, front) as JSON");
            AddOutput(c, "--csv", o.csv_path, "Write every evaluation as CSV (the map's after the search's)");
            AddOutput(c, "--svg", o.svg_path, "Draw the convergence (and the map, the front)");
            AddOutput(c, "--write-deck", o.deck_path, "Write the best design as a deck that ltca solve runs as it is");
          },
          [st] {
            return std::vector<std::string>{st->options.json_path, st->options.csv_path, st->options.svg_path, st->options.deck_path};
          },
          [st](const Streams& streams) { return RunOptimise(st->deck.Read(), st->options, streams); }};
}

}  // namespace ltca::cli
