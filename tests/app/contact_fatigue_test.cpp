// The pitting rating of the pin-cycloid contact (analysis/contact_fatigue.hpp) recomputed here
// from the solve's own per-position, per-pin Hertz pressures (`positions[].contact_stress_mpa` of
// `ltca solve --json -`): the test counts each pin's loaded runs around the turn itself, takes
// the cycles to pitting from ISO 6336-2's printed closed forms (Z_NT = (5e7 / N)^0.0756 and
// (5e7 / N)^0.0306 for steel, exponents rounded by the standard: hence 1e-3 where they enter,
// 1e-12 where only the counting does), and sums Miner's damage.
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

namespace contact_fatigue_test {

nlohmann::json Solve(std::vector<std::string> args) {
  args.insert(args.end(), {"--json", "-"});
  const auto r = ltca::test::RunCli(args);
  REQUIRE(r.code == 0);
  return nlohmann::json::parse(r.out);
}

/// The cycles to pitting of steel (sigma_Hlim 1500 MPa) from ISO 6336-2's printed closed forms.
double CyclesToPitting(double stress) {
  const double z = stress / 1500.0;
  if (z <= 0.85) return INFINITY;
  if (z > 1.6) return 0.0;
  const double a = std::log(1.6) / std::log(500.0), b = std::log(1.0 / 0.85) / std::log(200.0);
  return z >= 1.0 ? 5e7 * std::pow(z, -1.0 / a) : 5e7 * std::pow(z, -1.0 / b);
}

struct Recount {
  std::vector<int> cycles;       // per pin over the turn
  std::vector<double> damage;    // per pin over the turn
};

/// Each pin's loaded runs around a whole turn (the positions cover it without repeating the first),
/// a run below a tenth of the disc's largest pressure not counted (contact_fatigue.hpp's rule).
Recount Count(const nlohmann::json& positions, int pins, int disc) {
  Recount r{std::vector<int>(static_cast<std::size_t>(pins), 0), std::vector<double>(static_cast<std::size_t>(pins), 0.0)};
  const std::size_t n = positions.size();
  double largest = 0.0;
  for (const auto& p : positions) {
    for (int j = 0; j < pins; ++j) largest = std::max(largest, p.at("contact_stress_mpa").at(static_cast<std::size_t>(disc * pins + j)).get<double>());
  }
  for (int j = 0; j < pins; ++j) {
    std::vector<double> s;
    for (const auto& p : positions) s.push_back(p.at("contact_stress_mpa").at(static_cast<std::size_t>(disc * pins + j)).get<double>());
    // Start at an unloaded position (a pin loaded all the way round is one cycle a turn).
    const auto start = std::find(s.begin(), s.end(), 0.0);
    if (start == s.end()) {
      r.cycles[static_cast<std::size_t>(j)] = 1;
      r.damage[static_cast<std::size_t>(j)] = 1.0 / CyclesToPitting(*std::max_element(s.begin(), s.end()));
      continue;
    }
    std::rotate(s.begin(), start, s.end());
    double peak = 0.0;
    for (std::size_t k = 0; k <= n; ++k) {
      const double v = k < n ? s[k] : 0.0;
      if (v > 0.0) {
        peak = std::max(peak, v);
      } else if (peak > 0.0) {
        if (peak >= 0.1 * largest) {
          ++r.cycles[static_cast<std::size_t>(j)];
          r.damage[static_cast<std::size_t>(j)] += 1.0 / CyclesToPitting(peak);
        }
        peak = 0.0;
      }
    }
  }
  return r;
}

}  // namespace contact_fatigue_test

TEST_CASE("app: the pitting lives of a whole crank turn are Miner's sum over each pin's loaded runs") {
  using namespace contact_fatigue_test;
  // Liu's pair with a pitch error (pins differ), 720 positions covering the turn once, 1500 rpm.
  const nlohmann::json j = Solve({"solve", std::string(LTCA_CASES_DIR) + "/liu2021_sec52_pitch.toml", "--set",
                                  "sweep.crank_end_deg=359.5", "--set", "sweep.positions=720", "--set",
                                  "operation.input_speed_rpm=1500", "--set", "allowables.contact_life_hours=20000"});
  const nlohmann::json& f = j.at("summary").at("contact_fatigue");
  REQUIRE(f.at("discs").size() == 1);
  const nlohmann::json& d = f.at("discs").at(0);
  const Recount r = Count(j.at("positions"), 40, 0);
  const auto worst = static_cast<std::size_t>(std::max_element(r.damage.begin(), r.damage.end()) - r.damage.begin());
  double ring_damage = 0.0, ring_cycles = 0.0;
  for (int k = 0; k < 40; ++k) ring_damage += r.damage[static_cast<std::size_t>(k)], ring_cycles += r.cycles[static_cast<std::size_t>(k)];
  const double turns_per_hour = 1500.0 * 60.0;
  CHECK(d.at("worst_pin").get<int>() == static_cast<int>(worst) + 1);
  CHECK(d.at("pin_cycles_per_crank_turn").get<double>() == r.cycles[worst]);
  CHECK(d.at("tooth_cycles_per_crank_turn").get<double>() == doctest::Approx(ring_cycles / 39.0).epsilon(1e-12));
  REQUIRE(r.damage[worst] > 0.0);  // the test means something: the worst pin is damaged
  CHECK(d.at("pin_life_hours").get<double>() == doctest::Approx(1.0 / (r.damage[worst] * turns_per_hour)).epsilon(1e-9));
  CHECK(d.at("tooth_life_hours").get<double>() == doctest::Approx(39.0 / (ring_damage * turns_per_hour)).epsilon(1e-9));
  // S_H at 20,000 h: sigma_Hlim Z_NT(N_L) / the largest pressure, N_L a pin's cycles in that life.
  double largest = 0.0;
  for (const auto& p : j.at("positions")) {
    for (const auto& s : p.at("contact_stress_mpa")) largest = std::max(largest, s.get<double>());
  }
  const double n_pin = r.cycles[worst] * turns_per_hour * 20000.0;
  REQUIRE(n_pin > 5e7);
  CHECK(d.at("pin_safety").get<double>() ==
        doctest::Approx(1500.0 * std::pow(5e7 / n_pin, std::log(1.0 / 0.85) / std::log(200.0)) / largest).epsilon(1e-9));
  // The verdict on the shortest life against the required 20,000 h.
  bool judged = false;
  for (const auto& v : f.at("verdicts")) {
    if (v.at("figure") == "contact.shortest_life_hours") {
      judged = true;
      CHECK(v.at("verdict") == (f.at("shortest_life_hours").get<double>() >= 20000.0 ? "pass" : "FAIL"));
    }
  }
  CHECK(judged);
}

TEST_CASE("app: a repeating mesh period and a whole crank turn count the same cycles") {
  using namespace contact_fatigue_test;
  const std::string deck = std::string(LTCA_CASES_DIR) + "/liu2021_sec52_base.toml";
  const nlohmann::json period = Solve({"solve", deck}).at("summary");
  const nlohmann::json turn =
      Solve({"solve", deck, "--set", "sweep.crank_end_deg=360", "--set", "sweep.positions=3601"}).at("summary");
  REQUIRE(period.at("closed_period").get<bool>());
  const nlohmann::json& a = period.at("contact_fatigue").at("discs").at(0);
  const nlohmann::json& b = turn.at("contact_fatigue").at("discs").at(0);
  // d = 1: each pin once a crank turn, each tooth z_p / z_c = 40 / 39 times.
  CHECK(a.at("pin_cycles_per_crank_turn").get<double>() == 1.0);
  CHECK(b.at("pin_cycles_per_crank_turn").get<double>() == 1.0);
  CHECK(a.at("tooth_cycles_per_crank_turn").get<double>() == doctest::Approx(40.0 / 39.0).epsilon(1e-15));
  CHECK(b.at("tooth_cycles_per_crank_turn").get<double>() == doctest::Approx(40.0 / 39.0).epsilon(1e-15));
  // The same peak, sampled at 0.1 deg steps in both.
  CHECK(a.at("max_contact_stress_mpa").get<double>() == doctest::Approx(b.at("max_contact_stress_mpa").get<double>()).epsilon(1e-9));
  // No speed: no hours.
  CHECK(a.at("pin_life_hours").is_null());
  CHECK(period.at("contact_fatigue").at("basis").get<std::string>().find("mesh period") != std::string::npos);
  CHECK(turn.at("contact_fatigue").at("basis").get<std::string>().find("whole crank turn") != std::string::npos);
}

TEST_CASE("app: a run that begins at a repeating mesh period's first position is counted once, the default case") {
  using namespace contact_fatigue_test;
  // Liu's Table 1 pair (the default case, zero clearances, 19-20 pins loaded): a pin's run begins
  // at the period's first position (a pressure of a few MPa there) and, the last position being the
  // first turned by one pin, again at the last. Cut by the period's end that run is a few MPa, below
  // the tenth of the largest that marks a handover, yet it goes on to 230 MPa and more: d = 1, so
  // each pin is loaded once a crank turn, each tooth z_p / z_c = 40 / 39 times, as the whole turn counts.
  const std::string deck = std::string(LTCA_CASES_DIR) + "/liu2021_table1.toml";
  const nlohmann::json period = Solve({"solve", deck}).at("summary");
  REQUIRE(period.at("closed_period").get<bool>());
  const nlohmann::json turn =
      Solve({"solve", deck, "--set", "sweep.crank_end_deg=360", "--set", "sweep.positions=3601"}).at("summary");
  for (const nlohmann::json* s : {&period, &turn}) {
    const nlohmann::json& d = s->at("contact_fatigue").at("discs").at(0);
    CHECK(d.at("pin_cycles_per_crank_turn").get<double>() == 1.0);
    CHECK(d.at("tooth_cycles_per_crank_turn").get<double>() == doctest::Approx(40.0 / 39.0).epsilon(1e-15));
  }
}

TEST_CASE("app: a sweep that is neither a turn nor a repeating period is not rated, and says why") {
  using namespace contact_fatigue_test;
  const nlohmann::json f = Solve({"solve", std::string(LTCA_CASES_DIR) + "/liu2021_sec52_base.toml", "--set",
                                  "sweep.crank_end_deg=5", "--set", "sweep.positions=11"})
                               .at("summary")
                               .at("contact_fatigue");
  CHECK(f.at("discs").empty());
  CHECK(f.at("shortest_life_hours").is_null());
  CHECK(f.at("basis").get<std::string>().find("not rated") != std::string::npos);
}

TEST_CASE("app: two discs are rated each on its own, and a spectrum combines their pitting lives by Miner's rule") {
  using namespace contact_fatigue_test;
  const std::string deck = std::string(LTCA_CASES_DIR) + "/rv_two_discs.toml";
  const std::vector<std::string> turn = {"--set", "sweep.crank_end_deg=359", "--set", "sweep.positions=360"};
  const auto run = [&](const std::string& torque, const std::string& rpm) {
    std::vector<std::string> args = {"solve", deck, "--set", "load.torque_nm=" + torque, "--set", "operation.input_speed_rpm=" + rpm,
                                     "--set", "material.contact_fatigue_limit_mpa=1300"};
    args.insert(args.end(), turn.begin(), turn.end());
    return Solve(args).at("summary").at("contact_fatigue");
  };
  const nlohmann::json one = run("150", "1000"), two = run("412", "2500");
  REQUIRE(one.at("discs").size() == 2);
  // Disc 2 is damaged at both torques (disc 1 of this deck carries too little: its lives are infinite).
  for (const nlohmann::json* run : {&one, &two}) REQUIRE(run->at("discs").at(1).at("pin_life_hours").is_number());
  // The spectrum of the two runs, a quarter and three quarters of the time.
  std::ifstream in(deck);
  std::stringstream text;
  text << in.rdbuf() << "\n[[load_spectrum]]\ntorque_nm = 150\nspeed_rpm = 1000\ntime_share = 0.25\n"
       << "\n[[load_spectrum]]\ntorque_nm = 412\nspeed_rpm = 2500\ntime_share = 0.75\n";
  const auto path = std::filesystem::temp_directory_path() / "ltca_contact_fatigue_test_spectrum.toml";
  std::ofstream(path) << text.str();
  std::vector<std::string> args = {"solve", path.string(), "--set", "material.contact_fatigue_limit_mpa=1300"};
  args.insert(args.end(), turn.begin(), turn.end());
  const nlohmann::json spectrum = Solve(args).at("spectrum");
  const auto lives = spectrum.at("pitting_life_hours");
  REQUIRE(lives.size() == 4);
  for (std::size_t k = 0; k < 4; ++k) {
    const char* member = k % 2 == 0 ? "pin_life_hours" : "tooth_life_hours";
    const auto hours = [](const nlohmann::json& h) { return h.is_number() ? h.get<double>() : INFINITY; };  // "infinite"
    const double a = hours(one.at("discs").at(k / 2).at(member)), b = hours(two.at("discs").at(k / 2).at(member));
    CAPTURE(k);
    if (std::isinf(a) && std::isinf(b)) {
      CHECK(lives.at(k) == "infinite");
    } else {
      CHECK(lives.at(k).get<double>() == doctest::Approx(1.0 / (0.25 / a + 0.75 / b)).epsilon(1e-12));
    }
  }
}

TEST_CASE("app: a load handed over and back for one position is not a pitting cycle, a life without damage passes its target") {
  using namespace contact_fatigue_test;
  // The cycloidal drive at 1 deg steps: pin 14 is loaded over 83 positions (1500 MPa), then again
  // for one position at 160 MPa after a single unloaded one. That hump is not an engagement: every
  // tooth sees z_p / z_c = 40 / 39 cycles a turn, as at 3 deg steps.
  for (const char* positions : {"120", "360"}) {
    CAPTURE(positions);
    const std::string end = std::string(positions) == "120" ? "357" : "359";
    const nlohmann::json f = Solve({"solve", std::string(LTCA_CASES_DIR) + "/stage/cycloidal_drive.toml", "--set",
                                    std::string("sweep.positions=") + positions, "--set", "sweep.crank_end_deg=" + end})
                                 .at("summary")
                                 .at("contact_fatigue");
    CHECK(f.at("discs").at(0).at("tooth_cycles_per_crank_turn").get<double>() == doctest::Approx(40.0 / 39.0).epsilon(1e-15));
  }
  // No cycle above 0.85 sigma_Hlim: the life is infinite, written "infinite", and passes a required life.
  const nlohmann::json f = Solve({"solve", std::string(LTCA_CASES_DIR) + "/stage/rv_catalogue.toml", "--set",
                                  "allowables.contact_life_hours=1000", "--set", "material.contact_fatigue_limit_mpa=5000"})
                               .at("summary")
                               .at("contact_fatigue");
  CHECK(f.at("shortest_life_hours") == "infinite");
  bool judged = false;
  for (const auto& v : f.at("verdicts")) {
    if (v.at("figure") != "contact.shortest_life_hours") continue;
    judged = true;
    CHECK(v.at("value") == "infinite");
    CHECK(v.at("verdict") == "pass");
  }
  CHECK(judged);
}
