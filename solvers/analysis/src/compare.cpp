#include "ltca/analysis/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ltca/solvers/registry.hpp"

namespace ltca::analysis {

void SolverDifferences::Add(const PositionResult& p, const PositionResult& reference) {
  if (!p.succeeded() || !reference.succeeded()) return;
  ++compared;
  te = std::max(te, std::abs(p.result.te - reference.result.te));
  for (std::size_t k = 0; k < p.result.force.size() && k < reference.result.force.size(); ++k) {
    force = std::max(force, std::abs(p.result.force[k] - reference.result.force[k]));
  }
  pins = std::max(pins, std::abs(p.contacts - reference.contacts));
}

SolverSelection SelectSolvers(const std::vector<std::string>& asked, bool reducer, const std::string& deck) {
  SolverSelection selection;
  for (const auto& name : asked) {
    const std::unique_ptr<solvers::LoadSolver> solver = solvers::MakeSolver(name);
    if (reducer && !solver->supports_reducer()) {
      selection.skipped.push_back({name, "does not solve the reducer stage ([output]; docs/stage.md)"});
    } else {
      selection.run.push_back(name);
    }
  }
  if (selection.run.empty()) {
    throw std::invalid_argument(fmt::format("--solvers {}: none of them solves the reducer stage of deck '{}' ([output]); "
                                            "expected one of the solvers that do (docs/stage.md)",
                                            fmt::join(asked, ","), deck));
  }
  return selection;
}

bool CompareResult::all_succeeded() const {
  return std::all_of(solvers.begin(), solvers.end(), [](const SolverComparison& s) { return s.summary.all_succeeded(); });
}

bool CompareResult::any_failed() const {
  return std::any_of(solvers.begin(), solvers.end(), [](const SolverComparison& s) { return s.summary.failed > 0; });
}

CompareResult Compare(const Stage& stage, const SolverOptions& base, const std::vector<std::string>& names, double torque,
                      const std::vector<SkippedSolver>& skipped, const CompareSink& sink) {
  if (names.empty()) throw std::invalid_argument("Compare: expected at least one solver name");
  std::vector<SweepRunner> runners;
  for (const auto& name : names) {
    SolverOptions o = base;
    o.name = name;
    runners.emplace_back(stage, o, torque);
  }
  CompareResult result;
  result.skipped = skipped;
  result.cranks = stage.cranks();
  std::vector<SolverDifferences> differences(runners.size());
  std::vector<PositionResult> at(runners.size());
  for (const double crank : result.cranks) {
    at[0] = runners.front().Solve(crank);
    for (std::size_t r = 1; r < runners.size(); ++r) {
      at[r] = runners[r].Solve(crank);
      differences[r].Add(at[r], at[0]);
    }
    if (sink) sink(crank, at);
  }
  for (std::size_t r = 0; r < runners.size(); ++r) {
    result.solvers.push_back({runners[r].options(), runners[r].Summary(), differences[r]});
  }
  return result;
}

}  // namespace ltca::analysis
