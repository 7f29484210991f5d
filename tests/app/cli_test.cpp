// The `ltca` command line, run in-process: outputs, keys and exit codes.
#include <cstdlib>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstdio>
#include <unistd.h>
#include <map>
#include <sstream>
#include <utility>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>
#include <fmt/format.h>

#include "cli.hpp"
#include "cli_run.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/deviation_fit.hpp"
#include "ltca/geometry/inspection.hpp"
#include "ltca/geometry/kinematics.hpp"
#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/app/deck.hpp"
#include "deck_runs.hpp"
#include "ltca/analysis/sweep.hpp"
#include "output.hpp"

namespace {

using ltca::test::Outcome;
using ltca::test::RunCli;

std::filesystem::path TempFile(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("ltca_cli_test_" + name);
  std::ofstream(path) << text;
  return path;
}

using ltca::test::Case;

using ltca::test::ReadText;

/// cases/liu2021_table1.toml with [modification] pin_radius_mm = -0.02: dR_rp - dR_p = -20 um,
/// every pin overlaps the cycloid by 20 um at the theoretical position.
std::filesystem::path InterferingDeck() {
  std::string text = ReadText(Case("liu2021_table1.toml"));
  const auto at = text.find("[material]");
  REQUIRE(at != std::string::npos);
  REQUIRE(text.find("[modification]") == std::string::npos);
  text.insert(at, "[modification]\npin_radius_mm = -0.02\n\n");
  return TempFile("interference_20um.toml", text);
}

/// A folder of its own under the temporary folder, emptied.
std::filesystem::path FreshFolder(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("ltca_cli_test_dir_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::vector<std::string> FolderEntries(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

}  // namespace

TEST_CASE("cli: ltca geometry --json writes the keys of the issue with the library's values") {
  for (const std::string& deck_path : {Case("liu2021_table1.toml"), Case("chen2008/d2.toml"), Case("chen2008/dm1.toml")}) {
    CAPTURE(deck_path);
    const auto r = RunCli({"geometry", deck_path, "--json", "-"});
    REQUIRE(r.code == 0);
    const auto json = nlohmann::json::parse(r.out);
    const auto deck = ltca::app::LoadDeck(deck_path);
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

TEST_CASE("cli: ltca geometry describes the pair as made, the one the contact layer solves ([errors] applied)") {
  // Issue 9: one real pair. A 2 um profile layer changes the cycloid; `ltca geometry` reports the
  // layered profile (the one the mesh model contacts), not the nominal modified one.
  const auto with_layer = RunCli({"geometry", Case("liu2021_sec52_base.toml"), "--set",
                                  "errors.cycloid_profile_layer_mm=0.002", "--json", "-"});
  const auto without = RunCli({"geometry", Case("liu2021_sec52_base.toml"), "--json", "-"});
  REQUIRE(with_layer.code == 0);
  REQUIRE(without.code == 0);
  const auto a = nlohmann::json::parse(with_layer.out), b = nlohmann::json::parse(without.out);
  const auto deck = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"), {"errors.cycloid_profile_layer_mm=0.002"});
  CHECK(a.at("errors_applied").get<bool>());
  CHECK_FALSE(b.at("errors_applied").get<bool>());
  CHECK(a.at("min_curvature_radius_mm").get<double>() == deck.MakeModel().profile().min_curvature_radius());
  CHECK(a.at("min_curvature_radius_mm").get<double>() != b.at("min_curvature_radius_mm").get<double>());
}

TEST_CASE("cli: ltca geometry reports root, tip and, with [inspection] roller_diameter_mm, the dimension over "
          "rollers of the disc as made; a roller that is not positive is refused naming the key") {
  // Liu section 5.2's base: R' = 64 - 0.017, r' = 3 - 0.004 - 0.002 (the 2 um layer adds material), e = 1.3.
  const std::vector<std::string> sets = {"--set", "errors.cycloid_profile_layer_mm=0.002", "--set",
                                         "inspection.roller_diameter_mm=8"};
  std::vector<std::string> args = {"geometry", Case("liu2021_sec52_base.toml"), "--json", "-"};
  args.insert(args.end(), sets.begin(), sets.end());
  const auto r = RunCli(args);
  REQUIRE(r.code == 0);
  const auto json = nlohmann::json::parse(r.out);
  CHECK(json.at("root_diameter_mm").get<double>() == doctest::Approx(2.0 * (63.983 - 1.3 - 2.994)).epsilon(1e-12));
  CHECK(json.at("tip_diameter_mm").get<double>() == doctest::Approx(2.0 * (63.983 + 1.3 - 2.994)).epsilon(1e-12));
  // The rollers: the geometry layer's measurement of the pair as made, reported as it is.
  const auto deck = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"),
                                        {"errors.cycloid_profile_layer_mm=0.002", "inspection.roller_diameter_mm=8"});
  const auto m = ltca::geometry::MeasureOverRollers(deck.MakeRealPair().profile(), 8.0);
  CHECK(json.at("dimension_over_rollers_mm").get<double>() == m.dimension);
  CHECK(json.at("over_rollers").at("roller_centre_radius_mm").get<double>() == m.centre_radius);
  CHECK(json.at("over_rollers").at("contact").get<std::string>() == "flanks");
  CHECK(json.at("over_rollers").at("contacts_on_working_flanks").get<bool>());
  CHECK(json.at("over_rollers").at("measured").get<std::string>() == "over");
  const auto text = RunCli({"geometry", Case("liu2021_sec52_base.toml"), "--set", "inspection.roller_diameter_mm=8"});
  CHECK(text.out.find("dimension over rollers") != std::string::npos);
  CHECK(text.out.find("both working flanks") != std::string::npos);
  // Without [inspection]: the diameters, no rollers.
  const auto plain = nlohmann::json::parse(RunCli({"geometry", Case("liu2021_sec52_base.toml"), "--json", "-"}).out);
  CHECK(plain.at("dimension_over_rollers_mm").is_null());
  CHECK(plain.at("over_rollers").is_null());
  // A roller on the root is reported, and warned of in the text.
  const auto root = RunCli({"geometry", Case("liu2021_sec52_base.toml"), "--set", "inspection.roller_diameter_mm=5"});
  CHECK(root.out.find("rest on the root") != std::string::npos);
  for (const char* bad : {"inspection.roller_diameter_mm=0", "inspection.roller_diameter_mm=-8"}) {
    const auto refused = RunCli({"geometry", Case("liu2021_sec52_base.toml"), "--set", bad});
    CHECK(refused.code == 2);
    CHECK(refused.err.find("[inspection] roller_diameter_mm") != std::string::npos);
  }
}

TEST_CASE("cli: ltca geometry --dxf writes the drawing whole or not at all, never over another output") {
  const auto dir = FreshFolder("dxf");
  const auto dxf = dir / "disc.dxf";
  // With the other outputs: the DXF is a whole file (its end of file marker) beside the JSON.
  const auto ok = RunCli({"geometry", Case("stage/cycloidal_drive.toml"), "--json", (dir / "g.json").string(), "--dxf",
                          dxf.string()});
  if (ok.code == 2) {  // built without dxflib: refused, naming the option and the package
    CHECK(ok.err.find("--dxf") != std::string::npos);
    CHECK(ok.err.find("dxflib") != std::string::npos);
    return;
  }
  REQUIRE(ok.code == 0);
  const std::string text = ReadText(dxf);
  CHECK(text.find("DISC_PROFILE") != std::string::npos);
  CHECK(text.find("OUTPUT_PINS") != std::string::npos);
  CHECK(text.size() > 100000);
  CHECK(text.substr(text.size() - 8).find("EOF") != std::string::npos);
  // A folder that does not exist: exit 3 before anything is written, the JSON not written either.
  const auto missing = RunCli({"geometry", Case("stage/cycloidal_drive.toml"), "--json", (dir / "h.json").string(),
                               "--dxf", (dir / "no-such-folder" / "disc.dxf").string()});
  CHECK(missing.code == 3);
  CHECK(missing.err.find("--dxf") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "h.json"));
  // The same file twice, or standard output twice: refused.
  CHECK(RunCli({"geometry", Case("stage/cycloidal_drive.toml"), "--json", "-", "--dxf", "-"}).code == 2);
  CHECK(RunCli({"geometry", Case("stage/cycloidal_drive.toml"), "--csv", dxf.string(), "--dxf", dxf.string()}).code == 2);
  // --dxf - writes the drawing alone to standard output (the text goes to standard error).
  const auto out = RunCli({"geometry", Case("stage/cycloidal_drive.toml"), "--dxf", "-"});
  REQUIRE(out.code == 0);
  CHECK(out.out == text);
  CHECK(out.err.find("root diameter") != std::string::npos);
}

TEST_CASE("cli: ltca geometry's deviation chart of a trace made from a known modification returns it (1e-6 mm) in "
          "JSON, CSV and figure; refused without a trace") {
  // The trace: the normal deviation of Liu's section 5.2 pair made with dR_p + 12 um, dR_rp - 7 um
  // and 0.01 deg more, against the deck's design (geometry::ModificationDeviation, checked against
  // a bisection of its own in tests/geometry/deviation_fit_test.cpp), 61 points over the tooth space.
  const auto dir = FreshFolder("deviation");
  const auto deck = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"));
  const ltca::geometry::CycloidProfile design = deck.MakeRealPair().profile();
  ltca::geometry::Modification known;
  known.pin_circle_radius = 0.012, known.pin_radius = -0.007, known.rotation = ltca::units::DegToRad(0.01);
  {
    std::ofstream csv(dir / "trace.csv");
    csv << "profile_angle_deg, deviation_um\n";
    for (int i = 0; i <= 60; ++i) {
      const double u = design.phi_max() * (-0.98 + 1.96 * i / 60.0);
      csv << fmt::format("{:.17g}, {:.17g}\n", ltca::units::RadToDeg(u),
                         1e3 * ltca::geometry::ModificationDeviation(design, known, u));
    }
  }
  const std::string trace = "errors.profile_measured_csv=\"" + (dir / "trace.csv").string() + "\"";
  const auto r = RunCli({"geometry", Case("liu2021_sec52_base.toml"), "--set", trace, "--set",
                         "inspection.profile_tolerance_um=100", "--json", "-", "--deviation-csv",
                         (dir / "chart.csv").string(), "--deviation-svg", (dir / "chart.svg").string()});
  REQUIRE(r.code == 0);
  const auto fit = nlohmann::json::parse(r.out).at("profile_deviation_chart");
  CHECK(fit.at("points").get<int>() == 61);
  CHECK(std::abs(fit.at("fitted_modification").at("offset_pin_circle_radius_um").get<double>() - 12.0) <= 1e-3);
  CHECK(std::abs(fit.at("fitted_modification").at("isometric_pin_radius_um").get<double>() + 7.0) <= 1e-3);
  // 0.01 deg = 36 arcsec; 1e-6 mm on the 64 mm pin circle is 0.0032 arcsec.
  CHECK(std::abs(fit.at("fitted_modification").at("rotation_arcsec").get<double>() - 36.0) <= 0.0032);
  CHECK(fit.at("tolerance_um").get<double>() == 100.0);
  CHECK(fit.at("within_tolerance").get<bool>());
  const std::string table = ReadText(dir / "chart.csv");
  CHECK(table.rfind("u_deg,measured_um,fitted_um,residual_um,band_lower_um,band_upper_um\n", 0) == 0);
  CHECK(std::count(table.begin(), table.end(), '\n') == 62);
  const std::string svg = ReadText(dir / "chart.svg");
  CHECK(svg.find("measured trace") != std::string::npos);
  CHECK(svg.find("fitted modification") != std::string::npos);
  // Without a trace: refused, naming the option and the key, nothing written.
  const auto refused = RunCli({"geometry", Case("liu2021_sec52_base.toml"), "--deviation-csv", (dir / "no.csv").string()});
  CHECK(refused.code == 2);
  CHECK(refused.err.find("profile_measured_csv") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "no.csv"));
  // Without [inspection] profile_tolerance_um: no band.
  const auto plain = nlohmann::json::parse(
      RunCli({"geometry", Case("liu2021_sec52_base.toml"), "--set", trace, "--json", "-"}).out);
  CHECK(plain.at("profile_deviation_chart").at("tolerance_um").is_null());
  CHECK(nlohmann::json::parse(RunCli({"geometry", Case("liu2021_sec52_base.toml"), "--json", "-"}).out)
            .at("profile_deviation_chart")
            .is_null());
}

TEST_CASE("cli: ltca geometry reports the tolerance band of the dimension over rollers from [tolerances] in text and "
          "JSON") {
  const std::vector<std::string> args = {"geometry", Case("liu2021_sec52_base.toml"), "--set", "inspection.roller_diameter_mm=8",
                                         "--set", "tolerances.modification_pin_radius_mm={ distribution = \"uniform\", tolerance = 0.005 }"};
  std::vector<std::string> json_args = args;
  json_args.insert(json_args.end(), {"--json", "-"});
  const auto r = RunCli(json_args);
  REQUIRE(r.code == 0);
  const auto band = nlohmann::json::parse(r.out).at("dimension_over_rollers_tolerance");
  REQUIRE(band.is_object());
  CHECK(band.at("terms").size() == 1);
  CHECK(band.at("terms")[0].at("key").get<std::string>() == "modification_pin_radius_mm");
  const double half = std::abs(band.at("terms")[0].at("sensitivity_mm_per_key_unit").get<double>()) * 0.005;
  CHECK(band.at("worst_case_mm")[1].get<double>() - band.at("centre_mm").get<double>() == doctest::Approx(half));
  CHECK(nlohmann::json::parse(r.out).at("dimension_over_rollers_mm").get<double>() == band.at("nominal_mm").get<double>());
  const auto text = RunCli(args);
  CHECK(text.out.find("worst case") != std::string::npos);
  CHECK(nlohmann::json::parse(RunCli({"geometry", Case("liu2021_sec52_base.toml"), "--json", "-"}).out)
            .at("dimension_over_rollers_tolerance")
            .is_null());
}

TEST_CASE("cli: ltca geometry --step without ltca_step.so exits 1 naming the module, and writes nothing") {
  // LTCA_MODULE_DIR names the only folder modules are looked for in (app/modules.hpp): an empty one
  // makes the STEP writer missing by construction.
  const auto dir = FreshFolder("step");
  struct OnlyFolder {
    explicit OnlyFolder(const std::string& folder) { setenv("LTCA_MODULE_DIR", folder.c_str(), 1); }
    ~OnlyFolder() { unsetenv("LTCA_MODULE_DIR"); }
  } only(dir.string());
  const auto r = RunCli({"geometry", Case("stage/cycloidal_drive.toml"), "--json", (dir / "g.json").string(), "--step",
                         (dir / "disc.step").string()});
  CHECK(r.code == 1);
  CHECK(r.err.find("--step") != std::string::npos);
  CHECK(r.err.find("ltca_step.so") != std::string::npos);
  CHECK(r.err.find("OpenCASCADE") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "disc.step"));
  CHECK_FALSE(std::filesystem::exists(dir / "g.json"));
  // Without --step the module is never looked for.
  CHECK(RunCli({"geometry", Case("stage/cycloidal_drive.toml"), "--json", (dir / "g.json").string()}).code == 0);
}

TEST_CASE("cli: solve and compare name the model that ran (plane, its slices and surface)") {
  const auto solve = RunCli({"solve", Case("liu2021_table1.toml"), "--set", "sweep.positions=2", "--json", "-"});
  const auto elements = RunCli({"compare", Case("liu2021_sec52_base.toml"), "--set", "sweep.positions=2", "--set",
                                "geometry.geometry_mode=elements", "--solvers", "bisection", "--json", "-"});
  REQUIRE(solve.code == 0);
  REQUIRE(elements.code == 0);
  const auto a = nlohmann::json::parse(solve.out), b = nlohmann::json::parse(elements.out);
  CHECK(a.at("model").at("name") == "plane");
  CHECK(a.at("model").at("slices") == 1);
  CHECK(a.at("model").at("surface") == "analytic");
  CHECK(b.at("model").at("surface") == "elements");
}

TEST_CASE("cli: ltca with no argument runs the built-in Liu 2021 Table 1 case") {
  const auto r = RunCli({});
  CHECK(r.code == 0);
  CHECK(r.out.find("Liu 2021 Table 1") != std::string::npos);
  CHECK(r.out.find("54.3409 deg") != std::string::npos);  // alpha_max = arcsin(0.8125)
  CHECK(r.out.find("mean TE") != std::string::npos);      // and the loaded sweep
}

TEST_CASE("cli: ltca geometry of a stage draws its output pins in their holes, or its cranks (issue 25)") {
  // The SVG's metadata names every series: the holes and the pins for output pins, the crank
  // circle and both centres for cranks; eight pin-and-hole pairs of the deck's radii.
  const auto svg = std::filesystem::temp_directory_path() / "ltca_cli_test_stage.svg";
  const auto read = [&svg] {
    std::ifstream in(svg);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  REQUIRE(RunCli({"geometry", Case("stage/cycloidal_drive.toml"), "--svg", svg.string()}).code == 0);
  const std::string pins = read();
  CHECK(pins.find("<ltca:series label=\"holes r_h = 6.32 mm\"") != std::string::npos);
  CHECK(pins.find("<ltca:series label=\"output pins r_w = 5 mm\"") != std::string::npos);
  REQUIRE(RunCli({"geometry", Case("stage/rv_two_discs_cranks.toml"), "--svg", svg.string()}).code == 0);
  const std::string cranks = read();
  CHECK(cranks.find("<ltca:series label=\"crank circle R_c = 35 mm\"") != std::string::npos);
  CHECK(cranks.find("<ltca:series label=\"crank-hole centres (the eccentrics)\"") != std::string::npos);
  std::filesystem::remove(svg);
}

TEST_CASE("cli: --csv writes the whole profile and --svg draws the pair") {
  const auto csv = std::filesystem::temp_directory_path() / "ltca_cli_test_profile.csv";
  const auto svg = std::filesystem::temp_directory_path() / "ltca_cli_test_pair.svg";
  const auto r = RunCli({"geometry", Case("chen2008/d2.toml"), "--csv", csv.string(), "--svg", svg.string(), "--crank-deg", "3"});
  REQUIRE(r.code == 0);
  std::ifstream in(csv);
  std::string line;
  int rows = 0;
  std::getline(in, line);
  CHECK(line == "tooth_space,u_deg,x_mm,y_mm,normal_x,normal_y,curvature_radius_mm,part");
  while (std::getline(in, line)) ++rows;
  CHECK(rows == 22 * 121);  // z_c tooth spaces of 2 * 60 + 1 samples
  std::ifstream svg_in(svg);
  const std::string drawing((std::istreambuf_iterator<char>(svg_in)), std::istreambuf_iterator<char>());
  // Issue 16: PLplot draws the pins as filled outlines (no <circle>) and sets every text glyph by
  // glyph: the pin numbers 1..24 and the axis labels are checked with an XML parser by
  // tests/app/check_svg.py ("app: every deck's plots ..."). Here: an SVG whose metadata names the
  // drawing's axes and series.
  CHECK(drawing.rfind("<?xml", 0) == 0);
  CHECK(drawing.find("<svg") != std::string::npos);
  CHECK(drawing.find("cycloid and pins at crank 3 deg") != std::string::npos);
  CHECK(drawing.find("x_label=\"x_f (mm)\" y_label=\"y_f (mm)\"") != std::string::npos);
  CHECK(drawing.find("<ltca:series label=\"line of centres O_p O_c\"") != std::string::npos);
  CHECK(drawing.find("</svg>") != std::string::npos);
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
  const auto json = nlohmann::json::parse(r.out);
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

TEST_CASE("cli: ltca backlash reports a preloaded pair: no free play, its interference and the torques that unload a flank") {
  const std::string deck = std::string(
      "[case]\ntitle = \"preloaded\"\n[pair]\npin_count = 40\ntooth_count = 39\npin_radius_mm = 3.0\n"
      "pin_circle_radius_mm = 64.0\neccentricity_mm = 1.3\nface_width_mm = 12.0\n"
      "[modification]\npin_radius_mm = -0.005\n[material]\nyoung_modulus_mpa = 206000.0\npoisson_ratio = 0.3\n"
      "[sweep]\npositions = 1\n");
  const auto r = RunCli({"backlash", TempFile("interference.toml", deck).string(), "--json", "-"});
  INFO(r.err);
  CHECK(r.code == 0);
  const auto json = nlohmann::json::parse(r.out);
  const auto& p = json.at("positions").at(0);
  CHECK(p.at("backlash_arcsec").get<double>() == 0.0);
  CHECK(p.at("interference_arcsec").get<double>() > 0.0);
  CHECK(p.at("unload_torque_nm").get<double>() > 0.0);
  CHECK(p.at("unload_torque_reverse_nm").get<double>() > 0.0);
  CHECK(json.at("summary").at("preloaded_positions").get<int>() == 1);
}

TEST_CASE("cli: ltca mesh prints every pin with clearance and arm") {
  const auto r = RunCli({"mesh", Case("li_table1.toml"), "--crank-deg", "0", "--json", "-"});
  REQUIRE(r.code == 0);
  const auto json = nlohmann::json::parse(r.out);
  REQUIRE(json.at("pins").size() == 40);
  // Pin 1 sits in the root on the line of centres: clearance dR_rp - dR_p = 22 um, no arm.
  CHECK(json.at("pins").at(0).at("clearance_um").get<double>() == doctest::Approx(22.0).epsilon(1e-3));
  CHECK(std::abs(json.at("pins").at(0).at("arm_mm").get<double>()) < 1e-9);
}

TEST_CASE("cli: ltca solve writes the summary and per-position keys of the issue") {
  const auto r = RunCli({"solve", Case("liu2021_sec52_base.toml"), "--json", "-"});
  REQUIRE(r.code == 0);
  const auto json = nlohmann::json::parse(r.out);
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
  const auto json = nlohmann::json::parse(r.out);
  REQUIRE(json.at("solvers").size() == 2);
  const auto& other = json.at("solvers").at(1);
  CHECK(other.at("name") == "compatibility");
  CHECK(other.at("max_te_difference_arcsec").get<double>() < 1e-6);
  CHECK(other.at("max_contact_count_difference").get<int>() == 0);
  CHECK(other.contains("wall_seconds"));
  CHECK(RunCli({"compare", "--solvers", "bisection,newton"}).code != 0);
}

TEST_CASE("cli: --json - writes only JSON to stdout for every command") {
  const std::string deck = Case("liu2021_table1.toml");
  const std::vector<std::vector<std::string>> runs = {
      {"geometry", deck, "--json", "-"},
      {"backlash", deck, "--json", "-"},
      {"mesh", deck, "--crank-deg", "2", "--json", "-"},
      {"solve", deck, "--json", "-"},
      {"compare", deck, "--solvers", "bisection,compatibility", "--json", "-"},
      {"--json", "-"},        // the default job on the built-in deck
      {deck, "--json", "-"},  // the default job on a deck
  };
  for (const auto& args : runs) {
    CAPTURE(args.front());
    const auto r = RunCli(args);
    CHECK(r.code == 0);
    nlohmann::json json;
    CHECK_NOTHROW(json = nlohmann::json::parse(r.out));  // the whole of stdout is one document
    CHECK(json.is_object());
    // The human text still comes, on stderr.
    CHECK(r.err.find("case      Liu 2021 Table 1") != std::string::npos);
  }
  const auto job = nlohmann::json::parse(RunCli({deck, "--json", "-"}).out);
  CHECK(job.at("geometry").contains("k1"));
  CHECK(job.at("solve").at("summary").at("status") == "success");
}

TEST_CASE("cli: --csv - writes only the CSV to stdout, and the text to stderr") {
  const auto r = RunCli({"solve", Case("liu2021_table1.toml"), "--csv", "-"});
  REQUIRE(r.code == 0);
  std::istringstream rows(r.out);
  std::string line;
  std::getline(rows, line);
  CHECK(line == "crank_deg,te_arcsec,contacts,max_pin_force_n,max_contact_stress_mpa,status");
  int n = 0;
  while (std::getline(rows, line)) {
    ++n;
    CHECK(line.substr(line.rfind(',') + 1) == "success");
  }
  CHECK(n == ltca::app::LoadDeck(Case("liu2021_table1.toml")).sweep.positions);
  CHECK(r.err.find("mean TE") != std::string::npos);
  // Two documents cannot share stdout.
  const auto both = RunCli({"solve", Case("liu2021_table1.toml"), "--csv", "-", "--json", "-"});
  CHECK(both.code == 2);
  CHECK(both.out.empty());
}

TEST_CASE("cli: without an output '-' the text stays on stdout and stderr stays empty") {
  const auto r = RunCli({"solve", Case("liu2021_table1.toml")});
  CHECK(r.code == 0);
  CHECK(r.out.find("mean TE") != std::string::npos);
  CHECK(r.err.empty());  // also: no progress line in-process (stderr is not a terminal)
}

TEST_CASE("cli: a failed position exits 1 with its status, null figures and n/a in text") {
  const auto r = RunCli({"solve", Case("hard/law_cannot_carry.toml"), "--json", "-"});
  CHECK(r.code == 1);
  const auto json = nlohmann::json::parse(r.out);
  const auto& s = json.at("summary");
  CHECK(s.at("status") == "law-cannot-carry");
  CHECK(s.at("mean_te_arcsec").is_null());
  CHECK(s.at("pp_te_arcsec").is_null());
  CHECK(s.at("max_pin_force_n").is_null());
  CHECK(s.at("max_contact_stress_mpa").is_null());
  CHECK(s.at("failed_positions") == 1);
  CHECK(s.at("succeeded_positions") == 0);
  REQUIRE(json.at("positions").size() == 1);
  const auto& p = json.at("positions").at(0);
  CHECK(p.at("status") == "law-cannot-carry");
  CHECK(p.at("te_arcsec").is_null());
  CHECK(p.at("pin_force_n").is_null());
  CHECK(p.at("contact_stress_mpa").is_null());
  const auto text = RunCli({"solve", Case("hard/law_cannot_carry.toml")});
  CHECK(text.code == 1);
  CHECK(text.out.find("mean TE                n/a") != std::string::npos);
  CHECK(text.out.find("failed positions") != std::string::npos);
  // compare: the same failure in every solver, and exit 1.
  const auto cmp = RunCli({"compare", Case("hard/law_cannot_carry.toml"), "--solvers", "bisection", "--json", "-"});
  CHECK(cmp.code == 1);
  CHECK(nlohmann::json::parse(cmp.out).at("solvers").at(0).at("mean_te_arcsec").is_null());
}

TEST_CASE("app: the summary is taken over the successful positions only and counts the failed") {
  using ltca::analysis::PositionResult;
  using ltca::solvers::SolverStatus;
  const auto position = [](SolverStatus status, double te, double force, double stress, int contacts) {
    PositionResult p;
    p.result.status = status;
    p.result.te = te;
    p.result.force = {force, 0.5 * force};
    p.pin_force = p.result.force;  // the plane model: one point per pin
    p.contact_stress = {stress, 0.0};
    p.contacts = contacts;
    return p;
  };
  ltca::analysis::SummaryAccumulator acc;
  acc.Add(position(SolverStatus::kSuccess, -1e-5, 100.0, 900.0, 6));
  acc.Add(position(SolverStatus::kMaxIterations, 1.3e3, 170848.0, 1e6, 40));  // a wrong number
  acc.Add(position(SolverStatus::kSuccess, -3e-5, 300.0, 1100.0, 7));
  const auto s = acc.Summary();
  CHECK(s.succeeded == 2);
  CHECK(s.failed == 1);
  CHECK(s.positions() == 3);
  CHECK_FALSE(s.all_succeeded());
  CHECK(s.status == SolverStatus::kMaxIterations);
  CHECK(s.mean_te == doctest::Approx(-2e-5));
  CHECK(s.pp_te == doctest::Approx(2e-5));
  CHECK(s.max_pin_force == 300.0);
  CHECK(s.max_contact_stress == 1100.0);
  CHECK(s.contacts_min == 6);
  CHECK(s.contacts_max == 7);

  ltca::analysis::SummaryAccumulator none;
  none.Add(position(SolverStatus::kLawCannotCarry, 0.1, 1.0, 1.0, 1));
  const auto n = none.Summary();
  CHECK(n.failed == 1);
  CHECK(std::isnan(n.mean_te));
  CHECK(std::isnan(n.pp_te));
  CHECK(std::isnan(n.max_pin_force));
  CHECK(std::isnan(n.max_contact_stress));
}

TEST_CASE("app: streaming calls back every position in order and keeps none, with the same summary") {
  const auto deck = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"));
  const auto kept = ltca::test::SolveSweep(deck, deck.solver);
  std::vector<double> cranks, tes;
  ltca::analysis::SweepCallbacks callbacks;
  callbacks.keep_positions = false;
  callbacks.on_position = [&](const ltca::analysis::PositionResult& p) {
    cranks.push_back(p.crank);
    tes.push_back(p.result.te);
  };
  const auto streamed = ltca::test::SolveSweep(deck, deck.solver, callbacks);
  CHECK(streamed.positions.empty());
  REQUIRE(cranks.size() == kept.positions.size());
  CHECK(cranks == deck.sweep.CrankAngles());
  for (std::size_t i = 0; i < tes.size(); ++i) CHECK(tes[i] == kept.positions[i].result.te);
  CHECK(streamed.summary.mean_te == kept.summary.mean_te);
  CHECK(streamed.summary.pp_te == kept.summary.pp_te);
  CHECK(streamed.summary.succeeded == static_cast<std::int64_t>(kept.positions.size()));
}

TEST_CASE("cli: the solve JSON streams its positions and ends with the summary") {
  const auto r = RunCli({"solve", Case("liu2021_sec52_base.toml"), "--json", "-"});
  REQUIRE(r.code == 0);
  // Positions before the summary: the document is written while the sweep runs.
  CHECK(r.out.find("\"positions\"") < r.out.find("\"summary\""));
  const auto json = nlohmann::json::parse(r.out);
  const auto deck = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"));
  const auto sweep = ltca::test::SolveSweep(deck, deck.solver);
  CHECK(json.at("summary").at("mean_te_arcsec").get<double>() ==
        doctest::Approx(ltca::units::RadToArcsec(sweep.summary.mean_te)).epsilon(1e-12));
  CHECK(json.at("positions").size() == sweep.positions.size());
}

TEST_CASE("app: RequireNoInterference names the pins and overlaps, and accepts clearance") {
  const auto deck = ltca::app::LoadDeck(InterferingDeck().string());
  const auto model = deck.MakeModel();
  CHECK_THROWS_WITH_AS(ltca::contact::RequireNoInterference(model, 0.0), doctest::Contains("pin 1 by 20 um"),
                       std::invalid_argument);
  const auto ok = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"));
  CHECK_NOTHROW(ltca::contact::RequireNoInterference(ok.MakeModel(), 0.0));
  // The sweep solves it: a 20 um preload presses beyond the material's 4000 MPa at zero torque, so
  // every position cannot be assembled, naming the pins (a status, not an input error).
  int solved = 0;
  ltca::analysis::SweepCallbacks callbacks;
  callbacks.on_position = [&](const ltca::analysis::PositionResult& p) {
    ++solved;
    CHECK(p.result.status == ltca::solvers::SolverStatus::kCannotAssemble);
    CHECK(p.result.message.find("pin 1 by 20 um") != std::string::npos);
  };
  const auto sweep = ltca::test::SolveSweep(deck, deck.solver, callbacks);
  CHECK(solved == static_cast<int>(sweep.positions.size()));
  CHECK(sweep.summary.cannot_assemble == static_cast<std::int64_t>(sweep.positions.size()));
}

TEST_CASE("cli: a 20 um preload beyond the material is cannot-assemble, not exit 2, mesh and backlash tabulate it") {
  const std::string deck = InterferingDeck().string();
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"solve", deck, "--json", "-"}, {"compare", deck, "--json", "-"}, {deck, "--json", "-"}}) {
    CAPTURE(args.front());
    const auto r = RunCli(args);
    CHECK(r.code != 0);
    CHECK(r.code != 2);
    CHECK(r.out.find("cannot-assemble") != std::string::npos);
    // solve names the overlapping pin in each position's message; compare's document gives each
    // solver's status, not the positions' messages.
    if (args.front() != "compare") CHECK(r.out.find("pin 1 by 20 um") != std::string::npos);
    CHECK(nlohmann::json::accept(r.out));
  }
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"mesh", deck, "--json", "-"}, {"backlash", deck, "--json", "-"}}) {
    CAPTURE(args.front());
    const auto r = RunCli(args);
    CHECK(r.code == 0);
    CHECK(nlohmann::json::accept(r.out));
  }
}

TEST_CASE("cli: I/O errors exit 3, unwritable paths are found before computing, no partial file is left") {
  const auto r = RunCli({"solve", Case("liu2021_table1.toml"), "--csv", "/dev/full"});
  CHECK(r.code == 3);
  CHECK(r.err.find("/dev/full") != std::string::npos);

  const auto missing = RunCli({"solve", Case("liu2021_table1.toml"), "--json", "/no/such/folder/x.json"});
  CHECK(missing.code == 3);
  CHECK(missing.out.empty());  // found before the sweep: no summary was printed
  CHECK(missing.err.find("/no/such/folder") != std::string::npos);

  const auto dir = FreshFolder("io");
  CHECK(RunCli({"geometry", "--json", dir.string()}).code == 3);  // a folder is not a file

  // A run that fails (bad input) after the outputs were opened leaves the folder as it was:
  // no new file, no temporary file, and an existing file untouched.
  const auto kept = dir / "kept.json";
  std::ofstream(kept) << "old";
  // (no [material]: found by the sweep, after the outputs are opened)
  const auto no_material = TempFile("no_material.toml", "[pair]\npin_count = 40\ntooth_count = 39\npin_radius_mm = 3.0\n"
                                                        "pin_circle_radius_mm = 64.0\neccentricity_mm = 1.3\nface_width_mm = 12.0\n"
                                                        "[load]\ntorque_nm = 100.0\n");
  const auto bad = RunCli({"solve", no_material.string(), "--json", kept.string(), "--csv", (dir / "new.csv").string()});
  CHECK(bad.code == 2);
  CHECK(FolderEntries(dir) == std::vector<std::string>{"kept.json"});
  CHECK(ReadText(kept) == "old");

  // A successful run replaces it whole.
  CHECK(RunCli({"solve", Case("liu2021_table1.toml"), "--json", kept.string()}).code == 0);
  CHECK(nlohmann::json::parse(ReadText(kept)).at("summary").at("status") == "success");
  CHECK(FolderEntries(dir) == std::vector<std::string>{"kept.json"});
}

TEST_CASE("cli: Output reports a failed write and removes its temporary file") {
  const auto dir = FreshFolder("output");
  std::ostringstream out;
  {
    ltca::cli::Output o("--json", (dir / "a.json").string(), out);
    o.stream() << "partial";
    CHECK(FolderEntries(dir).size() == 1);  // the temporary file only
    // no Commit(): as when an exception unwinds
  }
  CHECK(FolderEntries(dir).empty());
  std::ostringstream bad;
  bad.setstate(std::ios::badbit);
  ltca::cli::Output to_stdout("--json", "-", bad);
  CHECK_THROWS_AS(to_stdout.Commit(), ltca::cli::OutputError);
  const auto failed = [&] {
    ltca::cli::Output full("--csv", "/dev/full", out);
    full.stream() << std::string(1 << 16, 'x');
    full.Commit();
  };
  CHECK_THROWS_AS(failed(), ltca::cli::OutputError);
}

TEST_CASE("cli: a deck path with non-UTF-8 bytes gives valid JSON") {
  const auto path = std::filesystem::temp_directory_path() / "ltca_cli_test_\xff\xfe_deck.toml";
  std::filesystem::copy_file(Case("liu2021_table1.toml"), path, std::filesystem::copy_options::overwrite_existing);
  for (const std::string command : {"geometry", "solve", "mesh"}) {
    CAPTURE(command);
    const auto r = RunCli({command, path.string(), "--json", "-"});
    REQUIRE(r.code == 0);
    nlohmann::json json;
    REQUIRE_NOTHROW(json = nlohmann::json::parse(r.out));
    CHECK(json.at("case").at("deck").get<std::string>().find("\xEF\xBF\xBD") != std::string::npos);  // U+FFFD
  }
}

TEST_CASE("cli: --crank-deg must be a finite angle within two output turns of the largest pair a deck may give") {
  for (const std::string bad : {"nan", "inf", "-inf", "1e400", "7200721", "-1e9", "12abc"}) {
    for (const std::string command : {"mesh", "geometry"}) {
      CAPTURE(bad);
      CAPTURE(command);
      const auto r = RunCli({command, "--crank-deg=" + bad});
      CHECK(r.code == 2);
      CHECK(r.err.find("--crank-deg") != std::string::npos);
    }
  }
  CHECK(ltca::analysis::kMaxCrankDeg == 7'200'720.0);  // 2 x 10,001 x 360
  CHECK(RunCli({"mesh", "--crank-deg", "3600"}).code == 0);
  CHECK(RunCli({"mesh", "--crank-deg", "14040"}).code == 0);  // an output revolution of the built-in pair
  CHECK(RunCli({"mesh", "--crank-deg", "-12.5"}).code == 0);
}

TEST_CASE("cli: --version prints the project version and the compiler, --help documents the exit codes") {
  const auto r = RunCli({"--version"});
  CHECK(r.code == 0);
  CHECK(r.out.find(std::string("ltca ") + LTCA_TEST_PROJECT_VERSION) != std::string::npos);
#if defined(__clang__)
  CHECK(r.out.find("clang") != std::string::npos);
#else
  CHECK(r.out.find(std::string("gcc ") + __VERSION__) != std::string::npos);
#endif
  const auto help = RunCli({"--help"});
  CHECK(help.code == 0);
  for (const char* line : {"Exit codes:", "  0  every position", "  1  the run finished", "  2  bad input",
                           "  3  an output could not", "  4  internal error"}) {
    CHECK(help.out.find(line) != std::string::npos);
  }
  CHECK(RunCli({"--no-such-option"}).code == 2);
}

TEST_CASE("cli: a deck without a command runs the default job on that deck") {
  const std::string path = Case("liu2021_sec52_base.toml");
  const auto deck = ltca::app::LoadDeck(path);
  const auto r = RunCli({path, "--json", "-"});
  REQUIRE(r.code == 0);
  const auto json = nlohmann::json::parse(r.out);
  CHECK(json.at("geometry").at("case").at("title") == deck.info.title);
  CHECK(json.at("geometry").at("k1").get<double>() ==
        ltca::geometry::CycloidProfile(deck.pair, deck.modification).k1());
  const auto sweep = ltca::test::SolveSweep(deck, deck.solver);
  CHECK(json.at("solve").at("summary").at("mean_te_arcsec").get<double>() ==
        doctest::Approx(ltca::units::RadToArcsec(sweep.summary.mean_te)).epsilon(1e-12));
  CHECK(json.at("solve").at("positions").size() == static_cast<std::size_t>(deck.sweep.positions));
  const auto text = RunCli({path});
  CHECK(text.code == 0);
  CHECK(text.out.find(deck.info.title) != std::string::npos);
  CHECK(text.out.find("mean TE") != std::string::npos);
  const auto nonsense = RunCli({"frobnicate"});
  CHECK(nonsense.code == 2);
  CHECK(nonsense.err.find("neither a command") != std::string::npos);
}

TEST_CASE("cli: the progress line shows only when enabled and after its delay") {
  std::ostringstream shown, hidden, early;
  {
    ltca::cli::Progress p(shown, true, "solving position", 10, 0.0);
    p.Update(5);
    CHECK(shown.str().find("solving position 5 of 10") != std::string::npos);
    p.Finish();
    CHECK(shown.str().back() == '\r');  // the line is cleared before the summary is printed
    const auto length = shown.str().size();
    p.Update(10);
    CHECK(shown.str().size() == length);  // and stays cleared
  }
  {
    ltca::cli::Progress p(hidden, false, "solving position", 10, 0.0);
    p.Update(5);
  }
  CHECK(hidden.str().empty());
  {
    ltca::cli::Progress p(early, true, "solving position", 10, 3600.0);
    p.Update(5);
  }
  CHECK(early.str().empty());
}

TEST_CASE("cli: a contact stress beyond [material] contact_stress_limit_mpa is a warning in JSON and text, exit 0") {
  // Liu 2021 Table 1 prints a largest contact stress of 1067.50 MPa (absolute convention): a
  // 500 MPa limit is exceeded, the default 4000 MPa is not. A warning keeps the status success.
  const auto warned = RunCli({"solve", Case("liu2021_table1_absolute.toml"), "--set", "material.contact_stress_limit_mpa=500",
                              "--set", "sweep.positions=5", "--json", "-"});
  REQUIRE(warned.code == 0);
  const auto j = nlohmann::json::parse(warned.out);
  CHECK(j.at("summary").at("warned_positions").get<int>() > 0);
  CHECK(j.at("summary").at("first_warning").get<std::string>().find("contact_stress_limit_mpa") != std::string::npos);
  CHECK(j.at("positions").at(0).at("warnings").size() >= 1);
  CHECK(warned.err.find("warnings") != std::string::npos);
  const auto plain = RunCli({"solve", Case("liu2021_table1_absolute.toml"), "--set", "sweep.positions=5", "--json", "-"});
  REQUIRE(plain.code == 0);
  const auto k = nlohmann::json::parse(plain.out);
  CHECK(k.at("summary").at("warned_positions").get<int>() == 0);
  CHECK(!k.at("summary").contains("first_warning"));
}

TEST_CASE("cli: backlash streams its positions, and its summary is the library's unloaded sweep") {
  // Issue 10: 100,000 positions of backlash --json peaked at 1.06 GB while the whole document was
  // built in memory; it is now written one position at a time (8.5 MB measured). The streamed
  // document must still be one JSON text whose figures equal contact::AnalyseUnloadedSweep's.
  const auto r = RunCli({"backlash", Case("liu2021_sec52_base.toml"), "--set", "sweep.positions=23", "--json", "-"});
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto deck = ltca::app::LoadDeck(Case("liu2021_sec52_base.toml"), {"sweep.positions=23"});
  // The deck's [solver] kinematics, as every command takes it (issue 26).
  const auto sweep = ltca::contact::AnalyseUnloadedSweep(deck.MakeModel(), deck.sweep.CrankAngles(), deck.kinematics);
  REQUIRE(j.at("positions").size() == 23);
  CHECK(j.at("summary").at("mean_backlash_arcsec").get<double>() ==
        doctest::Approx(ltca::units::RadToArcsec(sweep.mean_backlash)).epsilon(1e-12));
  CHECK(j.at("summary").at("pp_backlash_arcsec").get<double>() ==
        doctest::Approx(ltca::units::RadToArcsec(sweep.pp_backlash)).epsilon(1e-9));
  for (std::size_t i = 0; i < 23; ++i) {
    CHECK(j.at("positions").at(i).at("backlash_arcsec").get<double>() ==
          doctest::Approx(ltca::units::RadToArcsec(sweep.positions[i].backlash)).epsilon(1e-12));
  }
}

TEST_CASE("cli: the slice model's JSON and --pattern-csv carry the pin x slice pattern, and the slices of a pin sum to its total") {
  // Issue 11: cases/liu2021_sec53_phi.toml runs 20 slices. Per position the JSON has
  // slice_force_n (pin x slice) and load_centroid_mm; the pattern CSV has one row per position,
  // pin and slice. Independent check: the sum of a pin's slice forces is its pin_force_n, and its
  // force-weighted slice centre (z_k = (k + 1/2) B / n) is its load centroid.
  const auto json = RunCli({"solve", Case("liu2021_sec53_phi.toml"), "--set", "sweep.positions=3", "--json", "-"});
  REQUIRE(json.code == 0);
  const auto doc = nlohmann::json::parse(json.out);
  CHECK(doc["summary"]["model"] == "slices");
  CHECK(doc["summary"]["width_slices"] == 20);
  const auto csv = RunCli({"solve", Case("liu2021_sec53_phi.toml"), "--set", "sweep.positions=3", "--pattern-csv", "-"});
  REQUIRE(csv.code == 0);
  std::istringstream lines(csv.out);
  std::string line;
  std::getline(lines, line);
  CHECK(line == "crank_deg,pin,slice,z_mm,force_n,contact_stress_mpa,status");
  std::map<std::pair<int, int>, double> force;  // (position, pin) -> sum of slice forces
  int rows = 0;
  while (std::getline(lines, line)) {
    ++rows;
    double crank = 0, z = 0, f = 0;
    int pin = 0, slice = 0;
    REQUIRE(std::sscanf(line.c_str(), "%lf,%d,%d,%lf,%lf", &crank, &pin, &slice, &z, &f) == 5);
    CHECK(z == doctest::Approx((slice - 0.5) * 12.0 / 20));
    force[{(rows - 1) / 800, pin}] += f;
  }
  CHECK(rows == 3 * 40 * 20);
  for (int p = 0; p < 3; ++p) {
    const auto& pos = doc["positions"][static_cast<std::size_t>(p)];
    REQUIRE(pos["slice_force_n"].size() == 40);
    for (int j = 0; j < 40; ++j) {
      const double total = pos["pin_force_n"][static_cast<std::size_t>(j)];
      CHECK(force[{p, j + 1}] == doctest::Approx(total).epsilon(1e-8).scale(1e-6));
      double sum = 0, moment = 0;
      for (int k = 0; k < 20; ++k) {
        const double f = pos["slice_force_n"][static_cast<std::size_t>(j)][static_cast<std::size_t>(k)];
        sum += f;
        moment += f * (k + 0.5) * 12.0 / 20;
      }
      if (total > 0) {
        CHECK(pos["load_centroid_mm"][static_cast<std::size_t>(j)].get<double>() == doctest::Approx(moment / sum).epsilon(1e-12));
      } else {
        CHECK(pos["load_centroid_mm"][static_cast<std::size_t>(j)].is_null());
      }
    }
  }
}

TEST_CASE("cli: ltca stiffness writes the loop, its read-offs and a backlash equal to ltca backlash") {
  // Liu 5.2 base over 5 positions of the mesh period, linearised (the deck's kinematics): the
  // backlash of every position is that of `ltca backlash --kinematics linearised` (same cranks).
  const std::string deck = Case("liu2021_sec52_base.toml");
  const auto dir = FreshFolder("stiffness");
  const auto r = RunCli({"stiffness", deck, "--set", "sweep.positions=5", "--solver", "compatibility", "--json", "-", "--csv",
                         (dir / "loop.csv").string(), "--svg", (dir / "loop.svg").string()});
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto b = RunCli({"backlash", deck, "--set", "sweep.positions=5", "--kinematics", "linearised", "--json", "-"});
  REQUIRE(b.code == 0);
  const auto bj = nlohmann::json::parse(b.out);
  REQUIRE(j["positions"].size() == 5);
  for (std::size_t i = 0; i < 5; ++i) {
    const auto& p = j["positions"][i];
    CHECK(p["crank_deg"].get<double>() == doctest::Approx(bj["positions"][i]["crank_deg"].get<double>()).epsilon(1e-12));
    CHECK(p["backlash_arcmin"].get<double>() ==
          doctest::Approx(bj["positions"][i]["backlash_arcsec"].get<double>() / 60.0).epsilon(1e-9));
    CHECK(p["curve"].size() == 84);  // 2 x 41 levels, zero torque twice on each branch
    CHECK(p["status"] == "success");
  }
  const auto& s = j["summary"];
  for (const char* key : {"torsional_rigidity_nm_per_arcmin", "lost_motion_arcmin", "backlash_arcmin"}) {
    CAPTURE(key);
    REQUIRE(s[key].is_number());
    CHECK(s[std::string(key) + "_min"].get<double>() <= s[key].get<double>());
    CHECK(s[std::string(key) + "_max"].get<double>() >= s[key].get<double>());
  }
  CHECK(s["backlash_arcmin"].get<double>() == doctest::Approx(bj["summary"]["mean_backlash_arcsec"].get<double>() / 60.0).epsilon(1e-9));
  CHECK(s["hysteresis"] == false);
  CHECK(s["note"].get<std::string>().find("no friction") != std::string::npos);
  CHECK(s["curve"].size() == 84);
  CHECK(s["curve"][0]["torque_nm"].get<double>() == -206.0);
  CHECK(s["curve"][0]["branch"] == "increasing");
  CHECK(s["curve"][83]["branch"] == "decreasing");
  CHECK(j["solver"]["name"] == "compatibility");
  CHECK(j["model"]["name"] == "plane");
  CHECK(j["stiffness"]["steps_per_branch"] == 41);
  // CSV: a row per curve point and position; SVG: the loop with its marks.
  std::istringstream csv(ReadText(dir / "loop.csv"));
  std::string line;
  int rows = 0;
  std::getline(csv, line);
  CHECK(line == "crank_deg,branch,torque_nm,twist_arcmin,status");
  while (std::getline(csv, line)) ++rows;
  CHECK(rows == 5 * 84);
  const std::string svg = ReadText(dir / "loop.svg");
  for (const char* mark : {"<svg", "torque (N*m)", "twist (arcmin", "backlash", "lost motion", "rigidity"}) {
    CAPTURE(mark);
    CHECK(svg.find(mark) != std::string::npos);
  }
  // One crank: no _min / _max.
  const auto one = RunCli({"stiffness", deck, "--crank-deg", "2", "--steps", "5", "--json", "-"});
  REQUIRE(one.code == 0);
  const auto oj = nlohmann::json::parse(one.out);
  CHECK(oj["summary"].contains("backlash_arcmin"));
  CHECK(!oj["summary"].contains("backlash_arcmin_min"));
  CHECK(oj["summary"]["curve"].size() == 12);
  CHECK(oj["stiffness"]["crank_deg"] == 2.0);
}

TEST_CASE("cli: ltca stiffness rejects bad settings naming the key, the value and what is expected") {
  const std::string deck = Case("liu2021_table1.toml");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--steps", "40"}, "steps_per_branch = 40: expected an odd integer"},
      {{"--set", "stiffness.steps_per_branch=1"}, "steps_per_branch = 1: expected an odd integer"},
      {{"--rigidity", "tangent"}, "tangent_torque_nm = nan: expected a finite torque other than 0"},
      {{"--rigidity", "tangent", "--tangent-torque-nm", "0"}, "tangent_torque_nm = 0: expected"},
      {{"--lost-motion-fraction", "1.5"}, "lost_motion_fraction = 1.5: expected a fraction"},
      {{"--set", "stiffness.rigidity=chord"}, "rigidity = \"chord\": expected \"secant\" or \"tangent\""},
      {{"--set", "stiffness.bogus=1"}, "[stiffness] unknown key 'bogus'"},
      {{"--set", "load.torque_nm=0"}, "torque_nm = 0: expected the rated torque"},
      {{"--crank-deg", "nan"}, "--crank-deg"},
  };
  for (const auto& [args, message] : cases) {
    std::vector<std::string> all = {"stiffness", deck, "--json", "-"};
    all.insert(all.end(), args.begin(), args.end());
    CAPTURE(message);
    const auto r = RunCli(all);
    CHECK(r.code == 2);
    CHECK(r.out.empty());
    CHECK(r.err.find(message) != std::string::npos);
  }
}

TEST_CASE("cli: ltca stiffness exits 1 with null figures where a solve failed, keeping the figures valid solves produced") {
  // cases/hard/law_cannot_carry.toml: 5e6 N*m is beyond what the sagitta law carries, so the levels
  // +-T and +-T / 2 fail (law-cannot-carry) and the rigidity is null; the lost motion (+-3 % of T)
  // and the backlash (zero torque) come from valid solves.
  const auto r = RunCli({"stiffness", Case("hard/law_cannot_carry.toml"), "--crank-deg", "0", "--steps", "5", "--json", "-"});
  CHECK(r.code == 1);
  const auto j = nlohmann::json::parse(r.out);
  const auto& s = j["summary"];
  CHECK(s["status"] == "failed");
  CHECK(s["failed_positions"] == 1);
  CHECK(s["torsional_rigidity_nm_per_arcmin"].is_null());
  CHECK(s["lost_motion_arcmin"].is_number());
  CHECK(s["backlash_arcmin"].is_number());
  CHECK(s["first_failure"].get<std::string>().find("law-cannot-carry") != std::string::npos);
  CHECK(j["positions"][0]["curve"][0]["twist_arcmin"].is_null());
  CHECK(r.err.find("n/a N*m/arcmin") != std::string::npos);
}

TEST_CASE("cli: ltca report into a folder that holds the user's files (a folder where one of its files goes) exits 2 before writing anything") {
  // A review found index.html (or solve.svg) as a folder reported only after the other files were
  // written, naming an option (--svg) the user never gave. A report now replaces its folder whole,
  // so a folder with anything it did not write is refused (no marker file; --force replaces it).
  for (const std::string blocked : {"index.html", "solve.svg"}) {
    CAPTURE(blocked);
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("ltca_report_blocked_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / blocked);
    std::ostringstream out, err;
    const int code = ltca::cli::Run({"report", Case("liu2021_sec52_base.toml"), "--set", "sweep.positions=3", "-o", dir.string()}, out, err);
    CHECK(code == 2);
    CHECK(err.str().find("--force") != std::string::npos);
    CHECK(err.str().find("--svg") == std::string::npos);
    int entries = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++entries;
    CHECK(entries == 1);  // only the folder that was in the way
    std::filesystem::remove_all(dir);
  }
}

TEST_CASE("cli: two outputs to one file are refused (exit 2, naming both options), as two to stdout are") {
  // A review found --json X --csv X accepted, the CSV silently replacing the JSON.
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("ltca_same_file_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string same = (dir / "out.x").string();
  const std::string also = (dir / "." / "out.x").string();  // the same file, spelled differently
  for (const auto& command : std::vector<std::vector<std::string>>{
           {"solve", Case("liu2021_table1.toml"), "--json", same, "--csv", same},
           {"backlash", Case("liu2021_table1.toml"), "--json", same, "--svg", also}}) {
    std::ostringstream out, err;
    CHECK(ltca::cli::Run(command, out, err) == 2);
    CHECK(err.str().find("--json") != std::string::npos);
    CHECK(!std::filesystem::exists(same));
  }
  std::ostringstream out, err;
  CHECK(ltca::cli::Run({"solve", Case("liu2021_table1.toml"), "--json", same, "--csv", (dir / "other.csv").string()}, out, err) == 0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("cli: ltca report takes the options of the analyses it runs: --samples, --threads, --no-worst-case, --kinematics (issue 27)") {
  // cases/jiang2022_tolerances.toml asks 1000 samples and the worst case; the report runs 12 on one
  // thread without the worst case, and every analysis under exact kinematics. The documents the
  // page is built from say so; bad values are refused as `ltca tolerance` refuses them.
  const auto dir = FreshFolder("report_options");
  const std::string deck = Case("jiang2022_tolerances.toml");
  const auto run = RunCli({"report", deck, "-o", dir.string(), "--samples", "12", "--threads", "1", "--no-worst-case",
                           "--kinematics", "exact", "--set", "sweep.positions=5"});
  INFO(run.err);
  REQUIRE(run.code == 0);
  const auto tolerance = nlohmann::json::parse(ReadText(dir / "tolerance.json"));
  CHECK(tolerance["summary"]["samples"] == 12);
  CHECK(!tolerance["summary"].contains("worst_case"));
  const auto solve = nlohmann::json::parse(ReadText(dir / "solve.json"));
  CHECK(solve["solver"]["kinematics"] == "exact");
  const auto stiffness = nlohmann::json::parse(ReadText(dir / "stiffness.json"));
  CHECK(stiffness["solver"]["kinematics"] == "exact");
  CHECK(ReadText(dir / "index.html").find("worst-case) runs were skipped") != std::string::npos);
  CHECK(RunCli({"report", deck, "-o", dir.string(), "--samples", "0"}).code == 2);
  CHECK(RunCli({"report", deck, "-o", dir.string(), "--samples", "3", "--threads", "5000"}).code == 2);
  CHECK(RunCli({"report", deck, "-o", dir.string(), "--kinematics", "sideways"}).code == 2);
  std::filesystem::remove_all(dir);
}

TEST_CASE("cli: the solve figure of a two-disc deck over its 91 positions stays under 300 kB, SVG defaults left out (issue 27)") {
  // It was 2.34 MB: a map is thousands of PLplot cells, each a polyline restating SVG's defaults.
  // Now cells of one colour in a column are one rectangle, the defaults are left out, and runs of
  // unfilled lines of one style (dashes, grids, ticks) are one path of subpaths (346.7 kB before
  // the last; rendered the same in Chromium up to anti-aliasing: 20 pixels differ by more than
  // 20 % on a 2000 x 1510 screenshot of the tolerance histograms).
  // Since stop 37 a map's cells take the colour of their colour-bar step (64) and same-step runs
  // of neighbouring columns are one rectangle, drawn colour by colour so that each colour's are one
  // path; texts lose their default opacity and character references. So the maps show every one
  // of the 91 positions (they showed 1 in 2), also for two identical discs at crank 40-49 deg,
  // whose bands of loaded pins were 352 kB at 1 in 2.
  const auto path = std::filesystem::temp_directory_path() / ("ltca_cli_test_rv2_" + std::to_string(::getpid()) + ".svg");
  for (const std::vector<std::string>& sets :
       {std::vector<std::string>{}, std::vector<std::string>{"--set", "second_disc.indexing_deviation_mm=0", "--set",
                                                             "sweep.crank_start_deg=40", "--set", "sweep.crank_end_deg=49"}}) {
    CAPTURE(sets.size());
    std::vector<std::string> args = {"solve", Case("rv_two_discs.toml"), "--svg", path.string()};
    args.insert(args.end(), sets.begin(), sets.end());
    REQUIRE(RunCli(args).code == 0);
    const std::string svg = ReadText(path);
    CHECK(svg.size() < 300000);
    CHECK(svg.find("fill-rule=\"nonzero\"") == std::string::npos);
    std::size_t opaque = 0;  // the page's background rectangle states it; no text or cell does
    for (std::size_t at = svg.find("fill-opacity=\"1.000000\""); at != std::string::npos; at = svg.find("fill-opacity=\"1.000000\"", at + 1)) ++opaque;
    CHECK(opaque <= 1);
    CHECK(svg.find("<path stroke=") != std::string::npos);  // runs of lines merged
    CHECK(svg.find("Z M") != std::string::npos);            // rectangles of one colour merged
    CHECK(svg.find("cells=\"91x40\"") != std::string::npos);  // every position in the maps
    CHECK(svg.find("position in") == std::string::npos);
  }
  std::filesystem::remove(path);
}

TEST_CASE("cli: a decimated series keeps every point up to its buckets, and beyond them each run's least, largest and first gap, at most three a run (issue 46)") {
  using ltca::cli::DecimatedSeries;
  // No more points than buckets: every point, as given.
  DecimatedSeries all(5, 10);
  const std::vector<double> y = {3.0, NAN, 1.0, 4.0, 1.0};
  for (std::size_t i = 0; i < y.size(); ++i) all.Add(static_cast<std::int64_t>(i), 10.0 * static_cast<double>(i), y[i]);
  CHECK(all.stride() == 1);
  REQUIRE(all.x() == std::vector<double>{0.0, 10.0, 20.0, 30.0, 40.0});
  CHECK(all.y()[0] == 3.0);
  CHECK(std::isnan(all.y()[1]));  // a failed point: a gap
  CHECK(all.y()[4] == 1.0);
  // Runs of 4 (12 points in 3 buckets): of 0..3 the least (1 at 2) and the largest (5 at 1), in
  // their order; of 4..7 the first gap (5), the least (0 at 6) and the largest (9 at 7); of 8..11
  // the largest (7 at 8), the first gap (9) and the least (0 at 10, the first of equals).
  CHECK(DecimatedSeries(9, 3).stride() == 3);
  DecimatedSeries fours(12, 3);
  CHECK(fours.stride() == 4);
  const std::vector<double> v = {2.0, 5.0, 1.0, 3.0, 4.0, NAN, 0.0, 9.0, 7.0, NAN, 0.0, 0.0};
  for (std::size_t i = 0; i < v.size(); ++i) fours.Add(static_cast<std::int64_t>(i), static_cast<double>(i), v[i]);
  CHECK(fours.x() == std::vector<double>{1.0, 2.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0});
  // A million points in at most 2,000 runs, some numbers skipped (an evaluation not drawn): at
  // most two kept a run without gaps, the extremes among them.
  DecimatedSeries many(1'000'000);
  double lo = INFINITY, hi = -INFINITY;
  for (std::int64_t i = 0; i < 1'000'000; ++i) {
    if (i % 3 == 1) continue;
    const double value = std::sin(0.001 * static_cast<double>(i)) * static_cast<double>(i % 977);
    lo = std::min(lo, value), hi = std::max(hi, value);
    many.Add(i, static_cast<double>(i), value);
  }
  CHECK(many.stride() == 500);
  CHECK(many.x().size() <= 2u * 2000u);
  CHECK(many.x().size() > 2000u);
  CHECK(std::is_sorted(many.x().begin(), many.x().end()));
  CHECK(*std::min_element(many.y().begin(), many.y().end()) == lo);
  CHECK(*std::max_element(many.y().begin(), many.y().end()) == hi);
}
