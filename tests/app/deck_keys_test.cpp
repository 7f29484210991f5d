// The deck reader and the table of deck keys (analysis::DeckKeys) agree: every key of the table is
// read (a value of the wrong type is rejected with a message naming the key), every key read is in
// the table (an unknown key is rejected in every section; the reader's section accessor throws
// std::logic_error for a key the table does not list, which every deck read by the tests would
// meet), and the numbers the table binds to a setting default to the table's default_value.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/analysis/friction.hpp"
#include "ltca/analysis/keys.hpp"
#include "ltca/analysis/optimise.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/contact/bearing.hpp"
#include "ltca/contact/cranks.hpp"
#include "ltca/contact/laws.hpp"
#include "ltca/contact/material.hpp"
#include "ltca/contact/output_pins.hpp"
#include "ltca/contact/pin_bending.hpp"
#include "ltca/geometry/discrete_profile.hpp"
#include "ltca/solvers/load_solver.hpp"

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

TEST_CASE("app: a number the table binds to a setting defaults to the table's default_value, in the internal unit") {
  ltca::geometry::PairParameters pair;
  ltca::contact::ContactSettings contact;
  ltca::geometry::GeometrySettings geometry;
  ltca::contact::Material material;
  ltca::analysis::Sweep sweep;
  ltca::solvers::SolverOptions solver;
  ltca::analysis::StiffnessSettings stiffness;
  ltca::analysis::OperationSettings operation;
  ltca::analysis::FrictionSettings friction;
  ltca::analysis::OptimiseSettings optimise;
  ltca::contact::PinSupport pin_support;
  ltca::contact::PinSeat pin_seat;
  ltca::contact::OutputPins output_pins;
  ltca::contact::Cranks cranks;
  ltca::contact::BearingSettings bearing;
  const ltca::analysis::SettingsParts parts{.pair = &pair,
                                            .contact = &contact,
                                            .geometry = &geometry,
                                            .material = &material,
                                            .pin_support = &pin_support,
                                            .pin_seat = &pin_seat,
                                            .output_pins = &output_pins,
                                            .cranks = &cranks,
                                            .bearing = &bearing,
                                            .sweep = &sweep,
                                            .solver = &solver,
                                            .stiffness = &stiffness,
                                            .operation = &operation,
                                            .friction = &friction,
                                            .optimise = &optimise};
  int bound = 0, numeric_defaults = 0;
  for (const DeckKey& k : ltca::analysis::DeckKeys()) {
    if (k.setting == nullptr) continue;
    ++bound;
    CAPTURE(k.section);
    CAPTURE(k.name);
    CHECK((k.type == DeckKey::Type::kReal || k.type == DeckKey::Type::kInteger));
    const ltca::analysis::SettingField field = k.setting(parts);
    CHECK((field.integer != nullptr) == (k.type == DeckKey::Type::kInteger));
    CHECK((field.real != nullptr) == (k.type == DeckKey::Type::kReal));
    if (k.required) {
      CHECK(std::strlen(k.default_value) == 0);  // a required key has no default
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
    else CHECK(*field.integer == static_cast<int>(value));
  }
  CHECK(bound >= 40);
  CHECK(numeric_defaults >= 15);
}
