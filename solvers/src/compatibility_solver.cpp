#include "compatibility_solver.hpp"

#include <optional>

#include "first_contact.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <nlopt.hpp>

#include "coupled_contact.hpp"
#include "ltca/geometry/units.hpp"
#include "reducer_system.hpp"

namespace ltca::solvers {
namespace {

struct Potential {
  const LoadProblem* problem = nullptr;
  Workspace* workspace = nullptr;
  int evaluations = 0;
  std::exception_ptr error;  // NLopt swallows exceptions thrown in callbacks: keep and rethrow
  bool edge = false;
  std::vector<double> hints;  // warm starts of the law inversions, one per pin
  // The last evaluation, kept: the polish, the torque check and the answer ask for
  // NLopt's last point again. Storage reused from one evaluation to the next.
  std::vector<LoadProblem::PinAt> pins;
  std::vector<contact::ContactLaw> scratch;
  double last_psi = std::numeric_limits<double>::quiet_NaN(), last_pi = 0.0, last_torque = 0.0;
  bool last_edge = false;
  std::vector<double> last_force;

  // Pi(psi) and dPi/dpsi.
  double Evaluate(double psi, double* gradient) {
    if (psi != last_psi) {
      ++evaluations;
      double pi = -problem->torque() * psi, torque = 0.0;
      bool at_edge = false;
      problem->At(psi, *workspace, &scratch, &pins);
      hints.resize(pins.size(), 0.0);
      last_force.assign(pins.size(), 0.0);
      for (std::size_t i = 0; i < pins.size(); ++i) {
        const auto& pin = pins[i];
        if (pin.approach <= 0.0) continue;
        if (pin.law == nullptr) {
          at_edge = true;
          continue;
        }
        const double f = pin.law->Force(pin.approach, &hints[i]);
        pi += pin.law->StrainEnergy(pin.approach, f);  // U = F delta - E^c(F)
        torque += f * pin.arm;
        last_force[i] = f;
      }
      edge = edge || at_edge;
      last_psi = psi, last_pi = pi, last_torque = torque, last_edge = at_edge;
    }
    if (gradient != nullptr) *gradient = last_torque - problem->torque();
    return last_pi;
  }
};

double Objective(const std::vector<double>& x, std::vector<double>& grad, void* data) {
  auto* p = static_cast<Potential*>(data);
  try {
    double g = 0.0;
    const double value = p->Evaluate(x[0], grad.empty() ? nullptr : &g);
    if (!grad.empty()) grad[0] = g;
    return value;
  } catch (...) {
    p->error = std::current_exception();
    throw nlopt::forced_stop();
  }
}

}  // namespace

void CompatibilitySolver::DoSolve(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                                  LoadResult* result) const {
  if (problem.has_coupling()) {
    SolveCoupled(problem, options, workspace, result);
    return;
  }
  // A preloaded pair (result->preload set by LoadSolver::SolvePreloaded): the same potential, its
  // sum over the pins of both flanks (a pressed pin of negative arm adds U_i, convex in psi as any),
  // bracketed about the preload state instead of from a first contact (docs/solvers.md "Two flanks").
  const std::optional<double> preload =
      result->preload ? std::optional<double>(result->preload->rotation) : std::nullopt;
  if (problem.kinematics() == contact::ContactKinematics::kExact) {
    SolveExact(problem, options, workspace, result, preload);
    return;
  }
  if (preload) {
    SolveLinearised(problem, options, workspace, result, *preload, true);
    return;
  }
  SolveLinearised(problem, options, workspace, result);
}

void CompatibilitySolver::SolveCoupled(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                                      LoadResult* result) const {
  // Jiang 2022 eq. 10-11 with the coupled deflection: Newton on (psi, F) about the first contact.
  // Linearised kinematics: delta_i(psi0 + psi) = delta_i(psi0) + L_i psi is exact, one solve.
  // Exact kinematics: re-linearise about each new psi; at psi_k the forces of the exact
  // approaches (the coupled complementarity problem at psi_k) decide whether the torque balances.
  // A preloaded pair: linearised about its preload state (result->preload), the pins of both flanks
  // in the active-set Newton.
  double psi = 0.0;
  if (result->preload) {
    psi = result->preload->rotation;
  } else {
    const std::optional<double> first_contact = FirstContactOrFail(problem, result);
    if (!first_contact) return;
    psi = *first_contact;
  }
  CoupledContact& coupled = CoupledContactFor(problem, workspace);
  const ActiveSetCholmod::Stats before = coupled.stats();
  const double force_scale = CoupledForceScale(problem);
  const bool exact = problem.kinematics() == contact::ContactKinematics::kExact;
  std::vector<double> forces;
  std::vector<contact::ContactLaw> scratch;
  CoupledOutcome outcome;
  int outer = 0, newton = 0;
  bool balanced = false;
  for (; outer < 30; ++outer) {
    const std::vector<CoupledPoint> points = CoupledPoints(problem.At(psi, workspace, &scratch));
    if (outer > 0) {  // exact: the answer at the exact approaches of psi
      outcome = coupled.AtRotation(points, force_scale, &forces);
      newton += outcome.iterations;
      if (!outcome.converged || outcome.edge) break;
      balanced = problem.Balanced(psi, outcome.torque, options.torque_tolerance, workspace);
      if (balanced) break;
    }
    outcome = coupled.ForTorque(points, problem.torque(), &forces);
    newton += outcome.iterations;
    psi += outcome.rotation;
    if (!outcome.converged || outcome.edge) break;
    if (!exact) {
      balanced = problem.Balanced(psi, outcome.torque, options.torque_tolerance, workspace);
      break;
    }
  }
  result->rotation = psi;
  result->force = forces;
  result->force.resize(static_cast<std::size_t>(problem.point_count()), 0.0);
  result->iterations = newton;
  result->torque_evaluations = outer + 1;
  result->details = {{"newton_steps", newton}, {"relinearisations", outer + 1}};
  AddKernelDetails(before, coupled.stats(), &result->details);
  const double miss = std::abs(outcome.torque - problem.torque()) / problem.torque();
  if (outcome.saturated) {
    result->status = SolverStatus::kLawCannotCarry;
    result->message = outcome.failure;
  } else if (outcome.edge) {
    result->status = SolverStatus::kEdgeContact;
    result->message = "a loaded pin sits on a tip corner (edge contact); line-contact laws do not apply";
  } else if (!outcome.converged) {
    result->status = SolverStatus::kNumericalFailure;
    result->message = fmt::format("coupled Newton: {}", outcome.failure);
  } else if (balanced) {
    result->status = SolverStatus::kSuccess;
    result->message = fmt::format("coupled Newton on (psi, F): {} steps, {} linearisations, torque balanced to {:.3g}",
                                  newton, outer + 1, miss);
  } else {
    result->status = SolverStatus::kMaxIterations;
    result->message = fmt::format("coupled Newton: iteration limit reached ({} linearisations) before the torque balanced: "
                                  "off by {:.3g} relative at the stop, torque_tolerance {:.3g}",
                                  outer + 1, miss, options.torque_tolerance);
  }
}

void CompatibilitySolver::SolveExact(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                                     LoadResult* result, std::optional<double> preload) const {
  // Issue 4: the linearisation about the base state (psi = 0) is Jiang's problem; its solution psi_1
  // misses the exact balance by the kinematic nonlinearity only (second order in psi). From psi_1
  // the exact torque balance M(psi) = T is closed by Newton's method on M itself, where
  // it was closed by re-linearising about each psi_k and minimising the new potential with NLopt
  // (4 to 5 linearisations a position on Liu Table 1, each 40 laws and a whole NLopt run). The
  // fixed point is the same: M(psi) = T on the exact geometry, judged by the same rule.
  SolverOptions inner = options;
  // The linearisation about psi_k matches the exact torque at psi_k only: solve it to a quarter of
  // the tolerance, so that the exact torque at the settled rotation meets the tolerance itself
  // (at the requested 1e-10 one d = 3 position ended 1.01e-10 off).
  inner.torque_tolerance = 0.25 * options.torque_tolerance;
  int evaluations = 0, linearisations = 0;
  // Jiang's minimisation on the linearisation about the exact state at psi (its pins searched and
  // kept in the workspace; psi = 0: the base state); the new rotation, or a failure in *result.
  const auto relinearise = [&](double psi, double guess) -> std::optional<double> {
    const LoadProblem linear = [&] {
      if (linearisations == 0) return problem.Linearised();
      contact::MeshState state = problem.base_state();
      state.pins = problem.ExactPins(psi, workspace);
      state.loaded_rotation = psi;
      for (auto& pin : state.pins) pin.clearance += pin.arm * psi;  // L psi' - c~ = approach at psi' (first order)
      return problem.LinearisedOn(std::move(state));
    }();
    ++linearisations;
    LoadResult step;
    step.force.assign(static_cast<std::size_t>(problem.point_count()), 0.0);
    SolveLinearised(linear, inner, workspace, &step, guess, preload.has_value());
    evaluations += step.torque_evaluations;
    // Where double precision cannot refine to a quarter of the tolerance (the polish bracket
    // collapses: cases/hard/inflection_pin.toml at crank 23.166345849916095 deg stopped 2.5e-11
    // off) but the requested tolerance holds, the step is usable: the exact verdict decides.
    const bool refined_enough = step.status == SolverStatus::kNumericalFailure && std::isfinite(step.rotation) &&
                                linear.Balanced(step.rotation, linear.OutputTorque(step.rotation, workspace),
                                                options.torque_tolerance, workspace);
    if (step.status != SolverStatus::kSuccess && step.status != SolverStatus::kEdgeContact && !refined_enough) {
      *result = step;
      result->message = fmt::format("re-linearisation {}: {}", linearisations, step.message);
      return std::nullopt;
    }
    return step.rotation;
  };
  // (preloaded: the bracket of the linearisation about the base state starts at the preload state)
  const std::optional<double> first = relinearise(0.0, preload ? *preload : std::numeric_limits<double>::quiet_NaN());
  if (!first) return;
  double psi = *first;
  // Newton on M(psi) - T from psi_1. M = sum F_i(delta_i) L_i; its tangent with the geometry and
  // the laws held, t = sum k_i L_i^2 (d delta_i / d psi = L_i on the exact geometry, k_i =
  // dF_i / d delta_i = 1 / Compliance(F_i)), misses what turning does to the arms and to the laws
  // (the curvature at the moving foot point): a few 1e-4 of M' on Liu Table 1, which would leave
  // the iteration linear at that rate. From the second step on, the slope is t scaled by the
  // ratio of the secant of M over the last two rotations to the mean of their tangents, the
  // trapezoidal rule: that ratio carries the missing terms to second order in the step. The
  // confirmed evaluations (below) that bracket the balance keep the iteration inside: a step out
  // of the bracket bisects it instead.
  double lo = -INFINITY, hi = INFINITY;
  double psi_before = std::numeric_limits<double>::quiet_NaN(), torque_before = 0.0, tangent_before = 0.0;
  std::vector<double> hints(static_cast<std::size_t>(problem.point_count()), 0.0);
  std::vector<LoadProblem::PinAt> pins;
  std::vector<contact::ContactLaw> scratch;
  Loading loading;
  int newton = 0;
  bool balanced = false;
  for (; newton < 30; ++newton) {
    // An iterate searches the pins that may be pressed at psi (Freshness::kNear: a pin clearly
    // open on its extrapolation from its last search is not searched). One that balances is
    // confirmed with every pin that can be pressed searched (kLoadedOnly, whose skips are proven):
    // the forces and torque of every pin.
    problem.At(psi, workspace, &scratch, &pins, LoadProblem::Freshness::kNear);
    LoadAt(pins, &hints, &loading);
    ++evaluations;
    bool confirmed = false;  // the torque of every pin that can be pressed (kLoadedOnly)
    if (problem.Balanced(psi, loading.torque, 0.5 * options.torque_tolerance, pins, &loading.force)) {
      problem.At(psi, workspace, &scratch, &pins, LoadProblem::Freshness::kLoadedOnly);
      LoadAt(pins, &hints, &loading);
      confirmed = true;
      if (problem.Balanced(psi, loading.torque, 0.5 * options.torque_tolerance, pins, &loading.force)) {
        balanced = true;
        break;
      }
    }
    const double miss = problem.torque() - loading.torque;
    if (confirmed) (miss > 0.0 ? lo : hi) = psi;  // (an iterate's torque may miss a pin: no bracket)
    double tangent = 0.0;
    for (std::size_t i = 0; i < pins.size(); ++i) {
      const double f = loading.force[i];
      if (f > 0.0) tangent += pins[i].arm * pins[i].arm / pins[i].law->Compliance(f);
    }
    double slope = tangent;
    if (psi != psi_before && std::isfinite(psi_before)) {
      const double ratio = (loading.torque - torque_before) / (psi - psi_before) / (0.5 * (tangent + tangent_before));
      if (ratio > 0.5 && ratio < 2.0) slope *= ratio;  // (a pin closing or opening between them: not)
    }
    psi_before = psi, torque_before = loading.torque, tangent_before = tangent;
    double next = psi + miss / slope;
    if (!(slope > 0.0) || !(next > lo && next < hi)) {
      if (std::isfinite(lo) && std::isfinite(hi)) {
        next = 0.5 * (lo + hi);
      } else {  // no bracket on that side yet: the linearisation about psi, minimised
        const std::optional<double> step = relinearise(psi, psi);
        if (!step) return;
        next = *step;
      }
    }
    if (std::abs(next - psi) <= 1e-15 * std::max(std::abs(psi), 1e-12)) break;  // cannot move any more
    psi = next;
  }
  // The answer on the exact geometry: forces of the laws at the exact approaches (the last
  // evaluation, or the one at the rotation the iteration stopped on).
  if (!balanced) {
    problem.At(psi, workspace, &scratch, &pins, LoadProblem::Freshness::kLoadedOnly);
    LoadAt(pins, &hints, &loading);
  }
  result->force = loading.force;
  const double torque = loading.torque;
  result->rotation = psi;
  result->torque_evaluations = evaluations;
  result->iterations = linearisations + newton;
  result->details = {{"nlopt_result", 0.0}, {"polish_steps", 0.0}, {"linearisations", static_cast<double>(linearisations)},
                     {"newton_steps", static_cast<double>(newton)}};
  const double miss = std::abs(torque - problem.torque());
  if (loading.edge) {
    result->status = SolverStatus::kEdgeContact;
    result->message = "a loaded pin sits on a tip corner (edge contact); line-contact laws do not apply";
  } else if (problem.Balanced(psi, torque, options.torque_tolerance, pins, &loading.force)) {  // (every pin that can be pressed)
    result->status = SolverStatus::kSuccess;
    result->message = fmt::format("exact torque balance: linearisations {}, Newton steps {}, torque balanced to {:.3g}",
                                  linearisations, newton, miss / problem.torque());
  } else {
    result->status = SolverStatus::kMaxIterations;
    result->message = fmt::format("iteration limit reached (linearisations {}, Newton steps {}) before the torque "
                                  "balanced: off by {:.3g} relative at the stop, torque_tolerance {:.3g}",
                                  linearisations, newton, miss / problem.torque(), options.torque_tolerance);
  }
}

void CompatibilitySolver::SolveLinearised(const LoadProblem& problem, const SolverOptions& options,
                                          Workspace& workspace, LoadResult* result, double guess_rotation,
                                          bool two_flanks) const {
  nlopt::algorithm algorithm;
  try {
    algorithm = static_cast<nlopt::algorithm>(nlopt_algorithm_from_string(options.nlopt_algorithm.c_str()));
    if (static_cast<int>(algorithm) < 0) throw std::invalid_argument("unknown");
  } catch (const std::exception&) {
    throw std::invalid_argument(fmt::format(
        "[solver] nlopt_algorithm = \"{}\": not an NLopt algorithm name (e.g. LD_MMA, LD_LBFGS, LN_BOBYQA)",
        options.nlopt_algorithm));
  }
  Potential potential;
  potential.problem = &problem;
  potential.workspace = &workspace;
  // Bracket: from the first contact in the load direction to a rotation whose torque exceeds T.
  // A preloaded pair has none: its lower end is a rotation whose torque falls short of T, found from
  // guess_rotation (the preload state, M = 0 < T there) or, when the linearisation's own preload
  // state lies below it, stepping down from there in doubling steps from Liu's 1/60 arcsec (M is
  // non-decreasing in psi, the pins of either arm included: dM/dpsi = sum k_i L_i^2).
  double lo = 0.0;
  if (two_flanks) {
    lo = std::isfinite(guess_rotation) ? guess_rotation : 0.0;
    double g_lo = 0.0;
    potential.Evaluate(lo, &g_lo);
    double down = units::ArcsecToRad(1.0 / 60.0);
    const double top = lo;
    for (int i = 0; i < 200 && g_lo >= 0.0; ++i, down *= 2.0) {
      lo = top - down;
      potential.Evaluate(lo, &g_lo);
    }
    if (g_lo >= 0.0) {
      result->status = SolverStatus::kNumericalFailure;
      result->message = "two flanks: no rotation found whose output torque falls short of the load";
      return;
    }
  } else {
    const std::optional<double> first_contact = FirstContactOrFail(problem, result);
    if (!first_contact) return;
    lo = *first_contact;
  }
  // Linear prediction of the rotation from the secant stiffness of every closing pin at its share
  // of the load (forward law evaluations only), then a bracket grown from it.
  double guess = 0.0;
  {
    std::vector<contact::ContactLaw> scratch;
    double sum_arm = 0.0, stiffness = 0.0;
    const auto pins = problem.At(lo, workspace, &scratch);
    for (const auto& pin : pins) {
      if (pin.law != nullptr && pin.arm > 0.0 && pin.approach > -1e-3) sum_arm += pin.arm;
    }
    const double share = sum_arm > 0.0 ? problem.torque() / sum_arm : 0.0;
    for (const auto& pin : pins) {
      if (pin.law == nullptr || pin.arm <= 0.0 || !(pin.approach > -1e-3) || share <= 0.0) continue;
      const double w = pin.law->Approach(share);
      if (w > 0.0) stiffness += share / w * pin.arm * pin.arm;
    }
    guess = stiffness > 0.0 ? problem.torque() / stiffness : 1e-6;
  }
  double hi = lo + guess, g = 0.0;
  potential.Evaluate(hi, &g);
  double step = guess;
  for (int i = 0; i < 200 && g < 0.0; ++i) {
    lo = hi;
    step *= 2.0;
    hi = lo + step;
    potential.Evaluate(hi, &g);
  }
  if (g < 0.0) {
    result->status = SolverStatus::kLawCannotCarry;
    result->message = "the output torque stays below the load over every rotation tried";
    return;
  }
  const double start =
      std::isfinite(guess_rotation) ? std::clamp(guess_rotation, lo, hi) : std::clamp(lo + guess, lo, hi);
  nlopt::opt opt(algorithm, 1);
  opt.set_min_objective(Objective, &potential);
  opt.set_lower_bounds(std::vector<double>{lo});
  opt.set_upper_bounds(std::vector<double>{hi});
  opt.set_xtol_abs(1e-16 * std::max(hi, 1e-12));
  opt.set_xtol_rel(1e-15);
  opt.set_ftol_rel(0.0);
  opt.set_maxeval(options.max_iterations);
  std::vector<double> x{start};
  double value = 0.0;
  nlopt::result code = nlopt::FAILURE;
  try {
    code = opt.optimize(x, value);
  } catch (const nlopt::roundoff_limited&) {
    code = nlopt::ROUNDOFF_LIMITED;  // often at the optimum already: the torque check below decides
  } catch (const nlopt::forced_stop&) {
    if (potential.error) std::rethrow_exception(potential.error);
    code = nlopt::FORCED_STOP;
  } catch (const std::runtime_error&) {
    // Generic NLopt failure (e.g. a line search that gives up): with exact kinematics the law's
    // curvature follows psi, so the torque mismatch is not exactly dPi/dpsi there. x holds the
    // best point; the polish and the torque check below decide.
    code = nlopt::FAILURE;
  }
  result->native_code = static_cast<int>(code);
  // Polish: near its minimum Pi is flat to second order, so its value cannot resolve a torque
  // mismatch below ~1e-8 and NLopt may stop there (FTOL / roundoff / failure). Regula falsi
  // (Illinois) on the mismatch, inside the bracket [lo, hi] shrunk by NLopt's point, finishes
  // the job with guaranteed convergence; the steps are counted and reported.
  int polish = 0;
  double gx = 0.0;
  potential.Evaluate(x[0], &gx);
  if (!problem.Balanced(x[0], problem.torque() + gx, options.torque_tolerance, workspace)) {
    double a = lo, b = hi, ga = 0.0, gb = 0.0;
    potential.Evaluate(a, &ga);
    potential.Evaluate(b, &gb);
    if (gx < 0.0) a = x[0], ga = gx; else b = x[0], gb = gx;
    int side = 0;
    while (polish < 100) {
      if (problem.Balanced(x[0], problem.torque() + gx, options.torque_tolerance, workspace) ||
          b - a <= 4.0 * std::numeric_limits<double>::epsilon() * std::abs(b)) break;
      double c = (gb - ga) != 0.0 ? b - gb * (b - a) / (gb - ga) : 0.5 * (a + b);
      if (!(c > a && c < b)) c = 0.5 * (a + b);
      double gc = 0.0;
      potential.Evaluate(c, &gc);
      ++polish;
      x[0] = c, gx = gc;
      if (gc < 0.0) {
        a = c, ga = gc;
        if (side == -1) gb *= 0.5;  // Illinois: halve the stale end
        side = -1;
      } else {
        b = c, gb = gc;
        if (side == 1) ga *= 0.5;
        side = 1;
      }
    }
  }
  result->rotation = x[0];
  result->details = {{"nlopt_result", static_cast<double>(code)}, {"polish_steps", static_cast<double>(polish)}};
  result->torque_evaluations = potential.evaluations;
  result->iterations = potential.evaluations;
  // The answer: the forces of the last evaluation, which the polish or the torque check made at x.
  potential.Evaluate(x[0], nullptr);
  result->force = potential.last_force;
  const double torque = potential.last_torque;
  const double mismatch = std::abs(torque - problem.torque()) / problem.torque();
  // Edge contact is judged at the answer, not at the trial rotations of the search.
  potential.edge = potential.last_edge;
  // Every NLopt code maps to one status; success is verified on the torque, not believed.
  if (potential.edge) {
    result->status = SolverStatus::kEdgeContact;
    result->message = "a loaded pin sits on a tip corner (edge contact); line-contact laws do not apply";
  } else if (problem.Balanced(x[0], torque, options.torque_tolerance, workspace)) {
    // (the polish above guarantees this unless the resolution of double precision intervenes)
    result->status = SolverStatus::kSuccess;
    result->message = fmt::format("NLopt {} code {} ({} regula falsi polish steps), torque balanced to {:.3g}{}",
                                  options.nlopt_algorithm, static_cast<int>(code), polish, mismatch,
                                  mismatch > options.torque_tolerance ? " (limited by the resolution of the rotation)" : "");
  } else if (code == nlopt::MAXEVAL_REACHED || code == nlopt::MAXTIME_REACHED) {
    result->status = SolverStatus::kMaxIterations;
    result->message = fmt::format("NLopt {} hit its evaluation limit, torque off by {:.3g}", options.nlopt_algorithm, mismatch);
  } else {
    result->status = SolverStatus::kNumericalFailure;
    result->message = fmt::format("NLopt {} stopped (code {}) with the torque off by {:.3g}", options.nlopt_algorithm,
                                  static_cast<int>(code), mismatch);
  }
}

void CompatibilitySolver::DoSolveReducer(const LoadProblem&, const ReducerSystem& system, const SolverOptions& options,
                                       Workspace& workspace, LoadResult* result) const {
  Eigen::VectorXd q = ReducerStart(system, workspace, "compatibility-stage");
  ReducerSystem::Evaluation last;
  int iterations = 0;
  std::vector<double> hints;  // the law inversions' warm starts, from one evaluation to the next
  const auto outcome = system.Minimise(&q, false, options.torque_tolerance, options.max_iterations, &hints,
                                       &iterations, &last);
  FinishReducer(system, q, outcome, last, result);
  result->iterations = iterations;
  result->torque_evaluations = iterations;
  if (result->status == SolverStatus::kSuccess) KeepReducerStart(system, q, workspace, "compatibility-stage");
}

}  // namespace ltca::solvers
