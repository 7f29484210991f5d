// One rule per figure: the tolerance study's nominal sample (what its samples, the optimiser and the
// report are made of) gives, for every deck in cases/, the figures the single-purpose commands give
// for that deck: `ltca solve`'s summary (TE, stress, pin force, contacts, the stage's loads and life),
// `ltca backlash`'s (one disc, and two discs: the first contact of either disc), and for a reducer
// stage `ltca stiffness`'s free play over the sweep; lost motion as `ltca stiffness` gives it. The
// commands run in-process with their JSON on standard output. Before issue 46 the two-disc deck
// cases/rv_two_discs.toml gave 48.28 arcsec in the study (disc 0 alone) against `ltca backlash`'s
// 32.16. Tolerance: 1e-9 relative (the same code; the sums are in the same order).
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "ltca/app/deck.hpp"

namespace {

namespace fs = std::filesystem;
using ltca::test::RunCli;

/// Every deck in cases/ with a [load] and a [material] (the others have no loaded figure).
std::vector<fs::path> LoadedDecks() {
  std::vector<fs::path> decks;
  for (const auto& e : fs::recursive_directory_iterator(LTCA_CASES_DIR)) {
    if (e.path().extension() != ".toml") continue;
    const std::string rel = fs::relative(e.path(), LTCA_CASES_DIR).string();
    if (rel.rfind("scaling/", 0) == 0 && rel != "scaling/zp010.toml") continue;  // the same model, more pins
    decks.push_back(e.path());
  }
  std::sort(decks.begin(), decks.end());
  return decks;
}

/// A JSON number, or NaN for null.
double Num(const nlohmann::json& j, const std::string& key) {
  if (!j.contains(key) || !j[key].is_number()) return NAN;
  return j[key].get<double>();
}

void Same(double study, double command, const std::string& what) {
  CAPTURE(what);
  if (std::isnan(command)) {
    CHECK(std::isnan(study));
    return;
  }
  CHECK(study == doctest::Approx(command).epsilon(1e-9).scale(1e-9));
}

}  // namespace

TEST_CASE("app: for every deck in cases/, the tolerance study's nominal sample gives the figures of ltca solve, backlash and stiffness") {
  int compared = 0;
  for (const fs::path& path : LoadedDecks()) {
    const std::vector<std::string> few = {"--set", "sweep.positions=4"};
    ltca::app::Deck deck;
    try {
      deck = ltca::app::LoadDeck(path, {"sweep.positions=4"});
      deck.RequireMaterial();
      deck.RequireLoad();
    } catch (const std::invalid_argument&) {
      continue;  // no load or material, or a deck that is refused on purpose
    }
    CAPTURE(path.string());
    ltca::analysis::ToleranceSettings settings = deck.tolerances.value_or(ltca::analysis::ToleranceSettings{});
    settings.lost_motion = deck.RequireLoad().torque != 0.0;  // the loop runs to a rated torque
    const ltca::analysis::ToleranceStudy study(deck.MakeToleranceCase(), deck.solver, settings);
    const ltca::analysis::ToleranceSample s = study.Evaluate(deck.MakeToleranceCase());
    const auto& names = ltca::analysis::ToleranceSettings::FigureNames();
    const auto figure = [&](const std::string& name) {
      return s.figures[static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin())];
    };
    std::vector<std::string> args = {"solve", path.string(), "--json", "-"};
    args.insert(args.end(), few.begin(), few.end());
    const auto solve = RunCli(args);
    REQUIRE(solve.code <= 1);
    const nlohmann::json ss = nlohmann::json::parse(solve.out)["summary"];
    for (const char* key : {"mean_te_arcsec", "pp_te_arcsec", "max_contact_stress_mpa", "max_pin_force_n"}) Same(figure(key), Num(ss, key), key);
    if (deck.reducer) {
      for (const char* key : {"max_bearing_load_n", "shortest_l10_hours"}) Same(figure(key), Num(ss["stage"], key), key);
    }
    // The backlash: the mesh's unloaded analysis, or a reducer stage's free play over the sweep.
    if (!deck.reducer) {
      args = {"backlash", path.string(), "--json", "-"};
      args.insert(args.end(), few.begin(), few.end());
      const auto backlash = RunCli(args);
      REQUIRE(backlash.code <= 1);
      const nlohmann::json bs = nlohmann::json::parse(backlash.out)["summary"];
      Same(figure("mean_backlash_arcsec"), Num(bs, "mean_backlash_arcsec"), "mean_backlash_arcsec");
      Same(figure("pp_backlash_arcsec"), Num(bs, "pp_backlash_arcsec"), "pp_backlash_arcsec");
    } else if (!deck.stiffness.crank) {
      args = {"stiffness", path.string(), "--json", "-"};
      args.insert(args.end(), few.begin(), few.end());
      const auto loop = RunCli(args);
      REQUIRE(loop.code <= 1);
      const nlohmann::json ls = nlohmann::json::parse(loop.out)["summary"];
      if (loop.code == 0) {
        Same(figure("mean_backlash_arcsec"), 60.0 * Num(ls, "backlash_arcmin"), "mean_backlash_arcsec");
        Same(figure("pp_backlash_arcsec"), 60.0 * (Num(ls, "backlash_arcmin_max") - Num(ls, "backlash_arcmin_min")), "pp_backlash_arcsec");
      }
    }
    // Lost motion, as `ltca stiffness` solves it at the deck's [stiffness] cranks.
    args = {"stiffness", path.string(), "--json", "-"};
    args.insert(args.end(), few.begin(), few.end());
    const auto loop = RunCli(args);
    if (settings.lost_motion && loop.code == 0 && s.status == ltca::analysis::RunStatus::kSuccess) {
      Same(figure("lost_motion_arcmin"), Num(nlohmann::json::parse(loop.out)["summary"], "lost_motion_arcmin"), "lost_motion_arcmin");
    }
    ++compared;
  }
  CHECK(compared >= 40);
}
