#include "geometry_command.hpp"

#include <cmath>
#include <limits>
#include <string>
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
      // Issue 12: the relief that runs (from the deck, a default for |d| >= 2, or none), and
      // what it cuts: the flank ends at +-junction_deg of every space.
      {"tip_relief",
       {{"truncation_mm", profile.tip_cap().relief().truncation},
        {"rounding_radius_mm", profile.tip_cap().relief().rounding_radius},
        {"source", deck.tip_relief_source},
        {"note", deck.tip_relief_note.empty() ? nlohmann::json(nullptr) : nlohmann::json(deck.tip_relief_note)},
        {"active", profile.tip_cap().active()},
        {"junction_deg", RadToDeg(profile.tip_cap().junction())},
        {"land_half_width_mm", profile.tip_cap().land_half_width()},
        {"depth_mm", profile.tip_cap().depth()}}},
  };
}

/// The outline of the cycloid as made, tooth space by tooth space: the flank from -u_j to u_j
/// (u_j = phi_max without a tip relief), then, with a relief, the cap of the tip it runs into.
/// f(tooth_space, u or NaN on the cap, position, normal, curvature, part) per point.
template <class F>
void ForEachOutlinePoint(const CycloidProfile& profile, int samples, const F& f) {
  const geometry::TipCap& cap = profile.tip_cap();
  const auto flank = [&](int k, double lo, double hi) {
    for (int i = 0; i <= 2 * samples; ++i) {
      const double u = lo + (hi - lo) * i / (2 * samples);
      const auto p = profile.Evaluate(u, k);
      f(k, u, p.position, p.normal, p.curvature, geometry::SurfacePart::kFlank);
    }
  };
  // Tip `tip`'s cap from w_from to w_to (exclusive of the junctions, which the flanks draw).
  const auto tip_cap = [&](int k, int tip, double direction) {
    for (int i = samples - 1; i > -samples; --i) {
      const geometry::CapFoot c = cap.Point(direction * static_cast<double>(i) / samples, tip);
      f(k, std::numeric_limits<double>::quiet_NaN(), c.point, c.normal, c.curvature, c.part);
    }
  };
  for (int k = 0; k < profile.pair().tooth_count; ++k) {
    if (!cap.active()) {
      flank(k, -profile.phi_max(), profile.phi_max());
    } else if (profile.tooth_difference() > 0) {
      // Space k's flank, then the cap of tip k from space k's junction (w = 1) to space k + 1's.
      flank(k, -cap.junction(), cap.junction());
      tip_cap(k, k, 1.0);
    } else {
      // A ring: the flank u < 0, the cap of its tip at u = 0 (w = -1 on the u < 0 side), the flank u > 0.
      flank(k, -profile.phi_max(), -cap.junction());
      tip_cap(k, k, -1.0);
      flank(k, cap.junction(), profile.phi_max());
    }
  }
}

void WriteCsv(const CycloidProfile& profile, int samples, std::ostream& os) {
  // The whole profile, tooth space by tooth space; u_deg is empty on a tip relief's cap.
  os << "tooth_space,u_deg,x_mm,y_mm,normal_x,normal_y,curvature_radius_mm,part\n";
  ForEachOutlinePoint(profile, samples, [&](int k, double u, const Eigen::Vector2d& x, const Eigen::Vector2d& n,
                                            double curvature, geometry::SurfacePart part) {
    const double radius = curvature == 0.0 ? std::numeric_limits<double>::infinity() : 1.0 / curvature;
    fmt::print(os, "{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{}\n", k,
               std::isnan(u) ? std::string() : fmt::format("{:.9g}", RadToDeg(u)), x.x(), x.y(), n.x(), n.y(), radius,
               geometry::SurfacePartName(part));
  });
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
  bool first = true;
  ForEachOutlinePoint(profile, samples, [&](int, double, const Eigen::Vector2d& body, const Eigen::Vector2d&, double,
                                            geometry::SurfacePart) {
    const Eigen::Vector2d x = pose.ToFixed(body);
    fmt::print(os, "{}{:.5f},{:.5f} ", first ? "M" : "L", x.x(), x.y());
    first = false;
  });
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
  const geometry::TipCap& cap = profile.tip_cap();
  if (cap.active()) {
    fmt::print(out, "tip relief             truncation {:g} mm, rounding radius {:g} mm ({}): the flank ends at u = +-{:.6f} deg, "
                    "{:.4g} mm cut off the tip{}\n",
               cap.relief().truncation, cap.relief().rounding_radius,
               deck.tip_relief_source == "deck" ? "from the deck" : "default", RadToDeg(cap.junction()), cap.depth(),
               cap.truncated() ? fmt::format(", land {:.4g} mm wide", 2.0 * cap.land_half_width()) : "");
  } else {
    fmt::print(out, "tip relief             none{}\n", profile.has_tip_corners() ? " (sharp tip corners)" : "");
  }
  if (!deck.tip_relief_note.empty()) fmt::print(out, "                       {}\n", deck.tip_relief_note);
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
