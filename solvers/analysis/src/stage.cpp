#include "ltca/analysis/stage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <utility>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ltca/contact/holes.hpp"
#include "ltca/contact/output_pins.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::analysis {

geometry::RealPair StageDesign::MakeSecondRealPair() const {
  if (!second_disc) throw std::invalid_argument("the stage has no second disc ([second_disc])");
  return {pair, second_disc->modification, second_disc->errors, second_disc->assembly};
}

namespace {

/// The profile's root circle: the least distance of the flank from the disc centre (every tooth
/// space alike), sampled at 512 points of the reference space, mm.
double RootRadius(const geometry::CycloidProfile& profile) {
  constexpr int kSamples = 512;
  double root = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= kSamples; ++i) {
    const double u = profile.phi_max() * (-1.0 + 2.0 * i / kSamples);
    root = std::min(root, profile.Position(u, 0).norm());
  }
  return root;
}

/// The stage's scope in one line: what is elastic, what is rigid, and how the input is locked.
std::string StageScope(const StageDesign& d) {
  const solvers::ReducerSettings& r = *d.reducer;
  const bool cranks = r.kind == solvers::OutputKind::kCranks;
  std::vector<std::string> elastic{d.contact.seat.seated() ? "pin-cycloid contacts with the pins' seats" : "pin-cycloid contacts"};
  const std::string housing = std::isfinite(r.carrier_stiffness) ? "housing (its torsion in the carrier's spring)" : "housing";
  std::vector<std::string> rigid{d.disc.elastic() ? housing : "discs' bodies, " + housing};
  if (d.disc.elastic()) {
    // The cycloidal drive's bore holds the eccentric bearing's outer ring (clamped: a rigid ring); an
    // RV disc's bore is empty, clamped only to fix the body's rigid motion (docs/fe_disc.md).
    elastic.emplace_back(cranks ? "disc body (FE, its crank holes on the body, the empty bore its reference)"
                                : "disc body (FE, its output-pin holes on the body, the bore a rigid ring)");
  }
  if (d.pins) elastic.emplace_back("ring pins bending");
  else rigid.emplace_back("ring pins' bending");
  if (!cranks) elastic.emplace_back("output pins in holes");
  const std::string bearing = cranks ? "crank needle bearings" : "eccentric bearing";
  if (r.bearing.kind == contact::BearingKind::kRigid) rigid.push_back(bearing);
  else elastic.push_back(fmt::format("{} ({})", bearing, contact::ToString(r.bearing.kind)));
  if (cranks) {
    if (r.cranks.beam.given()) {
      elastic.push_back(fmt::format("crankshafts as Timoshenko beams ({:g} mm, {:g} mm span) on {} support bearings",
                                    r.cranks.beam.diameter, r.cranks.beam.span,
                                    std::isfinite(r.cranks.beam.support_stiffness) ? "elastic" : "rigid"));
    } else if (std::isfinite(r.cranks.shaft_stiffness)) {
      elastic.emplace_back("crankshafts (one spring per shaft and disc)");
    } else {
      rigid.emplace_back("crankshafts");
    }
  }
  if (std::isfinite(r.carrier_stiffness)) {
    elastic.push_back(fmt::format("carrier, output flange and housing in series ({:g} N*m/arcmin)",
                                  units::NmmPerRadToNmPerArcmin(r.carrier_stiffness)));
  } else {
    rigid.emplace_back("carrier and output flange");
  }
  std::string input = "input locked: ";
  if (!cranks) {
    input += "the eccentric keeps its direction";
  } else if (r.cranks.sun_teeth > 0) {
    input += fmt::format("first stage {}/{}, the eccentrics turn {:.6g} times the output", r.cranks.sun_teeth,
                         r.cranks.spur_teeth, r.cranks.turns_per_output_turn);
  } else if (r.cranks.turns_per_output_turn == 0.0) {
    input += "the eccentrics keep their direction (no first stage)";
  } else {
    input += fmt::format("the eccentrics turn {:.6g} times the output", r.cranks.turns_per_output_turn);
  }
  return fmt::format("elastic: {}; rigid: {}; {}", fmt::join(elastic, ", "), fmt::join(rigid, ", "), input);
}

}  // namespace

void StageDesign::Validate() const {
  if (second_disc && pins) {
    throw std::invalid_argument(
        "[second_disc] with [pins]: pin bending with two discs is not supported yet (the pin beams would couple "
        "both discs' contacts); expected one of the two sections");
  }
  if (!disc.elastic()) return;
  const auto refuse = [](const std::string& what) {
    throw std::invalid_argument("[disc] body = \"elastic\" " + what);
  };
  const bool cranks = reducer && reducer->kind == solvers::OutputKind::kCranks;
  if (cranks) {
    // Each needle roller a contact on its crank hole's wall (docs/fe_disc.md "The RV disc"): the
    // hole is the rollers' outer raceway, of radius (d_m + D_w) / 2.
    const contact::BearingSettings& b = reducer->bearing;
    if (b.kind != contact::BearingKind::kRollers) {
      refuse(fmt::format("with [bearing] kind = \"{}\" on crankshafts: the crank bearing on the elastic body is built "
                         "for needle rollers only (each roller a contact on the hole's wall); expected [bearing] kind = "
                         "\"rollers\", or body = \"rigid\"",
                         contact::ToString(b.kind)));
    }
    if (!(b.pitch_diameter > 0.0)) {
      throw std::invalid_argument(
          "[bearing] pitch_diameter_mm = 0 with [disc] body = \"elastic\" on crankshafts: expected the roller set's "
          "pitch diameter (the crank hole, the rollers' outer raceway, is (pitch_diameter_mm + roller_diameter_mm) / 2 "
          "in radius)");
    }
    const double hole = 0.5 * (b.pitch_diameter + b.roller_diameter);
    const double inside = reducer->cranks.circle_radius - hole - disc.element_size;
    if (!(disc.bore_radius < inside)) {
      throw std::invalid_argument(fmt::format(
          "[disc] bore_radius_mm = {}: expected a bore below {:g} mm with [output] kind = \"cranks\" (the crank holes' "
          "inner edge, circle_radius_mm {:g} less the hole radius {:g} mm = (pitch_diameter_mm + roller_diameter_mm) / "
          "2, less one element_size_mm {:g}: the empty central bore inside the crank holes)",
          disc.bore_radius, inside, reducer->cranks.circle_radius, hole, disc.element_size));
    }
    const double root = RootRadius(geometry::CycloidProfile(pair, modification));
    const double outer = reducer->cranks.circle_radius + hole;
    if (!(outer < root - 1.0)) {
      throw std::invalid_argument(fmt::format(
          "[bearing] pitch_diameter_mm = {:g} with [disc] body = \"elastic\": the crank holes reach {:g} mm from the "
          "disc centre ([output] circle_radius_mm {:g} plus the hole radius {:g} mm), expected a web of at least 1 mm "
          "to the root circle {:g} mm",
          b.pitch_diameter, outer, reducer->cranks.circle_radius, hole, root));
    }
  }
  if (reducer && !cranks) {
    // The body is clamped at its bore (the eccentric bearing's outer ring): the bore must lie inside
    // the output-pin holes with a web of an element size at least.
    const contact::OutputPins& w = reducer->pins;
    const double inside = w.circle_radius - w.hole_radius - disc.element_size;
    if (!(disc.bore_radius < inside)) {
      throw std::invalid_argument(fmt::format(
          "[disc] bore_radius_mm = {}: expected a bore below {:g} mm with [output] kind = \"pins\" (the holes' inner "
          "edge, circle_radius_mm {:g} less hole_radius_mm {:g}, less one element_size_mm {:g}: the eccentric "
          "bearing's bore inside the output-pin holes)",
          disc.bore_radius, inside, w.circle_radius, w.hole_radius, disc.element_size));
    }
  }
  if (contact.law != contact::LawKind::kHertzLine) {
    refuse(fmt::format("with [contact] law = \"{}\": the body's local field is the hertz-line law's; expected law = "
                       "\"hertz-line\"",
                       contact::ToString(contact.law)));
  }
  if (pair.ToothDifference() < 0) refuse("with d < 0 (the cycloid outside the pins): expected pin_count > tooth_count");
  disc.Validate(RootRadius(geometry::CycloidProfile(pair, modification)));
}

namespace {

/// The holes of the elastic body: a stage's output-pin holes at their nominal places in the body
/// frame (a hole's position deviation, micrometres, does not change the body's compliance more than
/// its mesh does, and a tolerance study then pays the set-up once); none for the mesh alone.
std::vector<contact::DiscHole> BodyHoles(const StageDesign& design, int disc) {
  std::vector<contact::DiscHole> holes;
  if (!design.reducer) return holes;
  // The holes (output-pin or crank) sit where the output member's pins or cranks are at the
  // nominal poses, in the disc's body frame: element j at alpha_j turned by the output member's
  // rotation less the disc's. The second disc turns pi / I behind the first (it is the first's
  // model half a crank turn on) while the output member turns with the first: its holes sit
  // -pi / I further on in its own frame (half a tooth pitch for d = 1), as ReducerSystem places
  // them (each disc's holes on the output member's rotation, its flank on its own model's).
  const geometry::Kinematics kinematics(design.pair);
  const double turn = disc == 0 ? 0.0
                                : kinematics.CycloidPose(0.0).rotation -
                                      kinematics.CycloidPose(contact::kSecondDiscCrankOffset).rotation;
  if (design.reducer->kind == solvers::OutputKind::kCranks) {
    // The crank holes (the rollers' outer raceways) on the crank circle R_c.
    const contact::Cranks& c = design.reducer->cranks;
    const contact::BearingSettings& b = design.reducer->bearing;
    for (int j = 0; j < c.count; ++j) {
      const double alpha = 2.0 * units::kPi * j / c.count + c.phase + turn;
      holes.push_back({c.circle_radius * Eigen::Vector2d(std::cos(alpha), std::sin(alpha)),
                       0.5 * (b.pitch_diameter + b.roller_diameter)});
    }
    return holes;
  }
  const contact::OutputPins& w = design.reducer->pins;
  for (int j = 0; j < w.count; ++j) {
    const double alpha = 2.0 * units::kPi * j / w.count + w.phase + turn;
    holes.push_back({contact::HoleInDisc(w.circle_radius, alpha, {}, j), w.hole_radius});
  }
  return holes;
}

std::string HolesKey(const StageDesign& design, int disc) {
  std::string key;
  for (const contact::DiscHole& h : BodyHoles(design, disc)) {
    key += fmt::format(" | {:a} {:a} {:a}", h.centre_mm.x(), h.centre_mm.y(), h.radius_mm);
  }
  return key;
}

/// Disc `disc`'s tip relief: the second disc's own ([second_disc] may give one), else the deck's.
const geometry::TipRelief& DiscTipRelief(const StageDesign& design, int disc) {
  return disc == 1 && design.second_disc ? design.second_disc->modification.tip_relief : design.modification.tip_relief;
}

bool SameTipRelief(const geometry::TipRelief& a, const geometry::TipRelief& b) {
  return a.truncation == b.truncation && a.rounding_radius == b.rounding_radius;
}

/// Whether the second disc's body is the first's turned: a turn by a whole number of tooth pitches
/// (the profile onto itself) that carries the first body's holes onto the second's (docs/fe_disc.md
/// "Two discs": on the two-disc drive, z_p and the output pins' count even, the turn pi z_p / z_c).
/// Found by trying every tooth pitch and checked on the bodies' own geometry: every hole centre
/// and radius, and the flank grid's first point, to 1e-9 of the pin-circle radius. nullopt: none
/// (an RV stage's three crank holes; the mesh alone, whose discs share one body as they are; two
/// discs whose tip reliefs differ, whose outlines then differ).
std::optional<Stage::BodyTurn> SecondBodyTurn(const StageDesign& design, const contact::DiscFlankCompliance& first) {
  if (!design.second_disc || !design.reducer) return std::nullopt;
  if (!SameTipRelief(DiscTipRelief(design, 0), DiscTipRelief(design, 1))) return std::nullopt;
  const std::vector<contact::DiscHole> a = BodyHoles(design, 0), b = BodyHoles(design, 1);
  const auto n = static_cast<int>(a.size());
  if (n == 0 || b.size() != a.size()) return std::nullopt;
  const int zc = design.pair.tooth_count;
  const double tol = 1e-9 * design.pair.pin_circle_radius;
  const int m = first.space_points();  // with a tip relief's caps more than grid().points_per_space
  for (int k = 0; k < zc; ++k) {
    const double angle = 2.0 * units::kPi * k / zc;
    const Eigen::Rotation2Dd turn(angle);
    // The first body's hole 0 lands on the second's hole `shift`; every other hole as far on.
    int shift = -1;
    for (int j = 0; j < n; ++j) {
      if ((turn * a[0].centre_mm - b[static_cast<std::size_t>(j)].centre_mm).norm() <= tol) shift = j;
    }
    if (shift < 0) continue;
    bool all = true;
    for (int j = 0; j < n && all; ++j) {
      const contact::DiscHole& from = a[static_cast<std::size_t>(j)];
      const contact::DiscHole& to = b[static_cast<std::size_t>((j + shift) % n)];
      all = (turn * from.centre_mm - to.centre_mm).norm() <= tol && from.radius_mm == to.radius_mm;
    }
    if (!all) continue;
    // The flank: the first body's space 0 lands on its space `spaces` (the profile repeats every pitch).
    const Eigen::Vector2d p = turn * first.grid_point(0);
    int spaces = -1;
    for (int s = 0; s < zc; ++s) {
      if ((first.grid_point(s * m) - p).norm() <= tol) spaces = s;
    }
    if (spaces < 0) continue;
    return Stage::BodyTurn{angle, spaces, shift};
  }
  return std::nullopt;
}

}  // namespace

std::shared_ptr<const contact::DiscFlankCompliance> ElasticDiscBody(const StageDesign& design, int disc) {
  const geometry::PairParameters& p = design.pair;
  const contact::DiscBodySettings& b = design.disc;
  const contact::Material& material = design.material.value();
  // Every number that shapes the body, exactly (hexadecimal floating point). The body is the
  // unmodified profile's: modifications and errors (micrometres to tens of micrometres) change its
  // coefficients by less than its mesh does (docs/fe_disc.md), and an optimiser over modifications
  // or a tolerance study then pays the set-up once. A tip relief is the exception: its caps (tenths
  // of a millimetre) change the outline where contacts can be, so the body is the unmodified
  // profile with the disc's tip relief, and the relief is in the key.
  const geometry::TipRelief& relief = DiscTipRelief(design, disc);
  const std::string key = fmt::format("{} {} {:a} {:a} {:a} {:a} | {:a} {} {:a} {} {:a} | {:a} {:a}", p.pin_count,
                                      p.tooth_count, p.pin_radius, p.pin_circle_radius, p.eccentricity, p.face_width,
                                      b.bore_radius, contact::ToString(b.plane), b.element_size, b.grid.points_per_space,
                                      b.grid.patch_half_width_mm, material.young_modulus, material.poisson_ratio) +
                          (relief.IsZero() ? std::string()
                                           : fmt::format(" | relief {:a} {:a}", relief.truncation, relief.rounding_radius)) +
                          HolesKey(design, disc);
  static std::mutex mutex;
  static std::vector<std::pair<std::string, std::shared_ptr<const contact::DiscFlankCompliance>>> kept;  // newest last
  constexpr std::size_t kKept = 4;
  const std::lock_guard<std::mutex> lock(mutex);
  for (auto it = kept.begin(); it != kept.end(); ++it) {
    if (it->first == key) {
      std::rotate(it, it + 1, kept.end());
      return kept.back().second;
    }
  }
  contact::DiscBodyDesign body;
  body.bore_radius_mm = b.bore_radius;
  body.plane = b.plane;
  body.young_modulus_mpa = material.young_modulus;
  body.poisson_ratio = material.poisson_ratio;
  body.thickness_mm = p.face_width;
  body.element_size_mm = b.element_size;
  body.refine_radius_mm = 2.0 * b.element_size;
  body.holes = BodyHoles(design, disc);
  geometry::Modification caps;  // the disc's tip relief alone
  caps.tip_relief = relief;
  auto flank = std::make_shared<const contact::DiscFlankCompliance>(geometry::CycloidProfile(p, caps), body, b.grid);
  if (kept.size() == kKept) kept.erase(kept.begin());
  kept.emplace_back(key, flank);
  return flank;
}

bool StageDesign::SlicesForced() const {
  if (pins) return true;
  if (!second_disc) return false;
  return errors.VariesAlongWidth() || assembly.VariesAlongWidth() || second_disc->errors.VariesAlongWidth() ||
         second_disc->assembly.VariesAlongWidth();
}

bool StageDesign::SecondDiscIsFirst() const {
  if (!second_disc) return false;
  const SecondDisc& s = *second_disc;
  const geometry::Modification &a = modification, &b = s.modification;
  const bool same_modification = a.pin_radius == b.pin_radius && a.pin_circle_radius == b.pin_circle_radius &&
                                 a.rotation == b.rotation && SameTipRelief(a.tip_relief, b.tip_relief);
  const geometry::ManufacturingErrors &e = errors, &f = s.errors;
  const bool same_errors = !e.HasProfileDeviation() && !f.HasProfileDeviation() &&
                           e.pin_circle_deviation == f.pin_circle_deviation && e.pin_circle_reading == f.pin_circle_reading &&
                           e.profile_layer == f.profile_layer && e.cumulative_pitch_deviation == f.cumulative_pitch_deviation &&
                           e.pin_radius_deviations == f.pin_radius_deviations &&
                           e.pin_radial_deviations == f.pin_radial_deviations && e.lead_crowning == f.lead_crowning &&
                           e.lead_slope == f.lead_slope;
  const geometry::AssemblyErrors &g = assembly, &h = s.assembly;
  const bool same_assembly = g.centre_dx == h.centre_dx && g.centre_dy == h.centre_dy &&
                             g.eccentricity_deviation == h.eccentricity_deviation &&
                             g.misalignment_xz == h.misalignment_xz && g.misalignment_yz == h.misalignment_yz &&
                             g.pivot == h.pivot;
  return s.indexing_deviation == 0.0 && same_modification && same_errors && same_assembly;
}

double* ReducerClearance(solvers::ReducerSettings& stage, std::string_view key) {
  if (key == "bearing.radial_clearance_mm") return &stage.bearing.radial_clearance;
  if (key == "output.hole_radius_mm") return &stage.pins.hole_radius;
  if (key == "output.pin_radius_mm") return &stage.pins.pin_radius;
  return nullptr;
}

std::string StageClearanceRefusal(const std::optional<solvers::ReducerSettings>& stage, std::string_view key) {
  if (!stage) return "the deck has no reducer stage; expected an [output] section (docs/stage.md)";
  if (key.starts_with("output.") && stage->kind != solvers::OutputKind::kPins) {
    return "expected [output] kind = \"pins\" (crankshafts have no output pins in holes; their play is [bearing] "
           "radial_clearance_mm)";
  }
  if (key.starts_with("bearing.") && stage->bearing.kind == contact::BearingKind::kRigid) {
    return "[bearing] kind = \"rigid\" has no play; expected kind = \"linear\" or \"rollers\"";
  }
  return "";
}

ModelInfo StageDesign::Model() const {
  ModelInfo m;
  m.surface = geometry.mode == geometry::GeometrySettings::Mode::kElements ? "elements" : "analytic";
  if (pins) {
    m.name = "slices+pin-bending";
    m.slices = geometry.width_slices;
  } else if (errors.VariesAlongWidth() || assembly.VariesAlongWidth() || SlicesForced()) {
    m.name = "slices";
    m.slices = geometry.width_slices;
  } else {
    m.name = "plane";
    m.slices = 1;
  }
  if (contact.seat.seated()) {  // the pins seated in housing grooves
    m.pin_seat = contact::ToString(contact.seat.kind);
    m.name += "+pin-seats";
  }
  if (second_disc) {  // two discs on one pin ring
    m.discs = 2;
    m.name += "+two-discs";
  }
  if (reducer) {  // the output mechanism and the bearings
    m.reducer = fmt::format("{}+{} bearing", solvers::ToString(reducer->kind), contact::ToString(reducer->bearing.kind));
    m.name += "+stage";
    m.scope = StageScope(*this);
  }
  if (disc.elastic()) {  // [disc] body
    m.disc_body = fmt::format(
        "elastic (plane {}, bore {:g} mm clamped; FE T6 {:g} mm, the flank condensed at {} points a tooth space{}{}, {:g} "
        "mm patches)",
        contact::ToString(disc.plane), disc.bore_radius, disc.element_size, disc.grid.points_per_space,
        modification.tip_relief.IsZero() ? "" : " shared with the tip relief's caps (at least every patch half-width)",
        reducer ? fmt::format(" and {} around each of the {} {} holes", disc.grid.points_per_hole,
                              reducer->kind == solvers::OutputKind::kPins ? reducer->pins.count : reducer->cranks.count,
                              reducer->kind == solvers::OutputKind::kPins ? "output-pin" : "crank")
                : std::string(),
        disc.grid.patch_half_width_mm);
    m.name += "+elastic-disc";
  }
  return m;
}

Stage::Stage(StageDesign design, std::vector<double> cranks) {
  if (design.disc.elastic()) {
    // The elastic body: its compliance couples the contacts, and the law's cycloid term becomes
    // the Hertz contact's local field beyond the body's patches (contact/disc_body.hpp).
    design.Validate();
    if (!design.material) throw std::invalid_argument("missing required section [material] for an elastic disc body");
    disc_body_ = ElasticDiscBody(design, 0);
    if (design.second_disc) {
      // Its holes half a tooth pitch on in its frame: the first body turned when a turn carries
      // one onto the other (one set-up), else a body of its own.
      second_turn_ = SecondBodyTurn(design, *disc_body_);
      second_body_ = second_turn_ ? disc_body_ : ElasticDiscBody(design, 1);
    }
    design.contact.cycloid_log_radius = disc_body_->cycloid_log_radius_mm();
  }
  design_ = std::make_shared<const StageDesign>(std::move(design));
  const StageDesign& d = *design_;
  if (d.reducer) {
    d.reducer->Validate(d.pair.eccentricity);
    reducer_ = std::make_shared<const solvers::ReducerSettings>(*d.reducer);
  }
  first_ = std::make_shared<const contact::MeshModel>(d.MakeModel());
  if (d.second_disc) {
    second_ = std::make_shared<const contact::MeshModel>(d.MakeSecondRealPair(), d.geometry, d.SlicesForced());
  }
  // Every crank's state evaluated once (kept while it fits).
  auto checked = std::make_shared<Checked>();
  checked->cranks = std::move(cranks);
  const std::size_t n = checked->cranks.size();
  const bool keep = n * static_cast<std::size_t>(first_->point_count() * disc_count()) * sizeof(contact::PinContact) <=
                    kKeptStatesBytes;
  checked->order.resize(n);
  for (std::size_t i = 0; i < n; ++i) checked->order[i] = i;
  std::stable_sort(checked->order.begin(), checked->order.end(),
                   [&c = checked->cranks](std::size_t a, std::size_t b) { return c[a] < c[b]; });
  // Two discs of one part (an RV stage's usual pair): the second disc at crank theta is the
  // first's model at theta + pi, so where the sweep holds that crank too (a whole crank turn holds
  // it for half its positions) its state is the first disc's there, evaluated once. The crank
  // theta + pi matches to a few ulps (the sweep's theta' against theta + pi in floating point).
  std::vector<contact::MeshState> own;
  if (keep && second_ && d.SecondDiscIsFirst()) {
    contact::RequireSamePinRing(*first_, *second_);
    own.reserve(n);
    for (std::size_t i = 0; i < n; ++i) own.push_back(first_->Evaluate(checked->cranks[i], 0.0));
  }
  const auto swept = [&c = *checked](double crank) -> std::ptrdiff_t {
    const double tol = 4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(crank));
    const auto it = std::lower_bound(c.order.begin(), c.order.end(), crank - tol,
                                     [&c](std::size_t i, double value) { return c.cranks[i] < value; });
    return it != c.order.end() && c.cranks[*it] <= crank + tol ? static_cast<std::ptrdiff_t>(*it) : -1;
  };
  contact::MeshState first;
  for (std::size_t i = 0; i < n; ++i) {
    const double crank = checked->cranks[i];
    contact::MeshState state;
    if (!own.empty()) {
      const double behind = crank + contact::kSecondDiscCrankOffset;
      const std::ptrdiff_t j = swept(behind);
      state = contact::CombineTwoDiscs(own[i], j >= 0 ? own[static_cast<std::size_t>(j)] : second_->Evaluate(behind, 0.0));
    } else {
      state = second_ ? contact::EvaluateTwoDiscs(*first_, *second_, crank) : first_->Evaluate(crank, 0.0);
    }
    // Pins overlapping the cycloid are a preload, not an input error: the mesh alone balances both
    // flanks (docs/solvers.md "Two flanks"), a reducer stage's floating discs find their preload
    // state (docs/stage.md); an assembly beyond its limits is the solve's status cannot-assemble.
    // An overlap beyond a tenth of the pin radius (a preload is micrometres; Hertz line contact
    // holds for half-widths within a tenth of the radii) is no preload: the pair does not mesh.
    for (const contact::PinContact& c : state.pins) {
      if (!(c.clearance >= -0.1 * d.pair.pin_radius)) {
        throw std::invalid_argument(fmt::format(
            "{}pin {} overlaps the cycloid by {:.6g} mm at crank {:.6g} deg, more than a tenth of the pin radius {:.6g} mm: not a "
            "preload, a pair that does not mesh; check [pair] pin_circle_radius_mm, pin_radius_mm and eccentricity_mm, "
            "[modification] and [errors]",
            c.disc > 0 ? "disc 2: " : "", c.pin + 1, -c.clearance, units::RadToDeg(crank), d.pair.pin_radius));
      }
    }
    if (i == 0) first = state;
    // A reducer stage's output pins or cranks turn against the line of centres at 1 - 1/I of the
    // crank: their pattern does not repeat with the mesh period (nor after one crank turn, which
    // moves them 2 pi / I along), so its sweep never counts as closed.
    if (i > 0 && i + 1 == n) checked->closed = !d.reducer && contact::SameMesh(first, state);
    if (keep) checked->states.push_back(std::move(state));
  }
  checked_ = std::move(checked);
  // Pin bending ([pins]): every pin a Timoshenko beam of the nominal pin radius and the
  // pin material, coupling the model's points; checked once (it does not change with the crank).
  auto coupling = std::make_shared<solvers::LoadProblem::CheckedCoupling>();
  if (d.pins && d.material) {
    const contact::PinBeam beam(*d.pins, *d.material, d.pair.pin_radius);
    const double crank = checked_->cranks.empty() ? 0.0 : checked_->cranks.front();
    const std::vector<contact::PinContact> points = first_->Evaluate(crank).pins;
    contact::FactoredPinBending f = contact::PinBendingFactors(points, beam, d.pair.face_width);
    *coupling = solvers::LoadProblem::CheckCoupling(contact::PinBendingCoupling(points, beam, d.pair.face_width),
                                                    first_->point_count(),
                                                    {std::move(f.stiffness), std::move(f.loads), std::move(f.local)});
  }
  coupling_ = std::move(coupling);
}

Stage Stage::WithKinematics(contact::ContactKinematics kinematics) const {
  Stage s = *this;
  StageDesign d = *design_;
  d.kinematics = kinematics;
  s.design_ = std::make_shared<const StageDesign>(std::move(d));
  return s;
}

double Stage::interference_tolerance() const {
  return std::max(first_->interference_tolerance(), second_ ? second_->interference_tolerance() : 0.0);
}

std::string Stage::SamplingNote() const {
  const std::vector<double>& cranks = checked_->cranks;
  if (cranks.size() < 2) return {};
  const double span = std::abs(cranks.back() - cranks.front());
  const double step = span / static_cast<double>(cranks.size() - 1);
  const double period = 2.0 * std::acos(-1.0) / design_->pair.pin_count;  // rad of crank
  if (!(step > 0.0) || period / step >= kMinPositionsPerMeshPeriod) return {};
  const double deg = 180.0 / std::acos(-1.0);
  const double largest = period / kMinPositionsPerMeshPeriod;
  const auto needed = static_cast<long long>(std::ceil(span / largest - 1e-9)) + 1;
  return fmt::format(
      "the sweep samples the mesh period ({:.6g} deg of crank, 360 / {} pins) with {:.3g} positions (a step of {:.6g} deg): "
      "TE, backlash and efficiency curves alias below about {:g} positions a period, and the pitting lives read each load "
      "cycle's peak between samples (too long: a 1 % lower peak is about 30 % more life); a step of at most {:.6g} deg "
      "([sweep] positions = {} over this range) resolves them",
      period * deg, design_->pair.pin_count, period / step, step * deg, kMinPositionsPerMeshPeriod, largest * deg, needed);
}

std::ptrdiff_t Stage::CheckedIndex(double crank) const {
  const Checked& c = *checked_;
  const auto it = std::lower_bound(c.order.begin(), c.order.end(), crank,
                                   [&c](std::size_t i, double value) { return c.cranks[i] < value; });
  if (it == c.order.end() || c.cranks[*it] != crank) return -1;
  return static_cast<std::ptrdiff_t>(*it);
}

contact::MeshState Stage::State(double crank) const {
  const std::ptrdiff_t k = CheckedIndex(crank);
  if (k >= 0 && !checked_->states.empty()) return checked_->states[static_cast<std::size_t>(k)];
  contact::MeshState state = second_ ? contact::EvaluateTwoDiscs(*first_, *second_, crank) : first_->Evaluate(crank, 0.0);
  return state;
}

const contact::Material& Stage::RequireMaterial() const {
  if (!design_->material) throw std::invalid_argument("missing required section [material] for a load problem");
  return *design_->material;
}

namespace {

/// The body's part of the coupled set: the problem's pin-ring points (in the problem's order)
/// followed by each disc's hole contacts, disc by disc (`holes[d]`, in the order given); each disc's
/// points and holes couple through its own body (`bodies[d]`) only, the two discs not at all.
Eigen::MatrixXd DiscBodiesCoupling(const solvers::LoadProblem& problem,
                                   std::vector<std::vector<contact::DiscHoleContact>> holes,
                                   const std::vector<const contact::DiscFlankCompliance*>& bodies,
                                   const std::optional<Stage::BodyTurn>& second_turn) {
  const std::vector<contact::PinContact>& all = problem.base_state().pins;
  const auto n = static_cast<Eigen::Index>(problem.point_count());
  Eigen::Index m = 0;
  for (const auto& h : holes) m += static_cast<Eigen::Index>(h.size());
  if (problem.disc_count() == 1) {
    // One disc: its body's coupling as it comes (every point is the disc's, in the problem's order).
    if (m == 0) return bodies.at(0)->Coupling(all);
    return bodies.at(0)->Coupling(all, holes.at(0));
  }
  Eigen::MatrixXd body = Eigen::MatrixXd::Zero(n + m, n + m);
  Eigen::Index next = n;  // the set's row of this disc's first hole contact
  for (int d = 0; d < problem.disc_count(); ++d) {
    std::vector<Eigen::Index> at;  // the set's row of each of this disc's entries
    std::vector<contact::PinContact> points;
    // The second disc on the first body turned: each of its points and hole contacts is the first
    // body's at the point and direction turned back (tooth space and hole index shifted).
    const Stage::BodyTurn* turn = d == 1 && second_turn ? &*second_turn : nullptr;
    for (std::size_t i = 0; i < all.size(); ++i) {
      if (all[i].disc != d) continue;
      at.push_back(static_cast<Eigen::Index>(i));
      points.push_back(all[i]);
      points.back().disc = 0;  // its own body's
      if (turn != nullptr) points.back().tooth_space -= turn->spaces;
    }
    std::vector<contact::DiscHoleContact>& own = holes.at(static_cast<std::size_t>(d));
    if (turn != nullptr) {
      const int n = bodies.at(0)->hole_count();
      const Eigen::Rotation2Dd back(-turn->angle);
      for (contact::DiscHoleContact& h : own) {
        h.hole = ((h.hole - turn->holes) % n + n) % n;
        h.direction = back * h.direction;
      }
    }
    const Eigen::MatrixXd c = own.empty() ? bodies.at(static_cast<std::size_t>(d))->Coupling(points)
                                          : bodies.at(static_cast<std::size_t>(d))->Coupling(points, own);
    for (std::size_t r = 0; r < own.size(); ++r) at.push_back(next++);
    const auto size = static_cast<Eigen::Index>(at.size());
    for (Eigen::Index x = 0; x < size; ++x) {
      for (Eigen::Index y = 0; y < size; ++y) body(at[static_cast<std::size_t>(x)], at[static_cast<std::size_t>(y)]) = c(x, y);
    }
  }
  return body;
}

}  // namespace

solvers::LoadProblem Stage::Problem(double crank, double torque) const {
  return Problem(State(crank), torque);
}

solvers::LoadProblem Stage::Problem(contact::MeshState state, double torque) const {
  const StageDesign& d = *design_;
  if (second_) {
    const solvers::LoadProblem both(first_, second_, std::move(state), d.contact, RequireMaterial(), torque, d.kinematics);
    if (!reducer_ && disc_body_) {
      // The mesh alone with two discs: each disc its own cyclic body clamped at its bore (no holes:
      // both discs' bodies are one design, one set-up), its points coupled through it alone.
      const Eigen::MatrixXd c = DiscBodiesCoupling(both, {{}, {}}, Bodies(), std::nullopt);
      const int points = both.point_count();
      return both.WithCoupling(
          solvers::LoadProblem::CheckCoupling(c, points, solvers::LoadProblem::PositiveSemidefiniteByConstruction{}));
    }
    if (!reducer_) return both;
    if (disc_body_) return WithStageBody(both.WithReducer(reducer_));
    return both.WithReducer(reducer_);
  }
  solvers::LoadProblem problem(first_, std::move(state), d.contact, RequireMaterial(), torque, d.kinematics);
  if (reducer_) problem = problem.WithReducer(reducer_);
  if (disc_body_ && reducer_) return WithStageBody(std::move(problem));
  if (disc_body_) {
    // The body couples this pose's contacts (its points move along the flanks with the crank):
    // pin bending's matrix (checked once) plus the body's, W K W^T + a non-negative diagonal with
    // K the condensed FE compliance (positive semidefinite by construction: the eigenvalue check
    // per pose is skipped, the other checks of the coupling are made).
    // Checked and kept dense (the dense kernel takes it as it is).
    Eigen::MatrixXd c = disc_body_->Coupling(problem.base_state().pins);
    if (coupling_->matrix) c += *coupling_->matrix;
    const int points = problem.point_count();
    return problem.WithCoupling(
        solvers::LoadProblem::CheckCoupling(std::move(c), points, solvers::LoadProblem::PositiveSemidefiniteByConstruction{}));
  }
  if (!coupling_->matrix) return problem;
  return problem.WithCoupling(*coupling_);
}

namespace {

/// The stage's coupled set from an elastic body's coupling `body` over the problem's pin-ring points
/// (the first n rows) and `further` contacts on the body's holes (output pins or needle rollers):
/// the problem's own coupling (the pin ring: the body's block and pin bending's, `bending`, may be
/// null), then the whole set's (LoadProblem::WithStageBodyCoupling).
solvers::LoadProblem WithBodyCoupling(solvers::LoadProblem problem, const Eigen::MatrixXd& body, int further,
                                      const Eigen::SparseMatrix<double>* bending) {
  const auto n = static_cast<Eigen::Index>(problem.point_count());
  Eigen::SparseMatrix<double> ring = Eigen::MatrixXd(body.topLeftCorner(n, n)).sparseView();
  if (bending) ring += *bending;
  problem = problem.WithCoupling(solvers::LoadProblem::CheckCoupling(
      std::move(ring), static_cast<int>(n), solvers::LoadProblem::PositiveSemidefiniteByConstruction{}));
  Eigen::MatrixXd total = body;
  total.topLeftCorner(n, n) = Eigen::MatrixXd(*problem.coupling());
  solvers::LoadProblem::StageBodyCoupling stage;
  stage.total = std::make_shared<const Eigen::SparseMatrix<double>>(total.sparseView());
  stage.body = std::make_shared<const Eigen::SparseMatrix<double>>(body.sparseView());
  stage.output_points = further;
  return problem.WithStageBodyCoupling(std::move(stage));
}

}  // namespace

std::vector<const contact::DiscFlankCompliance*> Stage::Bodies() const {
  std::vector<const contact::DiscFlankCompliance*> bodies{disc_body_.get()};
  if (second_) bodies.push_back(second_body_.get());
  return bodies;
}

solvers::LoadProblem Stage::WithStageBody(solvers::LoadProblem problem) const {
  if (reducer_->kind == solvers::OutputKind::kCranks) return WithCrankBody(std::move(problem));
  // The elastic body in a stage of output pins: one coupled set of the pin ring's points and every
  // disc's output pins' contacts on its holes' walls (ReducerSystem: disc by disc, pin by pin),
  // each contact at the nominal pose of this crank (the pin touches its hole where the line of the
  // two centres meets the wall; its direction in the body frame is the fixed frame's turned back by
  // the disc's nominal rotation: the output member's for disc 0, its own model's for disc 1, whose
  // holes BodyHoles places half a tooth pitch on). Each disc's points couple through its own body.
  const double output_rotation = problem.model().kinematics().CycloidPose(problem.crank()).rotation;
  std::vector<std::vector<contact::DiscHoleContact>> holes(static_cast<std::size_t>(problem.disc_count()));
  int count = 0;
  for (int d = 0; d < problem.disc_count(); ++d) {
    const contact::MeshModel& model = problem.DiscModel(d);
    const double crank = problem.DiscCrank(d);
    const geometry::Pose real = model.real_pair().CycloidPose(crank);
    const std::vector<contact::OutputPinContact> pins = contact::EvaluateOutputPins(
        reducer_->PinsOf(d), geometry::Pose{real.centre, output_rotation}, output_rotation);
    const Eigen::Rotation2Dd back(-model.kinematics().CycloidPose(crank).rotation);
    for (const contact::OutputPinContact& c : pins) holes[static_cast<std::size_t>(d)].push_back({c.pin, back * c.normal});
    count += static_cast<int>(pins.size());
  }
  const Eigen::MatrixXd body = DiscBodiesCoupling(problem, std::move(holes), Bodies(), second_turn_);
  return WithBodyCoupling(std::move(problem), body, count, coupling_->matrix.get());
}

solvers::LoadProblem Stage::WithCrankBody(solvers::LoadProblem problem) const {
  // The elastic body of an RV stage: one coupled set of the pin ring's points (both discs) and
  // every needle roller of every crank bearing (disc, crank, roller), each roller a contact on its
  // crank hole's wall along its direction at the nominal pose of this crank (roller k of a bearing
  // at the eccentric's direction + 2 pi k / Z in the fixed frame, as the bearing's law places it;
  // in the body frame turned back by the disc's nominal rotation). Each disc's points couple
  // through its own body only.
  const contact::BearingSettings& bearing = reducer_->bearing;
  const int z = bearing.roller_count;
  const int count = reducer_->cranks.count;
  std::vector<std::vector<contact::DiscHoleContact>> holes(static_cast<std::size_t>(problem.disc_count()));
  int rollers = 0;
  for (int d = 0; d < problem.disc_count(); ++d) {
    const contact::MeshModel& model = problem.DiscModel(d);
    const double crank = problem.DiscCrank(d);
    const geometry::Pose real = model.real_pair().CycloidPose(crank);
    const double phase = std::atan2(real.centre.y(), real.centre.x());  // ReducerSystem's roller phase
    const Eigen::Rotation2Dd back(-model.kinematics().CycloidPose(crank).rotation);
    for (int j = 0; j < count; ++j) {
      for (int k = 0; k < z; ++k) {
        const double angle = phase + 2.0 * units::kPi * k / z;
        holes[static_cast<std::size_t>(d)].push_back({j, back * Eigen::Vector2d(std::cos(angle), std::sin(angle))});
        ++rollers;
      }
    }
  }
  const Eigen::MatrixXd body = DiscBodiesCoupling(problem, std::move(holes), Bodies(), second_turn_);
  return WithBodyCoupling(std::move(problem), body, rollers, coupling_->matrix.get());
}

}  // namespace ltca::analysis
