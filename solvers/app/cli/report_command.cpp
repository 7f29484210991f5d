// `ltca report`: the page's HTML helpers (labels, tables, the inputs, an allowables row, inlined
// SVG), the tolerance and optimisation sections, ReportFolder (the output folder's safe staging),
// ReportContext (the results the sections share), the table of sections (Sections(): each one's
// analysis and HTML) and RunReport, which runs the table's analyses and builds the page from it.
#include "report_command.hpp"

#include "command.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "contact_commands.hpp"
#include "documents/analyses.hpp"
#include "documents/backlash.hpp"
#include "documents/efficiency.hpp"
#include "documents/geometry.hpp"
#include "documents/mesh.hpp"
#include "documents/optimise.hpp"
#include "documents/stiffness.hpp"
#include "documents/tolerance.hpp"
#include "ltca/analysis/allowables.hpp"
#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/efficiency.hpp"
#include "ltca/analysis/mesh.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/tolerance_run.hpp"
#include "geometry_command.hpp"
#include "optimise_command.hpp"
#include "ltca/analysis/keys.hpp"
#include "ltca/app/plots.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"
#include "documents/solve.hpp"
#include "ltca/analysis/spectrum.hpp"
#include "solve_command.hpp"
#include "tolerance_command.hpp"

namespace ltca::cli {
namespace documents = app::documents;
namespace {

namespace fs = std::filesystem;

std::string Html(const std::string& text) { return app::plots::XmlEscape(text); }

/// A JSON value as table text: numbers to 6 significant digits, null as n/a.
std::string Cell(const nlohmann::json& v) {
  if (v.is_null()) return "n/a";
  if (v.is_number_float()) return fmt::format("{:.6g}", v.get<double>());
  if (v.is_string()) return Html(v.get<std::string>());
  return Html(v.dump());
}
/// A number as table text: 6 significant digits, n/a when not finite.
std::string CellOf(double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : "n/a"; }

/// An output key as a reader reads it (the page showed raw keys): the unit its name ends
/// with in parentheses, words for the underscores, a nested key after its parent and a colon.
/// "tip_relief.land_half_width_mm" -> "tip relief: land half width (mm)",
/// "pp_te_arcsec" -> "peak-to-peak TE (arcsec)".
std::string Label(const std::string& key) {
  static const std::vector<std::pair<std::string, std::string>> kUnits = {
      {"_nm_per_arcmin", "N*m/arcmin"}, {"_mm2_per_s", "mm^2/s"}, {"_m_per_s", "m/s"}, {"_per_gpa", "1/GPa"}, {"_pa_s", "Pa*s"},
      {"_arcsec", "arcsec"}, {"_arcmin", "arcmin"}, {"_mpa", "MPa"}, {"_nmm", "N*mm"}, {"_nm", "N*m"},
      {"_rpm", "rpm"}, {"_deg", "deg"}, {"_mm", "mm"}, {"_um", "um"}, {"_n", "N"}, {"_w", "W"}, {"_j", "J"},
      {"_h", "h"}, {"_hours", "h"}, {"_mrev", "million revolutions"}};
  std::string text;
  std::size_t start = 0;
  while (start <= key.size()) {
    const std::size_t dot = key.find('.', start);
    std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    std::string unit;
    for (const auto& [suffix, name] : kUnits) {
      if (part.size() > suffix.size() && part.compare(part.size() - suffix.size(), suffix.size(), suffix) == 0) {
        unit = name;
        part.erase(part.size() - suffix.size());
        break;
      }
    }
    std::string words;
    std::size_t w = 0;
    while (w <= part.size()) {
      const std::size_t u = part.find('_', w);
      std::string word = part.substr(w, u == std::string::npos ? std::string::npos : u - w);
      if (word == "pp") word = "peak-to-peak";
      if (word == "te") word = "TE";
      if (word == "l10") word = "L10";
      if (!word.empty()) words += (words.empty() ? "" : " ") + word;
      if (u == std::string::npos) break;
      w = u + 1;
    }
    text += (text.empty() ? "" : ": ") + words + (unit.empty() ? "" : " (" + unit + ")");
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return text;
}

/// Rows that say how long a run took: the page's footnote, not a result.
bool Timing(const std::string& key) {
  return key.find("seconds") != std::string::npos || key.find("per_second") != std::string::npos;
}

/// A two-column table of the object's scalar members, labelled (nested objects: "parent: member"),
/// each row carrying its key (data-key) for the checks that read the page.
std::string Table(const nlohmann::json& object, const std::string& prefix = "") {
  std::string rows;
  for (const auto& [key, value] : object.items()) {
    if (Timing(key)) continue;
    if (value.is_object()) {
      rows += Table(value, prefix + key + ".");
    } else if (!value.is_array()) {
      rows += fmt::format("<tr data-key=\"{}\"><th>{}</th><td>{}</td></tr>\n", Html(prefix + key), Html(Label(prefix + key)),
                          Cell(value));
    }
  }
  return prefix.empty() ? "<table>\n" + rows + "</table>\n" : rows;
}

/// A text line of the commands ("model     plane (...)\nnote      ...") without its labels.
std::string Unlabelled(const std::string& line) {
  std::string out;
  std::istringstream in(line);
  for (std::string row; std::getline(in, row);) {
    const std::size_t space = row.find_first_not_of(' ', row.find(' '));
    out += (out.empty() ? "" : "; ") + (space == std::string::npos ? row : row.substr(space));
  }
  return out;
}

/// The deck's inputs, grouped as the deck is: every key of every section the deck has,
/// its meaning and unit from the key table (analysis::DeckKeys), the value the deck gives or the
/// default (marked), and the keys a section takes beyond the table ([tolerances] draws, [case]).
std::string InputsTable(const app::Deck& deck) {
  std::string html;
  std::vector<std::string> absent;
  for (const std::string& section : analysis::DeckSections()) {
    std::vector<const app::Deck::GivenKey*> given;
    for (const auto& g : deck.given) {
      if (g.section == section) given.push_back(&g);
    }
    if (given.empty()) {
      absent.push_back("[" + section + "]");
      continue;
    }
    std::string rows;
    std::vector<std::string> listed;
    for (const analysis::DeckKey& k : analysis::DeckKeys()) {
      if (section != k.section) continue;
      listed.emplace_back(k.name);
      const auto it = std::find_if(given.begin(), given.end(), [&](const app::Deck::GivenKey* g) { return g->key == k.name; });
      const bool from_deck = it != given.end();
      if (!from_deck && std::string(k.default_value).empty()) continue;  // required elsewhere, or absent: nothing ran with it
      rows += fmt::format("<tr data-key=\"{}.{}\"{}><th>{}</th><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                          Html(section), Html(k.name), from_deck ? "" : " class=\"default\"", Html(k.name),
                          Html(from_deck ? (*it)->value : std::string(k.default_value)), Html(k.unit), Html(k.meaning),
                          from_deck ? "deck" : "default");
    }
    for (const app::Deck::GivenKey* g : given) {
      if (std::find(listed.begin(), listed.end(), g->key) != listed.end()) continue;
      rows += fmt::format("<tr data-key=\"{}.{}\"><th>{}</th><td>{}</td><td></td><td></td><td>deck</td></tr>\n", Html(section),
                          Html(g->key), Html(g->key), Html(g->value));
    }
    html += fmt::format("<h3>[{}]</h3>\n<table class=\"inputs\">\n<tr><th>key</th><th>value</th><th>unit</th><th>meaning</th>"
                        "<th>from</th></tr>\n{}</table>\n",
                        Html(section), rows);
    if (section == "second_disc") {
      html += "<p class=\"note\">Every key of [modification] and every disc key of [errors] that [second_disc] does not "
              "give is the first disc's; the pin ring is common to both discs.</p>\n";
    }
  }
  if (!absent.empty()) {
    html += fmt::format("<p>Not in the deck (nothing of theirs ran): {}.</p>\n", Html(fmt::format("{}", fmt::join(absent, ", "))));
  }
  return html;
}

/// One row of the allowables table (analysis::CheckAllowables, the rule of analysis::Judge): the
/// figure, its value, the allowable (min and / or max), the margin to the nearer bound (positive:
/// inside) and the verdict; the Monte Carlo's pass fraction when it ran.
std::string AllowableRow(const analysis::AllowableRow& row) {
  const analysis::AllowableRange& r = row.range;
  const std::string allowable = !r.Given()                                  ? "none in the deck"
                                : std::isfinite(r.min) && std::isfinite(r.max) ? fmt::format("{:.6g} to {:.6g}", r.min, r.max)
                                : std::isfinite(r.max)                         ? fmt::format("&le; {:.6g}", r.max)
                                                                               : fmt::format("&ge; {:.6g}", r.min);
  const std::string margin = std::isfinite(row.margin) ? fmt::format("{:+.4g}", row.margin) : "";
  const std::string verdict = row.verdict == analysis::AllowableVerdict::kPass   ? "<span class=\"pass\">pass</span>"
                              : row.verdict == analysis::AllowableVerdict::kFail ? "<span class=\"fail\">FAIL</span>"
                                                                                 : analysis::ToString(row.verdict);
  return fmt::format("<tr data-key=\"{}\"><th>{}</th><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                     Html(row.figure), Html(row.name.empty() ? Label(row.figure) : row.name),
                     row.value > 0.0 && std::isinf(row.value) ? std::string("infinite") : CellOf(row.value), allowable,
                     margin, verdict, row.pass_fraction ? CellOf(*row.pass_fraction) : "", Html(row.basis));
}

/// A figure as SVG text (an error drawing it is an output error, as for a file).
std::string SvgOf(const app::plots::Figure& figure) {
  std::ostringstream os;
  try {
    app::plots::Write(figure, os, app::plots::Format::kSvg);
  } catch (const std::runtime_error& e) {
    throw OutputError(fmt::format("report: drawing '{}': {}", figure.title, e.what()));
  }
  return os.str();
}

/// An SVG document inlined in the page: from its <svg> element, every id and url(#...) reference
/// prefixed with `stem` (the page holds several figures), in one pass.
std::string InlineSvgText(const std::string& svg, const std::string& stem) {
  const auto at = svg.find("<svg");
  if (at == std::string::npos) return {};
  const std::string prefix = stem + "-";
  std::string out;
  out.reserve(svg.size() - at + svg.size() / 16);
  std::size_t from = at;
  while (true) {
    const std::size_t id = svg.find("id=\"", from), url = svg.find("url(#", from);
    const std::size_t next = std::min(id, url);
    if (next == std::string::npos) break;
    const std::size_t end = next + (next == id ? 4 : 5);
    out.append(svg, from, end - from).append(prefix);
    from = end;
  }
  return out.append(svg, from, std::string::npos);
}

/// The report's tolerance study: its study and result (rank 0 holds the summary) and its figure
/// as SVG text for the page.
struct ReportTolerance {
  std::optional<analysis::ToleranceStudy> study;
  std::optional<analysis::ToleranceResult> result;
  std::string svg;
  bool root() const { return result && result->rank == 0; }
  /// The worst case of a figure the study ran, or nullptr (no worst case, or not its figure).
  const analysis::WorstCaseFigure* WorstCase(const std::string& figure) const {
    if (!root() || !result->worst_case) return nullptr;
    const auto& names = analysis::ToleranceSettings::FigureNames();
    for (std::size_t f = 0; f < names.size(); ++f) {
      if (names[f] == figure && study->Runs(f)) return &result->worst_case->figures[f];
    }
    return nullptr;
  }
};

/// The page's tolerance section (rank 0): the counts, the study's notes, the percentiles and the
/// worst-case corners, the limits' pass fractions, the sensitivity ranking and the histograms.
std::string ToleranceHtml(const ReportTolerance& tol, const ReportOptions& options) {
  const analysis::ToleranceSummary& ts = tol.result->summary;
  const auto& names = analysis::ToleranceSettings::FigureNames();
  // The figures the study ran, in the order of their names.
  std::vector<std::size_t> figures;
  for (std::size_t f = 0; f < names.size(); ++f) {
    if (tol.study->Runs(f)) figures.push_back(f);
  }
  std::sort(figures.begin(), figures.end(), [&](std::size_t a, std::size_t b) { return names[a] < names[b]; });
  std::string html = fmt::format("<p>{} samples (seed {}): {} succeeded, {} failed, {} rejected (interference); all limits passed by "
                                 "a fraction {} of the samples.{}</p>\n",
                                 ts.samples, ts.seed, ts.succeeded, ts.failed, ts.rejected, CellOf(ts.pass_fraction),
                                 options.no_worst_case ? " The extreme-value (worst-case) runs were skipped (--no-worst-case)." : "");
  // The study's notes say what a figure is where it is not what its name suggests (a reducer
  // stage's backlash is its free play) and what part of the revolution was swept.
  for (const std::string& note : tol.study->notes()) html += fmt::format("<p class=\"note\">{}</p>\n", Html(note));
  html += "<h3>Percentiles per figure</h3>\n<table>\n<tr><th>figure</th><th>nominal</th><th>p5</th><th>p50</th><th>p95</th>"
          "<th>mean</th><th>std</th><th>worst case low</th><th>worst case high</th></tr>\n";
  for (const std::size_t f : figures) {
    const analysis::FigureStats& st = ts.figures[f];
    const analysis::WorstCaseFigure none;  // without the worst case: every figure n/a
    const analysis::WorstCaseFigure& w = tol.result->worst_case ? tol.result->worst_case->figures[f] : none;
    html += fmt::format("<tr data-key=\"{}\"><th>{}</th><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
                        "<td>{}</td><td>{}</td></tr>\n",
                        Html(names[f]), Html(Label(names[f])), CellOf(w.nominal), CellOf(st.p5), CellOf(st.p50), CellOf(st.p95),
                        CellOf(st.mean), CellOf(st.std), CellOf(w.corner_low), CellOf(w.corner_high));
  }
  html += "</table>\n<h3>Pass fraction per limit</h3>\n<table>\n<tr><th>figure</th><th>min</th><th>max</th><th>pass fraction</th></tr>\n";
  for (const analysis::LimitResult& x : ts.limits) {
    html += fmt::format("<tr><th>{}</th><td>{}</td><td>{}</td><td>{}</td></tr>\n", Html(Label(x.limit.figure)), CellOf(x.limit.min),
                        CellOf(x.limit.max), CellOf(x.fraction));
  }
  html += "</table>\n<h3>Sensitivity: what moves each figure</h3>\n<p>Each input's share of the figure's variance "
          "(standardised regression coefficients); an input whose share is within the noise floor (the share a random "
          "input of the same samples gets) is not told from chance.</p>\n<table>\n<tr><th>figure</th><th>R&sup2;</th>"
          "<th>ranking (share, noise floor)</th></tr>\n";
  for (const std::size_t f : figures) {
    const analysis::FigureSensitivity& fs = ts.sensitivity[f];
    std::string ranking;
    for (std::size_t k = 0; k < std::min<std::size_t>(4, fs.keys.size()); ++k) {
      const analysis::KeySensitivity& key = fs.keys[k];
      ranking += fmt::format("{}{} {} ({}{})", ranking.empty() ? "" : "; ", Html(key.key), CellOf(key.share), CellOf(key.noise_floor),
                             key.distinguishable ? "" : ", within noise");
    }
    html += fmt::format("<tr><th>{}</th><td>{}</td><td>{}</td></tr>\n", Html(Label(names[f])), CellOf(fs.r_squared),
                        ranking.empty() ? Html(fs.note.empty() ? std::string("no ranking") : fs.note) : ranking);
  }
  html += "</table>\n";
  return html + InlineSvgText(tol.svg, "tolerance");
}

/// The report's design optimisation: its search and run (rank 0 writes) and its figure as SVG
/// text for the page.
struct ReportOptimisation {
  std::optional<analysis::Optimiser> optimiser;
  std::optional<analysis::OptimiseRun> run;
  std::string svg;
  bool root() const { return run && optimiser->ranks().rank == 0; }
};

/// The page's optimisation section (rank 0): the objective and the rule, the phases, the variables
/// with the optimum, the optimum's objective and constraints judged, the convergence figure.
std::string OptimiseHtml(const ReportOptimisation& opt) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const analysis::OptimiseSettings& st = opt.optimiser->settings();
  const analysis::OptimiseResult& os = opt.run->search;
  const analysis::DesignEvaluation* best = opt.run->best();
  std::string rule = "on the nominal pair";
  if (st.robust) {
    rule = st.confidence > 0.0
               ? fmt::format("robust: each figure's p{} bounded at confidence {} over {} common samples of [tolerances] (the "
                             "{}th order statistic)",
                             CellOf(st.percentile), CellOf(st.confidence), st.robust_samples,
                             analysis::ConfidenceRank(st.robust_samples, st.percentile / 100.0, st.confidence))
               : fmt::format("robust: each figure's p{} over {} common samples of [tolerances]", CellOf(st.percentile),
                             st.robust_samples);
  }
  std::string phases;
  for (const analysis::OptimisePhase& ph : os.phases) {
    phases += fmt::format("{}{}: {} evaluations, stopped: {}", phases.empty() ? "" : "; then ", Html(ph.method), ph.evaluations, Html(ph.stop));
  }
  std::string html = fmt::format("<p>The search of the deck's <code>[optimise]</code> (docs/optimise.md): {} {}, {}; {} evaluations ({} failed, {} "
                                 "rejected: the pair interferes). {}.</p>\n",
                                 st.maximise ? "maximise" : "minimise", Html(Label(st.objective)), rule, os.evaluations, os.failed, os.rejected,
                                 phases);
  html += "<table>\n<tr><th>variable</th><th>lower</th><th>upper</th><th>optimum</th></tr>\n";
  for (std::size_t k = 0; k < st.variables.size(); ++k) {
    const analysis::OptimiseVariable& v = st.variables[k];
    html += fmt::format("<tr data-key=\"{}\"><th>{}</th><td>{}</td><td>{}</td><td>{}</td></tr>\n", Html(v.key), Html(Label(v.key)),
                        CellOf(v.lower), CellOf(v.upper), best == nullptr ? "none" : CellOf(best->x[k]));
  }
  html += "</table>\n";
  if (best == nullptr) {
    html += "<p class=\"note\">No evaluation met the constraints: there is no optimum to judge.</p>\n";
  } else {
    html += "<table>\n<tr><th>figure at the optimum</th><th>value</th><th>constraint</th><th>margin</th><th>verdict</th>"
            "<th></th><th>from</th></tr>\n";
    const std::string basis = st.robust ? "ltca optimise, robust" : "ltca optimise, the nominal pair";
    // A figure of the best design (NaN: none, or not a figure).
    const auto at_best = [&](const std::string& figure) {
      const int f = analysis::FigureIndex(figure);
      return f >= 0 ? best->figures[static_cast<std::size_t>(f)] : nan;
    };
    if (analysis::FigureIndex(st.objective) >= 0) {
      analysis::AllowableRow objective = analysis::Judge(st.objective, at_best(st.objective), basis);
      objective.name = Label(st.objective) + " (objective)";
      html += AllowableRow(objective);
    }
    for (const analysis::ToleranceLimit& c : st.constraints) {
      html += AllowableRow(analysis::Judge(c.figure, at_best(c.figure), basis, {c.min, c.max}));
    }
    html += "</table>\n";
  }
  return html + InlineSvgText(opt.svg, "optimise");
}

/// The report's folder while it is built. The page and its files are written into a fresh folder
/// beside DIR (mkdtemp, with the permissions of the folder it replaces, or of a new folder) and put
/// in place of DIR when complete (with the run's other outputs): a failure or Ctrl-C leaves DIR as
/// it was. DIR is replaced whole, so it must be new, empty, a report's (the marker file) or given up
/// (--force). The folder itself: its links followed (a report through a link replaces where it
/// points, as a file output is written through one), "out/", "out/." and "./out" all the folder out.
class ReportFolder {
 public:
  /// Checks the target (std::invalid_argument or OutputError naming -o), makes the staging folder
  /// and writes the marker into it; from here until Commit() the outputs go straight into it.
  ReportFolder(const ReportOptions& options, const Streams& streams) : run_(OutputTransaction::Current()) {
    const std::string& out_dir = options.out_dir;
    target_ = [&] {
      fs::path t = OutputTarget(out_dir);
      std::error_code e;
      t = fs::absolute(t, e).lexically_normal();
      while (!t.empty() && t.filename().empty() && t.has_parent_path() && t != t.root_path()) t = t.parent_path();
      return t;
    }();
    if (target_ == target_.root_path()) throw std::invalid_argument(fmt::format("-o {}: expected a folder other than the root", out_dir));
    std::error_code ec;
    const fs::file_status status = fs::status(target_, ec);
    if (fs::exists(status) && !fs::is_directory(status)) {
      throw OutputError(fmt::format("-o {}: is a file; expected a folder (new, empty, or an earlier report's)", out_dir));
    }
    if (fs::is_directory(status) && !fs::is_empty(target_, ec) && !fs::exists(target_ / kReportMarker) && !options.force) {
      throw std::invalid_argument(fmt::format(
          "-o {}: the folder holds files that ltca report did not write (no {} in it), and a report replaces the whole "
          "folder; give a new or empty folder, or --force to replace it",
          out_dir, kReportMarker));
    }
    if (run_ != nullptr) run_->OpenOutput("-o", target_);  // no input of the run (the deck, a trace) inside it
    const fs::path parent = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
    fs::create_directories(parent, ec);
    if (!fs::is_directory(parent)) {
      throw OutputError(fmt::format("-o {}: cannot create the folder '{}'{}", out_dir, parent.string(), ec ? ": " + ec.message() : ""));
    }
    std::string staging = (parent / ".ltca-new-XXXXXX").string();
    if (!app::CreateTemporary(staging, true)) {
      throw OutputError(fmt::format("-o {}: cannot write in the folder '{}': {}", out_dir, parent.string(), std::strerror(errno)));
    }
    {  // the permissions of the folder it replaces, or of a new folder (mkdtemp makes 0700)
      const mode_t mask = umask(0);
      umask(mask);
      struct stat existing {};
      chmod(staging.c_str(), stat(target_.c_str(), &existing) == 0 ? existing.st_mode & 07777 : 0777 & ~mask);
    }
    guard_.path = staging;
    direct_.emplace();  // the files below go straight into the private folder
    WriteTo("-o", File(kReportMarker), streams.out, [](std::ostream& os) {
      os << "Written by ltca report. `ltca report -o` may replace this folder whole.\n";
    });
  }
  ReportFolder(const ReportFolder&) = delete;
  ReportFolder& operator=(const ReportFolder&) = delete;

  /// The path of the file `name` in the staging folder.
  std::string File(const char* name) const { return (fs::path(guard_.path) / name).string(); }
  /// DIR, absolute and normalised.
  const fs::path& target() const { return target_; }
  /// Whether the folder goes in place with the run's outputs (else Commit() put it in place).
  bool handed_to_run() const { return run_ != nullptr; }
  /// Puts the complete folder in place of DIR: handed to the run's outputs, or in place now when
  /// there is no run; under mpirun the first rank's alone (every other rank's is removed).
  void Commit() {
    guard_.handed = true;
    if (!IsFirstRank()) {
      guard_.handed = false;
    } else if (run_ != nullptr) {
      run_->StageFolder("-o", guard_.path, target_.string());
    } else {
      OutputTransaction::Direct none;
      OutputTransaction local;
      local.StageFolder("-o", guard_.path, target_.string());
      local.CommitAll();
    }
  }

 private:
  struct Staging {  // removed on every way out until it is handed to the run's outputs
    std::string path;
    bool handed = false;
    ~Staging() {
      if (handed || path.empty()) return;
      std::error_code e;
      fs::remove_all(path, e);
      ForgetTemporary(path);
    }
  };
  OutputTransaction* run_;
  fs::path target_;
  Staging guard_;
  std::optional<OutputTransaction::Direct> direct_;
};

/// What the report's sections share: the deck, the options and streams, the staging folder's files,
/// and each analysis's result and figure (SVG text) once its section has run. The allowables are
/// judged from these results.
struct ReportContext {
  const app::Deck& deck;
  const ReportOptions& options;
  const Streams& streams;
  const Streams& quiet;  ///< for the analyses whose text the page does not show
  const ReportFolder& folder;  ///< where each analysis writes its files
  ReportContext(const app::Deck& d, const ReportOptions& o, const Streams& s, const Streams& q, const ReportFolder& f)
      : deck(d), options(o), streams(s), quiet(q), folder(f) {}
  solvers::SolverOptions solver;  ///< SolverFor(deck, --solver), set by the loaded sweep
  nlohmann::json geometry_json;
  std::string geometry_svg;
  std::optional<analysis::SweepResult> solved;
  std::string solve_svg;
  std::optional<analysis::BacklashResult> backlash;
  std::string backlash_svg;
  std::string mesh_svg;
  std::optional<analysis::StiffnessResult> stiff;
  std::string stiff_svg;
  std::optional<analysis::EfficiencySummary> eff;
  std::optional<analysis::EfficiencySpectrum> eff_spectrum;  ///< [[load_spectrum]]: the efficiency per bin and over them
  std::string eff_svg;
  std::optional<analysis::SpectrumResult> spectrum;  ///< [[load_spectrum]]: every bin and the lives over them
  ReportTolerance tol;
  ReportOptimisation opt;
  /// The generic analyses' outputs (documents/analyses.hpp) and their figures as SVG text, by name.
  std::map<std::string, std::pair<documents::AnalysisOutput, std::string>> generic;
};

/// The note of a section whose analysis did not run, and why.
std::string NotRun(const char* why) { return fmt::format("<p class=\"note\">Not run: {}.</p>\n", why); }

std::string InputsHtml(const ReportContext& ctx) {
  return "<p>Every value of the deck, grouped as the deck is; greyed rows are defaults (the deck does not give them). "
         "Units are those of the deck's keys.</p>\n" +
         InputsTable(ctx.deck);
}

/// The allowables table: analysis::CheckAllowables over the results of the sections that ran.
std::string AllowablesHtml(const ReportContext& ctx) {
  std::string html = "<p>Allowables come from the deck: <code>[material] contact_stress_limit_mpa</code> and every "
                     "<code>[tolerances] limits</code> entry, judged on the nominal deck (and, for the limits, as the Monte "
                     "Carlo's pass fraction), and the targets of <code>[allowables]</code>; with a <code>[[load_spectrum]]</code> its figures "
                     "(the rows <code>spectrum.*</code>) are judged against the same targets. A figure with no allowable in the deck "
                     "is listed with its value.</p>\n<table>\n"
                     "<tr><th>figure</th><th>value</th><th>allowable</th><th>margin</th><th>verdict</th>"
                     "<th>Monte Carlo pass fraction</th><th>from</th></tr>\n";
  const app::Deck& deck = ctx.deck;
  analysis::NominalResults nominal;
  nominal.reducer = deck.reducer.has_value();
  nominal.output_pins = deck.reducer && deck.reducer->kind == solvers::OutputKind::kPins;
  nominal.solve = &ctx.solved->summary;
  nominal.backlash = &*ctx.backlash;
  nominal.stiffness = ctx.stiff ? &*ctx.stiff : nullptr;
  nominal.efficiency = ctx.eff ? &*ctx.eff : nullptr;
  if (ctx.tol.root()) {
    nominal.study = &*ctx.tol.study;
    nominal.tolerance = &*ctx.tol.result;
  }
  analysis::Allowables allowables;
  allowables.contact_stress_limit = deck.RequireMaterial().contact_stress_limit;
  if (deck.tolerances) allowables.limits = deck.tolerances->limits;
  allowables.targets = deck.allowables;
  for (const analysis::AllowableRow& row : analysis::CheckAllowables(nominal, allowables)) html += AllowableRow(row);
  // A load spectrum: its figures (lives by Miner over the bins, the worst bin's static figures,
  // the pitting safety over the spectrum) against the same targets.
  if (ctx.spectrum) {
    for (const analysis::AllowableRow& row :
         analysis::SpectrumRatingRows(*ctx.spectrum, deck.allowables, allowables.contact_stress_limit, nominal.reducer)) {
      html += AllowableRow(row);
    }
  }
  return html + "</table>\n";
}

/// The derived geometry of the pair as made, and its drawing at crank 0: the documents `ltca
/// geometry` writes, built in this process, beside the page.
int RunGeometry(ReportContext& ctx) {
  const app::Deck& deck = ctx.deck;
  const geometry::RealPair real = deck.MakeRealPair();
  ctx.geometry_json = documents::Json(deck, real);
  WriteTo("-o", ctx.folder.File("geometry.json"), ctx.streams.out, [&](std::ostream& os) { os << Dump(ctx.geometry_json) << '\n'; });
  ctx.geometry_svg = SvgOf(documents::Figure(deck, real, deck.MakeModel().Evaluate(0.0), GeometryOptions{}.samples_per_flank));
  WriteTo("-o", ctx.folder.File("geometry.svg"), ctx.streams.out, [&](std::ostream& os) { os << ctx.geometry_svg; });
  return kExitSuccess;
}

std::string GeometryHtml(const ReportContext& ctx) {
  const auto& p = ctx.deck.pair;
  std::string html = "<div class=\"grid\">\n<div>\n<table>\n";
  html += fmt::format(
      "<tr><th>z_p (pins)</th><td>{}</td></tr><tr><th>z_c (teeth)</th><td>{}</td></tr><tr><th>r_rp (mm)</th><td>{:g}</td></tr>"
      "<tr><th>R_p (mm)</th><td>{:g}</td></tr><tr><th>e (mm)</th><td>{:g}</td></tr><tr><th>B_c (mm)</th><td>{:g}</td></tr>\n</table>\n",
      p.pin_count, p.tooth_count, p.pin_radius, p.pin_circle_radius, p.eccentricity, p.face_width);
  nlohmann::json derived = ctx.geometry_json;
  derived.erase("case");
  return html + Table(derived) + "</div>\n<div>" + InlineSvgText(ctx.geometry_svg, "geometry") + "</div>\n</div>\n";
}

/// The loaded sweep: its result in this process (app::SolveDeckSweep), its JSON streamed and its
/// figure drawn by the documents `ltca solve` writes, beside the page.
int RunLoaded(ReportContext& ctx) {
  const app::Deck& deck = ctx.deck;
  const Streams& streams = ctx.streams;
  ctx.solver = SolverFor(deck, ctx.options.solver);
  documents::SolveSeries solve_series(deck.sweep.positions);
  WriteTo("-o", ctx.folder.File("solve.json"), streams.out, [&](std::ostream& os) {
    documents::SolveJsonWriter writer(os, deck, ctx.solver);
    std::int64_t done = 0;
    Progress progress(streams.err, streams.progress, "solving position", deck.sweep.positions);
    analysis::SweepCallbacks callbacks;
    callbacks.keep_positions = false;
    callbacks.on_position = [&](const analysis::PositionResult& p) {
      writer.Add(p);
      solve_series.Add(p);
      progress.Update(++done);
    };
    ctx.solved = app::SolveDeckSweep(deck, ctx.solver, callbacks);
    progress.Finish();
    writer.Finish(deck, ctx.solved->summary);
  });
  const analysis::SweepSummary& ss = ctx.solved->summary;
  ctx.solve_svg = SvgOf(documents::Figure(deck, ctx.solver, solve_series, ss));
  WriteTo("-o", ctx.folder.File("solve.svg"), streams.out, [&](std::ostream& os) { os << ctx.solve_svg; });
  return ss.all_succeeded() ? kExitSuccess : kExitNotSucceeded;
}

std::string LoadedHtml(const ReportContext& ctx) {
  return Table(documents::Json(ctx.deck, ctx.solved->summary)) + InlineSvgText(ctx.solve_svg, "solve");
}

/// The unloaded backlash (analysis::Backlash) and the mesh state at crank 0 (analysis::MeshAt):
/// their results in this process, their JSON and figures by the documents `ltca backlash` and
/// `ltca mesh` write, beside the page. Its status is the backlash's.
int RunUnloaded(ReportContext& ctx) {
  const app::Deck& deck = ctx.deck;
  const analysis::Stage unloaded(deck, deck.sweep.CrankAngles());
  documents::BacklashSeries backlash_series(unloaded.cranks().size());
  WriteTo("-o", ctx.folder.File("backlash.json"), ctx.streams.out, [&](std::ostream& os) {
    documents::BacklashJsonWriter writer(os, deck, deck.kinematics, unloaded.disc_count() == 2);
    ctx.backlash = analysis::Backlash(unloaded, deck.kinematics, [&](const analysis::BacklashPosition& p) {
      writer.Add(p);
      backlash_series.Add(p);
    });
    writer.Finish(deck, *ctx.backlash);
  });
  ctx.backlash_svg = SvgOf(documents::Figure(deck, backlash_series, *ctx.backlash));
  WriteTo("-o", ctx.folder.File("backlash.svg"), ctx.streams.out, [&](std::ostream& os) { os << ctx.backlash_svg; });
  const analysis::MeshResult mesh = analysis::MeshAt(deck.MakeModel(), 0.0);
  WriteTo("-o", ctx.folder.File("mesh.json"), ctx.streams.out, [&](std::ostream& os) { os << Dump(documents::Json(deck, mesh)) << '\n'; });
  ctx.mesh_svg = SvgOf(documents::Figure(deck, mesh));
  WriteTo("-o", ctx.folder.File("mesh.svg"), ctx.streams.out, [&](std::ostream& os) { os << ctx.mesh_svg; });
  return ctx.backlash->summary.failed() == 0 ? kExitSuccess : kExitNotSucceeded;
}

std::string UnloadedHtml(const ReportContext& ctx) {
  std::string html;
  if (ctx.deck.reducer) {  // the unloaded analysis is the pin ring's; the stage's free play is the loop's
    html += "<p>The pin ring's mesh alone (Liu eq. 17). The stage's free play, which also takes up the output "
            "mechanism's and the bearings' clearances, is the backlash of the torsional stiffness below.</p>\n";
  }
  html += Table(documents::Json(ctx.deck, *ctx.backlash));  // the backlash's summary, from its result
  return html + InlineSvgText(ctx.backlash_svg, "backlash") + InlineSvgText(ctx.mesh_svg, "mesh");
}

/// None at zero torque, where there is no rated torque to run the loop to.
const char* StiffnessSkipped(const app::Deck& deck) {
  return deck.RequireLoad().torque != 0.0 ? nullptr : "the deck's torque is zero, so there is no rated torque to run the loop to";
}

/// The torque-twist loop at crank 0 (the deck's [stiffness] steps): its result in this process
/// (analysis::StiffnessRunner), its JSON streamed and its figure drawn by the documents `ltca
/// stiffness` writes, beside the page.
int RunStiffness(ReportContext& ctx) {
  const app::Deck& deck = ctx.deck;
  const Streams& streams = ctx.streams;
  analysis::StiffnessSettings settings = deck.stiffness;
  settings.crank = 0.0;
  settings.Validate();
  deck.RequireMaterial();
  analysis::StiffnessRunner runner(deck.MakeStage({0.0}), ctx.solver, settings, deck.RequireLoad().torque, deck.friction);
  WriteTo("-o", ctx.folder.File("stiffness.json"), streams.out, [&](std::ostream& os) {
    documents::StiffnessJsonWriter writer(os, deck, ctx.solver, settings, runner.rated_torque());
    Progress progress(streams.err, streams.progress, "stiffness loop at position", static_cast<std::int64_t>(runner.cranks().size()));
    std::int64_t done = 0;
    ctx.stiff = runner.Run([&](const analysis::StiffnessPosition& p) {
      writer.Add(p);
      progress.Update(++done);
    });
    progress.Finish();
    writer.Finish(*ctx.stiff);
  });
  ctx.stiff_svg = SvgOf(documents::Figure(deck, ctx.solver, *ctx.stiff));
  WriteTo("-o", ctx.folder.File("stiffness.svg"), streams.out, [&](std::ostream& os) { os << ctx.stiff_svg; });
  return ctx.stiff->all_succeeded() ? kExitSuccess : kExitNotSucceeded;
}

std::string StiffnessHtml(const ReportContext& ctx) {
  nlohmann::json summary = documents::Json(*ctx.stiff);  // the loop's summary, from its result
  summary.erase("curve");
  return "<p>The torque-twist loop at crank 0.</p>\n" + Table(summary) + InlineSvgText(ctx.stiff_svg, "stiffness");
}

/// Efficiency needs [friction], [operation] (the crank speed) and a torque (the output power).
const char* EfficiencySkipped(const app::Deck& deck) {
  return !deck.friction                     ? "the deck has no [friction] section"
         : !deck.operation                  ? "the deck has no [operation] section (the crank speed)"
         : deck.RequireLoad().torque == 0.0 ? "the deck's torque is zero (no output power)"
                                            : nullptr;
}

/// The efficiency (one disc or two): its result in this process (analysis::EfficiencyRunner over
/// the deck's sweep), its JSON streamed and its figure drawn by the documents `ltca efficiency`
/// writes, beside the page.
int RunEfficiency(ReportContext& ctx) {
  const app::Deck& deck = ctx.deck;
  const Streams& streams = ctx.streams;
  analysis::EfficiencyRunner runner(deck.MakeStage(), ctx.solver, deck.RequireLoad().torque, *deck.friction, *deck.operation);
  std::vector<analysis::EfficiencyPosition> kept;  // for the figure, without their contacts
  WriteTo("-o", ctx.folder.File("efficiency.json"), streams.out, [&](std::ostream& os) {
    documents::EfficiencyJsonWriter writer(os, deck, ctx.solver, deck.second_disc.has_value());
    const std::vector<double>& cranks = runner.cranks();
    Progress progress(streams.err, streams.progress, "efficiency at position", static_cast<std::int64_t>(cranks.size()));
    for (std::size_t i = 0; i < cranks.size(); ++i) {
      analysis::EfficiencyPosition p = runner.Solve(cranks[i]);
      writer.Add(p);
      p.contacts.clear();
      kept.push_back(std::move(p));
      progress.Update(static_cast<std::int64_t>(i + 1));
    }
    progress.Finish();
    ctx.eff = runner.Summary();
    if (!deck.load_spectrum.empty()) ctx.eff_spectrum = app::EfficiencyDeckSpectrum(deck, ctx.solver);
    writer.Finish(*ctx.eff, ctx.eff_spectrum ? &*ctx.eff_spectrum : nullptr);
  });
  ctx.eff_svg = SvgOf(documents::Figure(deck, ctx.solver, kept, *ctx.eff));
  WriteTo("-o", ctx.folder.File("efficiency.svg"), streams.out, [&](std::ostream& os) { os << ctx.eff_svg; });
  return ctx.eff->all_succeeded() && (!ctx.eff_spectrum || ctx.eff_spectrum->all_succeeded()) ? kExitSuccess
                                                                                               : kExitNotSucceeded;
}

std::string EfficiencyHtml(const ReportContext& ctx) {
  std::string spectrum;  // a bin per row, then the figures over the duty cycle (the efficiency's spectrum block)
  if (ctx.eff_spectrum) {
    const nlohmann::json j = documents::Json(*ctx.eff_spectrum);
    std::string rows;
    for (const auto& b : j.at("bins")) {
      rows += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n", Cell(b.at("torque_nm")),
                          Cell(b.at("speed_rpm")), Cell(b.at("time_share")), Cell(b.at("efficiency")),
                          Cell(b.at("output_power_w")), Cell(b.at("power_loss_w")));
    }
    spectrum = fmt::format("<p>Over the load spectrum: {}</p>\n<table>\n<tr><th>torque (N*m)</th><th>crank speed (rpm)</th>"
                           "<th>time share</th><th>efficiency</th><th>output power (W)</th><th>power loss (W)</th></tr>\n{}"
                           "</table>\n{}",
                           Html(j.at("note").get<std::string>()), rows,
                           Table({{"spectrum", {{"efficiency", j.at("efficiency")}, {"output_power_w", j.at("output_power_w")},
                                                {"power_loss_w", j.at("power_loss_w")},
                                                {"power_loss_by_source_w", j.at("power_loss_by_source_w")}}}}));
  }
  // The summary, from its result.
  return Table(documents::Json(*ctx.eff)) + spectrum + InlineSvgText(ctx.eff_svg, "efficiency");
}

constexpr const char* kNoTolerances = "the deck has no [tolerances] section";
constexpr const char* kNoOptimise = "the deck has no [optimise] section";

/// The study as `ltca tolerance` runs it, in this process: the deck's samples (or --samples) on
/// the report's threads and, under mpirun, its ranks; tolerance.json and tolerance.svg written by
/// the command's builders (rank 0).
int RunTolerance(ReportContext& ctx) {
  const app::Deck& deck = ctx.deck;
  const ReportOptions& options = ctx.options;
  const Streams& streams = ctx.streams;
  ReportTolerance& tol = ctx.tol;
  const analysis::ToleranceSettings settings = documents::ToleranceSettingsFor(deck, options.samples, std::nullopt, false);
  const int threads = analysis::ResolveThreads(options.threads);
  tol.study.emplace(deck.MakeToleranceCase(), ctx.solver, settings);
  std::unique_ptr<SampleFarm> farm = MakeSampleFarm();
  FailTogether(farm.get(), streams.err, [&]() -> int {
    const bool root = !farm || farm->rank() == 0;
    analysis::ToleranceRunPlan plan;
    plan.threads = threads;
    plan.ranks = farm.get();
    plan.worst_case = !options.no_worst_case;
    std::ostringstream unseen;  // the estimate, which the page does not show
    ToleranceProgressLines progress(ctx.quiet, ctx.quiet.progress && root, unseen, 2.0, threads, farm && farm->size() > 1,
                                    plan.worst_case);
    plan.progress = &progress;
    tol.result = analysis::RunToleranceStudy(*tol.study, plan);
    return kExitSuccess;
  });
  if (tol.root()) {
    WriteTo("-o", ctx.folder.File("tolerance.json"), streams.out,
            [&](std::ostream& os) { os << Dump(documents::Json(deck, ctx.solver, *tol.study, *tol.result)) << '\n'; });
    tol.svg = SvgOf(documents::Figure(deck, *tol.study, *tol.result));
    WriteTo("-o", ctx.folder.File("tolerance.svg"), streams.out, [&](std::ostream& os) { os << tol.svg; });
  }
  return !tol.result || tol.result->all_succeeded() ? kExitSuccess : kExitNotSucceeded;
}

/// The search as `ltca optimise` runs it, in this process, on the report's threads (and, under
/// mpirun, its ranks): optimise.json (its history spooled as the search makes it, so that the
/// page's memory does not grow with the evaluations) and optimise.svg by the command's builders.
int RunOptimise(ReportContext& ctx) {
  const app::Deck& deck = ctx.deck;
  const Streams& streams = ctx.streams;
  ReportOptimisation& opt = ctx.opt;
  const analysis::OptimiseSettings settings = documents::OptimiseSettingsFor(deck, std::nullopt);
  const int threads = analysis::ResolveThreads(ctx.options.threads);
  std::unique_ptr<SampleFarm> farm = MakeSampleFarm();
  FailTogether(farm.get(), streams.err, [&]() -> int {
    opt.optimiser.emplace(deck.MakeToleranceCase(), ctx.solver, settings, threads, RankGroupOf(farm.get()));
    const bool root = opt.optimiser->ranks().rank == 0;
    const analysis::OptimiseSettings& s = opt.optimiser->settings();
    std::unique_ptr<Spool> history;
    if (root) history = std::make_unique<Spool>("-o", ctx.folder.File("optimise.json"));
    documents::OptimiseSeries series(s, false);
    analysis::OptimiseRunPlan plan;
    plan.sink = [&](const analysis::DesignEvaluation& e) {
      if (history) {
        history->stream() << documents::HistoryItem(s, e);
        history->Check();
      }
      series.Add(e);
    };
    opt.run = analysis::RunOptimisation(*opt.optimiser, plan);
    if (root) {
      WriteTo("-o", ctx.folder.File("optimise.json"), streams.out, [&](std::ostream& os) {
        documents::WriteOptimiseJson(os, documents::OptimiseJsonHead(deck, ctx.solver, s, *opt.run),
                                     [&](std::ostream& items) { history->CopyTo(items); }, s, *opt.run);
      });
      history.reset();
      opt.svg = SvgOf(documents::Figure(deck, s, *opt.run, series));
      WriteTo("-o", ctx.folder.File("optimise.svg"), streams.out, [&](std::ostream& os) { os << opt.svg; });
    }
    return kExitSuccess;
  });
  return !opt.run || opt.run->best() != nullptr ? kExitSuccess : kExitNotSucceeded;
}

/// A generic analysis of the table (documents/analyses.hpp) as its command runs it with its
/// defaults and the report's --solver and --kinematics: NAME.json and NAME.svg beside the page.
int RunAnalysisSection(ReportContext& ctx, const documents::Analysis& analysis) {
  std::map<std::string, std::string> given;
  if (analysis.load_inputs && !ctx.options.solver.empty()) given["solver"] = ctx.options.solver;
  if (analysis.load_inputs && !ctx.options.kinematics.empty()) given["kinematics"] = ctx.options.kinematics;
  documents::AnalysisOutput output = documents::RunAnalysis(analysis, ctx.deck, documents::ParseOptions(analysis, given));
  WriteTo("-o", ctx.folder.File((analysis.name + ".json").c_str()), ctx.streams.out,
          [&](std::ostream& os) { os << Dump(output.json) << '\n'; });
  std::string svg;
  if (output.figure) {
    svg = SvgOf(*output.figure);
    WriteTo("-o", ctx.folder.File((analysis.name + ".svg").c_str()), ctx.streams.out, [&](std::ostream& os) { os << svg; });
  }
  const int code = output.exit_code;
  ctx.generic[analysis.name] = {std::move(output), std::move(svg)};
  return code;
}

/// A generic analysis's section: its own HTML, or its key figures tabled (labelled, each row
/// carrying its key), then its figure, in a block <div class="analysis" data-analysis="NAME">
/// that ends with the comment "end of analysis NAME".
std::string AnalysisHtml(const ReportContext& ctx, const documents::Analysis& analysis) {
  const auto& [output, svg] = ctx.generic.at(analysis.name);
  std::string html = output.report_html;
  if (html.empty()) {
    html = "<table>\n";
    for (const auto& [key, value] : output.key_figures) {
      html += fmt::format("<tr data-key=\"{}\"><th>{}</th><td>{}</td></tr>\n", Html(key), Html(Label(key)), CellOf(value));
    }
    html += "</table>\n";
  }
  // Marked as the table's, so that a check of the page tells its figures from the fixed sections'.
  return fmt::format("<div class=\"analysis\" data-analysis=\"{0}\">\n{1}{2}</div><!-- end of analysis {0} -->\n", Html(analysis.name),
                     html, InlineSvgText(svg, analysis.name));
}

/// One section of the page: its anchor and title (the contents list), its name in the status line
/// (nullptr: it has no status of its own), why its analysis does not run for a deck (nullptr:
/// always runs; the function returns nullptr when it runs), the analysis (writes its files into
/// the staging folder and keeps its result in the context; returns its exit code), its HTML from
/// the context, and the JSON documents its analysis leaves beside the page.
struct ReportSection {
  const char* id;
  const char* title;
  const char* part;
  const char* (*skipped)(const app::Deck&);
  int (*run)(ReportContext&);
  std::string (*html)(const ReportContext&);
  std::vector<std::string> documents;
  /// A generic analysis of the table: its run and HTML are RunAnalysisSection and AnalysisHtml.
  const documents::Analysis* analysis = nullptr;
};

constexpr const char* kNoSpectrum = "the deck has no [[load_spectrum]]";

/// The load spectrum: each bin solved as `ltca solve` solves it (app::SolveDeckSpectrum), its
/// document the solve's `spectrum` block.
int RunSpectrum(ReportContext& ctx) {
  ctx.spectrum = app::SolveDeckSpectrum(ctx.deck, ctx.solver);
  WriteTo("-o", ctx.folder.File("spectrum.json"), ctx.streams.out,
          [&](std::ostream& os) { os << documents::SpectrumJson(ctx.deck, *ctx.spectrum).dump(2) << '\n'; });
  return ctx.spectrum->all_succeeded() ? kExitSuccess : kExitNotSucceeded;
}

/// A bin per row (its torque, speed, share, status and shortest lives), then the lives over the
/// spectrum by Palmgren-Miner.
std::string SpectrumHtml(const ReportContext& ctx) {
  if (!ctx.spectrum) return NotRun(kNoSpectrum);
  const nlohmann::json j = documents::SpectrumJson(ctx.deck, *ctx.spectrum);
  std::string rows;
  int number = 0;
  for (const auto& b : j.at("bins")) {
    rows += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
                        "<td>{}</td><td>{}</td></tr>\n",
                        ++number, Cell(b.at("torque_nm")), Cell(b.at("speed_rpm")), Cell(b.at("time_share")), Cell(b.at("status")),
                        Cell(b.at("max_contact_stress_mpa")), Cell(b.at("shortest_l10_hours")),
                        Cell(b.at("shortest_load_zone_life_hours")),
                        Cell(b.at("shortest_pitting_life_hours")), Cell(b.at("smallest_static_safety")),
                        Cell(b.at("largest_roller_contact_stress_mpa")));
  }
  nlohmann::json lives = {{"shortest_l10_hours", j.at("shortest_l10_hours")},
                           {"shortest_load_zone_life_hours", j.at("shortest_load_zone_life_hours")},
                           {"shortest_pitting_life_hours", j.at("shortest_pitting_life_hours")}};
  std::string modified;  // ISO 281's modified lives per bin, when the deck gives the oil's viscosity
  if (j.contains("shortest_modified_life_hours")) {
    lives["shortest_modified_life_hours"] = j.at("shortest_modified_life_hours");
    lives["shortest_load_zone_modified_life_hours"] = j.at("shortest_load_zone_modified_life_hours");
    std::string mrows;
    for (const auto& b : j.at("bins")) {
      mrows += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n", Cell(b.at("torque_nm")),
                           Cell(b.at("speed_rpm")), Cell(b.at("viscosity_ratio")), Cell(b.at("shortest_modified_life_hours")),
                           Cell(b.at("shortest_load_zone_modified_life_hours")));
    }
    modified = fmt::format("<p>ISO 281:2007's modified lives, each bin's a_ISO at its own speed (nu_1, kappa):</p>\n<table>\n"
                           "<tr><th>torque (N*m)</th><th>crank speed (rpm)</th><th>kappa</th><th>shortest a_ISO L10 (h)</th>"
                           "<th>shortest a_ISO load-zone life (h)</th></tr>\n{}</table>\n",
                           mrows);
  }
  // The static figures: the worst bin's, each beside the bin that sets it (one row a figure, in
  // the order the text output gives them); then every verdict.
  std::vector<std::pair<std::string, std::string>> figures = {{"max_contact_stress_mpa", "max_contact_stress_bin"}};
  if (ctx.deck.reducer) {
    figures.push_back({"smallest_static_safety", "smallest_static_safety_bin"});
    figures.push_back({"largest_roller_contact_stress_mpa", "largest_roller_contact_stress_bin"});
  }
  std::string worst = "<table>\n<tr><th>figure</th><th>worst bin's value</th><th>bin</th></tr>\n";
  for (const auto& [value, bin] : figures) {
    worst += fmt::format("<tr data-key=\"worst bin.{}\"><th>{}</th><td>{}</td><td>{}</td></tr>\n", Html(value), Html(Label(value)),
                         Cell(j.at(value)), Cell(j.at(bin)));
  }
  worst += "</table>\n";
  if (!j.at("pitting_safety").empty()) {
    lives["smallest_pitting_safety"] = j.at("smallest_pitting_safety");
    lives["required_pitting_life_hours"] = j.at("required_pitting_life_hours");
  }
  std::string verdicts;
  for (const analysis::AllowableRow& row : analysis::SpectrumRatingRows(*ctx.spectrum, ctx.deck.allowables,
                                                                        ctx.deck.RequireMaterial().contact_stress_limit,
                                                                        ctx.deck.reducer.has_value())) {
    verdicts += AllowableRow(row);
  }
  return fmt::format("<p>{}</p>\n<table>\n<tr><th>bin</th><th>torque (N*m)</th><th>crank speed (rpm)</th><th>time share</th><th>status</th>"
                     "<th>largest contact stress (MPa)</th><th>shortest bearing L10 (h)</th><th>shortest load-zone life (h)</th>"
                     "<th>shortest pitting life (h)</th><th>smallest s_0</th><th>largest roller stress (MPa)</th></tr>\n{}</table>\n{}{}"
                     "<p>Static figures: {}.</p>\n{}"
                     "<p>The spectrum's figures against the deck's allowables:</p>\n<table>\n"
                     "<tr><th>figure</th><th>value</th><th>allowable</th><th>margin</th><th>verdict</th>"
                     "<th>Monte Carlo pass fraction</th><th>from</th></tr>\n{}</table>\n",
                     Html(j.at("rule").get<std::string>()), rows, modified, Table({{"spectrum", lives}}),
                     Html(j.at("static_rule").get<std::string>()), worst, verdicts);
}

/// The sections of the page, in order: each is always there, with its analysis or a note why it did
/// not run. The analyses run in this order, and the allowables are rendered from all of them.
const std::vector<ReportSection>& Sections() {
  static const std::vector<ReportSection> sections = {
      {"inputs", "Inputs", nullptr, nullptr, nullptr, InputsHtml, {}},
      {"allowables", "Results against allowables", nullptr, nullptr, nullptr, AllowablesHtml, {}},
      {"geometry", "Geometry", nullptr, nullptr, RunGeometry, GeometryHtml, {"geometry.json"}},
      {"loaded", "Loaded tooth contact analysis", "solve", nullptr, RunLoaded, LoadedHtml, {"solve.json"}},
      {"spectrum", "Load spectrum", "spectrum", [](const app::Deck& deck) { return deck.load_spectrum.empty() ? kNoSpectrum : nullptr; },
       RunSpectrum, SpectrumHtml, {"spectrum.json"}},
      {"unloaded", "Unloaded: backlash and mesh", "backlash", nullptr, RunUnloaded, UnloadedHtml, {"backlash.json", "mesh.json"}},
      {"stiffness", "Torsional stiffness", "stiffness", StiffnessSkipped, RunStiffness, StiffnessHtml, {"stiffness.json"}},
      {"efficiency", "Friction and meshing efficiency", "efficiency", EfficiencySkipped, RunEfficiency, EfficiencyHtml,
       {"efficiency.json"}},
      {"tolerance", "Tolerance analysis (Monte Carlo)", "tolerance",
       [](const app::Deck& deck) { return deck.tolerances ? nullptr : kNoTolerances; }, RunTolerance,
       [](const ReportContext& ctx) { return ctx.tol.root() ? ToleranceHtml(ctx.tol, ctx.options) : NotRun(kNoTolerances); },
       {"tolerance.json"}},
      {"optimise", "Design optimisation", "optimise", [](const app::Deck& deck) { return deck.optimise ? nullptr : kNoOptimise; },
       RunOptimise, [](const ReportContext& ctx) { return ctx.opt.root() ? OptimiseHtml(ctx.opt) : NotRun(kNoOptimise); },
       {"optimise.json"}}};
  return sections;
}

/// The sections of the page: the fixed ones, then a section for every generic analysis of the
/// table (documents::Analyses()), in the table's order.
const std::vector<ReportSection>& AllSections() {
  static const std::vector<ReportSection> sections = [] {
    std::vector<ReportSection> all = Sections();
    for (const documents::Analysis& a : documents::Analyses()) {
      if (!a.generic()) continue;
      all.push_back({a.report_anchor.c_str(), a.report_title.c_str(), a.name.c_str(), a.skipped, nullptr, nullptr, {a.name + ".json"}, &a});
    }
    return all;
  }();
  return sections;
}

/// The page's head: the style, the case, the model and solver, the load and sweep, and the contents
/// list of the sections.
std::string PageHead(const app::Deck& deck, const ReportOptions& options) {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char date[32] = {};
  std::tm utc{};
  gmtime_r(&now, &utc);
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", &utc);
  std::string html = fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>ltca report: {0}</title>\n"
      "<style>body{{font-family:sans-serif;max-width:1350px;margin:1em auto;padding:0 1em;color:#111}}"
      "table{{border-collapse:collapse;margin:0.5em 0 1.5em;max-width:100%}}th,td{{border:1px solid #ccc;padding:2px 8px;"
      "text-align:left;font-size:0.9em;vertical-align:top;overflow-wrap:break-word}}table.inputs td{{overflow-wrap:anywhere}}th{{background:#f3f3f3;font-weight:normal}}"
      "svg{{max-width:100%;height:auto;display:block;margin:0.5em 0 2em}}h2{{border-bottom:1px solid #ccc;margin-top:1.5em}}"
      "h3{{margin:1em 0 0.2em;font-size:1em}}.grid{{display:flex;gap:2em;flex-wrap:wrap}}.grid>div{{min-width:0;flex:1 1 400px}}"
      "tr.default td{{color:#666}}.pass{{color:#0a6e0a;font-weight:bold}}.fail{{color:#b00000;font-weight:bold}}"
      "header th,table.inputs th,table.inputs td:last-child{{white-space:nowrap}}table.inputs td:nth-child(2){{min-width:4em}}table.inputs td:nth-child(3){{white-space:nowrap}}"
      "nav ol{{columns:2;margin:0.3em 0}}.meta{{color:#444}}.note{{color:#444;font-style:italic}}"
      "@media print{{body{{max-width:none;margin:0;font-size:10pt}}nav{{display:none}}h2{{break-before:page}}"
      "h2#inputs{{break-before:auto}}svg{{break-inside:avoid;max-height:24cm;width:auto}}table,tr{{break-inside:avoid}}"
      "@page{{size:A4;margin:15mm}}}}</style>\n"
      "</head>\n<body>\n<header>\n<h1>{0}</h1>\n",
      Html(deck.info.title));
  html += fmt::format("<p class=\"meta\">Deck <code>{}</code> &middot; ltca {} &middot; generated {} &middot; {}</p>\n",
                      Html(deck.name), LTCA_VERSION, date, Html(deck.info.source));
  if (const std::vector<std::string> given = documents::OverrideArguments(deck); !given.empty()) {
    // A deck changed on the command line is not the deck its title names.
    html += fmt::format("<p class=\"meta\">Read with <code>{}</code></p>\n", Html(fmt::format("{}", fmt::join(given, " "))));
  }
  html += "<table>\n";
  html += fmt::format("<tr><th>model</th><td>{}</td></tr>\n", Html(Unlabelled(ModelLine(deck))));
  html += fmt::format("<tr><th>solver</th><td>{}</td></tr>\n", Html(Unlabelled(SolverLine(deck, SolverFor(deck, options.solver)))));
  html += fmt::format("<tr><th>load</th><td>T = {:g} N*m</td></tr>\n", units::NmmToNm(deck.RequireLoad().torque));
  html += fmt::format("<tr><th>sweep</th><td>{} positions, crank {:g} to {:g} deg</td></tr>\n</table>\n</header>\n",
                      deck.sweep.positions, units::RadToDeg(deck.sweep.crank_start), units::RadToDeg(deck.sweep.crank_end));
  html += "<nav>\n<h2 id=\"contents\">Contents</h2>\n<ol>\n";
  for (const ReportSection& s : AllSections()) html += fmt::format("<li><a href=\"#{}\">{}</a></li>\n", s.id, Html(s.title));
  return html + "</ol>\n</nav>\n";
}

}  // namespace

std::vector<std::pair<std::string, std::string>> ReportSectionTitles() {
  std::vector<std::pair<std::string, std::string>> titles;
  for (const ReportSection& s : AllSections()) titles.emplace_back(s.id, s.title);
  return titles;
}

int RunReport(const app::Deck& given, const ReportOptions& options, const Streams& streams) {
  // Every analysis of the page runs with --kinematics when given (the deck's otherwise).
  const app::Deck deck = DeckFor(given, options.kinematics);
  if (options.out_dir.empty()) throw std::invalid_argument("report: -o DIR: expected the folder to write index.html into");
  ReportFolder folder(options, streams);
  std::ostringstream sink;  // the analyses write their documents and figures into DIR; their text goes nowhere
  const Streams quiet{sink, sink, streams.err, streams.progress};
  ReportContext ctx{deck, options, streams, quiet, folder};
  // Each section's analysis, in the table's order, when the deck asks for it; then the page from
  // their results, section by section.
  const std::vector<ReportSection>& sections = AllSections();
  std::vector<const char*> not_run(sections.size(), nullptr);  // why, for an analysis that did not run
  std::vector<int> codes(sections.size(), kExitSuccess);
  std::string built_from;  // the documents of the analyses that ran
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const ReportSection& s = sections[i];
    if (s.skipped != nullptr && (not_run[i] = s.skipped(deck)) != nullptr) continue;
    if (s.analysis != nullptr) codes[i] = RunAnalysisSection(ctx, *s.analysis);
    if (s.run != nullptr) codes[i] = s.run(ctx);
    for (const std::string& name : s.documents) built_from += fmt::format("{}{}", built_from.empty() ? "" : ", ", name);
  }
  std::string html = PageHead(deck, options);
  for (std::size_t i = 0; i < sections.size(); ++i) {
    html += fmt::format("<h2 id=\"{}\">{}</h2>\n", sections[i].id, Html(sections[i].title));
    html += not_run[i] != nullptr                ? NotRun(not_run[i])
            : sections[i].analysis != nullptr ? AnalysisHtml(ctx, *sections[i].analysis)
                                              : sections[i].html(ctx);
  }
  const double seconds = ctx.solved->summary.wall_seconds;
  html += fmt::format("<p class=\"meta\">Built from {} in this folder (the loaded sweep took {} s). A static page: nothing is "
                      "fetched when it is viewed.</p>\n</body>\n</html>\n",
                      built_from, std::isfinite(seconds) ? fmt::format("{:.3g}", seconds) : "n/a");
  WriteTo("-o", folder.File("index.html"), streams.out, [&html](std::ostream& os) { os << html; });
  folder.Commit();
  // The page's status is every part's: the first part's code that is not success, and their names.
  std::string failed;
  int result = kExitSuccess;
  for (std::size_t i = 0; i < sections.size(); ++i) {
    if (codes[i] == kExitSuccess) continue;
    failed += fmt::format("{}{}", failed.empty() ? "" : ", ", sections[i].part);
    if (result == kExitSuccess) result = codes[i];
  }
  fmt::print(streams.text, "{} {} (case {}, {})\n", folder.handed_to_run() ? "writes" : "wrote",
             (folder.target() / "index.html").string(), deck.info.title,
             failed.empty() ? "every part succeeded" : fmt::format("not every part succeeded: {}; see their sections", failed));
  return result;
}

Command ReportCommand() {
  auto st = std::make_shared<DeckState<ReportOptions>>();
  return {"report",
          "One static HTML page, DIR/index.html, that a browser opens from disk (nothing fetched): the case, the model and "
          "solver, the geometry table, the summaries of the loaded sweep and of the backlash, and the figures inlined as "
          "SVG; the JSON documents it is built from are left beside it.",
          [st](CLI::App& c) {
            ReportOptions& o = st->options;
            AddLoadInputs(c, st->deck, o.solver, o.kinematics);
            c.add_option("-o,--out", o.out_dir, "Folder of index.html (created when missing)")->required()->type_name("DIR");
            // The tolerance study's options, as `ltca tolerance` takes them.
            AddSamplesOption(c, o.samples);
            c.add_option("--threads", o.threads, "Tolerance study: threads, 1 to 1024 (default 0: every hardware thread)");
            c.add_flag("--no-worst-case", o.no_worst_case, "Tolerance study: skip the extreme-value (worst-case) runs");
            c.add_flag("--force", o.force, "Replace DIR even when it holds files that no ltca report wrote");
          },
          [] { return std::vector<std::string>{}; },
          [st](const Streams& streams) {
            if (!st->options.solver.empty()) solvers::MakeSolver(st->options.solver);  // the name checked first
            return RunReport(st->deck.Read(), st->options, streams);
          }};
}

}  // namespace ltca::cli
