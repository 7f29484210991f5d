#include "documents/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "documents/common.hpp"
#include "ltca/contact/cranks.hpp"
#include "ltca/contact/output_pins.hpp"
#include "ltca/analysis/inspection.hpp"
#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/reducer.hpp"

namespace ltca::app::documents {
namespace {

using geometry::CycloidProfile;
using geometry::Kinematics;
using units::RadToDeg;

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

/// A round exaggeration factor (1, 2 or 5 x 10^k) that draws a typical mesh clearance (the
/// median over the pins of the working flank side) about 1.5 % of the drawing's extent.
double ExaggerationFactor(const std::vector<double>& clearance, double extent) {
  std::vector<double> c;
  for (const double v : clearance) {
    if (std::isfinite(v) && v > 1e-5) c.push_back(v);  // below 0.01 um: in contact, nothing to exaggerate
  }
  if (c.empty()) return 1.0;
  std::sort(c.begin(), c.end());
  const double typical = c[c.size() / 4];  // the tighter quarter: the pins that mesh
  const double want = 0.015 * extent / typical;
  if (want <= 1.0) return 1.0;
  if (want >= 1e4) return 1e4;
  const double decade = std::pow(10.0, std::floor(std::log10(want)));
  for (const double m : {5.0, 2.0, 1.0}) {
    if (m * decade <= want) return m * decade;
  }
  return decade;
}

/// The dimension over rollers as JSON (null without [inspection] roller_diameter_mm).
nlohmann::json RollersJson(const geometry::CycloidProfile& profile, const std::optional<geometry::RollerMeasurement>& m) {
  if (!m) return nullptr;
  const bool ring = profile.tooth_difference() < 0;
  return {{"roller_diameter_mm", m->roller_diameter},
          {"measured", ring ? "between" : "over"},
          {"convention", profile.pair().tooth_count % 2 == 0 ? "2 s + D_M (z_c even)" : "2 s cos(90 deg / z_c) + D_M (z_c odd)"},
          {"roller_centre_radius_mm", m->centre_radius},
          {"contact", geometry::RollerContactName(m->contact)},
          {"contacts_on_working_flanks", m->OnWorkingFlanks()},
          {"contact_u_deg", FiniteOrNull(RadToDeg(m->contact_u))},
          {"contact_diameter_mm", m->contact_diameter}};
}

/// The band of the dimension over rollers from [tolerances] (nullopt without rollers or tolerances).
std::optional<analysis::RollerToleranceBand> RollerBandOf(const Deck& deck) {
  if (!deck.inspection.roller_diameter || !deck.tolerances) return std::nullopt;
  return analysis::RollerTolerance(deck, *deck.tolerances, *deck.inspection.roller_diameter);
}

nlohmann::json RollerBandJson(const std::optional<analysis::RollerToleranceBand>& b) {
  if (!b) return nullptr;
  nlohmann::json terms = nlohmann::json::array();
  for (const analysis::RollerToleranceTerm& t : b->terms) {
    terms.push_back({{"key", t.key}, {"sensitivity_mm_per_key_unit", t.sensitivity}, {"worst_case_half_width", t.half_width},
                     {"sigma", t.sigma}, {"mean", t.mean}});
  }
  return {{"method", "sensitivity (central differences); worst case = centre +- sum |S_i| w_i, statistical (RSS) = "
                     "centre +- sqrt(sum (S_i w_i)^2); w_i: uniform tolerance or 3 sigma"},
          {"nominal_mm", b->nominal},
          {"centre_mm", b->centre},
          {"worst_case_mm", {b->worst_low, b->worst_high}},
          {"rss_mm", {b->rss_low, b->rss_high}},
          {"terms", terms}};
}

/// The deviation chart's fit as JSON (null without a measured trace).
nlohmann::json DeviationChartJson(const std::optional<analysis::DeviationChart>& c) {
  if (!c) return nullptr;
  return {{"source", c->source},
          {"points", c->u.size()},
          {"fitted_modification",
           {{"offset_pin_circle_radius_um", units::MmToUm(c->fit.offset)},
            {"isometric_pin_radius_um", units::MmToUm(c->fit.isometric)},
            {"rotation_arcsec", units::RadToArcsec(c->fit.rotation)},
            {"rms_residual_um", units::MmToUm(c->fit.rms_residual)},
            {"max_residual_um", units::MmToUm(c->fit.max_residual)},
            {"iterations", c->fit.iterations}}},
          {"tolerance_um", c->tolerance ? nlohmann::json(units::MmToUm(*c->tolerance)) : nlohmann::json(nullptr)},
          {"within_tolerance", c->tolerance ? nlohmann::json(c->WithinTolerance()) : nlohmann::json(nullptr)}};
}

}  // namespace

std::optional<analysis::DeviationChart> DeviationChartOf(const Deck& deck, const geometry::RealPair& real) {
  if (!deck.errors.profile_measured) return std::nullopt;
  return analysis::ChartProfileDeviation(real.profile(), *deck.errors.profile_measured, deck.inspection);
}

std::string DeviationCsv(const analysis::DeviationChart& c) {
  std::string text = "u_deg,measured_um,fitted_um,residual_um,band_lower_um,band_upper_um\n";
  const std::string lower = c.tolerance ? fmt::format("{:.17g}", -0.5 * units::MmToUm(*c.tolerance)) : "";
  const std::string upper = c.tolerance ? fmt::format("{:.17g}", 0.5 * units::MmToUm(*c.tolerance)) : "";
  for (std::size_t i = 0; i < c.u.size(); ++i) {
    text += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{},{}\n", RadToDeg(c.u[i]), units::MmToUm(c.measured[i]),
                        units::MmToUm(c.fitted[i]), units::MmToUm(c.measured[i] - c.fitted[i]), lower, upper);
  }
  return text;
}

plots::Figure DeviationFigure(const Deck& deck, const geometry::RealPair& real, const analysis::DeviationChart& c) {
  const bool ring = real.profile().tooth_difference() < 0;
  plots::Panel panel;
  panel.x_label = "profile parameter u (deg), tooth space 0";
  panel.y_label = "normal deviation (um), + material added";
  panel.title = fmt::format("fit: dR_p {:+.3f} um, dR_rp {:+.3f} um, rotation {:+.2f} arcsec", units::MmToUm(c.fit.offset),
                            units::MmToUm(c.fit.isometric), units::RadToArcsec(c.fit.rotation));
  plots::Series measured{"measured trace", {}, {}, plots::Style::kLineMarkers};
  plots::Series fitted{"fitted modification", {}, {}, plots::Style::kLine};
  plots::Series residual{fmt::format("trace - fit (rms {:.3f} um)", units::MmToUm(c.fit.rms_residual)), {}, {},
                         plots::Style::kLine};
  measured.colour = 0, fitted.colour = 1, residual.colour = 2;
  measured.marker_size = 0.6;
  residual.dashed = true;
  for (std::size_t i = 0; i < c.u.size(); ++i) {
    const double u = RadToDeg(c.u[i]);
    measured.x.push_back(u), measured.y.push_back(units::MmToUm(c.measured[i]));
    fitted.x.push_back(u), fitted.y.push_back(units::MmToUm(c.fitted[i]));
    residual.x.push_back(u), residual.y.push_back(units::MmToUm(c.measured[i] - c.fitted[i]));
  }
  panel.series.push_back(std::move(measured));
  panel.series.push_back(std::move(fitted));
  panel.series.push_back(std::move(residual));
  panel.marks.push_back({plots::Mark::Axis::kHorizontal, 0.0, "design", false, true});
  panel.marks.push_back({plots::Mark::Axis::kVertical, 0.0, ring ? "tip (u = 0)" : "root (u = 0)", false, true});
  if (c.tolerance) {
    const double half = 0.5 * units::MmToUm(*c.tolerance);
    panel.marks.push_back({plots::Mark::Axis::kHorizontal, half, fmt::format("+{:g} um", half), true, false});
    panel.marks.push_back({plots::Mark::Axis::kHorizontal, -half, fmt::format("-{:g} um", half), true, false});
  }
  panel.legend = plots::LegendPlace::kOutsideRight;  // the trace fills the panel: the legend beside it
  plots::Figure figure;
  figure.title = fmt::format("{}: profile deviation chart", CaseTitle(deck));
  figure.caption = FigureCaption(
      deck, fmt::format("{} ({} points, on every tooth space); fit: offset, isometric, rotation (least squares); {}",
                        c.source, c.u.size(),
                        c.tolerance ? fmt::format("tolerance band {:g} um ({})", units::MmToUm(*c.tolerance),
                                                  c.WithinTolerance() ? "the trace lies within it" : "the trace leaves it")
                                    : "no tolerance band ([inspection] profile_tolerance_um)"));
  figure.panels.push_back(std::move(panel));
  figure.width = 1100;
  figure.height = 600;
  return figure;
}

nlohmann::json Json(const Deck& deck, const geometry::RealPair& real) {
  const CycloidProfile& profile = real.profile();
  const Kinematics& kinematics = real.kinematics();
  const analysis::InspectionResult inspection = analysis::Inspect(profile, deck.inspection);
  return {
      {"case", CaseJson(deck)},
      {"tooth_difference", profile.tooth_difference()},
      {"k1", profile.k1()},
      {"phi_max_deg", RadToDeg(profile.phi_max())},
      {"contact_ratio", profile.contact_ratio()},
      {"theta_max_deg", RadToDeg(profile.theta_max())},
      {"alpha_max_deg", RadToDeg(profile.alpha_max())},
      {"min_curvature_radius_mm", profile.min_curvature_radius()},
      {"undercut_margin_mm", FiniteOrNull(profile.undercut_margin())},
      {"mesh_period_deg", RadToDeg(kinematics.MeshPeriod())},
      {"transmission_ratio", kinematics.TransmissionRatio()},
      // The figures above are of the cycloid as made: modification and [errors] applied.
      {"errors_applied", !real.errors().IsZero()},
      {"pin_circle_radius_as_assembled_mm", real.pin_circle_radius()},
      // The relief that runs (from the deck, or none), and what it cuts: the flank ends at
      // +-junction_deg of every space.
      {"tip_relief",
       {{"truncation_mm", profile.tip_cap().relief().truncation},
        {"rounding_radius_mm", profile.tip_cap().relief().rounding_radius},
        {"source", deck.tip_relief_source},
        {"note", deck.tip_relief_note.empty() ? nlohmann::json(nullptr) : nlohmann::json(deck.tip_relief_note)},
        {"active", profile.tip_cap().active()},
        {"junction_deg", RadToDeg(profile.tip_cap().junction())},
        {"land_half_width_mm", profile.tip_cap().land_half_width()},
        {"depth_mm", profile.tip_cap().depth()}}},
      // What an inspector measures on the disc as made (geometry/inspection.hpp).
      {"root_diameter_mm", inspection.root_diameter},
      {"tip_diameter_mm", inspection.tip_diameter},
      {"dimension_over_rollers_mm",
       inspection.rollers ? nlohmann::json(inspection.rollers->dimension) : nlohmann::json(nullptr)},
      {"over_rollers", RollersJson(profile, inspection.rollers)},
      {"dimension_over_rollers_tolerance", RollerBandJson(RollerBandOf(deck))},
      {"profile_deviation_chart", DeviationChartJson(DeviationChartOf(deck, real))},
  };
}

std::string Text(const Deck& deck, const geometry::RealPair& real) {
  std::string text;
  const CycloidProfile& profile = real.profile();
  const Kinematics& kinematics = real.kinematics();
  const auto& p = deck.pair;
  const auto& m = deck.modification;
  text += CaseLines(deck);
  if (!deck.info.source.empty()) text += fmt::format("source    {}\n", deck.info.source);
  text += fmt::format("pair      z_p = {}, z_c = {}, d = {}, r_rp = {} mm, R_p = {} mm, e = {} mm, B_c = {} mm\n",
                  p.pin_count, p.tooth_count, p.ToothDifference(), p.pin_radius, p.pin_circle_radius,
                  p.eccentricity, p.face_width);
  text += fmt::format("modif.    dR_rp = {:g} um, dR_p = {:g} um, rotation = {:g} arcsec\n",
                  units::MmToUm(m.pin_radius), units::MmToUm(m.pin_circle_radius),
                  units::RadToArcsec(m.rotation));
  if (!deck.errors.IsZero()) {
    const auto& e = deck.errors;
    text += fmt::format("errors    profile layer = {:g} um, pin circle radius as assembled = {:.6f} mm, pitch deviations: {}\n",
                    units::MmToUm(e.profile_layer), real.pin_circle_radius(),
                    e.cumulative_pitch_deviation.empty() ? "none" : "per pin (Liu eq. 5)");
    if (e.HasProfileDeviation()) {
      const auto& r = e.profile_random;
      text += fmt::format("          profile deviation along the profile: {}{}{}, |delta| <= {:g} um (Liu eq. 4; not in the figures below)\n",
                      r.zone == 0.0 ? "" : fmt::format("random zone {:g} um ({} elements, {}, {}, seed {})", units::MmToUm(r.zone),
                                                        r.elements,
                                                        r.distribution == geometry::ProfileRandomDistribution::kUniform ? "uniform" : "normal",
                                                        r.spacing == geometry::ProfileElementSpacing::kArcLength ? "arc_length" : "parameter",
                                                        r.seed),
                      r.zone != 0.0 && e.profile_measured ? " plus " : "",
                      e.profile_measured ? fmt::format("measured trace ({} points)", e.profile_measured->x.size()) : "",
                      units::MmToUm(real.profile_deviation().MaxAbs()));
    }
    text += fmt::format("          the figures below are of the cycloid as made ([errors] applied)\n");
  }
  text += fmt::format("K1                     {:.6f}       curtate coefficient (Chen eq. 12)\n", profile.k1());
  text += fmt::format("phi_max                {:.6f} deg   tooth-space half width (Chen eq. 16)\n",
                  RadToDeg(profile.phi_max()));
  text += fmt::format("contact ratio          {:.4f}       (Chen eq. 27)\n", profile.contact_ratio());
  text += fmt::format("theta_max              {:.4f} deg   pin's maximum contact angle (Chen eq. 20)\n",
                  RadToDeg(profile.theta_max()));
  text += fmt::format("alpha_max              {:.4f} deg   = arcsin K1 (Liu eq. 2)\n",
                  RadToDeg(profile.alpha_max()));
  text += fmt::format("min curvature radius   {:.4f} mm\n", profile.min_curvature_radius());
  if (std::isfinite(profile.undercut_margin())) {
    text += fmt::format("undercut margin        {:.4f} mm    (> 0: no undercut)\n", profile.undercut_margin());
  } else {
    text += fmt::format("undercut margin        none (no convex part on the offset side)\n");
  }
  const geometry::TipCap& cap = profile.tip_cap();
  if (cap.active()) {
    text += fmt::format("tip relief             truncation {:g} mm, rounding radius {:g} mm (from the deck): the flank ends at "
                         "u = +-{:.6f} deg, {:.4g} mm cut off the tip{}\n",
                    cap.relief().truncation, cap.relief().rounding_radius, RadToDeg(cap.junction()), cap.depth(),
                    cap.truncated() ? fmt::format(", land {:.4g} mm wide", 2.0 * cap.land_half_width()) : "");
  } else {
    text += fmt::format("tip relief             none{}\n", profile.has_tip_corners() ? " (sharp tip corners)" : "");
  }
  if (!deck.tip_relief_note.empty()) text += fmt::format("                       {}\n", deck.tip_relief_note);
  const analysis::InspectionResult inspection = analysis::Inspect(profile, deck.inspection);
  text += fmt::format("root diameter          {:.4f} mm   through the bottoms of the tooth spaces\n", inspection.root_diameter);
  text += fmt::format("tip diameter           {:.4f} mm   through the tips of the teeth\n", inspection.tip_diameter);
  if (const auto& m = inspection.rollers) {
    const int z = profile.pair().tooth_count;
    const bool ring = profile.tooth_difference() < 0;
    text += fmt::format("{} {:.4f} mm   rollers D_M = {:g} mm in spaces {} apart, {}\n",
                        ring ? "dim. between rollers  " : "dimension over rollers", m->dimension, m->roller_diameter,
                        z % 2 == 0 ? "180 deg" : fmt::format("180 deg x (1 - 1/{})", z),
                        z % 2 == 0 ? (ring ? "2 s - D_M" : "2 s + D_M")
                                   : (ring ? "2 s cos(90 deg / z_c) - D_M" : "2 s cos(90 deg / z_c) + D_M"));
    text += fmt::format("                       roller centres at s = {:.4f} mm; {}\n", m->centre_radius,
                        m->contact == geometry::RollerContact::kFlanks
                            ? fmt::format("they touch both working flanks at u = +-{:.4f} deg (on a {:.4f} mm circle)",
                                          RadToDeg(m->contact_u), m->contact_diameter)
                        : m->contact == geometry::RollerContact::kRoot
                            ? std::string("WARNING: they rest on the root, not on the working flanks (a larger roller is needed)")
                            : std::string("WARNING: they bear on the tips, not on the working flanks (a smaller roller is needed)"));
  }
  if (const auto band = RollerBandOf(deck)) {
    std::string keys;
    for (const analysis::RollerToleranceTerm& t : band->terms) {
      keys += fmt::format("{}{} ({:+.4g} mm per unit)", keys.empty() ? "" : ", ", t.key, t.sensitivity);
    }
    text += fmt::format("                       [tolerances]: worst case {:.4f} .. {:.4f} mm, statistical (RSS) "
                        "{:.4f} .. {:.4f} mm about {:.4f} mm, by sensitivity to {}\n",
                        band->worst_low, band->worst_high, band->rss_low, band->rss_high, band->centre,
                        keys.empty() ? std::string("no key of the disc's profile") : keys);
  }
  if (const auto chart = DeviationChartOf(deck, real)) {
    text += fmt::format("profile trace          {} ({} points): best explained by dR_p {:+.4f} um, dR_rp {:+.4f} um, rotation "
                        "{:+.3f} arcsec (least squares), rms residual {:.4f} um\n",
                        chart->source, chart->u.size(), units::MmToUm(chart->fit.offset), units::MmToUm(chart->fit.isometric),
                        units::RadToArcsec(chart->fit.rotation), units::MmToUm(chart->fit.rms_residual));
    if (chart->tolerance) {
      text += fmt::format("                       tolerance band {:g} um: the trace {}\n", units::MmToUm(*chart->tolerance),
                          chart->WithinTolerance() ? "lies within it" : "LEAVES it");
    }
  }
  text += fmt::format("mesh period            {:.6f} deg crank\n", RadToDeg(kinematics.MeshPeriod()));
  text += fmt::format("transmission ratio     {:.6g} (crank / cycloid)\n", kinematics.TransmissionRatio());
  return text;
}

std::string Csv(const CycloidProfile& profile, int samples_per_flank) {
  // The whole profile, tooth space by tooth space; u_deg is empty on a tip relief's cap.
  std::string csv = "tooth_space,u_deg,x_mm,y_mm,normal_x,normal_y,curvature_radius_mm,part\n";
  ForEachOutlinePoint(profile, samples_per_flank, [&](int k, double u, const Eigen::Vector2d& x, const Eigen::Vector2d& n,
                                            double curvature, geometry::SurfacePart part) {
    const double radius = curvature == 0.0 ? std::numeric_limits<double>::infinity() : 1.0 / curvature;
    csv += fmt::format("{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{}\n", k,
               std::isnan(u) ? std::string() : fmt::format("{:.9g}", RadToDeg(u)), x.x(), x.y(), n.x(), n.y(), radius,
               geometry::SurfacePartName(part));
  });
  return csv;
}

ProfileColumns Columns(const CycloidProfile& profile, int samples_per_flank) {
  ProfileColumns c;
  ForEachOutlinePoint(profile, samples_per_flank, [&](int k, double u, const Eigen::Vector2d& x, const Eigen::Vector2d& n,
                                                       double curvature, geometry::SurfacePart part) {
    c.tooth_space.push_back(k);
    c.u_deg.push_back(RadToDeg(u));  // NaN on a cap stays NaN
    c.x_mm.push_back(x.x());
    c.y_mm.push_back(x.y());
    c.normal_x.push_back(n.x());
    c.normal_y.push_back(n.y());
    c.curvature_radius_mm.push_back(curvature == 0.0 ? std::numeric_limits<double>::infinity() : 1.0 / curvature);
    c.part.emplace_back(geometry::SurfacePartName(part));
  });
  return c;
}

namespace {

/// A reducer stage's output elements, to scale (their clearances not exaggerated): output pins in
/// the disc's holes, or the crank holes' and the crankshafts' centres on their circle, the output
/// member turned as the disc at `pose`.
void AddOutputElements(plots::Panel& panel, const solvers::ReducerSettings& reducer, const geometry::Pose& pose) {
  const geometry::Pose holes{pose.centre, pose.rotation};  // the output member turned as the disc
  if (reducer.kind == solvers::OutputKind::kPins) {
    const contact::OutputPins& w = reducer.pins;
    bool first = true;
    for (const contact::OutputPinContact& c : contact::EvaluateOutputPins(w, holes, pose.rotation)) {
      plots::Series hole{first ? fmt::format("holes r_h = {:g} mm", w.hole_radius) : "", {}, {}, plots::Style::kOutline};
      plots::Series pin{first ? fmt::format("output pins r_w = {:g} mm", w.pin_radius) : "", {}, {}, plots::Style::kPolygon};
      hole.colour = 3;
      pin.colour = 5;
      for (int i = 0; i <= 96; ++i) {
        const double a = i * M_PI / 48.0;
        hole.x.push_back(c.hole_centre.x() + w.hole_radius * std::cos(a));
        hole.y.push_back(c.hole_centre.y() + w.hole_radius * std::sin(a));
        pin.x.push_back(c.pin_centre.x() + w.pin_radius * std::cos(a));
        pin.y.push_back(c.pin_centre.y() + w.pin_radius * std::sin(a));
      }
      panel.series.push_back(std::move(hole));
      panel.series.push_back(std::move(pin));
      first = false;
    }
  } else {
    const contact::Cranks& k = reducer.cranks;
    plots::Series circle{fmt::format("crank circle R_c = {:g} mm", k.circle_radius), {}, {}, plots::Style::kOutline};
    circle.colour = 3;
    circle.dashed = true;
    for (int i = 0; i <= 360; ++i) {
      circle.x.push_back(k.circle_radius * std::cos(i * M_PI / 180.0));
      circle.y.push_back(k.circle_radius * std::sin(i * M_PI / 180.0));
    }
    panel.series.push_back(std::move(circle));
    plots::Series cranks{"crankshaft centres", {}, {}, plots::Style::kMarkers};
    plots::Series holes_mark{"crank-hole centres (the eccentrics)", {}, {}, plots::Style::kMarkers};
    cranks.colour = 3;
    holes_mark.colour = 5;
    for (const contact::CrankContact& c : contact::EvaluateCranks(k, holes, pose.rotation)) {
      cranks.x.push_back(c.crank_centre.x()), cranks.y.push_back(c.crank_centre.y());
      holes_mark.x.push_back(c.hole_centre.x()), holes_mark.y.push_back(c.hole_centre.y());
    }
    panel.series.push_back(std::move(cranks));
    panel.series.push_back(std::move(holes_mark));
  }
}

}  // namespace

plots::Figure Figure(const Deck& deck, const geometry::RealPair& real, const contact::MeshState& unloaded, int samples_per_flank) {
  const int samples = samples_per_flank;
  const double crank = unloaded.crank;
  const CycloidProfile& profile = real.profile();
  const Kinematics& kinematics = real.kinematics();
  const auto& pair = profile.pair();
  const geometry::Pose pose = kinematics.CycloidPose(crank);
  const bool ring = profile.tooth_difference() < 0;  // the cycloid is the outer member
  const double outer = pair.pin_circle_radius + pair.pin_radius + 2.0 * pair.eccentricity;
  const double extent = (ring ? 1.15 * outer : outer) + 2.0;

  // The unloaded clearance of every pin (the smallest over its slices), from the contact layer.
  std::vector<double> clearance(static_cast<std::size_t>(pair.pin_count), INFINITY);
  for (const auto& c : unloaded.pins) {
    auto& v = clearance[static_cast<std::size_t>(c.pin)];
    v = std::min(v, c.clearance);
  }
  const double c_min = *std::min_element(clearance.begin(), clearance.end());
  const double factor = ExaggerationFactor(clearance, extent);

  plots::Panel panel;
  panel.x_label = "x_f (mm)";
  panel.y_label = "y_f (mm)";
  panel.equal_scale = true;
  panel.legend = plots::LegendPlace::kOutsideRight;
  panel.title = fmt::format("clearances drawn x{:g}", factor);
  plots::Series disc{ring ? "cycloid ring (as made)" : "cycloid disc (as made)", {}, {}, ring ? plots::Style::kOutline : plots::Style::kPolygon};
  disc.colour = 1;
  ForEachOutlinePoint(profile, samples, [&](int, double, const Eigen::Vector2d& body, const Eigen::Vector2d&, double,
                                            geometry::SurfacePart) {
    const Eigen::Vector2d x = pose.ToFixed(body);
    disc.x.push_back(x.x()), disc.y.push_back(x.y());
  });
  panel.series.push_back(std::move(disc));
  plots::Series pin_circle{fmt::format("pin circle R_p = {:g} mm", real.pin_circle_radius()), {}, {}, plots::Style::kOutline};
  pin_circle.colour = 6;
  pin_circle.dashed = true;
  for (int i = 0; i < 360; ++i) {
    pin_circle.x.push_back(real.pin_circle_radius() * std::cos(i * M_PI / 180.0));
    pin_circle.y.push_back(real.pin_circle_radius() * std::sin(i * M_PI / 180.0));
  }
  panel.series.push_back(std::move(pin_circle));
  bool first_pin = true, first_contact = true;
  std::string contact_pins;
  int touching_pins = 0;
  for (int j = 0; j < pair.pin_count; ++j) {
    const Eigen::Vector2d c = real.PinCentre(j);  // as assembled: pin-circle and pitch deviations
    const double g = std::max(0.0, clearance[static_cast<std::size_t>(j)]);
    const double r = std::max(pair.pin_radius - (factor - 1.0) * g, 0.3 * pair.pin_radius);
    const bool touching = clearance[static_cast<std::size_t>(j)] <= c_min + 1e-4;  // within 0.1 um of the first contact
    plots::Series pin{"", {}, {}, plots::Style::kPolygon};
    pin.colour = touching ? 2 : 0;
    if (touching && first_contact) pin.label = "first contact (least clearance)", first_contact = false;
    if (!touching && first_pin) pin.label = "pins", first_pin = false;
    if (touching) ++touching_pins;
    if (touching && touching_pins <= 6) contact_pins += fmt::format("{}{}", contact_pins.empty() ? "" : ", ", j + 1);
    if (touching && touching_pins == 7) contact_pins += ", ...";
    for (int i = 0; i < 48; ++i) {
      pin.x.push_back(c.x() + r * std::cos(i * M_PI / 24.0));
      pin.y.push_back(c.y() + r * std::sin(i * M_PI / 24.0));
    }
    panel.series.push_back(std::move(pin));
    // Outside the pins; inside them for a ring, whose outline runs outside the pin circle.
    const double label_radius = ring ? c.norm() - pair.pin_radius - 0.05 * extent : c.norm() + pair.pin_radius + 0.06 * extent;
    const double a = std::atan2(c.y(), c.x());
    panel.notes.push_back({label_radius * std::cos(a), label_radius * std::sin(a) - 0.012 * extent, fmt::format("{}", j + 1), 0.5, 0.7});
  }
  if (deck.reducer) AddOutputElements(panel, *deck.reducer, pose);
  if (deck.disc.bore_radius > 0.0) {  // the central bore ([disc] bore_radius_mm), moving with the disc
    plots::Series bore{fmt::format("bore r = {:g} mm", deck.disc.bore_radius), {}, {}, plots::Style::kOutline};
    bore.colour = 1;
    for (int i = 0; i <= 180; ++i) {
      const Eigen::Vector2d b = pose.ToFixed(deck.disc.bore_radius * Eigen::Vector2d(std::cos(i * M_PI / 90.0), std::sin(i * M_PI / 90.0)));
      bore.x.push_back(b.x()), bore.y.push_back(b.y());
    }
    panel.series.push_back(std::move(bore));
  }
  // The line of centres: from the pin-circle centre O_p through the cycloid centre O_c.
  plots::Series centres{"line of centres O_p O_c", {}, {}, plots::Style::kLine};
  centres.colour = 4;
  centres.dashed = true;
  const Eigen::Vector2d oc = pose.centre;
  const Eigen::Vector2d dir = oc.norm() > 0.0 ? Eigen::Vector2d(oc / oc.norm()) : Eigen::Vector2d(1.0, 0.0);
  centres.x = {-extent * dir.x(), extent * dir.x()};
  centres.y = {-extent * dir.y(), extent * dir.y()};
  panel.series.push_back(std::move(centres));
  plots::Series centre_mark{"cycloid centre O_c", {oc.x()}, {oc.y()}, plots::Style::kMarkers};
  centre_mark.colour = 4;
  panel.series.push_back(std::move(centre_mark));
  const double limit = extent + 0.1 * extent;
  panel.x_min = -limit, panel.x_max = limit, panel.y_min = -limit, panel.y_max = limit;

  plots::Figure figure;
  figure.title = fmt::format("{}: cycloid and pins at crank {:.4g} deg (unloaded)", CaseTitle(deck), RadToDeg(crank));
  figure.caption = FigureCaption(
      deck, fmt::format("z_p = {}, z_c = {}, R_p = {:g} mm, r_rp = {:g} mm, e = {:g} mm; least clearance {:.3f} um (pin {}); "
                        "pins numbered from +x_f counter-clockwise\n"
                        "clearances exaggerated x{:g}: each pin's radius is reduced by ({:g} - 1) x its clearance (at least 30 % kept)",
                        pair.pin_count, pair.tooth_count, pair.pin_circle_radius, pair.pin_radius, pair.eccentricity,
                        units::MmToUm(c_min) + 0.0, contact_pins, factor, factor));
  figure.panels.push_back(std::move(panel));
  // Wide enough that the legend beside the drawing leaves it a square box as tall as the page
  // allows (equal scale: the drawing is as large as its shorter side).
  figure.width = 1300;
  figure.height = 800;
  return figure;
}


}  // namespace ltca::app::documents
