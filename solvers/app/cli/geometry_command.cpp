#include "geometry_command.hpp"

#include <cmath>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/real_pair.hpp"
#include "ltca/geometry/units.hpp"
#include "output.hpp"

namespace ltca::cli {
namespace {

using geometry::CycloidProfile;
using geometry::Kinematics;
using units::RadToDeg;

nlohmann::json SummaryJson(const app::Deck& deck, const geometry::RealPair& real) {
  const CycloidProfile& profile = real.profile();
  const Kinematics& kinematics = real.kinematics();
  const auto finite_or_null = [](double v) -> nlohmann::json {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  return {
      {"case", {{"title", deck.info.title}, {"source", deck.info.source}, {"deck", deck.name}}},
      {"tooth_difference", profile.tooth_difference()},
      {"k1", profile.k1()},
      {"phi_max_deg", RadToDeg(profile.phi_max())},
      {"contact_ratio", profile.contact_ratio()},
      {"theta_max_deg", RadToDeg(profile.theta_max())},
      {"alpha_max_deg", RadToDeg(profile.alpha_max())},
      {"min_curvature_radius_mm", profile.min_curvature_radius()},
      {"undercut_margin_mm", finite_or_null(profile.undercut_margin())},
      {"mesh_period_deg", RadToDeg(kinematics.MeshPeriod())},
      {"transmission_ratio", kinematics.TransmissionRatio()},
      // The figures above are of the cycloid as made: modification and [errors] applied.
      {"errors_applied", !real.errors().IsZero()},
      {"pin_circle_radius_as_assembled_mm", real.pin_circle_radius()},
  };
}

void WriteCsv(const CycloidProfile& profile, int samples, std::ostream& os) {
  // The whole profile, tooth space by tooth space, from -phi_max to phi_max.
  os << "tooth_space,u_deg,x_mm,y_mm,normal_x,normal_y,curvature_radius_mm\n";
  const double phi = profile.phi_max();
  for (int k = 0; k < profile.pair().tooth_count; ++k) {
    for (int i = -samples; i <= samples; ++i) {
      const double u = phi * i / samples;
      const auto p = profile.Evaluate(u, k);
      fmt::print(os, "{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", k, RadToDeg(u),
                 p.position.x(), p.position.y(), p.normal.x(), p.normal.y(), p.CurvatureRadius());
    }
  }
}

void WriteSvg(const geometry::RealPair& real, double crank, int samples, std::ostream& os) {
  const CycloidProfile& profile = real.profile();
  const Kinematics& kinematics = real.kinematics();
  const auto& pair = profile.pair();
  const geometry::Pose pose = kinematics.CycloidPose(crank);
  // d < 0: the cycloid is the outer member (a ring); its material lies outside the profile.
  const bool ring = profile.tooth_difference() < 0;
  const double outer = pair.pin_circle_radius + pair.pin_radius + 2.0 * pair.eccentricity;
  const double extent = (ring ? 1.15 * outer : outer) + 2.0;
  fmt::print(os,
             "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{0} {0} {1} {1}\" "
             "width=\"800\" height=\"800\">\n",
             -extent, 2.0 * extent);
  fmt::print(os, "<title>{}: crank {:.4g} deg</title>\n", "cycloid and pins", RadToDeg(crank));
  os << "<g transform=\"scale(1,-1)\" fill=\"none\" stroke-width=\"" << extent / 400.0 << "\">\n";
  fmt::print(os, "<circle cx=\"0\" cy=\"0\" r=\"{}\" stroke=\"#bbb\"/>\n", real.pin_circle_radius());
  os << "<path stroke=\"#c0392b\" fill=\"#f5d5d0\" fill-rule=\"evenodd\" d=\"";
  const double phi = profile.phi_max();
  for (int k = 0; k < pair.tooth_count; ++k) {
    for (int i = -samples; i <= samples; ++i) {
      const Eigen::Vector2d x = pose.ToFixed(profile.Position(phi * i / samples, k));
      fmt::print(os, "{}{:.5f},{:.5f} ", (k == 0 && i == -samples) ? "M" : "L", x.x(), x.y());
    }
  }
  os << "Z";
  if (ring) {  // outer rim of the ring, so that the even-odd fill leaves the inside empty
    const double rim = 1.1 * outer;
    fmt::print(os, " M{0:.5f},{1:.5f} A{2},{2} 0 1,0 {3:.5f},{1:.5f} A{2},{2} 0 1,0 {0:.5f},{1:.5f} Z",
               pose.centre.x() + rim, pose.centre.y(), rim, pose.centre.x() - rim);
  }
  os << "\"/>\n";
  for (int j = 0; j < pair.pin_count; ++j) {
    const Eigen::Vector2d c = real.PinCentre(j);  // as assembled: pin-circle and pitch deviations
    fmt::print(os, "<circle cx=\"{:.5f}\" cy=\"{:.5f}\" r=\"{}\" stroke=\"#2c3e50\" fill=\"#d6dde5\"/>\n",
               c.x(), c.y(), pair.pin_radius);
  }
  fmt::print(os, "<circle cx=\"{:.5f}\" cy=\"{:.5f}\" r=\"{}\" fill=\"#c0392b\"/>\n", pose.centre.x(),
             pose.centre.y(), extent / 150.0);
  os << "</g>\n</svg>\n";
}

}  // namespace

nlohmann::json GeometryJson(const app::Deck& deck) {
  return SummaryJson(deck, deck.MakeRealPair());
}

void RunGeometry(const app::Deck& deck, const GeometryOptions& options, const Streams& streams) {
  RequireOneStdout({{"--json", options.json_path}, {"--csv", options.csv_path}, {"--svg", options.svg_path}});
  Output json("--json", options.json_path, streams.out);  // checked before computing
  Output csv("--csv", options.csv_path, streams.out);
  Output svg("--svg", options.svg_path, streams.out);
  std::ostream& out = streams.text;
  const geometry::RealPair real = deck.MakeRealPair();  // the pair as made: what every command sees
  const CycloidProfile& profile = real.profile();
  const Kinematics& kinematics = real.kinematics();
  const auto& p = deck.pair;
  const auto& m = deck.modification;
  fmt::print(out, "case      {}\n", deck.info.title);
  if (!deck.info.source.empty()) fmt::print(out, "source    {}\n", deck.info.source);
  fmt::print(out, "pair      z_p = {}, z_c = {}, d = {}, r_rp = {} mm, R_p = {} mm, e = {} mm, B_c = {} mm\n",
             p.pin_count, p.tooth_count, p.ToothDifference(), p.pin_radius, p.pin_circle_radius,
             p.eccentricity, p.face_width);
  fmt::print(out, "modif.    dR_rp = {:g} um, dR_p = {:g} um, rotation = {:g} arcsec\n",
             units::MmToUm(m.pin_radius), units::MmToUm(m.pin_circle_radius),
             units::RadToArcsec(m.rotation));
  if (!deck.errors.IsZero()) {
    const auto& e = deck.errors;
    fmt::print(out, "errors    profile layer = {:g} um, pin circle radius as assembled = {:.6f} mm, pitch deviations: {}\n",
               units::MmToUm(e.profile_layer), real.pin_circle_radius(),
               e.cumulative_pitch_deviation.empty() ? "none" : "per pin (Liu eq. 5)");
    if (e.HasProfileDeviation()) {
      const auto& r = e.profile_random;
      fmt::print(out, "          profile deviation along the profile: {}{}{}, |delta| <= {:g} um (Liu eq. 4; not in the figures below)\n",
                 r.zone == 0.0 ? "" : fmt::format("random zone {:g} um ({} elements, {}, {}, seed {})", units::MmToUm(r.zone),
                                                   r.elements,
                                                   r.distribution == geometry::ProfileRandomDistribution::kUniform ? "uniform" : "normal",
                                                   r.spacing == geometry::ProfileElementSpacing::kArcLength ? "arc_length" : "parameter",
                                                   r.seed),
                 r.zone != 0.0 && e.profile_measured ? " plus " : "",
                 e.profile_measured ? fmt::format("measured trace ({} points)", e.profile_measured->x.size()) : "",
                 units::MmToUm(real.profile_deviation().MaxAbs()));
    }
    fmt::print(out, "          the figures below are of the cycloid as made ([errors] applied)\n");
  }
  fmt::print(out, "K1                     {:.6f}       curtate coefficient (Chen eq. 12)\n", profile.k1());
  fmt::print(out, "phi_max                {:.6f} deg   tooth-space half width (Chen eq. 16)\n",
             RadToDeg(profile.phi_max()));
  fmt::print(out, "contact ratio          {:.4f}       (Chen eq. 27)\n", profile.contact_ratio());
  fmt::print(out, "theta_max              {:.4f} deg   pin's maximum contact angle (Chen eq. 20)\n",
             RadToDeg(profile.theta_max()));
  fmt::print(out, "alpha_max              {:.4f} deg   = arcsin K1 (Liu eq. 2)\n",
             RadToDeg(profile.alpha_max()));
  fmt::print(out, "min curvature radius   {:.4f} mm\n", profile.min_curvature_radius());
  if (std::isfinite(profile.undercut_margin())) {
    fmt::print(out, "undercut margin        {:.4f} mm    (> 0: no undercut)\n", profile.undercut_margin());
  } else {
    fmt::print(out, "undercut margin        none (no convex part on the offset side)\n");
  }
  fmt::print(out, "mesh period            {:.6f} deg crank\n", RadToDeg(kinematics.MeshPeriod()));
  fmt::print(out, "transmission ratio     {:.6g} (crank / cycloid)\n", kinematics.TransmissionRatio());

  if (json.enabled()) {
    json.stream() << Dump(SummaryJson(deck, real)) << '\n';
    json.Commit();
  }
  if (csv.enabled()) {
    WriteCsv(profile, options.samples_per_flank, csv.stream());
    csv.Commit();
  }
  if (svg.enabled()) {
    WriteSvg(real, units::DegToRad(options.crank_deg), options.samples_per_flank, svg.stream());
    svg.Commit();
  }
}

}  // namespace ltca::cli
