// ISO 281:2007's modified rating life (a_ISO, 9.3) of a stage's bearings in `ltca solve`. The
// expected values are recomputed here from the lives, loads and speed the same JSON prints and the
// deck's inputs, by the standard's formulas written again below (ModifiedLife: nu_1, kappa, a_ISO of
// a radial roller bearing; tests/contact/life_modification_test.cpp checks the library's against
// hand values): the bearing's speed n = 1e6 L10 / (60 L10h) from the printed basic life, C_u =
// C_0r / 8.2 (Annex B) or the given one, P the printed mean equivalent load for the basic life and
// P_lz for the load-zone life. Tolerance 1e-12 relative (the same arithmetic in another order, the
// JSON's round trip aside). A spectrum's modified lives are Miner's rule over the bins' printed
// modified lives, each bin at its own speed and so its own kappa.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"

namespace modified_life_test {

const std::string kDeck = std::string(LTCA_CASES_DIR) + "/stage/cycloidal_drive.toml";
const std::string kOil = "operation.oil_kinematic_viscosity_mm2_per_s=68";  // ISO VG 68 near 40 C

/// ISO 281:2007 9.3.3, radial roller bearings: a_ISO from nu (mm^2/s), n (r/min), D_pw (mm) and
/// e_C C_u / P, kappa clamped to [0.1, 4], a_ISO to 50.
double ModifiedLife(double nu, double rpm, double pitch_diameter, double load_ratio) {
  const double nu_1 = rpm < 1000.0 ? 45000.0 * std::pow(rpm, -0.83) * std::pow(pitch_diameter, -0.5)
                                   : 4500.0 * std::pow(rpm, -0.5) * std::pow(pitch_diameter, -0.5);
  const double kappa = std::min(std::max(nu / nu_1, 0.1), 4.0);
  double c = 1.2348, e = 0.071739;
  if (kappa < 0.4) c = 1.3993, e = 0.054381;
  else if (kappa < 1.0) e = 0.19087;
  const double bracket = 1.0 - (1.5859 - c / std::pow(kappa, e)) * std::pow(load_ratio, 0.4);
  return bracket <= 0.0 ? 50.0 : std::min(0.1 * std::pow(bracket, -9.185), 50.0);
}

nlohmann::json Solve(const std::vector<std::string>& args) {
  const auto r = ltca::test::RunCli(args);
  REQUIRE(r.code == 0);
  return nlohmann::json::parse(r.out);
}

std::vector<double> Numbers(const nlohmann::json& a) { return a.get<std::vector<double>>(); }

/// A stage deck of cases/ with `extra` appended, written to a temporary file.
std::string DeckWith(const std::string& deck, const std::string& extra, const std::string& name) {
  std::ifstream in(std::string(LTCA_CASES_DIR) + "/stage/" + deck);
  std::stringstream text;
  text << in.rdbuf() << "\n" << extra;
  const auto path = std::filesystem::temp_directory_path() / ("ltca_modified_life_test_" + name + ".toml");
  std::ofstream(path) << text.str();
  return path.string();
}

/// The stage's modified lives against the recomputation from its printed figures.
void CheckStage(const nlohmann::json& stage, double nu, double contamination, double fatigue_load_limit) {
  const nlohmann::json& m = stage.at("modified_life");
  const double l10 = stage.at("l10_million_revolutions").at(0).get<double>();
  const double rpm = 1e6 * l10 / (60.0 * stage.at("l10_hours").at(0).get<double>());
  const double pitch_diameter = 40.0;  // the deck's pitch_diameter_mm
  CHECK(m.at("kinematic_viscosity_mm2_per_s").get<double>() == nu);
  CHECK(m.at("contamination_factor").get<double>() == contamination);
  CHECK(m.at("fatigue_load_limit_n").get<double>() == doctest::Approx(fatigue_load_limit).epsilon(1e-15));
  const double nu_1 = rpm < 1000.0 ? 45000.0 * std::pow(rpm, -0.83) / std::sqrt(pitch_diameter) : 4500.0 / std::sqrt(rpm * pitch_diameter);
  CHECK(m.at("reference_viscosity_mm2_per_s").get<double>() == doctest::Approx(nu_1).epsilon(1e-12));
  CHECK(m.at("viscosity_ratio").get<double>() == doctest::Approx(nu / nu_1).epsilon(1e-12));
  const std::vector<double> p = Numbers(stage.at("mean_equivalent_load_n")), p_lz = Numbers(stage.at("load_zone_equivalent_load_n"));
  const std::vector<double> l10h = Numbers(stage.at("l10_hours")), lzh = Numbers(stage.at("load_zone_life_hours"));
  REQUIRE(!p.empty());
  double shortest = INFINITY, shortest_zone = INFINITY;
  for (std::size_t b = 0; b < p.size(); ++b) {
    CAPTURE(b);
    const double a = ModifiedLife(nu, rpm, pitch_diameter, contamination * fatigue_load_limit / p[b]);
    const double a_zone = ModifiedLife(nu, rpm, pitch_diameter, contamination * fatigue_load_limit / p_lz[b]);
    CHECK(m.at("load_ratio").at(b).get<double>() == doctest::Approx(contamination * fatigue_load_limit / p[b]).epsilon(1e-12));
    CHECK(m.at("a_iso").at(b).get<double>() == doctest::Approx(a).epsilon(1e-12));
    CHECK(m.at("life_hours").at(b).get<double>() == doctest::Approx(a * l10h[b]).epsilon(1e-12));
    CHECK(m.at("load_zone_a_iso").at(b).get<double>() == doctest::Approx(a_zone).epsilon(1e-12));
    CHECK(m.at("load_zone_life_hours").at(b).get<double>() == doctest::Approx(a_zone * lzh[b]).epsilon(1e-12));
    shortest = std::min(shortest, a * l10h[b]);
    shortest_zone = std::min(shortest_zone, a_zone * lzh[b]);
  }
  CHECK(m.at("shortest_life_hours").get<double>() == doctest::Approx(shortest).epsilon(1e-12));
  CHECK(m.at("shortest_load_zone_life_hours").get<double>() == doctest::Approx(shortest_zone).epsilon(1e-12));
}

nlohmann::json Verdict(const nlohmann::json& stage, const std::string& figure) {
  for (const auto& row : stage.at("verdicts")) {
    if (row.at("figure") == figure) return row;
  }
  return nullptr;
}

}  // namespace modified_life_test

TEST_CASE("app: a stage's modified lives are ISO 281's a_ISO on the basic and load-zone lives it prints") {
  using namespace modified_life_test;
  // Defaults: e_C 0.5 (ISO 281 Table 13, normal cleanliness), C_u = C_0r / 8.2 (Annex B).
  const nlohmann::json j = Solve({"solve", kDeck, "--json", "-", "--set", kOil, "--set", "allowables.bearing_life_hours=20000"});
  const nlohmann::json& stage = j.at("summary").at("stage");
  CheckStage(stage, 68.0, 0.5, 39424.0 / 8.2);
  CHECK(stage.at("modified_life").at("fatigue_load_limit_basis").get<std::string>().find("Annex B") != std::string::npos);
  // Both modified lives are judged against the required life, with the value the summary prints.
  const auto basic = Verdict(stage, "stage.shortest_modified_life_hours");
  const auto zone = Verdict(stage, "stage.shortest_load_zone_modified_life_hours");
  REQUIRE(basic.is_object());
  REQUIRE(zone.is_object());
  CHECK(basic.at("value") == stage.at("modified_life").at("shortest_life_hours"));
  CHECK(zone.at("value") == stage.at("modified_life").at("shortest_load_zone_life_hours"));
  CHECK(basic.at("verdict") == (basic.at("value").get<double>() >= 20000.0 ? "pass" : "FAIL"));
  CHECK(zone.at("verdict") == (zone.at("value").get<double>() >= 20000.0 ? "pass" : "FAIL"));
  // The bearing maker's C_u and a dirtier oil, and a thin oil at a low speed (kappa < 1).
  CheckStage(Solve({"solve", kDeck, "--json", "-", "--set", kOil, "--set", "bearing.fatigue_load_limit_n=4000", "--set",
                    "bearing.contamination_factor=0.2"})
                 .at("summary")
                 .at("stage"),
             68.0, 0.2, 4000.0);
  const nlohmann::json thin = Solve({"solve", kDeck, "--json", "-", "--set", "operation.oil_kinematic_viscosity_mm2_per_s=10", "--set",
                                     "operation.input_speed_rpm=300"})
                                  .at("summary")
                                  .at("stage");
  CheckStage(thin, 10.0, 0.5, 39424.0 / 8.2);
  CHECK(thin.at("modified_life").at("viscosity_ratio").get<double>() < 0.4);
  CHECK(thin.at("modified_life").at("a_iso").at(0).get<double>() < 1.0);  // below the basic life
  // The text names the modified lives and their inputs.
  const auto text = ltca::test::RunCli({"solve", kDeck, "--set", kOil});
  REQUIRE(text.code == 0);
  CHECK(text.out.find("modified life L10m") != std::string::npos);
  CHECK(text.out.find("modified load-zone") != std::string::npos);
  CHECK(text.out.find("e_C 0.5") != std::string::npos);
}

TEST_CASE("app: without the oil's viscosity a stage's summary has no modified life and no row for it (today's answers)") {
  using namespace modified_life_test;
  const nlohmann::json stage =
      Solve({"solve", kDeck, "--json", "-", "--set", "allowables.bearing_life_hours=8000"}).at("summary").at("stage");
  CHECK_FALSE(stage.contains("modified_life"));
  CHECK(Verdict(stage, "stage.shortest_modified_life_hours").is_null());
  CHECK(stage.at("verdicts").size() == 4);  // L10, load-zone life, s_0, roller stress
  // e_C and C_u alone change nothing: they serve a_ISO only.
  const nlohmann::json same = Solve({"solve", kDeck, "--json", "-", "--set", "allowables.bearing_life_hours=8000", "--set",
                                     "bearing.contamination_factor=0.1", "--set", "bearing.fatigue_load_limit_n=1000"})
                                  .at("summary")
                                  .at("stage");
  CHECK(same == stage);
  const auto text = ltca::test::RunCli({"solve", kDeck});
  CHECK(text.out.find("modified") == std::string::npos);
}

TEST_CASE("app: a one-bin spectrum's modified lives equal the plain run's, a two-bin one's are Miner's over the bins' own kappa") {
  using namespace modified_life_test;
  const std::string one = DeckWith("cycloidal_drive.toml", "[[load_spectrum]]\ntorque_nm = 206\nspeed_rpm = 1500\ntime_share = 1\n", "one_bin");
  const nlohmann::json j = Solve({"solve", one, "--json", "-", "--set", kOil});
  const nlohmann::json& plain = j.at("summary").at("stage").at("modified_life");
  const nlohmann::json& spectrum = j.at("spectrum");
  for (const auto& [combined, single] : {std::pair{"modified_life_hours", "life_hours"}, std::pair{"load_zone_modified_life_hours", "load_zone_life_hours"}}) {
    const std::vector<double> a = Numbers(plain.at(single)), c = Numbers(spectrum.at(combined));
    REQUIRE(!a.empty());
    REQUIRE(c.size() == a.size());
    for (std::size_t k = 0; k < a.size(); ++k) CHECK(c[k] == doctest::Approx(a[k]).epsilon(1e-12));
  }
  CHECK(spectrum.at("shortest_modified_life_hours").get<double>() ==
        doctest::Approx(plain.at("shortest_life_hours").get<double>()).epsilon(1e-12));
  CHECK(spectrum.at("bins").at(0).at("viscosity_ratio") == plain.at("viscosity_ratio"));

  // Two bins at different speeds: each bin's kappa is its own speed's; the lives Miner's rule.
  const std::string two = DeckWith("cycloidal_drive.toml",
                                   "[[load_spectrum]]\ntorque_nm = 100\nspeed_rpm = 300\ntime_share = 0.4\n\n"
                                   "[[load_spectrum]]\ntorque_nm = 206\nspeed_rpm = 2000\ntime_share = 0.6\n",
                                   "two_bins");
  const nlohmann::json s = Solve({"solve", two, "--json", "-", "--set", kOil}).at("spectrum");
  const auto single = [&](const std::string& torque, const std::string& rpm) {
    return Solve({"solve", kDeck, "--json", "-", "--set", kOil, "--set", "load.torque_nm=" + torque, "--set", "operation.input_speed_rpm=" + rpm})
        .at("summary")
        .at("stage");
  };
  const nlohmann::json a = single("100", "300"), b = single("206", "2000");
  CheckStage(a, 68.0, 0.5, 39424.0 / 8.2);  // each single run is ISO 281's at its own speed
  CHECK(s.at("bins").at(0).at("viscosity_ratio") == a.at("modified_life").at("viscosity_ratio"));
  CHECK(s.at("bins").at(1).at("viscosity_ratio") == b.at("modified_life").at("viscosity_ratio"));
  CHECK(a.at("modified_life").at("viscosity_ratio").get<double>() < b.at("modified_life").at("viscosity_ratio").get<double>());
  for (const auto& [combined, life] : {std::pair{"modified_life_hours", "life_hours"}, std::pair{"load_zone_modified_life_hours", "load_zone_life_hours"}}) {
    const std::vector<double> x = Numbers(a.at("modified_life").at(life)), y = Numbers(b.at("modified_life").at(life));
    const std::vector<double> c = Numbers(s.at(combined));
    REQUIRE(c.size() == x.size());
    for (std::size_t k = 0; k < c.size(); ++k) CHECK(c[k] == doctest::Approx(1.0 / (0.4 / x[k] + 0.6 / y[k])).epsilon(1e-12));
  }
  const auto text = ltca::test::RunCli({"solve", two, "--set", kOil});
  CHECK(text.out.find("spectrum modified L10m") != std::string::npos);
}

TEST_CASE("app: the modified life's inputs are refused with the key, value and expectation named") {
  using namespace modified_life_test;
  const auto refused = [](const std::vector<std::string>& args) {
    const auto r = ltca::test::RunCli(args);
    CHECK(r.code == 2);
    CHECK(r.out.empty());
    return r.err;
  };
  CHECK(refused({"solve", kDeck, "--json", "-", "--set", "operation.oil_kinematic_viscosity_mm2_per_s=0"})
            .find("[operation] oil_kinematic_viscosity_mm2_per_s = 0: expected a kinematic viscosity above 0") != std::string::npos);
  CHECK(refused({"solve", kDeck, "--json", "-", "--set", kOil, "--set", "bearing.contamination_factor=1.5"})
            .find("[bearing] contamination_factor = 1.5: expected a contamination factor e_C in [0, 1]") != std::string::npos);
  CHECK(refused({"solve", kDeck, "--json", "-", "--set", kOil, "--set", "bearing.fatigue_load_limit_n=-1"})
            .find("[bearing] fatigue_load_limit_n = -1") != std::string::npos);
  // No C_u and no C_0r to estimate it from.
  CHECK(refused({"solve", kDeck, "--json", "-", "--set", kOil, "--set", "bearing.static_load_rating_n=0"})
            .find("[bearing] fatigue_load_limit_n is 0 and ISO 281 Annex B's estimate") != std::string::npos);
  // Without the pitch diameter there is no nu_1.
  CHECK(refused({"solve", kDeck, "--json", "-", "--set", kOil, "--set", "bearing.pitch_diameter_mm=0"})
            .find("expected [output] with [bearing] kind = \"rollers\", pitch_diameter_mm and dynamic_load_rating_n") !=
        std::string::npos);
}
