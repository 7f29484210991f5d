#include "geometry_command.hpp"

#include "command.hpp"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "documents/geometry.hpp"
#ifdef LTCA_HAVE_DXFLIB
#include "documents/dxf.hpp"
#endif
#include "ltca/geometry/real_pair.hpp"
#include "ltca/geometry/units.hpp"
#include "output.hpp"

namespace ltca::cli {
namespace documents = app::documents;

void RunGeometry(const app::Deck& deck, const GeometryOptions& options, const Streams& streams) {
  RequireDistinctOutputs({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path},
                          {"--dxf", options.dxf_path}});
#ifndef LTCA_HAVE_DXFLIB
  if (!options.dxf_path.empty()) {
    throw std::invalid_argument("--dxf: this ltca was built without dxflib (install libdxflib-dev and rebuild)");
  }
#endif
  Output json("--json", options.json_path, streams.out);  // checked before computing
  Output csv("--csv", options.csv_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  Output dxf("--dxf", options.dxf_path, streams.out);
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
                      "[inspection] roller_diameter_mm; docs/export.md)");
            AddOutput(c, "--csv", st->options.csv_path,
                      "Write the whole profile to FILE: tooth_space, u_deg, x_mm, y_mm, normal_x, normal_y, "
                      "curvature_radius_mm (body frame)");
            AddOutput(c, "--svg", st->options.svg_path,
                      "Draw the cycloid and the pins at the crank angle --crank-deg to FILE");
            AddOutput(c, "--dxf", st->options.dxf_path,
                      "Write the disc as made as a DXF drawing to FILE (mm, disc centre at the origin): layers "
                      "DISC_PROFILE (the profile within 0.1 um), BORE, HOLES, PIN_RING and OUTPUT_PINS (at crank 0)");
            c.add_option("--crank-deg", st->options.crank_deg, "Crank angle of the drawing in degrees (default 0)")
                ->check(CrankAngle());
          },
          [st] {
            return std::vector<std::string>{st->options.json_path, st->options.csv_path, st->options.svg_path,
                                            st->options.dxf_path};
          },
          [st](const Streams& streams) {
            RunGeometry(st->deck.Read(), st->options, streams);
            return kExitSuccess;
          }};
}

}  // namespace ltca::cli
