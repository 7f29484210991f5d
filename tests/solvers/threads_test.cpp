// Issue 9: a LoadProblem is immutable and a solver object stateless, so problems and solvers may
// be shared across threads; each thread brings its own Workspace. Two threads solving the same
// sweep give bit-identical results, equal to one thread alone.
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <doctest/doctest.h>

#include "problems.hpp"

#include "ltca/solvers/load_solver.hpp"
#include "ltca/solvers/registry.hpp"
#include "ltca/solvers/workspace.hpp"

using ltca::contact::ContactKinematics;
using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::LoadSolver;
using ltca::solvers::SolverOptions;
using ltca::solvers::SolverStatus;
using ltca::solvers::Workspace;

namespace {

struct Run {
  std::string solver;
  ContactKinematics kinematics;
};

// Every solver over the shared problems in order, with one workspace per solver (as a sweep).
std::vector<LoadResult> SolveAll(const std::vector<Run>& runs, const std::vector<std::vector<LoadProblem>>& problems,
                                 const std::vector<std::unique_ptr<LoadSolver>>& solvers) {
  std::vector<LoadResult> out;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    Workspace workspace;
    SolverOptions options;
    options.name = runs[r].solver;
    for (const LoadProblem& p : problems[r]) out.push_back(solvers[r]->Solve(p, options, workspace));
  }
  return out;
}

bool BitIdentical(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("solvers: two threads sharing problems and solvers, each with its own workspace, give bit-identical results") {
  const ltca::test::PaperCase liu = ltca::test::LiuTable1();
  const auto model = liu.Model();
  std::vector<Run> runs;
  for (const auto& name : ltca::solvers::SolverNames()) {
    runs.push_back({name, ContactKinematics::kLinearised});
    runs.push_back({name, ContactKinematics::kExact});
  }
  // Every ninth position of the deck's mesh period (11), built once and shared by both threads.
  std::vector<std::vector<LoadProblem>> problems(runs.size());
  std::vector<std::unique_ptr<LoadSolver>> solvers;
  const auto cranks = liu.Cranks();
  for (std::size_t r = 0; r < runs.size(); ++r) {
    solvers.push_back(ltca::solvers::MakeSolver(runs[r].solver));
    for (std::size_t i = 0; i < cranks.size(); i += 9) {
      problems[r].push_back(liu.Problem(model, cranks[i], runs[r].kinematics));
    }
  }
  std::vector<LoadResult> a, b;
  std::thread ta([&] { a = SolveAll(runs, problems, solvers); });
  std::thread tb([&] { b = SolveAll(runs, problems, solvers); });
  ta.join();
  tb.join();
  const std::vector<LoadResult> alone = SolveAll(runs, problems, solvers);
  REQUIRE(a.size() == alone.size());
  REQUIRE(b.size() == alone.size());
  int compared = 0;
  for (std::size_t k = 0; k < alone.size(); ++k) {
    CAPTURE(k);
    CHECK(alone[k].status == SolverStatus::kSuccess);
    for (const auto* other : {&a[k], &b[k]}) {
      CHECK(other->status == alone[k].status);
      CHECK(BitIdentical(other->rotation, alone[k].rotation));
      REQUIRE(other->force.size() == alone[k].force.size());
      for (std::size_t i = 0; i < alone[k].force.size(); ++i) CHECK(BitIdentical(other->force[i], alone[k].force[i]));
      ++compared;
    }
  }
  CHECK(compared == static_cast<int>(2 * runs.size() * 11));  // both threads, every run, 11 positions
}
