#include "harness.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "ltca/geometry/units.hpp"
#include "ltca/app/plots.hpp"
#include "ltca/analysis/sweep.hpp"

namespace ltca::bench {

using namespace ltca::app;  // NOLINT: the harness runs the application's decks
namespace {

using units::RadToArcsec;

struct Figures {
  std::vector<double> te;        // rad per position
  std::vector<int> contacts;
  double max_force = 0, max_stress = 0, residual = 0;
  double evaluations = 0;
  SolverStatus status = SolverStatus::kSuccess;
};

Figures Collect(const analysis::SweepResult& sweep) {
  Figures f;
  f.status = sweep.summary.status;
  f.max_force = sweep.summary.max_pin_force;
  f.max_stress = sweep.summary.max_contact_stress;
  for (const auto& p : sweep.positions) {
    f.te.push_back(p.result.te);
    f.contacts.push_back(p.contacts);
    f.residual = std::max(f.residual, p.result.residuals.Normalised());
    f.evaluations += p.result.torque_evaluations > 0 ? p.result.torque_evaluations : p.result.iterations;
  }
  f.evaluations /= static_cast<double>(sweep.positions.size());
  return f;
}

double Mean(const std::vector<double>& v) {
  double s = 0;
  for (const double x : v) s += x;
  return s / static_cast<double>(v.size());
}
double PeakToPeak(const std::vector<double>& v) {
  return *std::max_element(v.begin(), v.end()) - *std::min_element(v.begin(), v.end());
}

}  // namespace

Deck WithPositions(Deck deck, int positions) {
  if (positions > 0) {
    deck.sweep.crank_start = 0.0;
    deck.sweep.crank_end = 2.0 * units::kPi / deck.pair.pin_count;
    deck.sweep.positions = positions;
  }
  return deck;
}

std::string BenchSetting::GeometryLabel() const {
  return geometry.mode == geometry::GeometrySettings::Mode::kElements
             ? fmt::format("elements {}x{}", geometry.profile_elements, geometry.width_slices)
             : "analytic";
}

std::pair<Deck, SolverOptions> BenchSetting::Apply(const Deck& deck) const {
  Deck run_deck = deck;
  run_deck.geometry = geometry;
  run_deck.kinematics = kinematics;
  SolverOptions options = deck.solver;
  if (!preset.empty()) options = ApplyPreset(options, preset);
  options.name = solver;
  if (preset.empty()) options.torque_tolerance = torque_tolerance;
  return {run_deck, options};
}

std::string BenchSetting::Label() const {
  return fmt::format("{} {} tol {:g}{}{}", solver,
                     kinematics == contact::ContactKinematics::kExact ? "exact" : "linearised", torque_tolerance,
                     preset.empty() ? "" : " (" + preset + ")",
                     geometry.mode == geometry::GeometrySettings::Mode::kElements ? ", " + GeometryLabel() : "");
}

BenchReport RunBench(const BenchMatrix& matrix, const BenchHeader& header) {
  BenchReport report;
  report.header = header;
  for (const BenchCase& c : matrix.cases) {
    const Deck deck = WithPositions(c.deck, matrix.positions);
    // Reference: analytic, exact kinematics, 1e-12, confirmed by a second solver.
    Deck ref_deck = deck;
    ref_deck.kinematics = contact::ContactKinematics::kExact;
    SolverOptions ref_options = deck.solver;
    ref_options.torque_tolerance = 1e-12;
    ref_options.name = "bisection";
    const Figures ref = Collect(SolveDeckSweep(ref_deck, ref_options));
    ref_options.name = "compatibility";
    const Figures confirm = Collect(SolveDeckSweep(ref_deck, ref_options));
    report.references.push_back({c.name, RadToArcsec(Mean(ref.te)),
                                 std::abs(RadToArcsec(Mean(ref.te) - Mean(confirm.te)))});
    for (const BenchSetting& s : matrix.settings) {
      if (!s.only_case.empty() && s.only_case != c.name) continue;
      const auto [run_deck, options] = s.Apply(deck);
      std::vector<double> per_position;
      Figures f;
      // One untimed run first: the first sweep of a row pays its first page faults, cache misses
      // and the CPU's clock ramp (the first row of the 2026-11-27 run: 66 us a position timed
      // here, 53 us in `--profile` of the same row).
      SolveDeckSweep(run_deck, options);
      for (int r = 0; r < std::max(1, matrix.repeats); ++r) {
        const auto start = std::chrono::steady_clock::now();
        const analysis::SweepResult sweep = SolveDeckSweep(run_deck, options);  // includes the stage: every position's mesh state
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        per_position.push_back(seconds / static_cast<double>(sweep.positions.size()));
        if (r == 0) f = Collect(sweep);
      }
      std::sort(per_position.begin(), per_position.end());
      BenchRow row;
      row.case_name = c.name;
      row.setting = s;
      if (!s.preset.empty()) row.setting.torque_tolerance = options.torque_tolerance;
      row.status = ToString(f.status);
      row.positions = static_cast<int>(f.te.size());
      row.seconds_per_position_median = per_position[per_position.size() / 2];
      row.seconds_per_position_min = per_position.front();
      row.seconds_per_position_max = per_position.back();
      row.evaluations_per_position = f.evaluations;
      row.residual = f.residual;
      row.mean_te_arcsec = RadToArcsec(Mean(f.te));
      row.errors.mean_te_arcsec = std::abs(RadToArcsec(Mean(f.te) - Mean(ref.te)));
      row.errors.pp_te_arcsec = std::abs(RadToArcsec(PeakToPeak(f.te) - PeakToPeak(ref.te)));
      row.errors.max_force_n = std::abs(f.max_force - ref.max_force);
      row.errors.max_stress_mpa = std::abs(f.max_stress - ref.max_stress);
      for (std::size_t i = 0; i < f.contacts.size(); ++i) {
        row.errors.contacts = std::max(row.errors.contacts, std::abs(f.contacts[i] - ref.contacts[i]));
      }
      report.rows.push_back(row);
    }
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  report.peak_rss_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in kB on Linux
  return report;
}

void WriteBenchJson(const BenchReport& report, const std::filesystem::path& path) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : report.rows) {
    rows.push_back({{"case", r.case_name},
                    {"solver", r.setting.solver},
                    {"kinematics", r.setting.kinematics == contact::ContactKinematics::kExact ? "exact" : "linearised"},
                    {"torque_tolerance", r.setting.torque_tolerance},
                    {"preset", r.setting.preset},
                    {"geometry_mode", r.setting.GeometryLabel()},
                    {"status", r.status},
                    {"positions", r.positions},
                    {"seconds_per_position_median", r.seconds_per_position_median},
                    {"seconds_per_position_min", r.seconds_per_position_min},
                    {"seconds_per_position_max", r.seconds_per_position_max},
                    {"evaluations_per_position", r.evaluations_per_position},
                    {"mean_te_arcsec", r.mean_te_arcsec},
                    {"error_mean_te_arcsec", r.errors.mean_te_arcsec},
                    {"error_pp_te_arcsec", r.errors.pp_te_arcsec},
                    {"error_max_pin_force_n", r.errors.max_force_n},
                    {"error_max_contact_stress_mpa", r.errors.max_stress_mpa},
                    {"error_contacts", r.errors.contacts},
                    {"residual", r.residual}});
  }
  nlohmann::json refs = nlohmann::json::array();
  for (const auto& r : report.references) {
    refs.push_back({{"case", r.case_name}, {"mean_te_arcsec", r.mean_te_arcsec},
                    {"two_solver_agreement_arcsec", r.agreement_arcsec}});
  }
  const nlohmann::json doc = {{"header", {{"date", report.header.date}, {"commit", report.header.commit},
                                          {"build_type", report.header.build_type}, {"compiler", report.header.compiler},
                                          {"machine", report.header.machine}}},
                              {"peak_rss_mb", report.peak_rss_mb},
                              {"references", refs},
                              {"rows", rows}};
  std::ofstream(path) << doc.dump(2) << '\n';
}

void WriteBenchCsv(const BenchReport& report, const std::filesystem::path& path) {
  std::ofstream os(path);
  os << "case,solver,kinematics,torque_tolerance,preset,geometry_mode,status,positions,seconds_per_position_median,"
        "seconds_per_position_min,seconds_per_position_max,evaluations_per_position,mean_te_arcsec,"
        "error_mean_te_arcsec,error_pp_te_arcsec,error_max_pin_force_n,error_max_contact_stress_mpa,error_contacts,"
        "residual\n";
  for (const auto& r : report.rows) {
    fmt::print(os, "{},{},{},{:g},{},{},{},{},{:.6g},{:.6g},{:.6g},{:.4g},{:.9g},{:.3g},{:.3g},{:.3g},{:.3g},{},{:.3g}\n",
               r.case_name, r.setting.solver,
               r.setting.kinematics == contact::ContactKinematics::kExact ? "exact" : "linearised",
               r.setting.torque_tolerance, r.setting.preset, r.setting.GeometryLabel(), r.status, r.positions,
               r.seconds_per_position_median,
               r.seconds_per_position_min, r.seconds_per_position_max, r.evaluations_per_position, r.mean_te_arcsec,
               r.errors.mean_te_arcsec, r.errors.pp_te_arcsec, r.errors.max_force_n, r.errors.max_stress_mpa,
               r.errors.contacts, r.residual);
  }
}

void WriteBenchSvg(const BenchReport& report, const std::filesystem::path& path) {
  // One panel per case, log-log: x = seconds per position, y = mean-TE error against the case's
  // reference (floored at 1e-12 arcsec to be drawable). A method keeps its colour and marker in
  // every panel.
  const auto method = [](const BenchRow& r) {
    return r.setting.solver + (r.setting.kinematics == contact::ContactKinematics::kExact ? " exact" : " linearised") +
           (r.setting.geometry.mode == geometry::GeometrySettings::Mode::kElements ? " elements" : "");
  };
  std::map<std::string, int> methods;
  std::vector<std::string> cases;
  for (const auto& r : report.rows) {
    methods.emplace(method(r), 0);
    if (std::find(cases.begin(), cases.end(), r.case_name) == cases.end()) cases.push_back(r.case_name);
  }
  int k = 0;
  for (auto& [name, index] : methods) index = k++;
  plots::Figure figure;
  figure.title = fmt::format("speed against error: mean-TE error against time per crank position, {} methods on {} cases",
                             methods.size(), cases.size());
  figure.caption = fmt::format("ltca-bench at {} ({} build, {}), {}; the error is against each case's reference "
                               "(bisection, exact kinematics, 1e-12, confirmed by compatibility); 0 is drawn at 1e-12 arcsec",
                               report.header.commit, report.header.build_type, report.header.compiler, report.header.date);
  figure.columns = cases.size() > 1 ? 2 : 1;
  figure.width = figure.columns == 2 ? 1500 : 900;
  figure.height = 120 + 400 * static_cast<int>((cases.size() + 1) / static_cast<std::size_t>(figure.columns));
  for (const auto& c : cases) {
    plots::Panel panel;
    panel.title = c;
    panel.x_label = "time per crank position (s)";
    panel.y_label = "mean-TE error (arcsec)";
    panel.log_x = panel.log_y = true;
    panel.legend = plots::LegendPlace::kOutsideRight;
    for (const auto& [name, index] : methods) {
      plots::Series series{name, {}, {}, plots::Style::kMarkers};
      series.colour = index % 8;
      series.marker = (index + index / 8) % 8;  // colour and marker together tell up to 64 methods apart
      for (const auto& r : report.rows) {
        if (r.case_name != c || method(r) != name) continue;
        series.x.push_back(r.seconds_per_position_median);
        series.y.push_back(std::max(r.errors.mean_te_arcsec, 1e-12));
      }
      if (!series.x.empty()) panel.series.push_back(std::move(series));
    }
    figure.panels.push_back(std::move(panel));
  }
  std::ofstream os(path, std::ios::binary);
  plots::Write(figure, os, plots::FormatForPath(path.string()));
  if (!os.flush()) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace ltca::bench
