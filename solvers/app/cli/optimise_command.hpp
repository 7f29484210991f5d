#pragma once
#include <limits>
#include <optional>
#include <string>

#include "ltca/analysis/optimise.hpp"
#include "ltca/app/deck.hpp"
#include "output.hpp"

namespace ltca::cli {

/// The command line of `ltca optimise` (docs/optimise.md).
struct OptimiseOptions {
  std::string solver, kinematics;
  std::string json_path, csv_path, svg_path, deck_path;
  int threads = 0;  ///< 0: every hardware thread
  std::optional<int> evaluations;
  int map = 0;  ///< points a variable of the objective's map (two variables), 0: none
  std::string pareto;  ///< the second figure of a Pareto front, "" none
  double pareto_from = std::numeric_limits<double>::quiet_NaN(), pareto_to = std::numeric_limits<double>::quiet_NaN();
  int pareto_steps = 11;
};

class SampleFarm;
/// The optimiser's view of the ranks of an MPI job (nullptr: this process alone): every rank runs
/// the search in lockstep and shares what divides through the farm's AllGather.
analysis::RankGroup RankGroupOf(SampleFarm* farm);

/// `ltca optimise`: the search of the deck's [optimise] (on MPI ranks under mpirun), its history,
/// convergence figure, best design as a deck, map and Pareto front. Returns kExitSuccess when a
/// design met the constraints, kExitNotSucceeded otherwise.
int RunOptimise(const app::Deck& deck, const OptimiseOptions& options, const Streams& streams);

}  // namespace ltca::cli
