// The `ltca` command line, run in-process: outputs, keys and exit codes.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/deck.hpp"

namespace {

struct Outcome {
  int code;
  std::string out, err;
};

Outcome RunCli(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = ltca::cli::Run(args, out, err);
  return {code, out.str(), err.str()};
}

std::filesystem::path TempFile(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("ltca_cli_test_" + name);
  std::ofstream(path) << text;
  return path;
}

std::string Case(const std::string& rel) { return std::string(LTCA_CASES_DIR) + "/" + rel; }

}  // namespace

TEST_CASE("cli: ltca geometry --json writes the keys of the issue with the library's values") {
  for (const std::string& deck_path : {Case("liu2021_table1.toml"), Case("chen2008/d2.toml"), Case("chen2008/dm1.toml")}) {
    CAPTURE(deck_path);
    const auto r = RunCli({"geometry", deck_path, "--json", "-"});
    REQUIRE(r.code == 0);
    const auto json = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    const auto deck = ltca::solvers::LoadDeck(deck_path);
    const ltca::geometry::CycloidProfile profile(deck.pair, deck.modification);
    const ltca::geometry::Kinematics kin(deck.pair);
    using ltca::units::RadToDeg;
    CHECK(json.at("k1").get<double>() == profile.k1());
    CHECK(json.at("phi_max_deg").get<double>() == RadToDeg(profile.phi_max()));
    CHECK(json.at("contact_ratio").get<double>() == profile.contact_ratio());
    CHECK(json.at("theta_max_deg").get<double>() == RadToDeg(profile.theta_max()));
    CHECK(json.at("alpha_max_deg").get<double>() == RadToDeg(profile.alpha_max()));
    CHECK(json.at("min_curvature_radius_mm").get<double>() == profile.min_curvature_radius());
    CHECK(json.at("mesh_period_deg").get<double>() == doctest::Approx(360.0 / deck.pair.pin_count));
    CHECK(json.contains("undercut_margin_mm"));
  }
}

TEST_CASE("cli: ltca with no argument runs the built-in Liu 2021 Table 1 case") {
  const auto r = RunCli({});
  CHECK(r.code == 0);
  CHECK(r.out.find("Liu 2021 Table 1") != std::string::npos);
  CHECK(r.out.find("54.3409 deg") != std::string::npos);  // alpha_max = arcsin(0.8125)
  CHECK(r.out.find("mean TE") != std::string::npos);      // and the loaded sweep
}

TEST_CASE("cli: --csv writes the whole profile and --svg draws every pin") {
  const auto csv = std::filesystem::temp_directory_path() / "ltca_cli_test_profile.csv";
  const auto svg = std::filesystem::temp_directory_path() / "ltca_cli_test_pair.svg";
  const auto r = RunCli({"geometry", Case("chen2008/d2.toml"), "--csv", csv.string(), "--svg", svg.string(), "--crank-deg", "3"});
  REQUIRE(r.code == 0);
  std::ifstream in(csv);
  std::string line;
  int rows = 0;
  std::getline(in, line);
  CHECK(line == "tooth_space,u_deg,x_mm,y_mm,normal_x,normal_y,curvature_radius_mm");
  while (std::getline(in, line)) ++rows;
  CHECK(rows == 22 * 121);  // z_c tooth spaces of 2 * 60 + 1 samples
  std::ifstream svg_in(svg);
  const std::string drawing((std::istreambuf_iterator<char>(svg_in)), std::istreambuf_iterator<char>());
  std::size_t circles = 0;
  for (auto pos = drawing.find("<circle"); pos != std::string::npos; pos = drawing.find("<circle", pos + 1)) ++circles;
  CHECK(circles == 24 + 2);  // pins, pin circle, cycloid centre
}

TEST_CASE("cli: each class of bad input gives its named error and a non-zero exit") {
  const auto deck = [](const std::string& pair_lines) {
    return "[case]\ntitle = \"bad\"\n[pair]\n" + pair_lines + "\n";
  };
  const std::string base = "pin_count = 40\ntooth_count = 39\npin_circle_radius_mm = 64.0\neccentricity_mm = 1.3\nface_width_mm = 12.0\n";
  struct Bad {
    std::string name, text, expected;
  };
  const Bad bads[] = {
      {"missing_key", deck(base), "missing required key 'pin_radius_mm'"},
      {"unknown_key", deck(base + "pin_radius_mm = 3.0\ncolour = 1\n"), "unknown key 'colour'"},
      {"wrong_sign", deck(base + "pin_radius_mm = -3.0\n"), "pin_radius_mm = -3"},
      {"undercut", deck(base + "pin_radius_mm = 4.8\n"), "undercut"},
      {"overlap", deck(base + "pin_radius_mm = 5.5\n"), "pins overlap"},
      {"zero_difference", deck("pin_count = 40\ntooth_count = 40\npin_circle_radius_mm = 64.0\neccentricity_mm = 1.3\nface_width_mm = 12.0\npin_radius_mm = 3.0"), "tooth_count = 40"},
  };
  for (const Bad& bad : bads) {
    CAPTURE(bad.name);
    const auto r = RunCli({"geometry", TempFile(bad.name + ".toml", bad.text).string()});
    CHECK(r.code != 0);
    CHECK(r.err.find(bad.expected) != std::string::npos);
    CHECK(r.err.find("ltca: error: deck '") != std::string::npos);
  }
  CHECK(RunCli({"geometry", "/no/such/deck.toml"}).code != 0);
  CHECK(RunCli({"geometry", "--no-such-flag"}).code != 0);
  CHECK(RunCli({"frobnicate"}).code != 0);
}

TEST_CASE("cli: --help describes the commands and the geometry outputs") {
  auto r = RunCli({"--help"});
  CHECK(r.code == 0);
  CHECK(r.out.find("geometry") != std::string::npos);
  r = RunCli({"geometry", "--help"});
  CHECK(r.code == 0);
  for (const char* word : {"--json", "--csv", "--svg", "--crank-deg", "phi_max_deg", "mesh_period_deg"}) {
    CHECK(r.out.find(word) != std::string::npos);
  }
}

TEST_CASE("cli: ltca backlash writes mean and peak-to-peak backlash and per-position rows") {
  // Liu section 5.2 base modification: the first-order closed form 2 [dR_rp - dR_p sqrt(1 - K1^2)]
  // / (e z_c) gives 48.1 arcsec; the mean of the exact TCA is within 1 % of it.
  const auto r = RunCli({"backlash", Case("liu2021_sec52_base.toml"), "--json", "-"});
  REQUIRE(r.code == 0);
  const auto json = nlohmann::json::parse(r.out.substr(r.out.find('{')));
  const double k1 = 40 * 1.3 / (64 - 0.017);
  const double closed = 2 * (-0.004 + 0.017 * std::sqrt(1 - k1 * k1)) / (1.3 * 39) * 180 / 3.14159265358979 * 3600;
  CHECK(json.at("summary").at("mean_backlash_arcsec").get<double>() == doctest::Approx(closed).epsilon(0.01));
  CHECK(json.at("summary").contains("pp_backlash_arcsec"));
  REQUIRE(json.at("positions").size() == 91);
  const auto& first = json.at("positions").at(0);
  for (const char* key : {"crank_deg", "theta_c1_arcsec", "theta_c2_arcsec", "backlash_arcsec", "first_contact_pin"}) {
    CHECK(first.contains(key));
  }
  CHECK(first.at("clearance_um").size() == 40);
}

TEST_CASE("cli: ltca backlash reports interference as an error naming the pins") {
  const std::string deck = std::string(
      "[case]\ntitle = \"interfering\"\n[pair]\npin_count = 40\ntooth_count = 39\npin_radius_mm = 3.0\n"
      "pin_circle_radius_mm = 64.0\neccentricity_mm = 1.3\nface_width_mm = 12.0\n"
      "[modification]\npin_radius_mm = -0.005\n");
  const auto r = RunCli({"backlash", TempFile("interference.toml", deck).string()});
  CHECK(r.code != 0);
  CHECK(r.err.find("interference") != std::string::npos);
  CHECK(r.err.find("pin 1 by 5") != std::string::npos);
}

TEST_CASE("cli: ltca mesh prints every pin with clearance and arm") {
  const auto r = RunCli({"mesh", Case("li_table1.toml"), "--crank-deg", "0", "--json", "-"});
  REQUIRE(r.code == 0);
  const auto json = nlohmann::json::parse(r.out.substr(r.out.find('{')));
  REQUIRE(json.at("pins").size() == 40);
  // Pin 1 sits in the root on the line of centres: clearance dR_rp - dR_p = 22 um, no arm.
  CHECK(json.at("pins").at(0).at("clearance_um").get<double>() == doctest::Approx(22.0).epsilon(1e-3));
  CHECK(std::abs(json.at("pins").at(0).at("arm_mm").get<double>()) < 1e-9);
}

TEST_CASE("cli: ltca solve writes the summary and per-position keys of the issue") {
  const auto r = RunCli({"solve", Case("liu2021_sec52_base.toml"), "--json", "-"});
  REQUIRE(r.code == 0);
  const auto json = nlohmann::json::parse(r.out.substr(r.out.find('{')));
  for (const char* key : {"mean_te_arcsec", "pp_te_arcsec", "contacts_min", "contacts_max", "max_pin_force_n",
                          "max_contact_stress_mpa", "wall_seconds", "status"}) {
    CHECK(json.at("summary").contains(key));
  }
  CHECK(json.at("summary").at("status") == "success");
  // Liu section 5.2: 6 to 7 pins in contact under the base modification (the paper's text).
  CHECK(json.at("summary").at("contacts_min").get<int>() >= 6);
  CHECK(json.at("summary").at("contacts_max").get<int>() <= 7);
  REQUIRE(json.at("positions").size() == 91);
  const auto& p = json.at("positions").at(0);
  for (const char* key : {"crank_deg", "te_arcsec", "contacts", "pin_force_n", "pin_angle_deg", "contact_stress_mpa", "status"}) {
    CHECK(p.contains(key));
  }
  CHECK(p.at("pin_force_n").size() == 40);
  CHECK(p.at("te_arcsec").get<double>() < 0.0);  // negative under load
  CHECK(RunCli({"solve", "--solver", "newton"}).code != 0);
}

TEST_CASE("cli: ltca compare runs the selected solvers side by side with their differences") {
  const auto r = RunCli({"compare", Case("liu2021_sec52_base.toml"), "--solvers", "bisection,compatibility", "--json", "-"});
  REQUIRE(r.code == 0);
  const auto json = nlohmann::json::parse(r.out.substr(r.out.find("{\n")));
  REQUIRE(json.at("solvers").size() == 2);
  const auto& other = json.at("solvers").at(1);
  CHECK(other.at("name") == "compatibility");
  CHECK(other.at("max_te_difference_arcsec").get<double>() < 1e-6);
  CHECK(other.at("max_contact_count_difference").get<int>() == 0);
  CHECK(other.contains("wall_seconds"));
  CHECK(RunCli({"compare", "--solvers", "bisection,newton"}).code != 0);
}
