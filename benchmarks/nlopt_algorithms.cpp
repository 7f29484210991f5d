// Measures every NLopt algorithm as the engine of the `compatibility` solver on three published
// decks (docs/solvers.md). Not a test: it prints a table. Usage: ltca-bench-nlopt
#include <algorithm>
#include <cstdio>
#include <string>

#include "ltca/solvers/registry.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/solvers/load_solver.hpp"

int main() {
  using namespace ltca;
  auto table1 = app::DefaultDeck();
  table1.contact.rho_convention = contact::RhoConvention::kAbsolute;
  auto base = app::LoadDeck(std::string(LTCA_CASES_DIR) + "/liu2021_sec52_base.toml");
  auto li = app::LoadDeck(std::string(LTCA_CASES_DIR) + "/li_table1.toml");
  std::printf("every third position of one mesh period (31), linearised, torque tolerance 1e-10\n");
  std::printf("algorithm      | Liu Table 1 (absolute rho) | Liu section 5.2 | Li Table 1\n");
  for (const char* algorithm : {"LD_MMA", "LD_CCSAQ", "LD_LBFGS", "LD_SLSQP", "LD_TNEWTON", "LD_VAR2", "LN_BOBYQA",
                                "LN_COBYLA", "LN_NELDERMEAD", "LN_SBPLX", "LN_PRAXIS"}) {
    std::printf("%-14s", algorithm);
    for (const auto* deck : {&table1, &base, &li}) {
      const contact::MeshModel model(deck->pair, deck->modification, deck->errors);
      solvers::SolverOptions options;
      options.name = "compatibility";
      options.nlopt_algorithm = algorithm;
      const auto solver = solvers::MakeSolver(options.name);
      int ok = 0;
      double evaluations = 0, seconds = 0, worst = 0;
      for (int i = 0; i < 91; i += 3) {
        const solvers::LoadProblem problem(model, units::DegToRad(9.0 * i / 90), deck->contact, *deck->material,
                                           deck->load->torque, contact::ContactKinematics::kLinearised);
        const auto r = solver->Solve(problem, options);
        ok += r.status == solvers::SolverStatus::kSuccess;
        evaluations += r.torque_evaluations;
        seconds += r.wall_seconds;
        worst = std::max(worst, r.residuals.torque_relative);
      }
      std::printf(" | ok %2d/31 evals %6.1f %7.1f us res %.1e", ok, evaluations / 31, seconds / 31 * 1e6, worst);
    }
    std::printf("\n");
  }
}
