#include "ltca/analysis/keys.hpp"

#include <algorithm>
#include <cmath>

#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ltca/analysis/allowables.hpp"
#include "ltca/analysis/friction.hpp"
#include "ltca/analysis/inspection.hpp"
#include "ltca/analysis/optimise.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/analysis/tolerance.hpp"
#include "ltca/contact/bearing.hpp"
#include "ltca/contact/cranks.hpp"
#include "ltca/contact/laws.hpp"
#include "ltca/contact/material.hpp"
#include "ltca/contact/output_pins.hpp"
#include "ltca/contact/pin_bending.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/discrete_profile.hpp"
#include "ltca/geometry/errors.hpp"
#include "ltca/geometry/profile_deviation.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "ltca/solvers/registry.hpp"
#include "ltca/solvers/reducer.hpp"

namespace ltca::analysis {
namespace {

using T = DeckKey::Type;
using L = DeckKey::Limit;

// Field accessors: where a number of [modification] or [errors] goes.
#define LTCA_FIELD(part, member) [](const DiscParts& p) -> double* { return &p.part->member; }
#define LTCA_LIST(member) [](const DiscParts& p) -> std::vector<double>* { return &p.errors->member; }
// Where a key of the other sections goes: a member of one of the deck's settings (SettingsParts);
// no field when that part is not being read.
#define LTCA_SETTING(part, member) \
  [](const SettingsParts& p) -> SettingField { return p.part == nullptr ? SettingField() : SettingField(&p.part->member); }
// A choice into an enum member: its values in the order of the key's choices.
#define LTCA_CHOICE(part, member, ...)                                                      \
  [](const SettingsParts& p) -> SettingField {                                               \
    return p.part == nullptr ? SettingField() : SettingField::Choice<__VA_ARGS__>(&p.part->member); \
  }
// A key of [output] common to both kinds: the member of the output pins, or else of the cranks.
#define LTCA_OUTPUT(member)                                                                             \
  [](const SettingsParts& p) -> SettingField {                                                          \
    return p.output_pins != nullptr ? SettingField(&p.output_pins->member)                              \
                                    : (p.cranks != nullptr ? SettingField(&p.cranks->member) : SettingField()); \
  }

// The enums the choices go to, in the order of each key's choices.
using Reading = geometry::ManufacturingErrors::PinCircleReading;
using Pivot = geometry::AssemblyErrors::Pivot;
using Distribution = geometry::ProfileRandomDistribution;
using Spacing = geometry::ProfileElementSpacing;
using Law = contact::LawKind;
using Rho = contact::RhoConvention;
using Mode = geometry::GeometrySettings::Mode;
using Support = contact::PinSupportKind;
using Seat = contact::PinSeat::Kind;
using Body = contact::DiscBodySettings::Body;
using Plane = contact::PlaneModel;
using Output = solvers::OutputKind;
using Bearing = contact::BearingKind;
using Kinematics = contact::ContactKinematics;
using LifeCurve = contact::LifeCurve;
using Rigidity = StiffnessSettings::Rigidity;
using Friction = FrictionSettings::Model;
using Balance = FrictionSettings::TorqueBalance;
using Global = OptimiseSettings::Global;
using Local = OptimiseSettings::Local;

/// The registered solvers, "a | b | ...": the [solver] name key follows the registry, so a new
/// solver needs no entry here.
const char* SolverChoices() {
  static const std::string choices = fmt::format("{}", fmt::join(solvers::SolverNames(), " | "));
  return choices.c_str();
}

const std::vector<DeckKey> kKeys = {
    // [case]
    {.section = "case", .name = "title", .type = T::kText, .unit = "", .meaning = "a short title of the case", .default_value = "",
     .setting = LTCA_SETTING(info, title), .required = true},
    {.section = "case", .name = "source", .type = T::kText, .unit = "", .meaning = "provenance: paper, table / section",
     .default_value = "\"\"", .setting = LTCA_SETTING(info, source)},
    // [pair]
    {.section = "pair", .name = "pin_count", .type = T::kInteger, .unit = "", .meaning = "number of pins z_p", .default_value = "",
     .setting = LTCA_SETTING(pair, pin_count), .required = true},
    {.section = "pair", .name = "tooth_count", .type = T::kInteger, .unit = "", .meaning = "number of cycloid teeth z_c",
     .default_value = "",
     .setting = LTCA_SETTING(pair, tooth_count), .required = true},
    {.section = "pair", .name = "pin_radius_mm", .type = T::kReal, .unit = "mm", .meaning = "pin radius r_rp in mm", .default_value = "",
     .setting = LTCA_SETTING(pair, pin_radius), .required = true},
    {.section = "pair", .name = "pin_circle_radius_mm", .type = T::kReal, .unit = "mm", .meaning = "pin-circle radius R_p in mm",
     .default_value = "",
     .setting = LTCA_SETTING(pair, pin_circle_radius), .required = true},
    {.section = "pair", .name = "eccentricity_mm", .type = T::kReal, .unit = "mm", .meaning = "eccentricity e in mm", .default_value = "",
     .setting = LTCA_SETTING(pair, eccentricity), .required = true},
    {.section = "pair", .name = "face_width_mm", .type = T::kReal, .unit = "mm", .meaning = "face width B_c in mm", .default_value = "",
     .setting = LTCA_SETTING(pair, face_width), .required = true},
    // [modification]: every key is the disc's
    {.section = "modification", .name = "pin_radius_mm", .type = T::kReal, .unit = "mm",
     .meaning = "isometric modification dR_rp in mm (the pin clearance with dR_p; pins it leaves overlapping the cycloid, e.g. dR_rp < 0 with dR_p = 0, are a preloaded zero-backlash pair, docs/stiffness.md \"Preload\")", .default_value = "0", .disc = true, .tolerance_stream = 12,
     .limit = L::kLength, .real = LTCA_FIELD(modification, pin_radius)},
    {.section = "modification", .name = "pin_circle_radius_mm", .type = T::kReal, .unit = "mm",
     .meaning = "offset modification dR_p in mm (the pin clearance with dR_rp; pins they leave overlapping the cycloid are a preloaded pair, docs/stage.md \"Preload\")", .default_value = "0", .disc = true, .tolerance_stream = 13,
     .limit = L::kLength, .real = LTCA_FIELD(modification, pin_circle_radius)},
    {.section = "modification", .name = "rotation_deg", .type = T::kReal, .unit = "deg",
     .meaning = "angle-rotation modification in deg", .default_value = "0", .disc = true, .tolerance_stream = 14,
     .limit = L::kRotation, .real = LTCA_FIELD(modification, rotation)},
    {.section = "modification", .name = "tip_truncation_mm", .type = T::kReal, .unit = "mm",
     .meaning = "tip truncation in mm along the tooth axis", .default_value = "0", .disc = true,
     .real = LTCA_FIELD(modification, tip_relief.truncation)},
    {.section = "modification", .name = "tip_rounding_radius_mm", .type = T::kReal, .unit = "mm",
     .meaning = "tip rounding radius in mm", .default_value = "0", .disc = true,
     .real = LTCA_FIELD(modification, tip_relief.rounding_radius)},
    // [errors]: the pin ring's keys (common to both discs), then the disc's
    {.section = "errors", .name = "pin_circle_deviation_mm", .type = T::kReal, .unit = "mm",
     .meaning = "pin-circle deviation delta_Rp of Liu eq. 5 in mm", .default_value = "0", .tolerance_stream = 0,
     .limit = L::kLength, .real = LTCA_FIELD(errors, pin_circle_deviation)},
    {.section = "errors", .name = "pin_circle_reading", .type = T::kText, .unit = "",
     .meaning = "how eq. 5 applies delta_Rp: radius | diameter", .default_value = "\"radius\"", .choices = "radius | diameter",
     .setting = LTCA_CHOICE(errors, pin_circle_reading, Reading::kRadius, Reading::kDiameter)},
    {.section = "errors", .name = "cumulative_pitch_deviation_mm", .type = T::kRealList, .unit = "mm",
     .meaning = "one cumulative pitch deviation per pin in mm", .default_value = "[]", .per_pin = true, .tolerance_stream = 2,
     .limit = L::kLength, .list = LTCA_LIST(cumulative_pitch_deviation)},
    {.section = "errors", .name = "pin_radius_deviations_mm", .type = T::kRealList, .unit = "mm",
     .meaning = "one pin radius deviation per pin in mm", .default_value = "[]", .per_pin = true, .tolerance_stream = 3,
     .limit = L::kLength, .list = LTCA_LIST(pin_radius_deviations)},
    {.section = "errors", .name = "pin_radial_deviations_mm", .type = T::kRealList, .unit = "mm",
     .meaning = "one radial pin position deviation per pin in mm", .default_value = "[]", .per_pin = true,
     .tolerance_stream = 4, .limit = L::kLength, .list = LTCA_LIST(pin_radial_deviations)},
    {.section = "errors", .name = "cycloid_profile_layer_mm", .type = T::kReal, .unit = "mm",
     .meaning = "uniform layer on the cycloid profile in mm", .default_value = "0", .disc = true, .tolerance_stream = 1,
     .limit = L::kLength, .real = LTCA_FIELD(errors, profile_layer)},
    {.section = "errors", .name = "lead_crowning_um", .type = T::kReal, .unit = "um",
     .meaning = "lead crowning of the cycloid in um", .default_value = "0", .disc = true, .tolerance_stream = 5,
     .limit = L::kLength, .real = LTCA_FIELD(errors, lead_crowning)},
    {.section = "errors", .name = "lead_slope_um", .type = T::kReal, .unit = "um",
     .meaning = "lead slope error of the cycloid over the face width in um", .default_value = "0", .disc = true,
     .tolerance_stream = 6, .limit = L::kLength, .real = LTCA_FIELD(errors, lead_slope)},
    {.section = "errors", .name = "centre_dx_mm", .type = T::kReal, .unit = "mm",
     .meaning = "frame-fixed offset of the cycloid centre along X in mm", .default_value = "0", .disc = true,
     .tolerance_stream = 7, .limit = L::kLength, .real = LTCA_FIELD(assembly, centre_dx)},
    {.section = "errors", .name = "centre_dy_mm", .type = T::kReal, .unit = "mm",
     .meaning = "frame-fixed offset of the cycloid centre along Y in mm", .default_value = "0", .disc = true,
     .tolerance_stream = 8, .limit = L::kLength, .real = LTCA_FIELD(assembly, centre_dy)},
    {.section = "errors", .name = "eccentricity_deviation_mm", .type = T::kReal, .unit = "mm",
     .meaning = "eccentricity deviation in mm", .default_value = "0", .disc = true, .tolerance_stream = 9,
     .limit = L::kLength, .real = LTCA_FIELD(assembly, eccentricity_deviation)},
    {.section = "errors", .name = "misalignment_xz_deg", .type = T::kReal, .unit = "deg",
     .meaning = "tilt phi of the cycloid axis in the XZ plane in deg", .default_value = "0", .disc = true,
     .tolerance_stream = 10, .limit = L::kTilt, .real = LTCA_FIELD(assembly, misalignment_xz)},
    {.section = "errors", .name = "misalignment_yz_deg", .type = T::kReal, .unit = "deg",
     .meaning = "tilt gamma of the cycloid axis in the YZ plane in deg", .default_value = "0", .disc = true,
     .tolerance_stream = 11, .limit = L::kTilt, .real = LTCA_FIELD(assembly, misalignment_yz)},
    {.section = "errors", .name = "misalignment_pivot", .type = T::kText, .unit = "", .meaning = "face | mid",
     .default_value = "\"face\"", .choices = "face | mid", .disc = true,
     .setting = LTCA_CHOICE(assembly, pivot, Pivot::kFace, Pivot::kMid)},
    {.section = "errors", .name = "profile_random_zone_um", .type = T::kReal, .unit = "um",
     .meaning = "full width of the random profile tolerance zone in um", .default_value = "0", .disc = true,
     .limit = L::kLength, .real = LTCA_FIELD(errors, profile_random.zone)},
    {.section = "errors", .name = "profile_random_elements", .type = T::kInteger, .unit = "",
     .meaning = "random profile elements per tooth space", .default_value = "800", .disc = true,
     .setting = LTCA_SETTING(errors, profile_random.elements)},
    {.section = "errors", .name = "profile_random_seed", .type = T::kUnsigned, .unit = "",
     .meaning = "seed of the random profile deviation", .default_value = "0", .disc = true,
     .setting = LTCA_SETTING(errors, profile_random.seed)},
    {.section = "errors", .name = "profile_random_distribution", .type = T::kText, .unit = "", .meaning = "uniform | normal",
     .default_value = "\"uniform\"", .choices = "uniform | normal", .disc = true,
     .setting = LTCA_CHOICE(errors, profile_random.distribution, Distribution::kUniform, Distribution::kNormal)},
    {.section = "errors", .name = "profile_random_spacing", .type = T::kText, .unit = "", .meaning = "arc_length | parameter",
     .default_value = "\"arc_length\"", .choices = "arc_length | parameter", .disc = true,
     .setting = LTCA_CHOICE(errors, profile_random.spacing, Spacing::kArcLength, Spacing::kParameter)},
    {.section = "errors", .name = "profile_measured_csv", .type = T::kText, .unit = "",
     .meaning = "path of a measured profile trace, relative to the deck", .default_value = "", .disc = true},
    // [contact]
    {.section = "contact", .name = "law", .type = T::kText, .unit = "", .meaning = "hertz-line | sagitta | linear",
     .default_value = "\"hertz-line\"", .choices = "hertz-line | sagitta | linear",
     .setting = LTCA_CHOICE(contact, law, Law::kHertzLine, Law::kSagitta, Law::kLinear)},
    {.section = "contact", .name = "rho_convention", .type = T::kText, .unit = "", .meaning = "signed | absolute",
     .default_value = "\"signed\"", .choices = "signed | absolute",
     .setting = LTCA_CHOICE(contact, rho_convention, Rho::kSigned, Rho::kAbsolute)},
    {.section = "contact", .name = "stiffness_n_per_mm2", .type = T::kReal, .unit = "N/mm^2",
     .meaning = "linear law: stiffness per mm of contact length", .default_value = "0",
     .setting = LTCA_SETTING(contact, stiffness_per_length)},
    {.section = "contact", .name = "log_radius_cap_mm", .type = T::kReal, .unit = "mm",
     .meaning = "largest cycloid radius in the hertz-line logarithm, mm", .default_value = "0",
     .setting = LTCA_SETTING(contact, log_radius_cap)},
    // [geometry]
    {.section = "geometry", .name = "geometry_mode", .type = T::kText, .unit = "",
     .meaning = "analytic | elements (Liu's discrete surface)", .default_value = "\"analytic\"", .choices = "analytic | elements",
     .setting = LTCA_CHOICE(geometry, mode, Mode::kAnalytic, Mode::kElements)},
    {.section = "geometry", .name = "profile_elements", .type = T::kInteger, .unit = "", .meaning = "elements along one tooth space",
     .default_value = "800",
     .setting = LTCA_SETTING(geometry, profile_elements)},
    {.section = "geometry", .name = "width_slices", .type = T::kInteger, .unit = "", .meaning = "slices across the face width",
     .default_value = "100",
     .setting = LTCA_SETTING(geometry, width_slices)},
    // [material]
    {.section = "material", .name = "young_modulus_mpa", .type = T::kReal, .unit = "MPa",
     .meaning = "Young's modulus of the cycloid in MPa", .default_value = "",
     .setting = LTCA_SETTING(material, young_modulus), .required = true},
    {.section = "material", .name = "poisson_ratio", .type = T::kReal, .unit = "", .meaning = "Poisson's ratio of the cycloid",
     .default_value = "",
     .setting = LTCA_SETTING(material, poisson_ratio), .required = true},
    {.section = "material", .name = "pin_young_modulus_mpa", .type = T::kReal, .unit = "MPa",
     .meaning = "Young's modulus of the pins in MPa", .default_value = "young_modulus_mpa",
     .setting = LTCA_SETTING(material, pin_young_modulus)},
    {.section = "material", .name = "pin_poisson_ratio", .type = T::kReal, .unit = "", .meaning = "Poisson's ratio of the pins",
     .default_value = "poisson_ratio",
     .setting = LTCA_SETTING(material, pin_poisson_ratio)},
    {.section = "material", .name = "contact_stress_limit_mpa", .type = T::kReal, .unit = "MPa",
     .meaning = "contact stress above which a result is flagged, MPa", .default_value = "4000",
     .setting = LTCA_SETTING(material, contact_stress_limit)},
    {.section = "material", .name = "contact_fatigue_limit_mpa", .type = T::kReal, .unit = "MPa",
     .meaning = "endurance limit sigma_Hlim of the flanks in pitting, MPa (contact fatigue; ISO 6336-5: 1500 for case-hardened "
                "steel MQ)",
     .default_value = "1500", .setting = LTCA_SETTING(material, contact_fatigue_limit)},
    {.section = "material", .name = "contact_life_curve", .type = T::kText, .unit = "",
     .meaning = "life factor Z_NT over the load cycles, ISO 6336-2: steel (St, V, Eh, IF) | steel-limited-pitting | nitrided | "
                "nitrocarburized",
     .default_value = "\"steel\"", .choices = "steel | steel-limited-pitting | nitrided | nitrocarburized",
     .setting = LTCA_CHOICE(material, life_curve, LifeCurve::kSteel, LifeCurve::kSteelLimitedPitting, LifeCurve::kNitrided,
                            LifeCurve::kNitrocarburized)},
    // [pins]
    {.section = "pins", .name = "span_mm", .type = T::kReal, .unit = "mm",
     .meaning = "pin bending: distance between the two supports of a pin in mm", .default_value = "",
     .setting = LTCA_SETTING(pin_support, span)},
    {.section = "pins", .name = "support", .type = T::kText, .unit = "", .meaning = "simply-supported | clamped",
     .default_value = "\"simply-supported\"", .choices = "simply-supported | clamped",
     .setting = LTCA_CHOICE(pin_support, support, Support::kSimplySupported, Support::kClamped)},
    {.section = "pins", .name = "face_offset_mm", .type = T::kReal, .unit = "mm",
     .meaning = "pin bending: from the first support to face B of the cycloid in mm", .default_value = "",
     .setting = LTCA_SETTING(pin_support, face_offset)},
    {.section = "pins", .name = "seat", .type = T::kText, .unit = "",
     .meaning = "pins seated along their length: rigid | linear | groove (not with span_mm)", .default_value = "\"rigid\"",
     .choices = "rigid | linear | groove",
     .setting = LTCA_CHOICE(pin_seat, kind, Seat::kRigid, Seat::kLinear, Seat::kGroove)},
    {.section = "pins", .name = "seat_stiffness_n_per_mm2", .type = T::kReal, .unit = "N/mm^2",
     .meaning = "linear seat: stiffness per mm of pin length in N/mm^2", .default_value = "",
     .setting = LTCA_SETTING(pin_seat, stiffness_per_length)},
    {.section = "pins", .name = "groove_radius_mm", .type = T::kReal, .unit = "mm",
     .meaning = "groove seat: radius of the housing groove in mm (> pin radius)", .default_value = "",
     .setting = LTCA_SETTING(pin_seat, groove_radius)},
    {.section = "pins", .name = "housing_young_modulus_mpa", .type = T::kReal, .unit = "MPa",
     .meaning = "groove seat: Young's modulus of the housing in MPa", .default_value = "young_modulus_mpa",
     .setting = LTCA_SETTING(pin_seat, housing_young_modulus)},
    {.section = "pins", .name = "housing_poisson_ratio", .type = T::kReal, .unit = "",
     .meaning = "groove seat: Poisson's ratio of the housing", .default_value = "poisson_ratio",
     .setting = LTCA_SETTING(pin_seat, housing_poisson_ratio)},
    // [disc] (docs/fe_disc.md): the disc body, rigid or elastic
    {.section = "disc", .name = "body", .type = T::kText, .unit = "",
     .meaning = "the disc body: rigid | elastic (its FE compliance couples the contacts)", .default_value = "\"rigid\"",
     .choices = "rigid | elastic", .setting = LTCA_CHOICE(disc_body, body, Body::kRigid, Body::kElastic)},
    {.section = "disc", .name = "bore_radius_mm", .type = T::kReal, .unit = "mm",
     .meaning = "elastic body: radius of the central bore in mm, clamped in the mesh alone", .default_value = "",
     .setting = LTCA_SETTING(disc_body, bore_radius)},
    {.section = "disc", .name = "plane", .type = T::kText, .unit = "",
     .meaning = "elastic body: strain (a thick disc) | stress (a thin disc)", .default_value = "\"strain\"",
     .choices = "strain | stress", .setting = LTCA_CHOICE(disc_body, plane, Plane::kStrain, Plane::kStress)},
    {.section = "disc", .name = "element_size_mm", .type = T::kReal, .unit = "mm",
     .meaning = "elastic body: FE element size away from the flank in mm", .default_value = "3",
     .setting = LTCA_SETTING(disc_body, element_size)},
    {.section = "disc", .name = "grid_points_per_space", .type = T::kInteger, .unit = "",
     .meaning = "elastic body: condensation points per tooth space, evenly in arc length", .default_value = "32",
     .setting = LTCA_SETTING(disc_body, grid.points_per_space)},
    {.section = "disc", .name = "patch_half_width_mm", .type = T::kReal, .unit = "mm",
     .meaning = "elastic body: half-width of each condensation point's load patch in mm (the flank meshed at it)",
     .default_value = "0.2", .setting = LTCA_SETTING(disc_body, grid.patch_half_width_mm)},
    // [output] (docs/stage.md): the output mechanism of the reducer stage
    {.section = "output", .name = "kind", .type = T::kText, .unit = "",
     .meaning = "pins (output pins in holes of the disc) | cranks (crankshafts in crank holes, RV)", .default_value = "",
     .choices = "pins | cranks",
     .setting = LTCA_CHOICE(reducer, kind, Output::kPins, Output::kCranks), .required = true},
    {.section = "output", .name = "count", .type = T::kInteger, .unit = "", .meaning = "output pins or crankshafts",
     .default_value = "",
     .setting = LTCA_OUTPUT(count)},
    {.section = "output", .name = "circle_radius_mm", .type = T::kReal, .unit = "mm",
     .meaning = "radius of the output pins' or the cranks' circle in mm", .default_value = "",
     .setting = LTCA_OUTPUT(circle_radius)},
    {.section = "output", .name = "phase_deg", .type = T::kReal, .unit = "deg",
     .meaning = "angle of element 0 from +X at crank 0 in deg", .default_value = "0",
     .setting = LTCA_OUTPUT(phase)},
    {.section = "output", .name = "hole_radial_deviations_mm", .type = T::kRealList, .unit = "mm",
     .meaning = "one radial position deviation per hole of the disc in mm (both discs, unless [second_disc] gives its own)",
     .default_value = "[]", .per_hole = true, .tolerance_stream = 19, .limit = L::kLength},
    {.section = "output", .name = "hole_tangential_deviations_mm", .type = T::kRealList, .unit = "mm",
     .meaning = "one tangential (counterclockwise) position deviation per hole in mm (both discs, unless [second_disc] gives its own)",
     .default_value = "[]", .per_hole = true, .tolerance_stream = 20, .limit = L::kLength},
    {.section = "output", .name = "pin_radius_mm", .type = T::kReal, .unit = "mm", .meaning = "pins: output pin radius in mm",
     .default_value = "", .tolerance_stream = 18, .limit = L::kLength,
     .setting = LTCA_SETTING(output_pins, pin_radius)},
    {.section = "output", .name = "hole_radius_mm", .type = T::kReal, .unit = "mm",
     .meaning = "pins: radius of the disc's holes in mm (clearance hole - pin - eccentricity; below pin + eccentricity every output pin is pressed into its hole at no load, a preload, docs/stage.md \"Preload\")", .default_value = "",
     .tolerance_stream = 17, .limit = L::kLength,
     .setting = LTCA_SETTING(output_pins, hole_radius)},
    {.section = "output", .name = "shaft_stiffness_n_per_mm", .type = T::kReal, .unit = "N/mm",
     .meaning = "cranks: radial stiffness of a crankshaft at its eccentric in N/mm, in series with the bearing",
     .default_value = "rigid",
     .setting = LTCA_SETTING(cranks, shaft_stiffness)},
    {.section = "output", .name = "crank_turns_per_output_turn", .type = T::kReal, .unit = "",
     .meaning = "cranks: turns of the eccentrics per output turn with the input locked", .default_value = "0",
     .setting = LTCA_SETTING(cranks, turns_per_output_turn)},
    {.section = "output", .name = "shaft_diameter_mm", .type = T::kReal, .unit = "mm",
     .meaning = "cranks: each crankshaft a Timoshenko beam of this solid diameter in mm, on two support bearings, carrying "
                "both discs' eccentrics (instead of shaft_stiffness_n_per_mm)",
     .default_value = "none", .setting = LTCA_SETTING(cranks, beam.diameter)},
    {.section = "output", .name = "shaft_span_mm", .type = T::kReal, .unit = "mm",
     .meaning = "cranks, beam: distance between the crankshaft's two support bearings in mm", .default_value = "none",
     .setting = LTCA_SETTING(cranks, beam.span)},
    {.section = "output", .name = "eccentric_positions_mm", .type = T::kRealList, .unit = "mm",
     .meaning = "cranks, beam: [a_1, a_2], the first and second disc's eccentric from the first support in mm",
     .default_value = "[]"},
    {.section = "output", .name = "support_stiffness_n_per_mm", .type = T::kReal, .unit = "N/mm",
     .meaning = "cranks, beam: radial stiffness of each support bearing in N/mm", .default_value = "rigid",
     .setting = LTCA_SETTING(cranks, beam.support_stiffness)},
    {.section = "output", .name = "first_stage_teeth", .type = T::kRealList, .unit = "",
     .meaning = "cranks: [z_sun, z_spur] of the first stage; with the input locked each eccentric turns (1 + z_sun / z_spur) "
                "times the output (instead of crank_turns_per_output_turn)",
     .default_value = "[]"},
    {.section = "output", .name = "carrier_torsional_stiffness_nm_per_arcmin", .type = T::kReal, .unit = "N*m/arcmin",
     .meaning = "torsional stiffness of the carrier, output flange and housing in series with the stage in N*m/arcmin "
                "(measured or FE)",
     .default_value = "rigid",
     .setting = LTCA_SETTING(reducer, carrier_stiffness)},
    // [bearing]: the eccentric bearing (pins) or the needle bearing of each crank hole (cranks)
    {.section = "bearing", .name = "kind", .type = T::kText, .unit = "", .meaning = "rigid | linear | rollers",
     .default_value = "\"rigid\"", .choices = "rigid | linear | rollers",
     .setting = LTCA_CHOICE(bearing, kind, Bearing::kRigid, Bearing::kLinear, Bearing::kRollers)},
    {.section = "bearing", .name = "radial_stiffness_n_per_mm", .type = T::kReal, .unit = "N/mm",
     .meaning = "linear: radial stiffness in N/mm", .default_value = "",
     .setting = LTCA_SETTING(bearing, radial_stiffness)},
    {.section = "bearing", .name = "radial_clearance_mm", .type = T::kReal, .unit = "mm",
     .meaning = "radial clearance (half the diametral play) in mm; negative: a preloaded bearing, every roller or element pressed by -c at no load (docs/stage.md \"Preload\")", .default_value = "0", .tolerance_stream = 16,
     .limit = L::kLength,
     .setting = LTCA_SETTING(bearing, radial_clearance)},
    {.section = "bearing", .name = "roller_count", .type = T::kInteger, .unit = "", .meaning = "rollers: number of rollers",
     .default_value = "",
     .setting = LTCA_SETTING(bearing, roller_count)},
    {.section = "bearing", .name = "roller_diameter_mm", .type = T::kReal, .unit = "mm", .meaning = "rollers: roller diameter in mm",
     .default_value = "",
     .setting = LTCA_SETTING(bearing, roller_diameter)},
    {.section = "bearing", .name = "roller_length_mm", .type = T::kReal, .unit = "mm",
     .meaning = "rollers: effective roller length in mm (Palmgren's line contact)", .default_value = "",
     .setting = LTCA_SETTING(bearing, roller_length)},
    {.section = "bearing", .name = "dynamic_load_rating_n", .type = T::kReal, .unit = "N",
     .meaning = "basic dynamic load rating C_r in N (ISO 281 life; 0: no life)", .default_value = "0",
     .setting = LTCA_SETTING(bearing, dynamic_load_rating)},
    {.section = "bearing", .name = "static_load_rating_n", .type = T::kReal, .unit = "N",
     .meaning = "basic static load rating C_0r in N (ISO 76 static safety s_0 = C_0r / P_0,max; 0: none)", .default_value = "0",
     .setting = LTCA_SETTING(bearing, static_load_rating)},
    {.section = "bearing", .name = "pitch_diameter_mm", .type = T::kReal, .unit = "mm",
     .meaning = "rollers: pitch diameter d_m of the roller set in mm (load-zone life, roller contact stress; 0: not given)",
     .default_value = "0",
     .setting = LTCA_SETTING(bearing, pitch_diameter)},
    {.section = "bearing", .name = "contamination_factor", .type = T::kReal, .unit = "",
     .meaning = "ISO 281 contamination factor e_C in [0, 1] (Table 13) for the modified life a_ISO L10; used only with "
                "[operation] oil_kinematic_viscosity_mm2_per_s",
     .default_value = "0.5",
     .setting = LTCA_SETTING(bearing, contamination_factor)},
    {.section = "bearing", .name = "fatigue_load_limit_n", .type = T::kReal, .unit = "N",
     .meaning = "ISO 281 fatigue load limit C_u in N for a_ISO; 0: Annex B's estimate C_0r / 8.2 (pitch diameter <= 100 mm); "
                "used only with [operation] oil_kinematic_viscosity_mm2_per_s",
     .default_value = "0",
     .setting = LTCA_SETTING(bearing, fatigue_load_limit)},
    // [load]
    {.section = "load", .name = "torque_nm", .type = T::kReal, .unit = "N*m",
     .meaning = "output torque of the stage in N*m: one disc's, or with [second_disc] both discs' together",
     .default_value = "", .setting = LTCA_SETTING(load, torque), .required = true},
    // [sweep]
    {.section = "sweep", .name = "crank_start_deg", .type = T::kReal, .unit = "deg", .meaning = "first crank angle in deg",
     .default_value = "0",
     .setting = LTCA_SETTING(sweep, crank_start)},
    {.section = "sweep", .name = "crank_end_deg", .type = T::kReal, .unit = "deg",
     .meaning = "last crank angle in deg (inclusive)", .default_value = "crank_start_deg + 360 / pin_count",
     .setting = LTCA_SETTING(sweep, crank_end)},
    {.section = "sweep", .name = "positions", .type = T::kInteger, .unit = "", .meaning = "number of crank positions",
     .default_value = "91",
     .setting = LTCA_SETTING(sweep, positions)},
    // [solver]
    {.section = "solver", .name = "name", .type = T::kText, .unit = "",
     .meaning = SolverChoices(), .default_value = "\"bisection\"", .choices = SolverChoices(),
     .setting = LTCA_SETTING(solver, name)},
    {.section = "solver", .name = "kinematics", .type = T::kText, .unit = "", .meaning = "linearised | exact",
     .default_value = "\"linearised\"", .choices = "linearised | exact",
     .setting = [](const SettingsParts& p) -> SettingField {
       return p.kinematics == nullptr ? SettingField() : SettingField::Choice<Kinematics::kLinearised, Kinematics::kExact>(p.kinematics);
     }},
    {.section = "solver", .name = "torque_tolerance", .type = T::kReal, .unit = "", .meaning = "relative torque tolerance",
     .default_value = "1e-10",
     .setting = LTCA_SETTING(solver, torque_tolerance)},
    {.section = "solver", .name = "max_iterations", .type = T::kInteger, .unit = "", .meaning = "iteration limit",
     .default_value = "500",
     .setting = LTCA_SETTING(solver, max_iterations)},
    {.section = "solver", .name = "preset", .type = T::kText, .unit = "", .meaning = "a named preset: liu2021", .default_value = "",
     .choices = "liu2021",
     .setting = [](const SettingsParts& p) -> SettingField { return p.preset == nullptr ? SettingField() : SettingField(p.preset); }},
    {.section = "solver", .name = "nlopt_algorithm", .type = T::kText, .unit = "", .meaning = "compatibility: NLopt algorithm name",
     .default_value = "\"LD_LBFGS\"",
     .setting = LTCA_SETTING(solver, nlopt_algorithm)},
    // [stiffness]
    {.section = "stiffness", .name = "steps_per_branch", .type = T::kInteger, .unit = "",
     .meaning = "torque levels per branch from -T to +T, odd", .default_value = "41",
     .setting = LTCA_SETTING(stiffness, steps)},
    {.section = "stiffness", .name = "rigidity", .type = T::kText, .unit = "", .meaning = "secant | tangent",
     .default_value = "\"secant\"", .choices = "secant | tangent",
     .setting = LTCA_CHOICE(stiffness, rigidity, Rigidity::kSecant, Rigidity::kTangent)},
    {.section = "stiffness", .name = "tangent_torque_nm", .type = T::kReal, .unit = "N*m",
     .meaning = "torque of the tangent rigidity in N*m", .default_value = "",
     .setting = LTCA_SETTING(stiffness, tangent_torque)},
    {.section = "stiffness", .name = "lost_motion_fraction", .type = T::kReal, .unit = "",
     .meaning = "fraction of T at which lost motion is read", .default_value = "0.03",
     .setting = LTCA_SETTING(stiffness, lost_motion_fraction)},
    {.section = "stiffness", .name = "crank_deg", .type = T::kReal, .unit = "deg", .meaning = "one crank angle in deg",
     .default_value = "",
     .setting = LTCA_SETTING(stiffness, crank)},
    // [second_disc]: its own key; the disc keys of [modification] and [errors] too (DeckKey::disc)
    {.section = "second_disc", .name = "indexing_deviation_mm", .type = T::kReal, .unit = "mm",
     .meaning = "indexing deviation of the second disc in mm along the pin circle", .default_value = "0",
     .tolerance_stream = 15, .limit = L::kLength,
     .setting = LTCA_SETTING(second_disc, indexing_deviation)},
    {.section = "second_disc", .name = "hole_radial_deviations_mm", .type = T::kRealList, .unit = "mm",
     .meaning = "with [output]: the second disc's own radial hole position deviations, one per hole in mm (instead of [output]'s)",
     .default_value = "[output]'s"},
    {.section = "second_disc", .name = "hole_tangential_deviations_mm", .type = T::kRealList, .unit = "mm",
     .meaning = "with [output]: the second disc's own tangential hole position deviations, one per hole in mm", .default_value = "[output]'s"},
    {.section = "second_disc", .name = "bearing_radial_clearance_mm", .type = T::kReal, .unit = "mm",
     .meaning = "with [output]: the radial play of the second disc's bearing(s) in mm (instead of [bearing]'s); negative: a preload, as [bearing] radial_clearance_mm",
     .default_value = "[bearing]'s"},
    // [tolerances]: its own keys; a distribution for each key with a tolerance_stream
    {.section = "tolerances", .name = "samples", .type = T::kInteger, .unit = "", .meaning = "number of samples",
     .default_value = "1000",
     .setting = LTCA_SETTING(tolerances, samples)},
    {.section = "tolerances", .name = "seed", .type = T::kUnsigned, .unit = "", .meaning = "seed of the counter-based stream",
     .default_value = "1",
     .setting = LTCA_SETTING(tolerances, seed)},
    {.section = "tolerances", .name = "lost_motion", .type = T::kBool, .unit = "", .meaning = "also lost motion per sample",
     .default_value = "false",
     .setting = LTCA_SETTING(tolerances, lost_motion)},
    {.section = "tolerances", .name = "limits", .type = T::kTable, .unit = "",
     .meaning = "acceptance limits: { figure = max } or { figure = { min = .., max = .. } }", .default_value = ""},
    {.section = "tolerances", .name = "chains", .type = T::kTable, .unit = "",
     .meaning = "assembly dimensional chains (extreme value and Monte Carlo of the closing link)", .default_value = ""},
    {.section = "tolerances", .name = "profile_random_per_sample", .type = T::kBool, .unit = "",
     .meaning = "every sample its own random profile deviation", .default_value = "false",
     .setting = LTCA_SETTING(tolerances, profile_random_per_sample)},
    // [operation]
    {.section = "operation", .name = "input_speed_rpm", .type = T::kReal, .unit = "rpm", .meaning = "crank (input) speed in rpm",
     .default_value = "required, or motor_speed_rpm",
     .setting = LTCA_SETTING(operation, input_speed)},
    {.section = "operation", .name = "motor_speed_rpm", .type = T::kReal, .unit = "rpm",
     .meaning = "RV: the motor's (first stage's sun) speed in rpm; with [output] first_stage_teeth the cranks turn "
                "k / |1 - (1 + k) / I| times it, k = z_sun / z_spur (instead of input_speed_rpm)",
     .default_value = ""},
    {.section = "operation", .name = "oil_viscosity_pa_s", .type = T::kReal, .unit = "Pa*s",
     .meaning = "dynamic viscosity of the oil in Pa*s", .default_value = "0.03",
     .setting = LTCA_SETTING(operation, viscosity)},
    {.section = "operation", .name = "oil_kinematic_viscosity_mm2_per_s", .type = T::kReal, .unit = "mm^2/s",
     .meaning = "kinematic viscosity nu of the bearings' oil at operating temperature in mm^2/s: the bearings' modified "
                "life a_ISO L10 (ISO 281, kappa = nu / nu_1); not given: no modified life",
     .default_value = "",
     .setting = LTCA_SETTING(operation, kinematic_viscosity)},
    {.section = "operation", .name = "pressure_viscosity_per_gpa", .type = T::kReal, .unit = "1/GPa",
     .meaning = "pressure-viscosity coefficient in 1/GPa", .default_value = "10",
     .setting = LTCA_SETTING(operation, pressure_viscosity)},
    {.section = "operation", .name = "roughness_ra_cycloid_um", .type = T::kReal, .unit = "um",
     .meaning = "Ra of the cycloid flank in um", .default_value = "0.3",
     .setting = LTCA_SETTING(operation, roughness_cycloid)},
    {.section = "operation", .name = "roughness_ra_pin_um", .type = T::kReal, .unit = "um", .meaning = "Ra of the pin (or sleeve) in um",
     .default_value = "0.3",
     .setting = LTCA_SETTING(operation, roughness_pin)},
    // [friction]
    {.section = "friction", .name = "model", .type = T::kText, .unit = "", .meaning = "coulomb | jiang-mixed",
     .default_value = "\"coulomb\"", .choices = "coulomb | jiang-mixed",
     .setting = LTCA_CHOICE(friction, model, Friction::kCoulomb, Friction::kJiangMixed)},
    {.section = "friction", .name = "coefficient", .type = T::kReal, .unit = "", .meaning = "Coulomb friction coefficient mu",
     .default_value = "",
     .setting = LTCA_SETTING(friction, coefficient)},
    {.section = "friction", .name = "boundary_coefficient", .type = T::kReal, .unit = "",
     .meaning = "boundary friction coefficient f_b", .default_value = "0.1",
     .setting = LTCA_SETTING(friction, boundary_coefficient)},
    {.section = "friction", .name = "limiting_shear_modulus_mpa", .type = T::kReal, .unit = "MPa",
     .meaning = "G of Jiang eq. 23 in MPa", .default_value = "1",
     .setting = LTCA_SETTING(friction, limiting_shear_modulus)},
    {.section = "friction", .name = "power_law_exponent", .type = T::kReal, .unit = "", .meaning = "n of Jiang eq. 22-23",
     .default_value = "0.5",
     .setting = LTCA_SETTING(friction, power_law_exponent)},
    {.section = "friction", .name = "limiting_shear_stress_coefficient", .type = T::kReal, .unit = "",
     .meaning = "gamma of the limiting shear stress tau_L = tau_L0 + gamma p capping jiang-mixed's full-film shear "
                "(Bair and Winer 1979); absent: no cap",
     .default_value = "",
     .setting = LTCA_SETTING(friction, limiting_shear_coefficient)},
    {.section = "friction", .name = "limiting_shear_stress_mpa", .type = T::kReal, .unit = "MPa",
     .meaning = "tau_L0 of the limiting shear stress tau_L = tau_L0 + gamma p in MPa", .default_value = "0",
     .setting = LTCA_SETTING(friction, limiting_shear_stress)},
    {.section = "friction", .name = "sleeve_bore_radius_mm", .type = T::kReal, .unit = "mm",
     .meaning = "radius of the pin inside its sleeve in mm", .default_value = "",
     .setting = LTCA_SETTING(friction, sleeve_bore_radius)},
    {.section = "friction", .name = "sleeve_coefficient", .type = T::kReal, .unit = "", .meaning = "mu at the sleeve bore",
     .default_value = "",
     .setting = LTCA_SETTING(friction, sleeve_coefficient)},
    {.section = "friction", .name = "output_pin_coefficient", .type = T::kReal, .unit = "",
     .meaning = "stage: Coulomb mu of the output pins sliding in their holes", .default_value = "0",
     .setting = LTCA_SETTING(friction, output_pin_coefficient)},
    {.section = "friction", .name = "bearing_coefficient", .type = T::kReal, .unit = "",
     .meaning = "stage: mu of the bearings' friction moment M = mu F d / 2 (eccentric or crank bearings)",
     .default_value = "0",
     .setting = LTCA_SETTING(friction, bearing_coefficient)},
    {.section = "friction", .name = "bearing_viscous_factor", .type = T::kReal, .unit = "",
     .meaning = "stage: Palmgren's f_0 of the bearings' viscous friction moment (needs [operation] "
                "oil_kinematic_viscosity_mm2_per_s; ltca efficiency only)",
     .default_value = "0",
     .setting = LTCA_SETTING(friction, bearing_viscous_factor)},
    {.section = "friction", .name = "bearing_diameter_mm", .type = T::kReal, .unit = "mm",
     .meaning = "stage: d of the bearings' friction moment in mm; absent: [bearing] pitch_diameter_mm",
     .default_value = "",
     .setting = LTCA_SETTING(friction, bearing_diameter)},
    {.section = "friction", .name = "torque_balance", .type = T::kText, .unit = "", .meaning = "solve | bound",
     .default_value = "\"solve\"", .choices = "solve | bound",
     .setting = LTCA_CHOICE(friction, torque_balance, Balance::kSolve, Balance::kBound)},
    // [optimise] (docs/optimise.md)
    {.section = "optimise", .name = "variables", .type = T::kTable, .unit = "",
     .meaning = "design variables with bounds in their unit: real keys of [modification] and [errors], or a stage's "
                "clearances (bearing.radial_clearance_mm, output.hole_radius_mm, output.pin_radius_mm): "
                "{ \"modification.pin_radius_mm\" = [-0.03, 0.0], ... }",
     .default_value = ""},
    {.section = "optimise", .name = "objective", .type = T::kText, .unit = "",
     .meaning = "a figure ([tolerances] limits' names, power_loss_w, efficiency) or a variable's key", .default_value = "",
     .setting = LTCA_SETTING(optimise, objective), .required = true},
    {.section = "optimise", .name = "maximise", .type = T::kBool, .unit = "", .meaning = "maximise the objective instead",
     .default_value = "false",
     .setting = LTCA_SETTING(optimise, maximise)},
    {.section = "optimise", .name = "constraints", .type = T::kTable, .unit = "",
     .meaning = "limits on figures: { figure = max } or { figure = { min = .., max = .. } }", .default_value = ""},
    {.section = "optimise", .name = "global", .type = T::kText, .unit = "", .meaning = "the global search (NLopt)",
     .default_value = "\"direct\"", .choices = "direct | crs2 | isres | none",
     .setting = LTCA_CHOICE(optimise, global, Global::kDirect, Global::kCrs2, Global::kIsres, Global::kNone)},
    {.section = "optimise", .name = "local", .type = T::kText, .unit = "", .meaning = "the local polish (NLopt)",
     .default_value = "\"cobyla\"", .choices = "cobyla | bobyqa | none",
     .setting = LTCA_CHOICE(optimise, local, Local::kCobyla, Local::kBobyqa, Local::kNone)},
    {.section = "optimise", .name = "evaluations", .type = T::kInteger, .unit = "", .meaning = "the budget of evaluations",
     .default_value = "200",
     .setting = LTCA_SETTING(optimise, evaluations)},
    {.section = "optimise", .name = "global_share", .type = T::kReal, .unit = "", .meaning = "share of the budget for the global search",
     .default_value = "0.6",
     .setting = LTCA_SETTING(optimise, global_share)},
    {.section = "optimise", .name = "tolerance", .type = T::kReal, .unit = "",
     .meaning = "the local search stops at a step below this fraction of the box", .default_value = "1e-6",
     .setting = LTCA_SETTING(optimise, tolerance)},
    {.section = "optimise", .name = "seed", .type = T::kUnsigned, .unit = "", .meaning = "random numbers of crs2 and isres",
     .default_value = "1",
     .setting = LTCA_SETTING(optimise, seed)},
    {.section = "optimise", .name = "robust", .type = T::kBool, .unit = "",
     .meaning = "every design over the samples of [tolerances], figures at the percentile", .default_value = "false",
     .setting = LTCA_SETTING(optimise, robust)},
    {.section = "optimise", .name = "robust_samples", .type = T::kInteger, .unit = "", .meaning = "samples a robust design",
     .default_value = "64",
     .setting = LTCA_SETTING(optimise, robust_samples)},
    {.section = "optimise", .name = "percentile", .type = T::kReal, .unit = "",
     .meaning = "robust: the percentile each figure is taken at", .default_value = "95",
     .setting = LTCA_SETTING(optimise, percentile)},
    {.section = "optimise", .name = "confidence", .type = T::kReal, .unit = "",
     .meaning = "robust: confidence that the order statistic taken bounds the percentile (0: point estimate)", .default_value = "0.9",
     .setting = LTCA_SETTING(optimise, confidence)},
    // [inspection] (docs/export.md): what an inspector measures on the disc
    {.section = "inspection", .name = "roller_diameter_mm", .type = T::kReal, .unit = "mm",
     .meaning = "diameter of the measuring rollers of the dimension over rollers in mm (> 0; the rollers in the tooth "
                "spaces nearest to opposite)",
     .default_value = "", .setting = LTCA_SETTING(inspection, roller_diameter)},
    // [allowables] (docs/stage.md): the targets of the bearing and pitting ratings
    // [[load_spectrum]]: an array of tables, each a bin of the duty cycle (issue 50; the deck
    // reader takes each entry apart into analysis::LoadBin, spectrum.hpp)
    {.section = "load_spectrum", .name = "torque_nm", .type = T::kReal, .unit = "N*m",
     .meaning = "a bin's output torque in N*m, signed like [load] torque_nm (each [[load_spectrum]] entry)",
     .default_value = "", .required = true},
    {.section = "load_spectrum", .name = "speed_rpm", .type = T::kReal, .unit = "rpm",
     .meaning = "a bin's crank (input) speed in rpm, as [operation] input_speed_rpm (> 0)", .default_value = "",
     .required = true},
    {.section = "load_spectrum", .name = "time_share", .type = T::kReal, .unit = "",
     .meaning = "a bin's share of the operating time, in (0, 1]; the shares add to 1 within 1e-9 (not normalised)",
     .default_value = "", .required = true},
    {.section = "allowables", .name = "bearing_life_hours", .type = T::kReal, .unit = "h",
     .meaning = "required life of every bearing of the stage in hours: its load-zone life and its ISO 281 L10, and with "
                "[operation] oil_kinematic_viscosity_mm2_per_s their modified lives a_ISO L (> 0)",
     .default_value = "", .setting = LTCA_SETTING(allowables, bearing_life_hours)},
    {.section = "allowables", .name = "min_static_safety", .type = T::kReal, .unit = "",
     .meaning = "least static safety s_0 = C_0 / P_0,max of every bearing (ISO 76; > 0)", .default_value = "",
     .setting = LTCA_SETTING(allowables, min_static_safety)},
    {.section = "allowables", .name = "contact_life_hours", .type = T::kReal, .unit = "h",
     .meaning = "required pitting life of the pins and the disc's teeth in hours; S_H is rated at it (> 0)", .default_value = "",
     .setting = LTCA_SETTING(allowables, contact_life_hours)},
    {.section = "allowables", .name = "min_contact_safety", .type = T::kReal, .unit = "",
     .meaning = "least pitting safety S_H = sigma_Hlim Z_NT / sigma_H of the pins and teeth at contact_life_hours (> 0)",
     .default_value = "", .setting = LTCA_SETTING(allowables, min_contact_safety)},
    {.section = "inspection", .name = "profile_tolerance_um", .type = T::kReal, .unit = "um",
     .meaning = "full width of the profile tolerance band of the deviation chart in um (> 0; +- half about the design)",
     .default_value = "", .setting = LTCA_SETTING(inspection, profile_tolerance)},
};

#undef LTCA_FIELD
#undef LTCA_LIST
#undef LTCA_SETTING
#undef LTCA_CHOICE
#undef LTCA_OUTPUT

}  // namespace

double DeckKey::ToInternal(double value) const {
  const std::string_view u = unit;
  if (u == "um") return units::UmToMm(value);
  if (u == "deg") return units::DegToRad(value);
  if (u == "N*m") return units::NmToNmm(value);
  if (u == "rpm") return units::RpmToRadPerS(value);
  if (u == "Pa*s") return units::PaSToMPaS(value);
  if (u == "1/GPa") return units::PerGPaToPerMPa(value);
  if (u == "N*m/arcmin") return units::NmToNmm(value) / units::ArcminToRad(1.0);
  return value;
}

double DeckKey::FromInternal(double value) const {
  const std::string_view u = unit;
  if (u == "um") return units::MmToUm(value);
  if (u == "deg") return units::RadToDeg(value);
  if (u == "N*m") return units::NmmToNm(value);
  if (u == "rpm") return units::RadPerSToRpm(value);
  if (u == "Pa*s") return units::MPaSToPaS(value);
  if (u == "1/GPa") return units::PerMPaToPerGPa(value);
  if (u == "N*m/arcmin") return units::NmmPerRadToNmPerArcmin(value);
  return value;
}

std::string DeckKey::ToleranceName() const {
  // [modification] and the stage's keys carry their section: "modification_pin_radius_mm" is not
  // the pins' radius deviation, "output_pin_radius_mm" not the ring pins'.
  const std::string_view s(section);
  return s == "modification" || s == "output" || s == "bearing" ? std::string(section) + "_" + name : std::string(name);
}

double DeckKey::Reach(double internal, const geometry::PairParameters& pair) const {
  switch (limit) {
    case Limit::kRotation: return pair.pin_circle_radius * internal;
    case Limit::kTilt: return pair.face_width * std::tan(internal);
    case Limit::kLength:
    case Limit::kNone: break;
  }
  return internal;
}

void RequireSmallDeviation(double reach, std::string_view section, std::string_view key,
                           const geometry::PairParameters& pair, const std::string& shown) {
  const double limit = DeckKey::kMaxDeviationFraction * pair.pin_radius;
  if (std::isfinite(reach) && std::abs(reach) > limit) {
    throw std::invalid_argument(fmt::format(
        "[{}] {} = {}: looks like an absolute value; a modification or manufacturing error is a "
        "small change of the geometry, at most {:g} % of [pair] pin_radius_mm = {} ({:.6g} mm){} "
        "(docs/decks.md, Limits)",
        section, key, shown.empty() ? fmt::format("{}", reach) : shown, 100.0 * DeckKey::kMaxDeviationFraction,
        pair.pin_radius, limit, shown.empty() ? "" : fmt::format("; this one moves the profile by {:.6g} mm", std::abs(reach))));
  }
}

void RequireSmallDeviations(std::string_view section, std::string_view table_section, const DiscParts& parts,
                            const geometry::PairParameters& pair) {
  for (const DeckKey& k : kKeys) {
    if (k.section != table_section || k.limit == DeckKey::Limit::kNone) continue;
    const bool mm = std::string_view(k.unit) == "mm";
    if (k.real != nullptr) {
      const double v = *k.real(parts);
      RequireSmallDeviation(k.Reach(v, pair), section, k.name, pair, mm ? "" : fmt::format("{}", k.FromInternal(v)));
    } else if (k.list != nullptr) {
      const std::vector<double>& list = *k.list(parts);
      for (std::size_t j = 0; j < list.size(); ++j) {
        RequireSmallDeviation(k.Reach(list[j], pair), section, fmt::format("{}[{}]", k.name, j), pair,
                              mm ? "" : fmt::format("{}", k.FromInternal(list[j])));
      }
    }
  }
}

std::vector<std::string> Choices(const DeckKey& key) {
  std::vector<std::string> out;
  const std::string_view choices(key.choices);
  for (std::size_t from = 0; from < choices.size();) {
    const std::size_t bar = std::min(choices.find(" | ", from), choices.size());
    out.emplace_back(choices.substr(from, bar - from));
    from = bar + 3;
  }
  return out;
}

std::string ChoiceMessage(std::string_view section, const DeckKey& key, std::string_view value) {
  std::vector<std::string> quoted;
  for (const std::string& choice : Choices(key)) quoted.push_back("\"" + choice + "\"");
  std::string expected = quoted.empty() ? std::string() : quoted.back();
  if (quoted.size() > 1) {
    quoted.pop_back();
    expected = fmt::format("{} or {}", fmt::join(quoted, ", "), expected);
  }
  return fmt::format("[{}] {} = \"{}\": expected {}", section, key.name, value, expected);
}

const std::vector<DeckKey>& DeckKeys() { return kKeys; }

std::vector<std::string> DeckSections() {
  std::vector<std::string> out;
  for (const DeckKey& k : kKeys) {
    if (std::find(out.begin(), out.end(), k.section) == out.end()) out.emplace_back(k.section);
  }
  return out;
}

std::vector<std::string> SectionKeys(std::string_view section) {
  std::vector<std::string> out;
  for (const DeckKey& k : kKeys) {
    if (k.section == section) out.emplace_back(k.name);
  }
  return out;
}

const DeckKey* FindKey(std::string_view section, std::string_view name) {
  for (const DeckKey& k : kKeys) {
    if (k.section == section && k.name == name) return &k;
  }
  return nullptr;
}

std::vector<const DeckKey*> ToleranceVariableKeys() {
  std::vector<const DeckKey*> out;
  for (const DeckKey& k : kKeys) {
    if (k.tolerance_stream >= 0) out.push_back(&k);
  }
  std::sort(out.begin(), out.end(), [](const DeckKey* a, const DeckKey* b) { return a->tolerance_stream < b->tolerance_stream; });
  return out;
}

const DeckKey* FindToleranceKey(std::string_view tolerance_name) {
  for (const DeckKey* k : ToleranceVariableKeys()) {
    if (k->ToleranceName() == tolerance_name) return k;
  }
  return nullptr;
}

const char* ToString(DeckKey::Type type) {
  switch (type) {
    case DeckKey::Type::kReal: return "number";
    case DeckKey::Type::kRealList: return "list of numbers";
    case DeckKey::Type::kInteger: return "integer";
    case DeckKey::Type::kUnsigned: return "integer >= 0";
    case DeckKey::Type::kText: return "text";
    case DeckKey::Type::kBool: return "true | false";
    case DeckKey::Type::kTable: return "table";
  }
  return "?";
}

}  // namespace ltca::analysis
