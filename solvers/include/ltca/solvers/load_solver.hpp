#pragma once
// One door for every load solver (pattern: Drake's SolverBase). The public Solve() is not
// virtual: it validates the options and the problem, handles the trivial cases every solver
// shares (zero torque), times the solve, fills the shared part of the result and judges it with
// the shared residual; each backend implements DoSolve().
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ltca/solvers/load_problem.hpp"

namespace ltca::solvers {

class ReducerSystem;  // solvers/src/reducer_system.hpp: the stage's assembly, private to the solver layer

/// Every native status of every backend maps to one of these (the native code is kept).
enum class SolverStatus {
  kNotSolved,         ///< Solve() was not called
  kSuccess,           ///< converged; the shared residual confirms it
  kMaxIterations,     ///< iteration or evaluation limit reached
  kLawCannotCarry,    ///< a pin needs more force than its contact law can represent
  kEdgeContact,       ///< a loaded pin sits on a tip corner: edge contact, not solved as line contact
  kTooManyGroups,     ///< energy-groups: the candidate tooth groups exceed the limit
  kNumericalFailure,  ///< the backend failed (NaN, restoration failure, ...)
  kResidualTooLarge,  ///< the backend claimed success, the shared residual disagrees
  kInterference,      ///< a pin overlaps the cycloid at the theoretical position: not solved
  kRotationOutOfRange,  ///< the rotation lies outside [first contact, single-pin bound] or beyond
                        ///< a quarter tooth pitch: not the physically meaningful solution
  kCouplingUnsupported,  ///< the problem has a compliance coupling (LoadProblem::WithCoupling) and
                         ///< the backend cannot solve it: refused before solving, no numbers
  kReducerUnsupported,  ///< the problem has a reducer stage (LoadProblem::WithReducer) and the backend
                      ///< cannot solve it, or not in this form: refused before solving, no numbers
  /// A preloaded pair (LoadProblem::preloaded: both flanks overlap, no rotation seats the disc)
  /// that cannot be assembled: its zero-torque two-flank balance has no solution within the
  /// contact laws (a pin beyond its law's largest force, a pressed tip corner, no balance within a
  /// quarter tooth pitch), or its largest contact stress there exceeds [material]
  /// contact_stress_limit_mpa. The preload figures are kept where its balance was found (the
  /// stress limit; LoadResult::preload), none where it was not.
  kCannotAssemble,
  /// A preloaded pair and a backend that searches one flank from first contact: refused before
  /// solving, no numbers (the preload state, LoadResult::preload, is reported).
  kPreloadUnsupported,
};
const char* ToString(SolverStatus status);

/// Which flank carried the load: the sign of the torque picks it (LoadProblem).
enum class Flank {
  kNone,   ///< zero torque: no pin is loaded
  kDrive,  ///< T > 0: the cycloid turns in the model's load direction (docs/conventions.md)
  kCoast,  ///< T < 0: the other flank, the cycloid turns the other way
};
const char* ToString(Flank flank);

/// The [solver] section and the per-run settings. Plain struct with defaults and a validation.
/// The kinematics is the problem's (LoadProblem::kinematics), not an option of the solve.
struct SolverOptions {
  std::string name = "bisection";
  double torque_tolerance = 1e-10;   ///< relative |T_out - T| / T
  int max_iterations = 500;          ///< torque evaluations (bisection) or iterations
  /// compatibility: the NLopt algorithm by name (chosen from measurements, docs/solvers.md).
  std::string nlopt_algorithm = "LD_LBFGS";
  /// The shared residual accepted for kSuccess (normalised, see Residuals).
  double residual_tolerance = 1e-6;
  /// Preset name applied by ApplyPreset (e.g. "liu2021": torque_tolerance 1e-2, as Liu's stopping rule).
  void Validate() const;
};
/// "liu2021": the paper's 1 % torque stopping rule.
SolverOptions ApplyPreset(SolverOptions options, const std::string& preset);

/// What only one backend has (pattern: Drake's per-solver details), as named figures: e.g.
/// "ipopt_iterations", "candidates", "groups_evaluated", "polish_steps". A new backend adds its
/// own names without touching this header.
using BackendDetails = std::map<std::string, double>;

struct LoadResult {
  SolverStatus status = SolverStatus::kNotSolved;
  std::string message = "Solve() was not called";
  int native_code = 0;                  ///< the backend's own status code
  double rotation = std::numeric_limits<double>::quiet_NaN();  ///< psi, rad, in the direction of the torque
  /// Loaded TE (Liu eq. 16), rad: -psi for T >= 0; for T < 0 the cycloid lags the other way,
  /// +psi, so that a perfect pair gives TE(-T) = -TE(T) on the mirrored flank.
  double te = std::numeric_limits<double>::quiet_NaN();
  Flank flank = Flank::kNone;           ///< the flank that carried the load
  std::vector<double> force;            ///< N, per pin
  std::vector<double> approach;         ///< mm, per pin (geometric approach at psi)
  std::vector<int> active;              ///< 0-based pins carrying load
  double energy = 0.0;                  ///< total complementary elastic energy, N*mm (+ 1/2 F^T C F coupled)
  Residuals residuals;                  ///< the shared judge's verdict
  int iterations = 0;
  int torque_evaluations = 0;
  double wall_seconds = -1.0;
  BackendDetails details;               ///< the backend's own figures
  /// Set by the judge on a success whose figures lie beyond what the model or the material
  /// stands for (contact stress above [material] contact_stress_limit_mpa, a Hertz half-width
  /// beyond valid_half_width()): the numbers are solved, but say so. Empty otherwise.
  std::vector<std::string> warnings;
  /// A stage problem's poses, output-element and bearing forces; empty for the mesh alone.
  std::optional<ReducerSolution> reducer;
  /// A preloaded pair's zero-torque state (LoadProblem::preloaded); empty for a pair with free play.
  struct Preload {
    double rotation = 0.0;       ///< psi of the zero-torque balance, rad, in the problem's frame
    std::vector<double> force;   ///< N, per point, at zero torque
    double max_force_n = 0.0;    ///< the largest point force at zero torque, N
    double max_stress_mpa = 0.0; ///< the largest Hertz contact stress at zero torque, MPa
    int contacts = 0;            ///< points pressed at zero torque
    /// Sum of F_i |L_i| over the points of the flank opposite the load (L_i < 0) at zero torque,
    /// N*mm: the moment each flank carries against the other in the preload state.
    double opposing_torque_nmm = 0.0;
  };
  std::optional<Preload> preload;
};

/// The shared judge on a whole result: a stage problem's every balance (from the result's poses and
/// element forces, as Solve judges it), else ComputeResiduals(problem, rotation, force).
Residuals ComputeResiduals(const LoadProblem& problem, const LoadResult& result);

/// LoadSolver::Solve calls in this process so far, over every solver and thread (a relaxed atomic
/// counter): shows that something, e.g. reading a deck, runs no load solve.
std::uint64_t SolveCallCount();

class LoadSolver {
 public:
  virtual ~LoadSolver() = default;
  virtual std::string name() const = 0;
  /// Whether the backend solves problems with a compliance coupling (LoadProblem::has_coupling).
  /// Solve() refuses a coupled problem with kCouplingUnsupported before a backend without it runs.
  virtual bool supports_coupling() const { return false; }
  /// Whether the backend solves a reducer stage (LoadProblem::has_reducer). Solve() refuses a stage
  /// problem with kReducerUnsupported before a backend without it runs.
  virtual bool supports_reducer() const { return false; }
  /// Whether the backend solves a preloaded mesh (LoadProblem::preloaded: both flanks pressed,
  /// docs/solvers.md "Two flanks"). Solve() refuses one with kPreloadUnsupported otherwise.
  virtual bool supports_two_flanks() const { return false; }
  /// Validates, solves, fills the shared fields, checks the residual. Never throws for a
  /// failure to converge (that is a status); throws std::invalid_argument for bad options.
  /// A solver object holds no state: one may serve several threads, each with its own
  /// workspace (warm starts and scratch live there, so a sweep passes the same one each time).
  LoadResult Solve(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace) const;
  /// The same with a fresh workspace (no warm start).
  LoadResult Solve(const LoadProblem& problem, const SolverOptions& options) const;

 private:
  /// Sets status, message, native_code, rotation, force, iterations / evaluations.
  virtual void DoSolve(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                       LoadResult* result) const = 0;
  /// The stage's solve (only called when supports_reducer()), on the stage assembled once by Solve()
  /// (solvers/src/reducer_system.hpp): sets status, message, iterations and, through the assembly,
  /// rotation, forces and the stage's solution.
  virtual void DoSolveReducer(const LoadProblem& problem, const ReducerSystem& system, const SolverOptions& options,
                            Workspace& workspace, LoadResult* result) const;
  /// Exact kinematics of the stage: DoSolveReducer on the stage re-linearised about each iterate's
  /// poses until they stay; returns the poses (coordinates) the result reports.
  Eigen::VectorXd SolveReducerExact(const LoadProblem& problem, const ReducerSystem& nominal, const SolverOptions& options,
                                  Workspace& workspace, LoadResult* result) const;
  /// Solve()'s path for a preloaded mesh: the preload state (two_flanks.hpp at zero torque), the
  /// assembly's limits (kCannotAssemble), then DoSolve when the backend solves two flanks.
  void SolvePreloaded(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                      LoadResult* result) const;
  /// A stage whose pins overlap: its zero-torque balance first (the preload state, the assembly's
  /// limits: kCannotAssemble), then the loaded one.
  /// elements: a bearing or output pins are pressed at no load too (StageElementsPreloaded).
  void SolveReducerPreloaded(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                             LoadResult* result, bool elements = false) const;
  /// The stage's solve and judge at the problem's torque; at zero torque the nominal poses without
  /// forces unless solve_zero (a preloaded stage's zero-torque balance is solved).
  void SolveReducerBody(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                        LoadResult* result, bool solve_zero = false) const;
  /// TE, flank, active points and energy of a stage's result.
  void FinishReducerResult(const LoadProblem& problem, LoadResult* result) const;
  /// Solve()'s path for a stage: refusals, zero torque, DoSolveReducer and the stage's judge.
  void SolveReducer(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                  LoadResult* result) const;
};

}  // namespace ltca::solvers
