#include "ltca/app/bench.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "ltca/geometry/units.hpp"
#include "ltca/app/sweep.hpp"

namespace ltca::app {
namespace {

using units::RadToArcsec;

struct Figures {
  std::vector<double> te;        // rad per position
  std::vector<int> contacts;
  double max_force = 0, max_stress = 0, residual = 0;
  double evaluations = 0;
  SolverStatus status = SolverStatus::kSuccess;
};

Figures Collect(const SweepResult& sweep) {
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

Deck WithPositions(Deck deck, int positions) {
  if (positions > 0) {
    deck.sweep.crank_start = 0.0;
    deck.sweep.crank_end = 2.0 * units::kPi / deck.pair.pin_count;
    deck.sweep.positions = positions;
  }
  return deck;
}

}  // namespace

std::string BenchSetting::GeometryLabel() const {
  return geometry.mode == geometry::GeometrySettings::Mode::kElements
             ? fmt::format("elements {}x{}", geometry.profile_elements, geometry.width_slices)
             : "analytic";
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
    SolverOptions ref_options = deck.solver;
    ref_options.kinematics = contact::ContactKinematics::kExact;
    ref_options.torque_tolerance = 1e-12;
    ref_options.name = "bisection";
    const Figures ref = Collect(SolveSweep(deck, ref_options));
    ref_options.name = "compatibility";
    const Figures confirm = Collect(SolveSweep(deck, ref_options));
    report.references.push_back({c.name, RadToArcsec(Mean(ref.te)),
                                 std::abs(RadToArcsec(Mean(ref.te) - Mean(confirm.te)))});
    for (const BenchSetting& s : matrix.settings) {
      if (!s.only_case.empty() && s.only_case != c.name) continue;
      Deck run_deck = deck;
      run_deck.geometry = s.geometry;
      SolverOptions options = deck.solver;
      if (!s.preset.empty()) options = ApplyPreset(options, s.preset);
      options.name = s.solver;
      options.kinematics = s.kinematics;
      if (s.preset.empty()) options.torque_tolerance = s.torque_tolerance;
      std::vector<double> per_position;
      Figures f;
      for (int r = 0; r < std::max(1, matrix.repeats); ++r) {
        const auto start = std::chrono::steady_clock::now();
        const SweepResult sweep = SolveSweep(run_deck, options);  // includes the mesh state of every position
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
  // Log-log: x = seconds per position, y = mean-TE error (floored at 1e-12 arcsec to be drawable).
  const double w = 760, h = 480, pad = 70;
  double x_lo = 1e300, x_hi = 1e-300, y_lo = 1e300, y_hi = 1e-300;
  const auto y_of = [](const BenchRow& r) { return std::max(r.errors.mean_te_arcsec, 1e-12); };
  for (const auto& r : report.rows) {
    x_lo = std::min(x_lo, r.seconds_per_position_median);
    x_hi = std::max(x_hi, r.seconds_per_position_median);
    y_lo = std::min(y_lo, y_of(r));
    y_hi = std::max(y_hi, y_of(r));
  }
  const double lx0 = std::floor(std::log10(x_lo)), lx1 = std::ceil(std::log10(x_hi) + 1e-9);
  const double ly0 = std::floor(std::log10(y_lo)), ly1 = std::ceil(std::log10(y_hi) + 1e-9);
  const auto px = [&](double x) { return pad + (std::log10(x) - lx0) / std::max(lx1 - lx0, 1.0) * (w - 2 * pad); };
  const auto py = [&](double y) { return h - pad - (std::log10(y) - ly0) / std::max(ly1 - ly0, 1.0) * (h - 2 * pad); };
  std::ofstream os(path);
  fmt::print(os, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"11\">\n", w + 220, h);
  fmt::print(os, "<rect x=\"{0}\" y=\"{0}\" width=\"{1}\" height=\"{2}\" fill=\"none\" stroke=\"#888\"/>\n", pad, w - 2 * pad, h - 2 * pad);
  fmt::print(os, "<text x=\"{}\" y=\"20\">mean-TE error (arcsec) against time per crank position (s), log-log; one series per method</text>\n", pad);
  for (double e = lx0; e <= lx1; e += 1) {
    fmt::print(os, "<text x=\"{:.1f}\" y=\"{}\">1e{}</text>\n", px(std::pow(10, e)) - 10, h - pad + 16, e);
  }
  for (double e = ly0; e <= ly1; e += 1) {
    fmt::print(os, "<text x=\"8\" y=\"{:.1f}\">1e{}</text>\n", py(std::pow(10, e)) + 4, e);
  }
  const char* colours[] = {"#c0392b", "#2980b9", "#27ae60", "#8e44ad", "#d35400", "#16a085", "#7f8c8d", "#2c3e50"};
  std::map<std::string, std::vector<const BenchRow*>> series;
  for (const auto& r : report.rows) {
    series[r.setting.solver + (r.setting.kinematics == contact::ContactKinematics::kExact ? " exact" : " linearised") +
           (r.setting.geometry.mode == geometry::GeometrySettings::Mode::kElements ? " elements" : "")]
        .push_back(&r);
  }
  int k = 0;
  for (const auto& [name, rows] : series) {
    const char* colour = colours[k % 8];
    for (const BenchRow* r : rows) {
      fmt::print(os, "<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"4\" fill=\"{}\"><title>{} {}: {:.3g} s, {:.3g} arcsec</title></circle>\n",
                 px(r->seconds_per_position_median), py(y_of(*r)), colour, r->case_name, r->setting.Label(),
                 r->seconds_per_position_median, r->errors.mean_te_arcsec);
    }
    fmt::print(os, "<circle cx=\"{}\" cy=\"{}\" r=\"4\" fill=\"{}\"/><text x=\"{}\" y=\"{}\">{}</text>\n", w + 10,
               pad + 18 * k, colour, w + 20, pad + 18 * k + 4, name);
    ++k;
  }
  os << "</svg>\n";
}

}  // namespace ltca::app
