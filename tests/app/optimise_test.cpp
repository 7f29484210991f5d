// Issue 28: design optimisation (ltca optimise, analysis::Optimiser). Independent references: a
// 41 x 41 grid of the same variables, the backlash `ltca backlash` gives for the optimum's
// written deck, a root of the backlash found by bisection over `ltca backlash` runs, and the
// same search on one and two threads.
#include <cmath>
#include <algorithm>
#include <filesystem>
#include <random>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "helpers.hpp"
#include "ltca/analysis/optimise.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/geometry/units.hpp"
#include "solve_command.hpp"

using ltca::analysis::DesignEvaluation;
using ltca::analysis::Optimiser;
using ltca::analysis::OptimiseSettings;
using ltca::analysis::RunStatus;
using ltca::test::Case;
using ltca::test::RunCli;

namespace {

Optimiser Make(const ltca::app::Deck& deck, int threads = 1) {
  return Optimiser(deck.MakeToleranceCase(), ltca::cli::SolverFor(deck, ""), *deck.optimise, threads);
}

/// Mean backlash of `ltca backlash` on the deck with these overrides, arcsec.
double Backlash(const std::string& deck, const std::vector<std::string>& sets) {
  std::vector<std::string> args = {"backlash", deck, "--json", "-"};
  for (const std::string& s : sets) args.push_back("--set"), args.push_back(s);
  const auto r = RunCli(args);
  REQUIRE(r.code == 0);
  return nlohmann::json::parse(r.out).at("summary").at("mean_backlash_arcsec").get<double>();
}

}  // namespace

TEST_CASE("app: optimise on two variables beats the best feasible point of a 41 x 41 grid, the constraint active where the map has it") {
  // cases/liu2021_optimise.toml: least pp TE over the isometric and offset modifications with the
  // mean backlash within 60..120 arcsec and the stress under 1500 MPa. The grid is evaluated on
  // the same figures (the tolerance sample's: ltca backlash's and ltca solve's summaries); the
  // optimum's figures are then checked against ltca solve and ltca backlash on its written deck.
  const ltca::app::Deck deck = ltca::app::LoadDeck(Case("liu2021_optimise.toml"));
  const Optimiser optimiser = Make(deck, 2);
  std::vector<DesignEvaluation> history;
  const auto result = optimiser.Run([&](const DesignEvaluation& e) { history.push_back(e); });
  REQUIRE(result.best >= 0);
  const DesignEvaluation& best = result.best_design;
  CHECK(best.feasible);
  const std::vector<DesignEvaluation> grid = optimiser.Grid(41);
  REQUIRE(grid.size() == 41u * 41u);
  const DesignEvaluation* grid_best = nullptr;
  int feasible = 0, rejected = 0;
  for (const DesignEvaluation& e : grid) {
    feasible += e.feasible;
    rejected += e.status == RunStatus::kRejected || e.status == RunStatus::kCannotAssemble;
    if (e.feasible && (grid_best == nullptr || e.objective < grid_best->objective)) grid_best = &e;
  }
  REQUIRE(grid_best != nullptr);
  CAPTURE(grid_best->objective);
  CAPTURE(best.objective);
  CHECK(feasible > 20);
  CHECK(rejected > 0);  // designs preloaded beyond the material are in the box: infeasible, never a number
  CHECK(best.objective <= grid_best->objective);
  // The lower backlash limit is active at both (the map: feasible cells end there).
  const auto backlash = [](const DesignEvaluation& e) { return e.figures[ltca::analysis::kMeanBacklashArcsec]; };
  CHECK(backlash(best) == doctest::Approx(60.0).epsilon(2e-3));
  CHECK(backlash(*grid_best) < 60.0 + 0.05 * 60.0);
  // Every rejected evaluation has no figure.
  for (const DesignEvaluation& e : history) {
    if (e.status != RunStatus::kSuccess) CHECK(std::isnan(e.objective));
  }
  // The written deck: ltca solve and ltca backlash give the optimum's figures.
  const auto path = std::filesystem::temp_directory_path() / ("ltca_optimise_best_" + std::to_string(::getpid()) + ".toml");
  const auto w = RunCli({"optimise", Case("liu2021_optimise.toml"), "--threads", "1", "--write-deck", path.string()});
  REQUIRE(w.code == 0);
  const auto solve = RunCli({"solve", path.string(), "--json", "-"});
  REQUIRE(solve.code == 0);
  const auto j = nlohmann::json::parse(solve.out);
  CHECK(j.at("summary").at("pp_te_arcsec").get<double>() == doctest::Approx(best.objective).epsilon(1e-9));
  CHECK(Backlash(path.string(), {}) == doctest::Approx(backlash(best)).epsilon(1e-9));
  std::filesystem::remove(path);
}

TEST_CASE("app: the least power loss over the offset modification is at least as good as 11 ltca efficiency runs, and its deck gives it") {
  // Issue 28: efficiency figures as objectives. The references are `ltca efficiency --json` runs:
  // on an 11-point grid of the variable, and on the written deck of the optimum.
  const std::string deck_path = Case("jiang2022_table2_efficiency.toml");
  const std::vector<std::string> sets = {
      "optimise.variables={ \"modification.pin_circle_radius_mm\" = [-0.03, -0.002] }", "optimise.objective=\"power_loss_w\"",
      "optimise.constraints={ efficiency = { min = 0.5 } }", "optimise.evaluations=40", "sweep.positions=7"};
  const ltca::app::Deck deck = ltca::app::LoadDeck(deck_path, sets);
  const auto result = Make(deck).Run();
  REQUIRE(result.best >= 0);
  const DesignEvaluation& best = result.best_design;
  const auto loss = [&](double offset) {
    const auto r = RunCli({"efficiency", deck_path, "--set", "sweep.positions=7", "--set", fmt::format("modification.pin_circle_radius_mm={}", offset),
                           "--json", "-"});
    REQUIRE(r.code == 0);
    const auto s = nlohmann::json::parse(r.out).at("summary");
    return std::pair{s.at("power_loss_w").get<double>(), s.at("efficiency").get<double>()};
  };
  const auto [at_best, efficiency_at_best] = loss(best.x[0]);
  CHECK(best.figures[ltca::analysis::kPowerLossW] == doctest::Approx(at_best).epsilon(1e-9));
  CHECK(best.figures[ltca::analysis::kEfficiency] == doctest::Approx(efficiency_at_best).epsilon(1e-9));
  for (int k = 0; k <= 10; ++k) {
    const double offset = -0.03 + 0.028 * k / 10.0;
    CAPTURE(offset);
    CHECK(best.objective <= loss(offset).first + 1e-9);
  }
  // The efficiency needs [friction] and [operation], and is not a robust figure.
  CHECK_THROWS_WITH_AS(Make(ltca::app::LoadDeck(Case("liu2021_optimise.toml"), {"optimise.objective=\"power_loss_w\""})),
                       doctest::Contains("[friction]"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(ltca::app::LoadDeck(Case("liu2021_robust.toml"), {"optimise.objective=\"efficiency\"", "optimise.maximise=true"}),
                       doctest::Contains("robust = true with power_loss_w or efficiency"), std::invalid_argument);
}

TEST_CASE("app: the written deck keeps a title with quotes and a backslash as the deck gave it") {
  // TOML 1.0 basic strings: the reader of the written deck is the reference.
  const std::string title = "a \"quoted\" title \\ with a backslash";
  const auto path = std::filesystem::temp_directory_path() / ("ltca_optimise_title_" + std::to_string(::getpid()) + ".toml");
  const auto w = RunCli({"optimise", Case("liu2021_optimise.toml"), "--threads", "1", "--evaluations", "30", "--set",
                         "case.title=\"a \\\"quoted\\\" title \\\\ with a backslash\"", "--write-deck", path.string()});
  REQUIRE(w.code == 0);
  const ltca::app::Deck written = ltca::app::LoadDeck(path.string());
  CHECK(written.info.title == title);
  std::filesystem::remove(path);
}

TEST_CASE("app: optimise finds the closed-form optimum of the least offset at a given mean backlash (1e-3 um)") {
  // Mean backlash grows with the pin circle's deviation (4.76 arcsec/um, docs/validation.md) and
  // as the offset modification dR_p grows more negative. "The least offset (dR_p nearest 0) with
  // a mean backlash of at least B" therefore puts the deviation at its upper bound and dR_p where
  // the backlash is B: found here independently by bisection over `ltca backlash` runs.
  const std::string deck_path = Case("liu2021_optimise.toml");
  const double b_target = 80.0, deviation_max = 0.003;  // arcsec, mm
  const std::vector<std::string> sets = {
      "optimise.variables={ \"modification.pin_circle_radius_mm\" = [-0.04, -0.004], \"errors.pin_circle_deviation_mm\" = [0.0, 0.003] }",
      "optimise.objective=\"modification.pin_circle_radius_mm\"", "optimise.maximise=true",
      fmt::format("optimise.constraints={{ mean_backlash_arcsec = {{ min = {} }} }}", b_target), "optimise.global=\"none\"",
      "optimise.evaluations=300", "optimise.tolerance=1e-9"};
  const ltca::app::Deck deck = ltca::app::LoadDeck(deck_path, sets);
  const auto result = Make(deck).Run();
  REQUIRE(result.best >= 0);
  const DesignEvaluation& best = result.best_design;
  // Variables in key order: errors.pin_circle_deviation_mm, modification.pin_circle_radius_mm.
  const auto& vars = deck.optimise->variables;
  const std::size_t dev = vars[0].key == "errors.pin_circle_deviation_mm" ? 0 : 1, off = 1 - dev;
  CHECK(std::abs(best.x[dev] - deviation_max) * 1e3 < 1e-3);  // um
  // The root of backlash(dR_p) = B at the upper deviation, by bisection on ltca backlash.
  const std::string dev_set = fmt::format("errors.pin_circle_deviation_mm={}", deviation_max);
  double lo = -0.04, hi = -0.004;  // backlash(lo) > B > backlash(hi); above -0.004 the pins interfere
  REQUIRE(Backlash(deck_path, {dev_set, fmt::format("modification.pin_circle_radius_mm={}", lo)}) > b_target);
  REQUIRE(Backlash(deck_path, {dev_set, fmt::format("modification.pin_circle_radius_mm={}", hi)}) < b_target);
  for (int k = 0; k < 40; ++k) {
    const double mid = 0.5 * (lo + hi);
    (Backlash(deck_path, {dev_set, fmt::format("modification.pin_circle_radius_mm={}", mid)}) > b_target ? lo : hi) = mid;
  }
  CAPTURE(best.x[off]);
  CAPTURE(lo);
  CHECK(std::abs(best.x[off] - 0.5 * (lo + hi)) * 1e3 < 1e-3);  // um
}

TEST_CASE("app: a stage clearance as a variable: the largest output-pin hole within a lost-motion limit is where ltca stiffness puts the limit, and the holes add 2 / R_w") {
  // cases/stage/cycloidal_drive_clearance.toml with the hole radius alone (bearing play at the
  // deck's 5 um), 7 positions: "the largest hole with lost motion <= 5 arcmin". Lost motion grows
  // with the hole's clearance, so the optimum is the root of LM(r_h) = 5, found here independently
  // by bisection over `ltca stiffness` runs on the deck with the radius set by --set.
  const std::string deck_path = Case("stage/cycloidal_drive_clearance.toml");
  const double limit = 5.0, lo0 = 6.302, hi0 = 6.34;  // arcmin, mm
  const std::vector<std::string> sweep = {"sweep.positions=7", "sweep.crank_end_deg=9.0"};
  std::vector<std::string> sets = sweep;
  sets.push_back(fmt::format("optimise.variables={{ \"output.hole_radius_mm\" = [{}, {}] }}", lo0, hi0));
  sets.insert(sets.end(), {"optimise.global=\"none\"", "optimise.tolerance=1e-10", "optimise.evaluations=200"});
  const ltca::app::Deck deck = ltca::app::LoadDeck(deck_path, sets);
  const Optimiser optimiser = Make(deck);
  const auto result = optimiser.Run();
  REQUIRE(result.best >= 0);
  const DesignEvaluation& best = result.best_design;
  CHECK(best.feasible);
  const auto lost_motion = [&](double hole) {
    std::vector<std::string> args = {"stiffness", deck_path, "--json", "-", "--set", fmt::format("output.hole_radius_mm={:.17g}", hole)};
    for (const std::string& s : sweep) args.push_back("--set"), args.push_back(s);
    const auto r = RunCli(args);
    REQUIRE(r.code == 0);
    return nlohmann::json::parse(r.out).at("summary").at("lost_motion_arcmin").get<double>();
  };
  double lo = lo0, hi = hi0;
  REQUIRE(lost_motion(lo) < limit);
  REQUIRE(lost_motion(hi) > limit);
  for (int k = 0; k < 30; ++k) {
    const double mid = 0.5 * (lo + hi);
    (lost_motion(mid) < limit ? lo : hi) = mid;
  }
  CAPTURE(best.x[0]);
  CAPTURE(lo);
  CHECK(std::abs(best.x[0] - 0.5 * (lo + hi)) * 1e3 < 1e-3);  // um
  // At least as good as every feasible point of a 41-point grid of the same variable.
  for (const DesignEvaluation& g : optimiser.Grid(41)) {
    if (g.feasible) CHECK(g.x[0] <= best.x[0] + 1e-12);
  }
  // The holes are in series with the rest of the stage: a hole's clearance c adds c / cos(alpha)
  // of output-pin-circle arc on each flank (R_w psi = c / cos(alpha), alpha the angle between the
  // eccentric's direction and the tangent of the pin that closes first; small c / e). With 8
  // pins some tangent lies within 22.5 deg of it, so dLM / dc is within 2 / R_w .. 2 / (R_w cos 22.5 deg).
  const double r_w = deck.reducer->pins.circle_radius;
  const double slope = ltca::units::ArcminToRad(lost_motion(6.33) - lost_motion(6.31)) / 0.02;  // rad / mm
  CAPTURE(slope * r_w / 2.0);
  CHECK(slope >= 2.0 / r_w * (1.0 - 1e-3));
  CHECK(slope <= 2.0 / (r_w * std::cos(ltca::units::DegToRad(22.5))));
}

TEST_CASE("app: the stage's clearance variables write the fields the deck reader writes, the free play is solved when named, and bad ones name the key") {
  // Each of the three keys set by Optimiser::Apply against the same value set by the deck reader
  // (--set): the same stage settings, bit for bit.
  const std::string deck_path = Case("stage/cycloidal_drive_clearance.toml");
  const std::vector<std::string> sweep = {"sweep.positions=3", "sweep.crank_end_deg=6.0"};
  std::vector<std::string> sets = sweep;
  sets.push_back("optimise.variables={ \"output.hole_radius_mm\" = [6.302, 6.34], \"bearing.radial_clearance_mm\" = [0.002, 0.015], "
                 "\"output.pin_radius_mm\" = [4.99, 5.0] }");
  const ltca::app::Deck deck = ltca::app::LoadDeck(deck_path, sets);
  const Optimiser optimiser = Make(deck);
  const std::map<std::string, double> value = {
      {"output.hole_radius_mm", 6.3251}, {"bearing.radial_clearance_mm", 0.0071}, {"output.pin_radius_mm", 4.9937}};
  std::vector<double> x;
  std::vector<std::string> read = sweep;
  for (const auto& v : deck.optimise->variables) {
    x.push_back(value.at(v.key));
    read.push_back(fmt::format("{}={:.17g}", v.key, value.at(v.key)));
  }
  const auto applied = optimiser.Apply(x);
  const ltca::app::Deck reference = ltca::app::LoadDeck(deck_path, read);
  REQUIRE(applied.design.reducer.has_value());
  CHECK(applied.design.reducer->pins.hole_radius == reference.reducer->pins.hole_radius);
  CHECK(applied.design.reducer->pins.pin_radius == reference.reducer->pins.pin_radius);
  CHECK(applied.design.reducer->bearing.radial_clearance == reference.reducer->bearing.radial_clearance);
  CHECK(reference.reducer->pins.hole_radius == 6.3251);  // the reader's own value: the reference moved
  // The free play (two stage solves a crank) runs only when a backlash figure is named.
  const DesignEvaluation lost = optimiser.Evaluate(x);
  CHECK(lost.status == RunStatus::kSuccess);
  CHECK(std::isfinite(lost.figures[ltca::analysis::kLostMotionArcmin]));
  CHECK(std::isnan(lost.figures[ltca::analysis::kMeanBacklashArcsec]));
  std::vector<std::string> with_backlash = sets;
  with_backlash.push_back("optimise.constraints={ lost_motion_arcmin = { max = 5.0 }, mean_backlash_arcsec = { max = 400.0 } }");
  const ltca::app::Deck named = ltca::app::LoadDeck(deck_path, with_backlash);
  CHECK(std::isfinite(Make(named).Evaluate(x).figures[ltca::analysis::kMeanBacklashArcsec]));
  // Bad input: std::invalid_argument naming the key and its bounds, before any evaluation.
  const auto error = [](const std::string& text, std::vector<std::string> overrides) {
    try {
      const ltca::app::Deck d = ltca::app::ParseDeck(text, "t", overrides);
      Make(d);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string stage = ltca::test::ReadText(deck_path);
  const std::string clearance = "optimise.variables={ \"bearing.radial_clearance_mm\" = [0.0, 0.01] }";
  CHECK(error(ltca::test::ReadText(Case("liu2021_optimise.toml")), {clearance})
            .find("variables.\"bearing.radial_clearance_mm\" = [0, 0.01]: the deck has no reducer stage; expected an [output] section") != std::string::npos);
  const std::size_t bearing = stage.find("[bearing]"), contact = stage.find("[contact]");
  REQUIRE(bearing < contact);
  const std::string rigid = stage.substr(0, bearing) + "[bearing]\nkind = \"rigid\"\n\n" + stage.substr(contact);
  CHECK(error(rigid, {}).find("variables.\"bearing.radial_clearance_mm\" = [0.002, 0.015]: [bearing] kind = \"rigid\" has no play") !=
        std::string::npos);
  CHECK(error(rigid, {"optimise.variables={ \"output.hole_radius_mm\" = [6.302, 6.34] }"}) == "accepted");  // the holes are fine on it
  const std::string cranks = ltca::test::ReadText(Case("stage/rv_two_discs_cranks.toml")) +
                             "\n[optimise]\nvariables = { \"output.hole_radius_mm\" = [6.302, 6.34] }\nobjective = \"pp_te_arcsec\"\n";
  CHECK(error(cranks, {}).find("expected [output] kind = \"pins\"") != std::string::npos);
  CHECK(error(ltca::test::ReadText(Case("liu2021_optimise.toml")), {"optimise.constraints={ shortest_l10_hours = { min = 1000.0 } }"})
            .find("[optimise] shortest_l10_hours: a figure of a reducer stage; expected an [output] section") != std::string::npos);
  CHECK(error(cranks, {"optimise.variables={ \"bearing.radial_clearance_mm\" = [0.0, 0.01] }", "optimise.objective=\"max_output_pin_force_n\""})
            .find("a figure of a reducer stage with output pins") != std::string::npos);
  CHECK(error(stage, {"load.torque_nm=0", "optimise.constraints={ mean_backlash_arcsec = { max = 400.0 } }"})
            .find("torque_nm = 0: expected a non-zero rated torque") != std::string::npos);
}

TEST_CASE("app: a bearing-life constraint on a stage's clearance is active at the optimum, and ltca solve gives the optimum's life") {
  // cases/stage/cycloidal_drive.toml over a whole crank turn at 12 positions: the least lost
  // motion over the eccentric bearing's play with its ISO 281 life at least 10,000 h. On this
  // stage the life grows with the play (the mean bearing load falls as the disc floats), lost
  // motion too, so the constraint is active: the optimum's life is the limit, and `ltca solve` on
  // the deck with the play set by --set gives that life (the figure is solve's, not a copy).
  const std::string deck_path = Case("stage/cycloidal_drive.toml");
  const std::vector<std::string> sweep = {"sweep.positions=12", "sweep.crank_end_deg=330.0"};
  std::vector<std::string> sets = sweep;
  sets.insert(sets.end(), {"optimise.variables={ \"bearing.radial_clearance_mm\" = [0.0, 0.015] }", "optimise.objective=\"lost_motion_arcmin\"",
                           "optimise.constraints={ shortest_l10_hours = { min = 10000.0 } }", "optimise.global=\"none\"",
                           "optimise.tolerance=1e-10", "optimise.evaluations=100"});
  const ltca::app::Deck deck = ltca::app::LoadDeck(deck_path, sets);
  const auto result = Make(deck).Run();
  REQUIRE(result.best >= 0);
  const DesignEvaluation& best = result.best_design;
  const double life = best.figures[ltca::analysis::kShortestL10Hours];
  CAPTURE(best.x[0]);
  CHECK(life >= 10000.0);
  CHECK(life <= 10000.0 * (1.0 + 1e-4));
  std::vector<std::string> args = {"solve", deck_path, "--json", "-", "--set", fmt::format("bearing.radial_clearance_mm={:.17g}", best.x[0])};
  for (const std::string& v : sweep) args.push_back("--set"), args.push_back(v);
  const auto r = RunCli(args);
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(r.out).at("summary").at("stage").at("shortest_l10_hours").get<double>() == doctest::Approx(life).epsilon(1e-9));
  // The play at either bound: the life is below the limit at the lower one, the lost motion larger at the upper one.
  const Optimiser o = Make(deck);
  CHECK(o.Evaluate({0.0}).figures[ltca::analysis::kShortestL10Hours] < 10000.0);
  CHECK(o.Evaluate({0.015}).figures[ltca::analysis::kLostMotionArcmin] > best.figures[ltca::analysis::kLostMotionArcmin]);
}

TEST_CASE("app: a robust optimisation gives the same evaluations on one and two threads, bit for bit") {
  // Common random numbers: every design runs the same samples (seed, i), whatever the threads.
  const std::vector<std::string> sets = {"sweep.positions=3", "optimise.robust=true", "optimise.robust_samples=6",
                                         "optimise.evaluations=12", "optimise.percentile=90", "optimise.confidence=0",
                                         "tolerances.pin_circle_deviation_mm={ distribution = \"normal\", tolerance = 0.003 }",
                                         "tolerances.seed=7"};
  const ltca::app::Deck deck = ltca::app::LoadDeck(Case("liu2021_optimise.toml"), sets);
  std::vector<DesignEvaluation> one, two;
  const auto one_result = Make(deck, 1).Run([&](const DesignEvaluation& e) { one.push_back(e); });
  const auto two_result = Make(deck, 2).Run([&](const DesignEvaluation& e) { two.push_back(e); });
  REQUIRE(one.size() == two.size());
  CHECK(one_result.best == two_result.best);
  for (std::size_t i = 0; i < one.size(); ++i) {
    CAPTURE(i);
    CHECK(one[i].x == two[i].x);
    const double a = one[i].objective, b = two[i].objective;
    CHECK(((std::isnan(a) && std::isnan(b)) || a == b));
    CHECK(one[i].samples == (one[i].status == RunStatus::kRejected ? 0 : 6));
  }
}

TEST_CASE("app: the order statistic that bounds a percentile at a confidence matches exact binomial sums and covers it in a simulation") {
  using ltca::analysis::ConfidenceRank;
  using ltca::analysis::ConfidenceSamples;
  // Source: the least k with sum_{j<k} C(n,j) q^j (1-q)^(n-j) >= c, summed in exact rational
  // arithmetic (Python fractions.Fraction and math.comb), not by this code.
  CHECK(ConfidenceRank(64, 0.95, 0.9) == 64);
  CHECK(ConfidenceRank(200, 0.95, 0.9) == 195);
  CHECK(ConfidenceRank(500, 0.95, 0.9) == 482);
  CHECK(ConfidenceRank(64, 0.95, 0.5) == 62);
  CHECK(ConfidenceRank(100, 0.9, 0.95) == 96);
  CHECK(ConfidenceRank(45, 0.95, 0.9) == 45);
  CHECK(ConfidenceRank(44, 0.95, 0.9) == 0);  // 1 - 0.95^44 = 0.895 < 0.9
  CHECK(ConfidenceSamples(0.95, 0.9) == 45);
  // Coverage: over 20,000 sets of 200 uniform samples the 195th smallest lies above the 0.95
  // quantile in at least 90 % of them (the law gives P = 0.9189... ; 3 standard errors of 0.2 %).
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int covered = 0;
  const int trials = 20000;
  std::vector<double> v(200);
  for (int t = 0; t < trials; ++t) {
    for (double& x : v) x = u(rng);
    std::nth_element(v.begin(), v.begin() + 194, v.end());
    covered += v[194] >= 0.95 ? 1 : 0;
  }
  CAPTURE(covered);
  CHECK(static_cast<double>(covered) / trials > 0.9 - 0.006);
  CHECK(static_cast<double>(covered) / trials < 0.94);  // and the 195th is not needlessly high
}

TEST_CASE("app: the robust optimum keeps its constraints at the 95th percentile over a fresh Monte Carlo of 2000 samples, and the nominal optimum does not") {
  // Issue 28's must-show: cases/liu2021_robust.toml (the tolerances of liu2021_tolerances.toml).
  // The reference is `ltca tolerance` over 2,000 samples drawn with another seed (777, not the
  // deck's 20261123) for the design each search returns: the constraint at the percentile means
  // p5 of the mean backlash >= 60 arcsec, its p95 <= 120 and the p95 of the stress <= 2100 MPa.
  const std::string deck_path = Case("liu2021_robust.toml");
  const auto fresh = [&](const DesignEvaluation& best, const ltca::app::Deck& deck) {
    std::vector<std::string> args = {"tolerance", deck_path, "--samples", "2000", "--set", "tolerances.seed=777", "--no-worst-case",
                                     "--threads", "2", "--json", "-"};
    for (std::size_t k = 0; k < best.x.size(); ++k) {
      args.push_back("--set");
      args.push_back(fmt::format("{}={}", deck.optimise->variables[k].key, best.x[k]));
    }
    const auto r = RunCli(args);
    REQUIRE(r.code != 2);
    return nlohmann::json::parse(r.out).at("summary").at("figures");
  };
  const ltca::app::Deck robust_deck = ltca::app::LoadDeck(deck_path);
  const auto robust = Make(robust_deck, 2).Run();
  REQUIRE(robust.best >= 0);
  const auto r = fresh(robust.best_design, robust_deck);
  const ltca::app::Deck nominal_deck = ltca::app::LoadDeck(deck_path, {"optimise.robust=false"});
  const auto nominal = Make(nominal_deck).Run();
  REQUIRE(nominal.best >= 0);
  const auto n = fresh(nominal.best_design, nominal_deck);
  CAPTURE(r.dump());
  CAPTURE(n.dump());
  CHECK(r.at("mean_backlash_arcsec").at("p5").get<double>() >= 60.0);
  CHECK(r.at("mean_backlash_arcsec").at("p95").get<double>() <= 120.0);
  CHECK(r.at("max_contact_stress_mpa").at("p95").get<double>() <= 2100.0);
  // The nominal optimum meets the constraints on the nominal pair, on the backlash bound, and so
  // misses it for a large share of the reducers built.
  const DesignEvaluation& nb = nominal.best_design;
  CHECK(nb.figures[0] == doctest::Approx(60.0).epsilon(1e-3));  // mean_backlash_arcsec, active
  CHECK(n.at("mean_backlash_arcsec").at("p5").get<double>() < 60.0);
}

TEST_CASE("app: [optimise] bad input names the key, and an evaluation that fails is null in JSON, never a number") {
  const auto bad = [](std::vector<std::string> sets) {
    try {
      ltca::app::LoadDeck(Case("liu2021_optimise.toml"), sets);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK(bad({"optimise.objective=\"pp_te\""}).find("objective") != std::string::npos);
  CHECK(bad({"optimise.variables={ \"pair.pin_count\" = [30, 40] }"}).find("pair.pin_count") != std::string::npos);
  CHECK(bad({"optimise.variables={ \"modification.pin_radius_mm\" = [0.0, -0.01] }"}).find("lower < upper") != std::string::npos);
  CHECK(bad({"optimise.constraints={ backlash = 1.0 }"}).find("constraints.backlash") != std::string::npos);
  CHECK(bad({"optimise.global=\"genetic\""}).find("global") != std::string::npos);
  CHECK(bad({"optimise.robust=true"}).find("[tolerances]") != std::string::npos);
  CHECK(bad({"optimise.evaluations=0"}).find("evaluations") != std::string::npos);
  // Too few robust samples to bound the p95 at 90 % confidence: the least number is named.
  const std::string few = bad({"tolerances.pin_circle_deviation_mm={ distribution = \"normal\", tolerance = 0.003 }", "optimise.robust=true",
                               "optimise.robust_samples=20"});
  CHECK(few.find("robust_samples = 20") != std::string::npos);
  CHECK(few.find("at least 45 samples") != std::string::npos);
  CHECK(bad({"tolerances.pin_circle_deviation_mm={ distribution = \"normal\", tolerance = 0.003 }", "optimise.robust=true",
             "optimise.confidence=1"}).find("confidence") != std::string::npos);
  CHECK(RunCli({"optimise", Case("liu2021_table1.toml")}).code == 2);  // no [optimise]
  // The centre of the box overlaps by 20 um (dR_rp -35 um, dR_p -15 um): a preload beyond the
  // material, so the first evaluation cannot be assembled, its figures null.
  const auto r = RunCli({"optimise", Case("liu2021_optimise.toml"), "--evaluations", "20", "--json", "-", "--set",
                         "optimise.variables = { \"modification.pin_radius_mm\" = [-0.07, 0.0], "
                         "\"modification.pin_circle_radius_mm\" = [-0.03, 0.0] }"});
  CHECK(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j.at("model").at("name").is_string());  // every output names the model that ran
  const auto& first = j.at("history").at(0);
  CHECK(first.at("status") == "cannot-assemble");
  CHECK(first.at("objective").is_null());
  CHECK(first.at("figures").at("pp_te_arcsec").is_null());
  CHECK(j.at("summary").at("rejected").get<int>() >= 1);
}

namespace {

/// The best of a whole history as Optimiser::Run chose it when it kept every evaluation (before
/// issue 46): a successful evaluation with an objective; feasible before infeasible; the lower
/// objective (higher when maximising) among feasible ones, the less violation among infeasible
/// ones; the lowest index among equals. Over the first `upto` evaluations; -1 when none.
std::int64_t BestOfHistory(const std::vector<DesignEvaluation>& history, bool maximise, bool feasible_only,
                           std::size_t upto = static_cast<std::size_t>(-1)) {
  std::int64_t best = -1;
  for (std::size_t i = 0; i < history.size() && i < upto; ++i) {
    const DesignEvaluation& e = history[i];
    if (e.status != RunStatus::kSuccess || !std::isfinite(e.objective) || (feasible_only && !e.feasible)) continue;
    if (best < 0) {
      best = static_cast<std::int64_t>(i);
      continue;
    }
    const DesignEvaluation& b = history[static_cast<std::size_t>(best)];
    if (e.feasible != b.feasible) {
      if (e.feasible) best = static_cast<std::int64_t>(i);
    } else if (e.feasible ? (maximise ? e.objective > b.objective : e.objective < b.objective) : e.violation < b.violation) {
      best = static_cast<std::int64_t>(i);
    }
  }
  return best;
}

/// Two evaluations the same bit for bit (NaN equal to NaN).
void CheckSame(const DesignEvaluation& a, const DesignEvaluation& b) {
  const auto same = [](double x, double y) { return (std::isnan(x) && std::isnan(y)) || x == y; };
  CHECK(a.index == b.index);
  CHECK(a.phase == b.phase);
  CHECK(a.x == b.x);
  CHECK(same(a.objective, b.objective));
  CHECK(same(a.violation, b.violation));
  CHECK(a.feasible == b.feasible);
  CHECK(a.status == b.status);
  for (std::size_t f = 0; f < a.figures.size(); ++f) CHECK(same(a.figures[f], b.figures[f]));
}

}  // namespace

TEST_CASE("app: the search hands every evaluation to its sink once, in order, and keeps only the best: the best, the local start, the phases and the counts of the whole history (issue 46)") {
  // Issue 46 item 13: Optimiser::Run keeps no history. The reference is the whole history as the
  // sink collects it, judged by the rule the search applied to its kept history before (BestOfHistory).
  for (const std::vector<std::string>& method :
       {std::vector<std::string>{"optimise.global=\"direct\"", "optimise.local=\"cobyla\""},
        std::vector<std::string>{"optimise.global=\"crs2\"", "optimise.local=\"bobyqa\"", "optimise.objective=\"mean_backlash_arcsec\"",
                                 "optimise.maximise=true"}}) {
    std::vector<std::string> sets = {"sweep.positions=5", "optimise.evaluations=200"};
    sets.insert(sets.end(), method.begin(), method.end());
    CAPTURE(sets.back());
    const ltca::app::Deck deck = ltca::app::LoadDeck(Case("liu2021_optimise.toml"), sets);
    const Optimiser optimiser = Make(deck);
    const bool maximise = optimiser.settings().maximise;
    std::vector<DesignEvaluation> history;
    const auto r = optimiser.Run([&](const DesignEvaluation& e) { history.push_back(e); });
    // Every evaluation once, in index order.
    REQUIRE(static_cast<std::int64_t>(history.size()) == r.evaluations);
    REQUIRE(r.evaluations > 20);
    for (std::size_t i = 0; i < history.size(); ++i) CHECK(history[i].index == static_cast<std::int64_t>(i));
    std::int64_t in_phases = 0;
    for (const auto& p : r.phases) in_phases += p.evaluations;
    CHECK(in_phases + 1 == r.evaluations);  // and the centre
    std::int64_t failed = 0, rejected = 0;
    for (const DesignEvaluation& e : history) {
      failed += e.status == RunStatus::kFailed;
      rejected += e.status == RunStatus::kRejected || e.status == RunStatus::kCannotAssemble;  // both not built
    }
    CHECK(r.failed == failed);
    CHECK(r.rejected == rejected);
    CHECK(rejected > 0);  // the centre cannot be assembled: the rule's infeasible branch is exercised
    // The best feasible one, as the whole history gives it.
    const std::int64_t best = BestOfHistory(history, maximise, true);
    REQUIRE(best >= 0);
    CHECK(r.best == best);
    CheckSame(r.best_design, history[static_cast<std::size_t>(best)]);
    // The local phase starts from the best of all evaluations before it, feasible or not.
    const auto local = std::find_if(history.begin(), history.end(), [](const DesignEvaluation& e) { return e.phase == "local"; });
    REQUIRE(local != history.end());
    const std::int64_t from = BestOfHistory(history, maximise, false, static_cast<std::size_t>(local - history.begin()));
    REQUIRE(from >= 0);
    for (std::size_t j = 0; j < local->x.size(); ++j) {
      CHECK(local->x[j] == doctest::Approx(history[static_cast<std::size_t>(from)].x[j]).epsilon(1e-12));
    }
    // The sink changes nothing: the same search without one.
    const auto plain = optimiser.Run();
    CHECK(plain.evaluations == r.evaluations);
    CHECK(plain.best == r.best);
    CheckSame(plain.best_design, r.best_design);
    CHECK(plain.failed == r.failed);
    CHECK(plain.first_failure == r.first_failure);
    REQUIRE(plain.phases.size() == r.phases.size());
    for (std::size_t k = 0; k < r.phases.size(); ++k) {
      CHECK(plain.phases[k].method == r.phases[k].method);
      CHECK(plain.phases[k].stop == r.phases[k].stop);
      CHECK(plain.phases[k].evaluations == r.phases[k].evaluations);
    }
  }
}

TEST_CASE("app: a Pareto step keeps the best of its search, the one its whole history gives (issue 46)") {
  const ltca::app::Deck deck = ltca::app::LoadDeck(Case("liu2021_optimise.toml"), {"sweep.positions=5", "optimise.evaluations=40"});
  const Optimiser optimiser = Make(deck);
  const double lo = 70.0, hi = 110.0;  // arcsec, within the deck's backlash window
  const auto front = optimiser.Pareto("mean_backlash_arcsec", lo, hi, 2);
  REQUIRE(front.size() == 2u);
  // The last step again as a search of its own, its history collected.
  OptimiseSettings s = *deck.optimise;
  s.constraints.push_back({"mean_backlash_arcsec", -std::numeric_limits<double>::infinity(), hi});
  const Optimiser step(deck.MakeToleranceCase(), ltca::cli::SolverFor(deck, ""), s, 1);
  std::vector<DesignEvaluation> history;
  step.Run([&](const DesignEvaluation& e) { history.push_back(e); });
  const std::int64_t best = BestOfHistory(history, s.maximise, true);
  REQUIRE(best >= 0);
  CHECK(front[1].epsilon == hi);
  CHECK(front[1].best == best);
  DesignEvaluation expected = history[static_cast<std::size_t>(best)];
  expected.phase = "pareto";
  CheckSame(front[1].design, expected);
}

TEST_CASE("app: a stage clearance whose bounds span a preload (a negative bearing play) is evaluated as a preloaded design, not refused (issue 52)") {
  // cases/stage/cycloidal_drive.toml, 3 positions: the eccentric roller bearing's play over
  // [-4, 4] um. A negative play is a preloaded bearing (docs/stage.md "Preload"): every evaluation
  // of the search is judged like any design (none rejected), and the figures of a preloaded design
  // are those `ltca solve` gives for the deck with that play (the CLI's own pathway, 1e-9).
  const std::string deck_path = Case("stage/cycloidal_drive.toml");
  const std::vector<std::string> sweep = {"sweep.positions=3", "sweep.crank_end_deg=20.0"};
  std::vector<std::string> sets = sweep;
  sets.insert(sets.end(), {"optimise.variables={ \"bearing.radial_clearance_mm\" = [-0.004, 0.004] }", "optimise.objective=\"pp_te_arcsec\"",
                           "optimise.global=\"none\"", "optimise.evaluations=8"});
  const ltca::app::Deck deck = ltca::app::LoadDeck(deck_path, sets);
  const Optimiser o = Make(deck);
  std::vector<DesignEvaluation> history;
  const auto result = o.Run([&](const DesignEvaluation& e) { history.push_back(e); });
  REQUIRE(result.best >= 0);
  for (const DesignEvaluation& e : history) {
    CAPTURE(e.x[0]);
    INFO(e.message);
    CHECK(e.status != RunStatus::kRejected);
  }
  const DesignEvaluation preloaded = o.Evaluate({-0.002});
  INFO(preloaded.message);
  REQUIRE(preloaded.status == RunStatus::kSuccess);
  std::vector<std::string> args = {"solve", deck_path, "--json", "-", "--set", "bearing.radial_clearance_mm=-0.002"};
  for (const std::string& v : sweep) args.push_back("--set"), args.push_back(v);
  const auto r = RunCli(args);
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(r.out).at("summary").at("pp_te_arcsec").get<double>() ==
        doctest::Approx(preloaded.figures[ltca::analysis::kPpTeArcsec]).epsilon(1e-9));
}
