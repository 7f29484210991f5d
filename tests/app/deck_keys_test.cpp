// The deck reader and the table of deck keys (analysis::DeckKeys) agree: every key of the table is
// read (a value of the wrong type is rejected with a message naming the key, and a value other
// than the deck's reaches the field the table binds it to), every key read is in the table (an
// unknown key is rejected in every section; the reader's section accessor throws
// std::logic_error for a key the table does not list, which every deck read by the tests would
// meet), every key but the tables, lists and file its section's reader takes apart has a binder,
// and the fields the table binds default to the table's default_value.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ltca/analysis/friction.hpp"
#include "ltca/analysis/allowables.hpp"
#include "ltca/analysis/inspection.hpp"
#include "ltca/analysis/keys.hpp"
#include "ltca/analysis/optimise.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/analysis/tolerance.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/contact/bearing.hpp"
#include "ltca/contact/cranks.hpp"
#include "ltca/contact/laws.hpp"
#include "ltca/contact/material.hpp"
#include "ltca/contact/output_pins.hpp"
#include "ltca/contact/pin_bending.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/discrete_profile.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "ltca/solvers/reducer.hpp"

namespace {

using ltca::analysis::DeckKey;

/// Decks of cases/ that between them have every section in a form that reads all its keys: one
/// disc, pins held at their ends and seated, two discs, [operation] and [friction], [tolerances],
/// [optimise], a stage with output pins and one with cranks.
const std::vector<std::string> kBases = {
    "liu2021_table1.toml",      "pin_bending.toml",         "pin_seats.toml",
    "rv_two_discs.toml",        "jiang2022_table2_efficiency.toml", "liu2021_tolerances.toml",
    "liu2021_optimise.toml",    "stage/cycloidal_drive.toml",       "stage/rv_two_discs_cranks.toml",
};

/// The errors the bases give with the override, "" for a base that reads it without error.
std::vector<std::string> ErrorsWith(const std::string& override_text) {
  std::vector<std::string> errors;
  for (const std::string& base : kBases) {
    try {
      ltca::app::LoadDeck(std::filesystem::path(LTCA_CASES_DIR) / base, {override_text});
      errors.emplace_back();
    } catch (const std::invalid_argument& e) {
      errors.emplace_back(e.what());
    }
  }
  return errors;
}

/// A value of the wrong type for the key, as --set writes it.
std::string WrongValue(DeckKey::Type type) {
  switch (type) {
    case DeckKey::Type::kReal:
    case DeckKey::Type::kRealList:
    case DeckKey::Type::kInteger:
    case DeckKey::Type::kUnsigned: return "\"not a number\"";
    case DeckKey::Type::kText:
    case DeckKey::Type::kBool:
    case DeckKey::Type::kTable: return "7";
  }
  return "7";
}

/// Whether some base rejects the value with a message that names `[section] key` or the key.
bool SomeBaseNames(const std::string& override_text, const std::string& key) {
  for (const std::string& error : ErrorsWith(override_text)) {
    if (error.find(key) != std::string::npos) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("app: every key of the table of deck keys is read: a value of the wrong type is rejected naming the key") {
  for (const DeckKey& k : ltca::analysis::DeckKeys()) {
    const std::string set = std::string(k.section) + "." + k.name + "=" + WrongValue(k.type);
    CAPTURE(set);
    CHECK(SomeBaseNames(set, k.name));
  }
  // [second_disc] takes the disc keys of [modification] and [errors] and reads them too.
  for (const DeckKey& k : ltca::analysis::DeckKeys()) {
    if (!k.disc) continue;
    const std::string set = std::string("second_disc.") + k.name + "=" + WrongValue(k.type);
    CAPTURE(set);
    CHECK(SomeBaseNames(set, std::string("[second_disc] ") + k.name));
  }
  // [tolerances] takes one distribution (an inline table) per key it may vary.
  for (const DeckKey* k : ltca::analysis::ToleranceVariableKeys()) {
    const std::string set = "tolerances." + k->ToleranceName() + "=7";
    CAPTURE(set);
    CHECK(SomeBaseNames(set, "[tolerances] " + k->ToleranceName()));
  }
}

TEST_CASE("app: a key not in the table of deck keys is rejected in every section") {
  for (const std::string& section : ltca::analysis::DeckSections()) {
    const std::string set = section + ".not_a_deck_key=1";
    CAPTURE(set);
    // No base takes it; those where nothing else stops the section first name it as unknown.
    int named = 0;
    for (const std::string& error : ErrorsWith(set)) {
      CAPTURE(error);
      CHECK(!error.empty());
      named += error.find("unknown key 'not_a_deck_key'") != std::string::npos ? 1 : 0;
    }
    CHECK(named >= static_cast<int>(kBases.size()) - 2);
  }
  for (const std::string& error : ErrorsWith("not_a_section.key=1")) {
    CHECK(error.find("unknown section or key 'not_a_section'") != std::string::npos);
  }
}

TEST_CASE("app: a field the table binds to a setting defaults to the table's default_value, in the internal unit") {
  ltca::analysis::CaseInfo info;
  ltca::geometry::PairParameters pair;
  ltca::geometry::ManufacturingErrors errors;
  ltca::geometry::AssemblyErrors assembly;
  ltca::contact::ContactSettings contact;
  ltca::geometry::GeometrySettings geometry;
  ltca::contact::Material material;
  ltca::analysis::LoadCase load;
  ltca::analysis::Sweep sweep;
  ltca::solvers::SolverOptions solver;
  ltca::contact::ContactKinematics kinematics = ltca::contact::ContactKinematics::kLinearised;
  std::string preset;
  ltca::analysis::StiffnessSettings stiffness;
  ltca::analysis::SecondDisc second_disc;
  ltca::analysis::ToleranceSettings tolerances;
  ltca::analysis::OperationSettings operation;
  ltca::analysis::FrictionSettings friction;
  ltca::analysis::OptimiseSettings optimise;
  ltca::analysis::InspectionSettings inspection;
  ltca::analysis::AllowablesSettings allowables;
  ltca::contact::PinSupport pin_support;
  ltca::contact::PinSeat pin_seat;
  ltca::contact::DiscBodySettings disc_body;
  ltca::solvers::ReducerSettings reducer;
  ltca::contact::OutputPins output_pins;
  ltca::contact::Cranks cranks;
  ltca::contact::BearingSettings bearing;
  const ltca::analysis::SettingsParts parts{.info = &info,
                                            .pair = &pair,
                                            .errors = &errors,
                                            .assembly = &assembly,
                                            .contact = &contact,
                                            .geometry = &geometry,
                                            .material = &material,
                                            .pin_support = &pin_support,
                                            .pin_seat = &pin_seat,
                                            .disc_body = &disc_body,
                                            .reducer = &reducer,
                                            .output_pins = &output_pins,
                                            .cranks = &cranks,
                                            .bearing = &bearing,
                                            .load = &load,
                                            .sweep = &sweep,
                                            .solver = &solver,
                                            .kinematics = &kinematics,
                                            .preset = &preset,
                                            .stiffness = &stiffness,
                                            .second_disc = &second_disc,
                                            .tolerances = &tolerances,
                                            .operation = &operation,
                                            .friction = &friction,
                                            .optimise = &optimise,
                                            .inspection = &inspection,
                                            .allowables = &allowables};
  int bound = 0, numeric_defaults = 0, choice_defaults = 0;
  for (const DeckKey& k : ltca::analysis::DeckKeys()) {
    if (k.setting == nullptr) continue;
    ++bound;
    CAPTURE(k.section);
    CAPTURE(k.name);
    const ltca::analysis::SettingField field = k.setting(parts);
    REQUIRE(!field.empty());
    // The field's kind is the key's type.
    switch (k.type) {
      case DeckKey::Type::kReal: CHECK((field.real != nullptr || field.optional_real != nullptr)); break;
      case DeckKey::Type::kInteger: CHECK((field.integer != nullptr || field.int64 != nullptr)); break;
      case DeckKey::Type::kUnsigned: CHECK(field.uint64 != nullptr); break;
      case DeckKey::Type::kBool: CHECK(field.boolean != nullptr); break;
      case DeckKey::Type::kText: CHECK((field.text != nullptr || field.choice != nullptr)); break;
      case DeckKey::Type::kRealList:
      case DeckKey::Type::kTable: FAIL("a list or table bound to a setting"); break;
    }
    const std::vector<std::string> choices = ltca::analysis::Choices(k);
    if (field.choice != nullptr) {
      // One value per choice, each a different one.
      REQUIRE(field.choice_count == choices.size());
      REQUIRE(!choices.empty());
      for (std::size_t c = 0; c < choices.size(); ++c) {
        std::vector<unsigned char> scratch(64);  // any enum field fits
        field.choose(scratch.data(), c);
        CHECK(field.chosen(scratch.data()) == c);
      }
      // Its default: the default_value's choice.
      const std::string quoted = k.default_value;
      if (quoted.size() > 2) {
        const auto it = std::find(choices.begin(), choices.end(), quoted.substr(1, quoted.size() - 2));
        REQUIRE(it != choices.end());
        CHECK(field.chosen(field.choice) == static_cast<std::size_t>(it - choices.begin()));
        ++choice_defaults;
      }
      continue;
    }
    if (field.text != nullptr) {
      const std::string quoted = k.default_value;
      CHECK(*field.text == (quoted.size() >= 2 ? quoted.substr(1, quoted.size() - 2) : std::string()));
      continue;
    }
    if (field.boolean != nullptr) {
      CHECK(std::string(*field.boolean ? "true" : "false") == k.default_value);
      continue;
    }
    if (k.required) {
      CHECK(std::strlen(k.default_value) == 0);  // a required key has no default
      continue;
    }
    if (field.optional_real != nullptr) {
      CHECK(!field.optional_real->has_value());  // absent unless given
      CHECK(std::strlen(k.default_value) == 0);
      continue;
    }
    // A default that names another key of the section: that key's field.
    if (const DeckKey* named = ltca::analysis::FindKey(k.section, k.default_value)) {
      REQUIRE((named->setting != nullptr));
      const ltca::analysis::SettingField from = named->setting(parts);
      if (field.real != nullptr) CHECK(*field.real == *from.real);
      else CHECK(*field.integer == *from.integer);
      continue;
    }
    // A number: the field's initial value, bit for bit (a key not given keeps it).
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(k.default_value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != std::strlen(k.default_value)) continue;  // "" or a rule in words
    ++numeric_defaults;
    if (field.real != nullptr) CHECK(*field.real == k.ToInternal(value));
    else if (field.integer != nullptr) CHECK(*field.integer == static_cast<int>(value));
    else if (field.int64 != nullptr) CHECK(*field.int64 == static_cast<std::int64_t>(value));
    else CHECK(*field.uint64 == static_cast<std::uint64_t>(value));
  }
  CHECK(bound >= 80);
  CHECK(numeric_defaults >= 20);
  CHECK(choice_defaults >= 15);
}

namespace {

/// The keys no binder reads: the tables and lists their section's reader takes apart, and the file
/// of a measured trace. Every other key of the table has a binder (DeckKey::setting, or ::real /
/// ::list for the numbers of [modification] and [errors]).
const std::vector<std::string> kTakenApart = {
    "errors.profile_measured_csv",       "output.hole_radial_deviations_mm", "output.hole_tangential_deviations_mm", "output.first_stage_teeth",
    "output.eccentric_positions_mm",
    "tolerances.limits",                 "tolerances.chains",                "optimise.variables",
    "optimise.constraints",
    // [[load_spectrum]]: each entry read into an analysis::LoadBin (tests/app/spectrum_test.cpp
    // shows every key reaching its bin)
    "load_spectrum.torque_nm",           "load_spectrum.speed_rpm",          "load_spectrum.time_share",
    // [second_disc]'s own stage elements, read into solvers::ReducerSettings (tests/app/stage_as_built_test.cpp
    // shows each reaching its field)
    "second_disc.hole_radial_deviations_mm", "second_disc.hole_tangential_deviations_mm",
    "second_disc.bearing_radial_clearance_mm",
    // read into [operation]'s crank speed through the first stage (tests/app/stage_as_built_test.cpp)
    "operation.motor_speed_rpm",
};

/// Where the deck's keys went: its settings, and a disc's parts (the first or the second).
ltca::analysis::SettingsParts PartsOf(ltca::app::Deck& d) {
  ltca::analysis::SettingsParts p{.info = &d.info,
                                  .pair = &d.pair,
                                  .errors = &d.errors,
                                  .assembly = &d.assembly,
                                  .contact = &d.contact,
                                  .geometry = &d.geometry,
                                  .pin_seat = &d.contact.seat,
                                  .disc_body = &d.disc,
                                  .sweep = &d.sweep,
                                  .solver = &d.solver,
                                  .kinematics = &d.kinematics,
                                  .stiffness = &d.stiffness,
                                  .inspection = &d.inspection,
                                  .allowables = &d.allowables};
  if (d.material) p.material = &*d.material;
  if (d.pins) p.pin_support = &*d.pins;
  if (d.reducer) {
    p.reducer = &*d.reducer;
    p.bearing = &d.reducer->bearing;
    if (d.reducer->kind == ltca::solvers::OutputKind::kPins) p.output_pins = &d.reducer->pins;
    else p.cranks = &d.reducer->cranks;
  }
  if (d.load) p.load = &*d.load;
  if (d.second_disc) p.second_disc = &*d.second_disc;
  if (d.tolerances) p.tolerances = &*d.tolerances;
  if (d.operation) p.operation = &*d.operation;
  if (d.friction) p.friction = &*d.friction;
  if (d.optimise) p.optimise = &*d.optimise;
  return p;
}

/// A disc's parts of the deck: the first disc's, or the second's.
ltca::analysis::DiscParts DiscOf(ltca::app::Deck& d, bool second) {
  if (second) return {&d.second_disc->modification, &d.second_disc->errors, &d.second_disc->assembly};
  return {&d.modification, &d.errors, &d.assembly};
}

/// The value a key's field holds, as text (a choice by its position), or nullopt when the deck
/// has no such part.
std::optional<std::string> ValueOf(const DeckKey& k, ltca::app::Deck& d, bool second) {
  if (second && !d.second_disc) return std::nullopt;
  if (k.real != nullptr) return fmt::format("{}", *k.real(DiscOf(d, second)));
  if (k.list != nullptr) return fmt::format("{}", fmt::join(*k.list(DiscOf(d, second)), ","));
  ltca::analysis::SettingsParts parts = PartsOf(d);
  if (second) parts = {.errors = &d.second_disc->errors, .assembly = &d.second_disc->assembly};
  const ltca::analysis::SettingField f = k.setting(parts);
  if (f.empty()) return std::nullopt;
  if (f.real != nullptr) return fmt::format("{}", *f.real);
  if (f.optional_real != nullptr) return f.optional_real->has_value() ? fmt::format("{}", **f.optional_real) : "none";
  if (f.integer != nullptr) return fmt::format("{}", *f.integer);
  if (f.int64 != nullptr) return fmt::format("{}", *f.int64);
  if (f.uint64 != nullptr) return fmt::format("{}", *f.uint64);
  if (f.boolean != nullptr) return fmt::format("{}", *f.boolean);
  if (f.text != nullptr) return *f.text;
  return fmt::format("choice {}", f.chosen(f.choice));
}

/// Values to try for a key, as --set writes them: the other choices, the other truth value, or
/// numbers near the deck's and some of every scale.
std::vector<std::string> Candidates(const DeckKey& k, const std::string& current, int pins) {
  std::vector<std::string> out;
  if (k.type == DeckKey::Type::kRealList) {  // one value per pin
    for (const char* v : {"0.001", "-0.002"}) {
      out.push_back("[" + fmt::format("{}", fmt::join(std::vector<std::string>(static_cast<std::size_t>(pins), v), ", ")) + "]");
    }
    return out;
  }
  const std::vector<std::string> choices = ltca::analysis::Choices(k);
  for (const std::string& c : choices) out.push_back("\"" + c + "\"");
  if (!choices.empty()) return out;
  switch (k.type) {
    case DeckKey::Type::kBool: return {"true", "false"};
    case DeckKey::Type::kText:
      return {"\"max_contact_stress_mpa\"", "\"mean_te_arcsec\"", "\"LN_COBYLA\"", "\"another text\""};
    case DeckKey::Type::kInteger:
    case DeckKey::Type::kUnsigned:
      for (const char* v : {"5", "7", "3", "9", "11", "13", "61", "101", "400", "1000", "1"}) out.emplace_back(v);
      return out;
    default: break;
  }
  double base = 0.0;
  try {
    base = k.FromInternal(std::stod(current));
  } catch (const std::exception&) {
    base = 0.0;
  }
  if (base != 0.0 && std::isfinite(base)) {
    for (const double f : {1.01, 0.99, 1.2, 0.8}) out.push_back(fmt::format("{}", base * f));
  }
  for (const char* v : {"0.001", "-0.001", "0.002", "0.01", "0.1", "0.3", "0.5", "0.9", "1", "2", "5", "10", "30", "100",
                        "1000", "2e5", "1e6", "1e-5"}) {
    out.emplace_back(v);
  }
  return out;
}

/// The first base and value with which `--set section.key=value` reads and changes the key's field
/// from the base deck's; "" when none does.
std::string ReachesField(const DeckKey& k, const std::string& section, bool second) {
  std::vector<std::string> bases = kBases;
  bases.emplace_back("liu2021_robust.toml");
  for (const std::string& base : bases) {
    const std::filesystem::path path = std::filesystem::path(LTCA_CASES_DIR) / base;
    ltca::app::Deck plain = ltca::app::LoadDeck(path);
    const std::optional<std::string> before = ValueOf(k, plain, second);
    if (!before) continue;  // the base has no such part
    for (const std::string& value : Candidates(k, *before, plain.pair.pin_count)) {
      ltca::app::Deck set;
      try {
        set = ltca::app::LoadDeck(path, {section + "." + k.name + "=" + value});
      } catch (const std::invalid_argument&) {
        continue;
      }
      const std::optional<std::string> after = ValueOf(k, set, second);
      if (after && after != before) return base + ": " + value + " -> " + *after;
    }
  }
  return "";
}

/// Keys whose other value a rule ties to other keys (a kind and the keys it needs, a pair's counts,
/// limits that need lost motion): the base, the overrides, and the value the field then holds.
struct Tied {
  std::string key, base;
  std::vector<std::string> overrides;
  std::string expected;
};
const std::vector<Tied> kTied = {
    {"pair.pin_count", "liu2021_table1.toml", {"pair.pin_count=41", "pair.tooth_count=40"}, "41"},
    {"pair.tooth_count", "liu2021_table1.toml", {"pair.pin_count=41", "pair.tooth_count=40"}, "40"},
    {"contact.stiffness_n_per_mm2", "liu2021_table1.toml", {"contact.law=\"linear\"", "contact.stiffness_n_per_mm2=2e5"}, "200000"},
    {"pins.seat", "liu2021_table1.toml", {"pins.seat=\"linear\"", "pins.seat_stiffness_n_per_mm2=1e5"}, "choice 1"},
    {"pins.seat_stiffness_n_per_mm2", "liu2021_table1.toml", {"pins.seat=\"linear\"", "pins.seat_stiffness_n_per_mm2=1e5"}, "100000"},
    {"output.kind", "liu2021_table1.toml",
     {"output.kind=\"cranks\"", "output.count=3", "output.circle_radius_mm=35", "output.shaft_stiffness_n_per_mm=1e5"}, "choice 1"},
    // Crankshafts as beams (issue 49): the diameter, the span and both eccentrics together, two discs.
    {"output.shaft_diameter_mm", "liu2021_table1.toml", {"output.kind=\"cranks\"", "output.count=3", "output.circle_radius_mm=35", "bearing.kind=\"linear\"",
      "bearing.radial_stiffness_n_per_mm=3e5", "second_disc.indexing_deviation_mm=0", "output.shaft_diameter_mm=20",
      "output.shaft_span_mm=40", "output.eccentric_positions_mm=[15, 27]", "output.support_stiffness_n_per_mm=5e5"}, "20"},
    {"output.shaft_span_mm", "liu2021_table1.toml", {"output.kind=\"cranks\"", "output.count=3", "output.circle_radius_mm=35", "bearing.kind=\"linear\"",
      "bearing.radial_stiffness_n_per_mm=3e5", "second_disc.indexing_deviation_mm=0", "output.shaft_diameter_mm=20",
      "output.shaft_span_mm=40", "output.eccentric_positions_mm=[15, 27]", "output.support_stiffness_n_per_mm=5e5"}, "40"},
    {"output.support_stiffness_n_per_mm", "liu2021_table1.toml", {"output.kind=\"cranks\"", "output.count=3", "output.circle_radius_mm=35", "bearing.kind=\"linear\"",
      "bearing.radial_stiffness_n_per_mm=3e5", "second_disc.indexing_deviation_mm=0", "output.shaft_diameter_mm=20",
      "output.shaft_span_mm=40", "output.eccentric_positions_mm=[15, 27]", "output.support_stiffness_n_per_mm=5e5"}, "500000"},
    {"bearing.kind", "liu2021_table1.toml",
     {"output.kind=\"pins\"", "output.count=8", "output.circle_radius_mm=40", "output.pin_radius_mm=5", "output.hole_radius_mm=6.32",
      "bearing.kind=\"linear\"", "bearing.radial_stiffness_n_per_mm=1e6"},
     "choice 1"},
    {"bearing.radial_stiffness_n_per_mm", "liu2021_table1.toml",
     {"output.kind=\"pins\"", "output.count=8", "output.circle_radius_mm=40", "output.pin_radius_mm=5", "output.hole_radius_mm=6.32",
      "bearing.kind=\"linear\"", "bearing.radial_stiffness_n_per_mm=1e6"},
     "1000000"},
    {"stiffness.rigidity", "liu2021_table1.toml", {"stiffness.rigidity=\"tangent\"", "stiffness.tangent_torque_nm=10"}, "choice 1"},
    {"tolerances.lost_motion", "liu2021_tolerances.toml",
     {"tolerances.lost_motion=false", "tolerances.limits={ pp_te_arcsec = { max = 8.0 } }"}, "false"},
    {"tolerances.profile_random_per_sample", "liu2021_tolerances.toml",
     {"errors.profile_random_zone_um=3", "tolerances.profile_random_per_sample=true"}, "true"},
    {"friction.model", "jiang2022_table2_efficiency.toml", {"friction.model=\"coulomb\"", "friction.coefficient=0.05"}, "choice 0"},
    {"friction.output_pin_coefficient", "stage/cycloidal_drive.toml",
     {"friction.coefficient=0", "friction.output_pin_coefficient=0.05"}, "0.05"},
    {"friction.bearing_coefficient", "stage/cycloidal_drive.toml",
     {"friction.coefficient=0", "friction.bearing_coefficient=0.002"}, "0.002"},
    {"friction.bearing_viscous_factor", "stage/cycloidal_drive.toml",
     {"friction.coefficient=0", "friction.bearing_viscous_factor=4"}, "4"},
    {"friction.limiting_shear_stress_mpa", "jiang2022_table2_efficiency.toml",
     {"friction.limiting_shear_stress_coefficient=0.06", "friction.limiting_shear_stress_mpa=2"}, "2"},
    {"disc.body", "liu2021_table1.toml", {"disc.body=\"elastic\"", "disc.bore_radius_mm=22"}, "choice 1"},
    {"disc.bore_radius_mm", "liu2021_table1.toml", {"disc.body=\"elastic\"", "disc.bore_radius_mm=22"}, "22"},
    {"disc.plane", "liu2021_table1.toml", {"disc.body=\"elastic\"", "disc.bore_radius_mm=22", "disc.plane=\"stress\""}, "choice 1"},
    {"disc.element_size_mm", "liu2021_table1.toml", {"disc.body=\"elastic\"", "disc.bore_radius_mm=22", "disc.element_size_mm=2"}, "2"},
    {"disc.grid_points_per_space", "liu2021_table1.toml",
     {"disc.body=\"elastic\"", "disc.bore_radius_mm=22", "disc.grid_points_per_space=16"}, "16"},
    {"disc.patch_half_width_mm", "liu2021_table1.toml",
     {"disc.body=\"elastic\"", "disc.bore_radius_mm=22", "disc.patch_half_width_mm=0.1"}, "0.1"},
};

}  // namespace

TEST_CASE("app: every key of the table reaches its field, and only the tables and lists taken apart have no binder") {
  int reached = 0;
  for (const DeckKey& k : ltca::analysis::DeckKeys()) {
    const std::string key = std::string(k.section) + "." + k.name;
    CAPTURE(key);
    const bool bound = k.setting != nullptr || k.real != nullptr || k.list != nullptr;
    const bool taken_apart = std::find(kTakenApart.begin(), kTakenApart.end(), key) != kTakenApart.end();
    CHECK(bound != taken_apart);
    if (!bound) continue;
    if (key == "solver.preset") {  // no field of its own: the preset's values (Liu's 1 % torque tolerance)
      const ltca::app::Deck d = ltca::app::LoadDeck(std::filesystem::path(LTCA_CASES_DIR) / "liu2021_table1.toml",
                                                    {"solver.preset=liu2021"});
      CHECK(d.solver.torque_tolerance == 1e-2);
      ++reached;
      continue;
    }
    if (const auto tied = std::find_if(kTied.begin(), kTied.end(), [&](const Tied& t) { return t.key == key; });
        tied != kTied.end()) {
      const std::filesystem::path path = std::filesystem::path(LTCA_CASES_DIR) / tied->base;
      ltca::app::Deck plain = ltca::app::LoadDeck(path);
      ltca::app::Deck set = ltca::app::LoadDeck(path, tied->overrides);
      CHECK(ValueOf(k, plain, false) != tied->expected);
      CHECK(ValueOf(k, set, false) == tied->expected);
      ++reached;
      continue;
    }
    const std::string how = ReachesField(k, k.section, false);
    CAPTURE(how);
    CHECK(!how.empty());
    reached += how.empty() ? 0 : 1;
    if (k.disc) {  // and the second disc's own
      const std::string second = ReachesField(k, "second_disc", true);
      CAPTURE(second);
      CHECK(!second.empty());
    }
  }
  CHECK(reached == static_cast<int>(ltca::analysis::DeckKeys().size() - kTakenApart.size()));
}
