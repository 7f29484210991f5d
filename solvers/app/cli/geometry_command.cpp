#include "geometry_command.hpp"

#include "command.hpp"


#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <utility>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "documents/geometry.hpp"
#include "documents/step.hpp"
#ifdef LTCA_HAVE_DXFLIB
#include "documents/dxf.hpp"
#endif
#include "ltca/app/modules.hpp"
#include "ltca/app/temporaries.hpp"
#include "ltca/geometry/real_pair.hpp"
#include "ltca/geometry/units.hpp"
#include "output.hpp"
#include "step/ltca_step.h"

namespace ltca::cli {
namespace documents = app::documents;

namespace step_module {

/// The STEP writer's entry point in the module ltca_step.so (app/modules.hpp: the module alone links
/// OpenCASCADE, which no other command loads), or nullptr with `why`.
LtcaStepWriteFn Load(std::string& why) {
  try {
    return app::ModuleFunction<LtcaStepWriteFn>("step", LTCA_STEP_ENTRY);
  } catch (const std::runtime_error& e) {
    why = e.what();
    return nullptr;
  }
}

/// The STEP text of the disc, written by the module to a private temporary and read back.
std::string Write(LtcaStepWriteFn write, const documents::StepDisc& disc, const std::string& name, LtcaStepReport& report) {
  app::ScratchFile scratch;
  std::string pattern = std::filesystem::temp_directory_path().string() + "/.ltca-step-XXXXXX";
  if (!app::CreateTemporary(pattern, false)) {
    throw std::runtime_error(fmt::format("{}: cannot create a temporary file for the STEP ({})", pattern, std::strerror(errno)));
  }
  scratch.path = pattern;
  LtcaStepDisc in{};
  in.abi_version = LTCA_STEP_ABI_VERSION;
  in.piece_count = static_cast<int>(disc.piece_offsets.size()) - 1;
  in.piece_offsets = disc.piece_offsets.data();
  in.points_xy = disc.points_xy.data();
  in.check_offsets = disc.check_offsets.data();
  in.check_xy = disc.check_xy.data();
  in.hole_count = static_cast<int>(disc.holes_xyr.size() / 3);
  in.holes_xyr = disc.holes_xyr.data();
  in.width_mm = disc.width_mm;
  in.tolerance_mm = documents::kStepTolerance;
  in.path = scratch.path.c_str();
  in.description = disc.description.c_str();
  in.name = name.c_str();
  if (write(&in, &report) != 0) throw std::runtime_error(fmt::format("the STEP writer: {}", report.error));
  std::ifstream file(scratch.path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  if (!file && !file.eof()) throw std::runtime_error(fmt::format("{}: cannot read back the STEP", scratch.path));
  return text.str();
}

}  // namespace step_module

int RunGeometry(const app::Deck& deck, const GeometryOptions& options, const Streams& streams) {
  RequireDistinctOutputs({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path},
                          {"--dxf", options.dxf_path}, {"--step", options.step_path},
                          {"--deviation-csv", options.deviation_csv_path}, {"--deviation-svg", options.deviation_svg_path}});
  for (const auto& [option, path] : {std::pair<const char*, const std::string&>{"--deviation-csv", options.deviation_csv_path},
                                     std::pair<const char*, const std::string&>{"--deviation-svg", options.deviation_svg_path}}) {
    if (!path.empty() && !deck.errors.profile_measured) {
      throw std::invalid_argument(fmt::format("{} {}: the deck has no measured profile trace: expected [errors] "
                                              "profile_measured_csv (docs/export.md, \"Deviation chart\")",
                                              option, path));
    }
  }
  // The STEP writer is loaded before anything is computed or opened: without it nothing is written.
  LtcaStepWriteFn write_step = nullptr;
  if (!options.step_path.empty()) {
    std::string why;
    write_step = step_module::Load(why);
    if (write_step == nullptr) {
      fmt::print(streams.err,
                 "ltca: error: --step: the STEP writer ltca_step.so (built with OpenCASCADE, libocct-*-dev) is not "
                 "usable: {}\n",
                 why);
      return kExitNotSucceeded;
    }
  }
#ifndef LTCA_HAVE_DXFLIB
  if (!options.dxf_path.empty()) {
    throw std::invalid_argument("--dxf: this ltca was built without dxflib (install libdxflib-dev and rebuild)");
  }
#endif
  Output json("--json", options.json_path, streams.out);  // checked before computing
  Output csv("--csv", options.csv_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  Output dxf("--dxf", options.dxf_path, streams.out);
  Output step("--step", options.step_path, streams.out);
  Output deviation_csv("--deviation-csv", options.deviation_csv_path, streams.out);
  Output deviation_svg("--deviation-svg", options.deviation_svg_path, streams.out);
  const geometry::RealPair real = deck.MakeRealPair();  // the pair as made: what every command sees
  streams.text << documents::Text(deck, real);
  if (json.enabled()) {
    json.stream() << Dump(documents::Json(deck, real)) << '\n';
    json.Commit();
  }
  if (csv.enabled()) {
    csv.stream() << documents::Csv(real.profile(), options.samples_per_flank);
    csv.Commit();
  }
  if (svg.enabled()) {
    // The drawing's clearances: the unloaded mesh state at its crank.
    const contact::MeshState unloaded = deck.MakeModel().Evaluate(units::DegToRad(options.crank_deg));
    WriteFigure(documents::Figure(deck, real, unloaded, options.samples_per_flank), svg);
  }
#ifdef LTCA_HAVE_DXFLIB
  if (dxf.enabled()) {
    std::string text;
    try {
      text = documents::Dxf(deck, real, std::filesystem::temp_directory_path().string());
    } catch (const std::runtime_error& e) {
      throw OutputError(fmt::format("--dxf {}: {}", options.dxf_path, e.what()));
    }
    dxf.stream() << text;
    dxf.Commit();
  }
#endif
  if (deviation_csv.enabled() || deviation_svg.enabled()) {
    const std::optional<analysis::DeviationChart> chart = documents::DeviationChartOf(deck, real);
    if (deviation_csv.enabled()) {
      deviation_csv.stream() << documents::DeviationCsv(*chart);
      deviation_csv.Commit();
    }
    if (deviation_svg.enabled()) WriteFigure(documents::DeviationFigure(deck, real, *chart), deviation_svg);
  }
  if (step.enabled()) {
    const documents::StepDisc disc = documents::MakeStepDisc(deck, real);
    LtcaStepReport report{};
    std::string text;
    try {
      const std::string name = options.step_path == "-" ? std::string("disc.step") : std::filesystem::path(options.step_path).filename().string();
      text = step_module::Write(write_step, disc, name, report);
    } catch (const std::runtime_error& e) {
      throw OutputError(fmt::format("--step {}: {}", options.step_path, e.what()));
    }
    step.stream() << text;
    step.Commit();
    fmt::print(streams.text,
               "STEP solid             {} B-spline poles in {} pieces through {} profile points; they stray at most "
               "{:.2g} um from the analytic profile at {} points between; {} holes; {} mm wide\n",
               report.poles, disc.piece_offsets.size() - 1, disc.points_xy.size() / 2,
               report.max_check_deviation_mm * 1e3, disc.check_xy.size() / 2, disc.holes_xyr.size() / 3, disc.width_mm);
    for (const std::string& note : disc.notes) fmt::print(streams.text, "                       {}\n", note);
  }
  return kExitSuccess;
}

Command GeometryCommand() {
  auto st = std::make_shared<DeckState<GeometryOptions>>();
  return {"geometry",
          "Derived geometry of the pair: K1, phi_max (Chen eq. 16), contact ratio (eq. 27), theta_max (eq. 20), "
          "alpha_max (Liu eq. 2), minimum radius of curvature, undercut margin, mesh period, root and tip diameters and "
          "the dimension over rollers; optionally the profile as CSV, a drawing as SVG and the disc as DXF.",
          [st](CLI::App& c) {
            AddDeckInputs(c, st->deck, "Case deck (TOML); default: the built-in Liu 2021 Table 1 deck");
            AddOutput(c, "--json", st->options.json_path,
                      "Write the summary as JSON to FILE ('-' for standard output); keys k1, phi_max_deg, contact_ratio, "
                      "theta_max_deg, alpha_max_deg, min_curvature_radius_mm, undercut_margin_mm, mesh_period_deg, "
                      "transmission_ratio, root_diameter_mm, tip_diameter_mm, dimension_over_rollers_mm (with "
                      "[inspection] roller_diameter_mm; its band dimension_over_rollers_tolerance with [tolerances]), "
                      "profile_deviation_chart (with [errors] profile_measured_csv; docs/export.md)");
            AddOutput(c, "--csv", st->options.csv_path,
                      "Write the whole profile to FILE: tooth_space, u_deg, x_mm, y_mm, normal_x, normal_y, "
                      "curvature_radius_mm (body frame)");
            AddOutput(c, "--svg", st->options.svg_path,
                      "Draw the cycloid and the pins at the crank angle --crank-deg to FILE");
            AddOutput(c, "--dxf", st->options.dxf_path,
                      "Write the disc as made as a DXF drawing to FILE (mm, disc centre at the origin): layers "
                      "DISC_PROFILE (the profile within 0.1 um), BORE, HOLES, PIN_RING and OUTPUT_PINS (at crank 0)");
            AddOutput(c, "--step", st->options.step_path,
                      "Write the disc as made as a STEP solid (AP214, mm) to FILE: the profile as B-splines within "
                      "0.1 um, the bore and the output pins' holes cut, extruded over the face width (needs the "
                      "module ltca_step.so beside ltca, built with OpenCASCADE)");
            AddOutput(c, "--deviation-csv", st->options.deviation_csv_path,
                      "With [errors] profile_measured_csv: write the deviation chart's table to FILE: u_deg, measured_um, "
                      "fitted_um (the offset, isometric and rotation modification fitted to the trace), residual_um, "
                      "band_lower_um, band_upper_um ([inspection] profile_tolerance_um)");
            AddOutput(c, "--deviation-svg", st->options.deviation_svg_path,
                      "With [errors] profile_measured_csv: draw the deviation chart (trace, fit, band) to FILE (.svg, .png, .pdf)");
            c.add_option("--crank-deg", st->options.crank_deg, "Crank angle of the drawing in degrees (default 0)")
                ->check(CrankAngle());
          },
          [st] {
            return std::vector<std::string>{st->options.json_path, st->options.csv_path, st->options.svg_path,
                                            st->options.dxf_path, st->options.step_path,
                                            st->options.deviation_csv_path, st->options.deviation_svg_path};
          },
          [st](const Streams& streams) {
            return RunGeometry(st->deck.Read(), st->options, streams);
          }};
}

}  // namespace ltca::cli
