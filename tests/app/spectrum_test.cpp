// Issue 50, item 5: a load spectrum ([[load_spectrum]]) in `ltca solve`. Its bins must be the deck's
// sweep at each bin's torque and crank speed, i.e. the plain runs with `--set load.torque_nm=T
// --set operation.input_speed_rpm=n`, and its lives the Palmgren-Miner combination of those runs'
// lives over the time shares, L = 1 / sum(share_i / L_i), recomputed here from the single runs'
// printed lives (tolerance 1e-12 relative: the same arithmetic, the JSON round trip aside).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "ltca/analysis/spectrum.hpp"

namespace spectrum_test {

/// A stage deck of cases/ with `bins` appended, written to a temporary file.
std::string DeckWith(const std::string& deck, const std::string& bins, const std::string& name) {
  std::ifstream in(std::string(LTCA_CASES_DIR) + "/stage/" + deck);
  std::stringstream text;
  text << in.rdbuf() << "\n" << bins;
  const auto path = std::filesystem::temp_directory_path() / ("ltca_spectrum_test_" + name + ".toml");
  std::ofstream(path) << text.str();
  return path.string();
}

nlohmann::json Solve(const std::vector<std::string>& args) {
  const auto r = ltca::test::RunCli(args);
  REQUIRE(r.code == 0);
  return nlohmann::json::parse(r.out);
}

/// The plain run of the deck at a torque (N*m) and crank speed (rpm).
nlohmann::json SingleRun(const std::string& deck, const std::string& torque, const std::string& rpm) {
  return Solve({"solve", std::string(LTCA_CASES_DIR) + "/stage/" + deck, "--json", "-", "--set", "load.torque_nm=" + torque,
                "--set", "operation.input_speed_rpm=" + rpm});
}

std::vector<double> Numbers(const nlohmann::json& a) { return a.get<std::vector<double>>(); }

}  // namespace spectrum_test

TEST_CASE("app: a two-bin load spectrum's lives are Miner's combination of the two single runs") {
  using namespace spectrum_test;
  const std::string deck = DeckWith("rv_two_discs_cranks.toml",
                                    "[[load_spectrum]]\ntorque_nm = 150\nspeed_rpm = 1000\ntime_share = 0.25\n\n"
                                    "[[load_spectrum]]\ntorque_nm = 412\nspeed_rpm = 2500\ntime_share = 0.75\n",
                                    "two_bins");
  const nlohmann::json spectrum = Solve({"solve", deck, "--json", "-"}).at("spectrum");
  const nlohmann::json one = SingleRun("rv_two_discs_cranks.toml", "150", "1000").at("summary");
  const nlohmann::json two = SingleRun("rv_two_discs_cranks.toml", "412", "2500").at("summary");
  REQUIRE(spectrum.at("bins").size() == 2);
  for (const char* life : {"l10_hours", "load_zone_life_hours"}) {
    const std::vector<double> a = Numbers(one.at("stage").at(life)), b = Numbers(two.at("stage").at(life));
    const std::vector<double> combined = Numbers(spectrum.at(life));
    REQUIRE(a.size() == 6);  // three cranks, two discs: six bearings
    REQUIRE(combined.size() == a.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
      CAPTURE(life);
      CAPTURE(k);
      CHECK(combined[k] == doctest::Approx(1.0 / (0.25 / a[k] + 0.75 / b[k])).epsilon(1e-12));
      // The combination lies between the two bins' lives (the 412 N*m bin at 2500 rpm is the shorter).
      CHECK(combined[k] > b[k]);
      CHECK(combined[k] < a[k]);
      // Each bin's own lives are the single run's.
      CHECK(spectrum.at("bins").at(0).at(life).at(k).get<double>() == doctest::Approx(a[k]).epsilon(1e-12));
      CHECK(spectrum.at("bins").at(1).at(life).at(k).get<double>() == doctest::Approx(b[k]).epsilon(1e-12));
    }
  }
  // The bins' figures are the single runs'.
  for (const auto& [bin, run] : {std::pair{0, one}, std::pair{1, two}}) {
    const nlohmann::json& b = spectrum.at("bins").at(bin);
    CHECK(b.at("mean_te_arcsec").get<double>() == doctest::Approx(run.at("mean_te_arcsec").get<double>()).epsilon(1e-12));
    CHECK(b.at("max_pin_force_n").get<double>() == doctest::Approx(run.at("max_pin_force_n").get<double>()).epsilon(1e-12));
    CHECK(b.at("max_contact_stress_mpa").get<double>() ==
          doctest::Approx(run.at("max_contact_stress_mpa").get<double>()).epsilon(1e-12));
  }
  CHECK(spectrum.at("bins").at(1).at("torque_nm").get<double>() == 412.0);
  CHECK(spectrum.at("bins").at(0).at("speed_rpm").get<double>() == doctest::Approx(1000.0).epsilon(1e-12));
  CHECK(spectrum.at("bins").at(0).at("time_share").get<double>() == 0.25);
}

TEST_CASE("app: a one-bin load spectrum's lives equal the plain run's") {
  using namespace spectrum_test;
  // The deck's own torque and speed (206 N*m, 1500 rpm).
  const std::string deck = DeckWith("cycloidal_drive.toml", "[[load_spectrum]]\ntorque_nm = 206\nspeed_rpm = 1500\ntime_share = 1\n",
                                    "one_bin");
  const nlohmann::json j = Solve({"solve", deck, "--json", "-"});
  const nlohmann::json& spectrum = j.at("spectrum");
  const nlohmann::json& plain = j.at("summary").at("stage");
  for (const char* life : {"l10_hours", "load_zone_life_hours"}) {
    const std::vector<double> a = Numbers(plain.at(life)), combined = Numbers(spectrum.at(life));
    REQUIRE(!a.empty());
    REQUIRE(combined.size() == a.size());
    for (std::size_t k = 0; k < a.size(); ++k) CHECK(combined[k] == doctest::Approx(a[k]).epsilon(1e-12));
  }
  CHECK(spectrum.at("shortest_l10_hours").get<double>() == doctest::Approx(plain.at("shortest_l10_hours").get<double>()).epsilon(1e-12));
  CHECK(spectrum.at("shortest_load_zone_life_hours").get<double>() ==
        doctest::Approx(plain.at("shortest_load_zone_life_hours").get<double>()).epsilon(1e-12));
  // The pitting safety over one bin is the plain run's S_H (SpectrumContactSafety with one load).
  const nlohmann::json rated = Solve({"solve", deck, "--json", "-", "--set", "allowables.contact_life_hours=20000"});
  CHECK(rated.at("spectrum").at("smallest_pitting_safety").get<double>() ==
        doctest::Approx(rated.at("summary").at("contact_fatigue").at("smallest_safety").get<double>()).epsilon(1e-12));
  // The text names the spectrum's lives.
  const auto text = ltca::test::RunCli({"solve", deck});
  CHECK(text.out.find("load spectrum          1 bins") != std::string::npos);
  CHECK(text.out.find("spectrum load-zone") != std::string::npos);
}

TEST_CASE("app: a load spectrum is refused with the entry, key and value named") {
  using namespace spectrum_test;
  const auto refused = [](const std::string& bins, const std::string& name) {
    const auto r = ltca::test::RunCli({"solve", DeckWith("cycloidal_drive.toml", bins, name), "--json", "-"});
    CHECK(r.code == 2);
    CHECK(r.out.empty());  // no partial document
    return r.err;
  };
  const std::string ok = "[[load_spectrum]]\ntorque_nm = 100\nspeed_rpm = 1000\ntime_share = 0.5\n";
  CHECK(refused(ok, "sum").find("the shares add to 0.5: expected 1") != std::string::npos);
  CHECK(refused(ok + "[[load_spectrum]]\ntorque_nm = 100\nspeed_rpm = 0\ntime_share = 0.5\n", "speed")
            .find("[[load_spectrum]] #2 speed_rpm = 0: expected a crank speed > 0") != std::string::npos);
  CHECK(refused(ok + "[[load_spectrum]]\ntorque_nm = 100\ntime_share = 0.5\n", "missing")
            .find("[load_spectrum #2] missing required key 'speed_rpm'") != std::string::npos);
  CHECK(refused(ok + "[[load_spectrum]]\ntorque_nm = 100\nspeed_rpm = 1000\ntime_share = 0.5\nshare = 1\n", "unknown")
            .find("[load_spectrum #2] unknown key 'share'") != std::string::npos);
  CHECK(refused("[[load_spectrum]]\ntorque_nm = 100\nspeed_rpm = 1000\ntime_share = 1.5\n", "share")
            .find("[[load_spectrum]] #1 time_share = 1.5: expected a share of the time > 0 and <= 1") != std::string::npos);
  // A single table ([load_spectrum]) instead of an array of them.
  CHECK(refused("[load_spectrum]\ntorque_nm = 100\nspeed_rpm = 1000\ntime_share = 1\n", "table").find("[[load_spectrum]]: expected an array of tables") != std::string::npos);
}

TEST_CASE("analysis: Miner's rule over a spectrum's bins, by hand") {
  // 0.5 h share at 1000 h and 0.5 at 4000 h: damage per hour 0.5/1000 + 0.5/4000 = 6.25e-4, L = 1600 h.
  CHECK(ltca::analysis::MinerHours({1000.0, 4000.0}, {0.5, 0.5}) == doctest::Approx(1600.0).epsilon(1e-15));
  // A bin without load (infinite life) adds no damage; a bin not rated makes the life unknown.
  CHECK(ltca::analysis::MinerHours({1000.0, INFINITY}, {0.5, 0.5}) == doctest::Approx(2000.0).epsilon(1e-15));
  CHECK(std::isnan(ltca::analysis::MinerHours({1000.0, NAN}, {0.5, 0.5})));
}

TEST_CASE("app: an idle bin of a load spectrum adds no damage: half the time idle doubles every life") {
  // Review finding: an unloaded bearing's infinite life was taken as missing, and every combined
  // life printed n/a. Miner: L = 1 / (0.5 / inf + 0.5 / L_loaded) = 2 L_loaded.
  using namespace spectrum_test;
  const std::string deck = DeckWith("cycloidal_drive.toml",
                                    "[[load_spectrum]]\ntorque_nm = 0\nspeed_rpm = 1500\ntime_share = 0.5\n\n"
                                    "[[load_spectrum]]\ntorque_nm = 206\nspeed_rpm = 1500\ntime_share = 0.5\n",
                                    "idle_bin");
  const nlohmann::json spectrum = Solve({"solve", deck, "--json", "-", "--set", "sweep.positions=13"}).at("spectrum");
  const nlohmann::json loaded = Solve({"solve", std::string(LTCA_CASES_DIR) + "/stage/cycloidal_drive.toml", "--json", "-",
                                       "--set", "sweep.positions=13", "--set", "load.torque_nm=206", "--set",
                                       "operation.input_speed_rpm=1500"})
                                    .at("summary");
  for (const char* life : {"l10_hours", "load_zone_life_hours"}) {
    CAPTURE(life);
    const std::vector<double> combined = Numbers(spectrum.at(life)), single = Numbers(loaded.at("stage").at(life));
    REQUIRE(combined.size() == single.size());
    for (std::size_t i = 0; i < single.size(); ++i) CHECK(combined[i] == doctest::Approx(2.0 * single[i]).epsilon(1e-12));
  }
}

TEST_CASE("app: ltca report of a deck with a load spectrum has its section and document, the solve's spectrum") {
  using namespace spectrum_test;
  const std::string deck = DeckWith("cycloidal_drive.toml",
                                    "[[load_spectrum]]\ntorque_nm = 150\nspeed_rpm = 1000\ntime_share = 0.25\n\n"
                                    "[[load_spectrum]]\ntorque_nm = 206\nspeed_rpm = 1500\ntime_share = 0.75\n",
                                    "report");
  const auto folder = std::filesystem::temp_directory_path() / "ltca_spectrum_test_report";
  std::filesystem::remove_all(folder);
  const auto r = ltca::test::RunCli({"report", deck, "-o", folder.string(), "--set", "sweep.positions=12", "--set",
                                     "sweep.crank_end_deg=330"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  std::ifstream in(folder / "spectrum.json");
  REQUIRE(in.good());
  const nlohmann::json page = nlohmann::json::parse(in);
  const nlohmann::json solved =
      Solve({"solve", deck, "--json", "-", "--set", "sweep.positions=12", "--set", "sweep.crank_end_deg=330"}).at("spectrum");
  for (const char* life : {"l10_hours", "load_zone_life_hours", "pitting_life_hours"}) {
    CAPTURE(life);
    REQUIRE(page.at(life).size() == solved.at(life).size());
    for (std::size_t k = 0; k < solved.at(life).size(); ++k) CHECK(page.at(life).at(k) == solved.at(life).at(k));
  }
  std::ifstream html(folder / "index.html");
  std::stringstream text;
  text << html.rdbuf();
  CHECK(text.str().find("<h2 id=\"spectrum\">Load spectrum</h2>") != std::string::npos);
  CHECK(text.str().find("spectrum: shortest pitting life (h)") != std::string::npos);
  // The worst bin's static figures: one row a figure, its value beside the bin that sets it.
  const std::string row = "<tr data-key=\"worst bin.max_contact_stress_mpa\">";
  const std::size_t at = text.str().find(row);
  REQUIRE(at != std::string::npos);
  const std::string line = text.str().substr(at, text.str().find('\n', at) - at);
  CHECK(line.find(fmt::format("<td>{}</td></tr>", solved.at("max_contact_stress_bin").get<int>())) != std::string::npos);
  std::filesystem::remove_all(folder);
}

TEST_CASE("app: a load spectrum's efficiency is the energy ratio of the single runs, one bin is the plain run, an idle bin delivers and loses nothing") {
  using namespace spectrum_test;
  // Efficiency over the duty cycle: sum share P_out / sum share (P_out + P_loss), each bin's powers
  // the plain run's at its torque and crank speed (docs/efficiency.md, "Over a load spectrum").
  const std::vector<std::string> friction = {"--set", "friction.coefficient=0.05", "--set", "friction.output_pin_coefficient=0.03",
                                             "--set", "friction.bearing_coefficient=0.0015", "--set", "sweep.positions=7"};
  const auto efficiency = [&](std::vector<std::string> args) {
    args.insert(args.begin(), "efficiency");
    args.insert(args.end(), friction.begin(), friction.end());
    args.insert(args.end(), {"--json", "-"});
    return Solve(args);
  };
  const auto single = [&](const std::string& torque, const std::string& rpm) {
    return efficiency({std::string(LTCA_CASES_DIR) + "/stage/cycloidal_drive.toml", "--set", "load.torque_nm=" + torque, "--set",
                       "operation.input_speed_rpm=" + rpm})
        .at("summary");
  };
  const nlohmann::json one = single("100", "300"), two = single("206", "1000");
  const nlohmann::json spectrum = efficiency({DeckWith("cycloidal_drive.toml",
                                                       "[[load_spectrum]]\ntorque_nm = 100\nspeed_rpm = 300\ntime_share = 0.3\n\n"
                                                       "[[load_spectrum]]\ntorque_nm = 206\nspeed_rpm = 1000\ntime_share = 0.5\n\n"
                                                       "[[load_spectrum]]\ntorque_nm = 0\nspeed_rpm = 1000\ntime_share = 0.2\n",
                                                       "efficiency")})
                                      .at("spectrum");
  REQUIRE(spectrum.at("bins").size() == 3);
  CHECK(spectrum.at("succeeded").get<bool>());
  const double out = 0.3 * one.at("output_power_w").get<double>() + 0.5 * two.at("output_power_w").get<double>();
  const double loss = 0.3 * one.at("power_loss_w").get<double>() + 0.5 * two.at("power_loss_w").get<double>();
  CHECK(spectrum.at("output_power_w").get<double>() == doctest::Approx(out).epsilon(1e-12));
  CHECK(spectrum.at("power_loss_w").get<double>() == doctest::Approx(loss).epsilon(1e-12));
  CHECK(spectrum.at("efficiency").get<double>() == doctest::Approx(out / (out + loss)).epsilon(1e-12));
  for (const char* source : {"mesh", "output", "bearings"}) {
    CAPTURE(source);
    const double expected = 0.3 * one.at("power_loss_by_source_w").at(source).get<double>() +
                            0.5 * two.at("power_loss_by_source_w").at(source).get<double>();
    CHECK(expected > 0.0);
    CHECK(spectrum.at("power_loss_by_source_w").at(source).get<double>() == doctest::Approx(expected).epsilon(1e-12));
  }
  CHECK(spectrum.at("bins")[1].at("efficiency").get<double>() == doctest::Approx(two.at("efficiency").get<double>()).epsilon(1e-12));
  CHECK(spectrum.at("bins")[2].at("power_loss_w").get<double>() == 0.0);
  CHECK(spectrum.at("bins")[2].at("efficiency").is_null());
  // The ratio of energies, not the mean of the bins' efficiencies.
  CHECK(std::abs(spectrum.at("efficiency").get<double>() -
                 (0.3 * one.at("efficiency").get<double>() + 0.5 * two.at("efficiency").get<double>()) / 0.8) > 1e-6);
  const nlohmann::json alone =
      efficiency({DeckWith("cycloidal_drive.toml", "[[load_spectrum]]\ntorque_nm = 206\nspeed_rpm = 1000\ntime_share = 1\n", "efficiency_one")})
          .at("spectrum");
  CHECK(alone.at("efficiency").get<double>() == doctest::Approx(two.at("efficiency").get<double>()).epsilon(1e-14));
  CHECK(alone.at("power_loss_w").get<double>() == doctest::Approx(two.at("power_loss_w").get<double>()).epsilon(1e-14));
}

TEST_CASE("app: an idle bin of a preloaded stage is a named failure of the efficiency's spectrum, whose figures are then null") {
  using namespace spectrum_test;
  // At zero torque a preload presses the pins: its friction would lose power with none delivered,
  // which the efficiency (a ratio to the output power) does not model.
  const auto r = ltca::test::RunCli({"efficiency",
                                     DeckWith("rv_catalogue.toml",
                                              "[[load_spectrum]]\ntorque_nm = 412\nspeed_rpm = 1000\ntime_share = 0.5\n\n"
                                              "[[load_spectrum]]\ntorque_nm = 0\nspeed_rpm = 1000\ntime_share = 0.5\n",
                                              "preloaded_idle"),
                                     "--set", "modification.pin_circle_radius_mm=-0.002", "--set", "friction.coefficient=0.05",
                                     "--set", "sweep.positions=3", "--json", "-"});
  CHECK(r.code == 1);
  const nlohmann::json spectrum = nlohmann::json::parse(r.out).at("spectrum");
  CHECK_FALSE(spectrum.at("succeeded").get<bool>());
  CHECK(spectrum.at("efficiency").is_null());
  CHECK_FALSE(spectrum.at("bins")[1].at("succeeded").get<bool>());
  CHECK(spectrum.at("bins")[1].at("power_loss_w").is_null());
}

TEST_CASE("app: a load spectrum's static figures are the worst of the single runs at each bin's torque, each naming its bin, and its verdicts flip where a figure crosses its target") {
  // Issue 50 (static safety and verdicts over a spectrum). Recomputed here from the two single runs
  // at the bins' torques and speeds: s_0 = C_0 / P_0,max with P_0,max the largest of the runs'
  // printed per-bearing loads and C_0 the deck's [bearing] static_load_rating_n (ISO 76); the
  // largest roller stress and tooth-contact stress the larger of the runs'. Tolerance 1e-12
  // relative (the JSON round trip). The worst bin is the 412 N*m bin, bin 2.
  using namespace spectrum_test;
  const std::string name = "rv_two_discs_cranks.toml";
  const std::string deck = DeckWith(name,
                                    "[[load_spectrum]]\ntorque_nm = 150\nspeed_rpm = 1000\ntime_share = 0.25\n\n"
                                    "[[load_spectrum]]\ntorque_nm = 412\nspeed_rpm = 2500\ntime_share = 0.75\n",
                                    "static");
  const std::vector<std::string> life = {"--set", "allowables.contact_life_hours=20000"};
  const auto run = [&](std::vector<std::string> args) {
    args.insert(args.end(), life.begin(), life.end());
    return Solve(args);
  };
  const nlohmann::json spectrum = run({"solve", deck, "--json", "-"}).at("spectrum");
  const std::string path = std::string(LTCA_CASES_DIR) + "/stage/" + name;
  const nlohmann::json one =
      run({"solve", path, "--json", "-", "--set", "load.torque_nm=150", "--set", "operation.input_speed_rpm=1000"}).at("summary");
  const nlohmann::json two =
      run({"solve", path, "--json", "-", "--set", "load.torque_nm=412", "--set", "operation.input_speed_rpm=2500"}).at("summary");
  const double c0 = 26611.2;  // the deck's static_load_rating_n
  const std::vector<double> p1 = Numbers(one.at("stage").at("max_bearing_load_per_bearing_n"));
  const std::vector<double> p2 = Numbers(two.at("stage").at("max_bearing_load_per_bearing_n"));
  const std::vector<double> q1 = Numbers(one.at("stage").at("max_roller_contact_stress_mpa"));
  const std::vector<double> q2 = Numbers(two.at("stage").at("max_roller_contact_stress_mpa"));
  const std::vector<double> s0 = Numbers(spectrum.at("static_safety")), q = Numbers(spectrum.at("max_roller_contact_stress_mpa"));
  REQUIRE(p1.size() == 6);
  REQUIRE(s0.size() == 6);
  REQUIRE(q.size() == 6);
  double smallest = INFINITY, largest = 0.0;
  for (std::size_t k = 0; k < 6; ++k) {
    CAPTURE(k);
    const double expected = c0 / std::max(p1[k], p2[k]);
    CHECK(s0[k] == doctest::Approx(expected).epsilon(1e-12));
    CHECK(spectrum.at("static_safety_bin").at(k).get<int>() == (p2[k] > p1[k] ? 2 : 1));
    CHECK(q[k] == doctest::Approx(std::max(q1[k], q2[k])).epsilon(1e-12));
    CHECK(spectrum.at("max_roller_contact_stress_bin").at(k).get<int>() == (q2[k] > q1[k] ? 2 : 1));
    smallest = std::min(smallest, expected);
    largest = std::max(largest, std::max(q1[k], q2[k]));
  }
  CHECK(spectrum.at("smallest_static_safety").get<double>() == doctest::Approx(smallest).epsilon(1e-12));
  CHECK(spectrum.at("smallest_static_safety_bin").get<int>() == 2);
  CHECK(spectrum.at("largest_roller_contact_stress_mpa").get<double>() == doctest::Approx(largest).epsilon(1e-12));
  CHECK(spectrum.at("largest_roller_contact_stress_bin").get<int>() == 2);
  const double stress1 = one.at("max_contact_stress_mpa").get<double>(), stress2 = two.at("max_contact_stress_mpa").get<double>();
  CHECK(stress2 > stress1);
  CHECK(spectrum.at("max_contact_stress_mpa").get<double>() == doctest::Approx(stress2).epsilon(1e-12));
  CHECK(spectrum.at("max_contact_stress_bin").get<int>() == 2);
  // The single runs' own S_H bound the spectrum's: the 412 N*m run as if it ran the whole life
  // from below, the 150 N*m run from above.
  const double s_h = spectrum.at("smallest_pitting_safety").get<double>();
  CHECK(s_h > two.at("contact_fatigue").at("smallest_safety").get<double>());
  CHECK(s_h < one.at("contact_fatigue").at("smallest_safety").get<double>());

  // The verdicts: each target a hair (1e-6) on either side of the spectrum's figure.
  const double zone = spectrum.at("shortest_load_zone_life_hours").get<double>();
  const double s0_min = spectrum.at("smallest_static_safety").get<double>();
  const auto targets = [&](double f_life, double f_s0, double f_sh) {
    return std::vector<std::string>{"--set", fmt::format("allowables.bearing_life_hours={:.17g}", zone * f_life),
                                    "--set", fmt::format("allowables.min_static_safety={:.17g}", s0_min * f_s0),
                                    "--set", fmt::format("allowables.min_contact_safety={:.17g}", s_h * f_sh)};
  };
  const auto verdict = [](const nlohmann::json& s, const std::string& figure) {
    for (const auto& v : s.at("verdicts")) {
      if (v.at("figure") == figure) return v.at("verdict").get<std::string>();
    }
    return std::string("missing");
  };
  const double up = 1.0 + 1e-6, down = 1.0 - 1e-6;
  std::vector<std::string> a = {"solve", deck, "--json", "-"}, b = a;
  for (const std::string& s : targets(up, down, up)) a.push_back(s);
  for (const std::string& s : targets(down, up, down)) b.push_back(s);
  const nlohmann::json ja = run(a).at("spectrum"), jb = run(b).at("spectrum");
  CHECK(verdict(ja, "spectrum.shortest_load_zone_life_hours") == "FAIL");
  CHECK(verdict(jb, "spectrum.shortest_load_zone_life_hours") == "pass");
  CHECK(verdict(ja, "spectrum.smallest_static_safety") == "pass");
  CHECK(verdict(jb, "spectrum.smallest_static_safety") == "FAIL");
  CHECK(verdict(ja, "spectrum.smallest_pitting_safety") == "FAIL");
  CHECK(verdict(jb, "spectrum.smallest_pitting_safety") == "pass");
  CHECK(verdict(ja, "spectrum.largest_roller_contact_stress_mpa") == (largest <= 4000.0 ? "pass" : "FAIL"));
  CHECK(verdict(ja, "spectrum.max_contact_stress_mpa") == "pass");  // the deck's limit, 4,000 MPa by default
  // The text says the same.
  std::vector<std::string> text_args(b.begin(), b.end());
  text_args.erase(text_args.begin() + 2, text_args.begin() + 4);  // no --json -
  for (const std::string& s : life) text_args.push_back(s);
  const auto text = ltca::test::RunCli(text_args);
  CHECK(text.out.find("spectrum static s_0") != std::string::npos);
  CHECK(text.out.find("(bin 2)") != std::string::npos);
  CHECK(text.out.find("FAIL   smallest bearing static safety s_0 over the spectrum") != std::string::npos);
  CHECK(text.out.find("pass   smallest pitting safety S_H over the spectrum") != std::string::npos);
}
