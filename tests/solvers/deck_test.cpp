// Case decks: every deck in cases/ loads; each class of bad input is rejected with an error that
// names the key, the value and what is expected.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <doctest/doctest.h>

#include "ltca/geometry/units.hpp"
#include "ltca/solvers/deck.hpp"

using ltca::solvers::ParseDeck;

namespace {

const char* kGood = R"(
[case]
title = "test"
source = "unit test"
[pair]
pin_count = 40
tooth_count = 39
pin_radius_mm = 3
pin_circle_radius_mm = 64.0
eccentricity_mm = 1.3
face_width_mm = 12.0
[material]
young_modulus_mpa = 206000.0
poisson_ratio = 0.3
[load]
torque_nm = 206.0
)";

std::string ErrorOf(const std::string& text) {
  try {
    ParseDeck(text, "t.toml");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  REQUIRE(pos != std::string::npos);
  return text.replace(pos, from.size(), to);
}

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

}  // namespace

TEST_CASE("solvers: every deck in cases/ loads and names its source") {
  int count = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(LTCA_CASES_DIR)) {
    if (entry.path().extension() != ".toml") continue;
    CAPTURE(entry.path().string());
    const auto deck = ltca::solvers::LoadDeck(entry.path());
    CHECK(!deck.info.title.empty());
    CHECK(!deck.info.source.empty());
    ++count;
  }
  CHECK(count >= 5);
}

TEST_CASE("solvers: the built-in default deck is cases/liu2021_table1.toml") {
  std::ifstream in(std::string(LTCA_CASES_DIR) + "/liu2021_table1.toml");
  std::ostringstream text;
  text << in.rdbuf();
  CHECK(ltca::solvers::DefaultDeckText() == text.str());
  const auto deck = ltca::solvers::DefaultDeck();
  CHECK(deck.pair.pin_count == 40);
  CHECK(deck.pair.tooth_count == 39);
}

TEST_CASE("solvers: deck values are converted to the internal units once") {
  auto text = std::string(kGood) + "[modification]\nrotation_deg = 0.01\npin_radius_mm = 0.002\n"
                                   "[sweep]\ncrank_start_deg = 1.0\ncrank_end_deg = 2.0\npositions = 3\n";
  const auto deck = ParseDeck(text, "t.toml");
  CHECK(deck.RequireLoad().torque == doctest::Approx(206000.0));   // N*m -> N*mm
  CHECK(deck.pair.pin_radius == 3.0);                               // integer accepted as a length
  CHECK(deck.modification.rotation == doctest::Approx(0.01 * ltca::units::kPi / 180));
  CHECK(deck.modification.pin_radius == 0.002);
  CHECK(deck.RequireMaterial().pin_young_modulus == 206000.0);     // pin defaults to the gear
  const auto cranks = deck.sweep.CrankAngles();
  REQUIRE(cranks.size() == 3);
  CHECK(cranks[1] == doctest::Approx(1.5 * ltca::units::kPi / 180));
  // Without [sweep]: one mesh period (360 / z_p = 9 deg) in 91 positions (0.1 deg steps).
  const auto plain = ParseDeck(kGood, "t.toml");
  CHECK(plain.sweep.positions == 91);
  CHECK(plain.sweep.crank_end == doctest::Approx(9.0 * ltca::units::kPi / 180));
}

TEST_CASE("solvers: bad decks name the key, the value and what is expected") {
  const std::string good = kGood;
  CHECK(ErrorOf(good) == "");
  // Unknown key, unknown section, missing key, missing section, wrong type.
  CHECK(Contains(ErrorOf(Replace(good, "pin_radius_mm = 3", "pin_radius = 3")), "[pair] unknown key 'pin_radius'"));
  CHECK(Contains(ErrorOf(good + "[solverz]\nname = \"x\"\n"), "unknown section or key 'solverz'"));
  CHECK(Contains(ErrorOf(Replace(good, "eccentricity_mm = 1.3", "")), "[pair] missing required key 'eccentricity_mm'"));
  CHECK(Contains(ErrorOf(Replace(good, "[case]\ntitle = \"test\"", "[casex]\ntitle = \"test\"")), "casex"));
  CHECK(Contains(ErrorOf(Replace(good, "pin_count = 40", "pin_count = 40.5")), "[pair] pin_count = 40.5: expected an integer"));
  CHECK(Contains(ErrorOf(Replace(good, "face_width_mm = 12.0", "face_width_mm = \"12\"")), "[pair] face_width_mm"));
  // Wrong sign.
  CHECK(Contains(ErrorOf(Replace(good, "torque_nm = 206.0", "torque_nm = -206.0")), "[load] torque_nm = -206"));
  CHECK(Contains(ErrorOf(Replace(good, "pin_radius_mm = 3", "pin_radius_mm = -3")), "[pair] pin_radius_mm = -3"));
  CHECK(Contains(ErrorOf(Replace(good, "young_modulus_mpa = 206000.0", "young_modulus_mpa = 0.0")), "[material] young_modulus_mpa = 0"));
  CHECK(Contains(ErrorOf(Replace(good, "poisson_ratio = 0.3", "poisson_ratio = 0.5")), "[material] poisson_ratio = 0.5"));
  CHECK(Contains(ErrorOf(good + "[sweep]\ncrank_start_deg = 5.0\ncrank_end_deg = 1.0\n"), "[sweep] crank_end_deg = 1"));
  CHECK(Contains(ErrorOf(good + "[sweep]\npositions = 0\n"), "[sweep] positions = 0"));
  // Impossible geometry: tooth difference zero, K1 >= 1, overlapping pins, undercut profile.
  CHECK(Contains(ErrorOf(Replace(good, "tooth_count = 39", "tooth_count = 40")), "[pair] tooth_count = 40"));
  CHECK(Contains(ErrorOf(Replace(good, "eccentricity_mm = 1.3", "eccentricity_mm = 1.7")), "curtate coefficient"));
  CHECK(Contains(ErrorOf(Replace(good, "pin_radius_mm = 3", "pin_radius_mm = 5.5")), "pins overlap"));
  CHECK(Contains(ErrorOf(Replace(good, "pin_radius_mm = 3", "pin_radius_mm = 4.8")), "undercut"));
  CHECK(Contains(ErrorOf(good + "[modification]\npin_circle_radius_mm = -20.0\n"), "[modification] pin_circle_radius_mm = -20"));
  // TOML syntax errors carry the deck name.
  CHECK(Contains(ErrorOf("[pair\n"), "deck 't.toml'"));
  // Every message starts with the deck's name.
  CHECK(Contains(ErrorOf(Replace(good, "pin_radius_mm = 3", "pin_radius_mm = -3")), "deck 't.toml': "));
}

TEST_CASE("solvers: a geometry-only deck has no load, and load commands say so") {
  const auto deck = ParseDeck(Replace(kGood, "[load]\ntorque_nm = 206.0", ""), "t.toml");
  CHECK(!deck.load);
  CHECK_THROWS_WITH_AS(deck.RequireLoad(), doctest::Contains("missing required section [load]"), std::invalid_argument);
}
