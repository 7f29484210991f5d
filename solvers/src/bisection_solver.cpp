#include "bisection_solver.hpp"

#include <optional>

#include "first_contact.hpp"
#include "two_flanks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "coupled_contact.hpp"
#include "reducer_system.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::solvers {
namespace {

struct Evaluation {
  double torque = 0.0;
  bool edge = false;       // a pin on a tip corner is pressed
  bool saturated = false;  // a pin is beyond its law's largest force
  std::string failure;     // coupled only: the complementarity problem of the trial did not converge
};

// Storage reused over the trials of one solve (no allocation per trial). The accepted
// trial's pins and laws are kept (swapped, so the laws' addresses stay valid): the convergence
// check at the accepted rotation reads its torque resolution from them instead of evaluating
// every pin at that rotation again after each overshoot (exact kinematics: a closest-point search
// per pin).
struct Buffers {
  std::vector<LoadProblem::PinAt> pins;
  std::vector<contact::ContactLaw> scratch;
  std::vector<LoadProblem::PinAt> accepted_pins;
  std::vector<contact::ContactLaw> accepted_scratch;
  Loading loading;
  std::vector<CoupledPoint> points;  // coupled: the trial's points
  void Accept() {
    pins.swap(accepted_pins);
    scratch.swap(accepted_scratch);
  }
};

Evaluation Evaluate(const LoadProblem& problem, double psi, Workspace& workspace, std::vector<double>* forces,
                    std::vector<double>* hints, Buffers& buffers) {
  // Only the pressed pins matter to a trial's torque: a pin that cannot have closed since its last
  // search is not searched again (exact kinematics; LoadProblem::Freshness).
  problem.At(psi, workspace, &buffers.scratch, &buffers.pins, LoadProblem::Freshness::kLoadedOnly);
  buffers.loading.force.swap(*forces);  // the trial's storage, filled in place
  LoadAt(buffers.pins, hints, &buffers.loading);
  forces->swap(buffers.loading.force);
  return {buffers.loading.torque, buffers.loading.edge, buffers.loading.saturated, {}};
}

// Coupled: the forces at psi solve the complementarity problem w(F) + C F - delta(psi)
// >= 0, F >= 0, complementary (coupled_contact.hpp), started from *forces (the last accepted
// trial's forces: a warm start).
Evaluation EvaluateCoupled(const LoadProblem& problem, double psi, Workspace& workspace, CoupledContact& coupled,
                           double force_scale, std::vector<double>* forces, Buffers& buffers) {
  problem.At(psi, workspace, &buffers.scratch, &buffers.pins);  // the buffers' storage, reused
  CoupledPoints(buffers.pins, &buffers.points);
  const CoupledOutcome o = coupled.AtRotation(buffers.points, force_scale, forces);
  return {o.torque, o.edge, o.saturated, o.converged || o.saturated ? std::string() : o.failure};
}

// Exact kinematics: the geometry linearised about the last trial evaluated on it, which
// decides the trials whose verdict it makes clear. About psi_e each pin's approach is
// a_i + L_i (psi - psi_e) with the law of psi_e; the torque this predicts is exact but for what
// turning does to the arms and the laws (first order in the step, a few 1e-4 of the change on Liu
// Table 1) and the pins that close on the way (their law is the unloaded state's, their gap a
// bound where the trial skipped them). The prediction carries a bound: `error` times the change
// it predicts (1 % at least, and 4 times the last misprediction beyond the other two terms), the
// whole torque of the pins it has closing, and twice the torque the exact geometry's rounding
// leaves unresolved. A trial whose torque +- the bound lies on one side of the target is decided
// so; any other trial, and every verdict of convergence, is evaluated on the exact geometry.
struct Linearisation {
  bool valid = false;
  double psi = 0.0, torque = 0.0;
  double error = 0.5;  // before any misprediction is measured: a half
  double resolution = 0.0;  // the torque the exact geometry's rounding leaves unresolved at psi_e
  std::vector<LoadProblem::PinAt> pins;
  std::vector<contact::ContactLaw> laws;
  std::vector<double> hints;

  struct Prediction {
    double torque = 0.0, bound = INFINITY;
    double closing = 0.0;  // the part of the bound that is the pins closing since psi_e
    bool usable = false;  // false: a pressed tip corner or a law beyond its range in the prediction
  };

  // The pins and laws of an exact evaluation at `at`, copied (the laws the pins point to in
  // `scratch` are pointed to in the copy).
  void Take(double at, double exact_torque, const std::vector<LoadProblem::PinAt>& from,
            const std::vector<contact::ContactLaw>& scratch, double torque_resolution) {
    psi = at, torque = exact_torque, resolution = torque_resolution, valid = true;
    pins = from;
    laws = scratch;
    const std::less<const contact::ContactLaw*> before;
    for (auto& pin : pins) {
      if (pin.law != nullptr && !scratch.empty() && !before(pin.law, scratch.data()) &&
          before(pin.law, scratch.data() + scratch.size())) {
        pin.law = laws.data() + (pin.law - scratch.data());
      }
    }
    hints.assign(pins.size(), 0.0);
  }

  Prediction At(double at) {
    Prediction p;
    p.torque = 0.0;
    p.usable = valid;
    for (std::size_t i = 0; i < pins.size() && p.usable; ++i) {
      const auto& pin = pins[i];
      const double approach = pin.approach + pin.arm * (at - psi);
      if (approach <= 0.0) continue;
      if (pin.law == nullptr || approach >= pin.law->max_approach()) {
        p.usable = false;
        break;
      }
      const double moment = pin.law->Force(approach, &hints[i]) * pin.arm;
      p.torque += moment;
      if (pin.approach <= 0.0) p.closing += std::abs(moment);
    }
    // (twice the resolution: that of psi_e's torque, and that of the trial's)
    p.bound = error * std::abs(p.torque - torque) + p.closing + 2.0 * resolution;
    return p;
  }

  // What the exact evaluation at a predicted rotation measured: the misprediction beyond what the
  // closing pins account for, as a fraction of the predicted change, sets the next bound.
  void Observe(const Prediction& p, double exact_torque) {
    const double change = std::abs(p.torque - torque);
    if (!p.usable || !(change > 0.0)) return;
    const double missed = std::max(0.0, std::abs(exact_torque - p.torque) - p.closing - 2.0 * resolution) / change;
    error = std::max(0.01, 4.0 * missed);
  }
};

// The accepted trial's verdict when a saturated pin (its law's largest force) holds the torque
// below the target: law-cannot-carry, with that trial's rotation and forces. Both searches stop here.
bool CannotCarry(const Evaluation& at, double target, double psi, const std::vector<double>& forces, int evaluations,
                 const SolverOptions& options, LoadResult* result) {
  if (!(at.saturated && at.torque < target * (1.0 - options.torque_tolerance))) return false;
  result->status = SolverStatus::kLawCannotCarry;
  result->message = fmt::format("a pin reached the largest force its contact law can carry at {:.6g} N*m of {:.6g}",
                                units::NmmToNm(at.torque), units::NmmToNm(target));
  result->rotation = psi;
  result->force = forces;
  result->torque_evaluations = evaluations;
  return true;
}

// The search's verdict at its last accepted trial (torque `torque` of `target`): balanced, edge
// contact (a tip corner stopped it), or out of iterations or of resolution. Both searches end here.
void Conclude(bool balanced, bool edge_blocked, double torque, double target, int evaluations, const SolverOptions& options,
              LoadResult* result) {
  const double miss = std::abs(torque - target) / target;
  if (balanced) {
    result->status = SolverStatus::kSuccess;
    result->message = fmt::format("torque balanced to {:.3g} after {} evaluations{}", miss, evaluations,
                                  miss > options.torque_tolerance ? " (limited by the resolution of the rotation in double precision)" : "");
  } else if (edge_blocked) {
    result->status = SolverStatus::kEdgeContact;
    result->message = fmt::format("the load cannot be reached before a tip corner is pressed (edge contact; line-contact "
                                  "laws do not apply): torque off by {:.3g}", miss);
  } else {
    result->status = SolverStatus::kMaxIterations;
    result->message = evaluations >= options.max_iterations
                          ? fmt::format("iteration limit reached (max_iterations = {}) before the torque balanced: the output "
                                        "torque at the stop is off by {:.3g} relative, torque_tolerance {:.3g}",
                                        options.max_iterations, miss, options.torque_tolerance)
                          : fmt::format("the rotation step fell below the resolution of double precision after {} evaluations "
                                        "before the torque balanced: off by {:.3g} relative, torque_tolerance {:.3g}",
                                        evaluations, miss, options.torque_tolerance);
  }
}

// Coupled: Liu's search on the rotation with each trial's torque from the coupled complementarity
// problem at that rotation (EvaluateCoupled). A trial costs a coupled solve (the elastic disc
// body: every contact of a slice coupled to every other), so the step doubling and halving of the
// uncoupled search (about 74 trials a position) is replaced by a safeguarded Newton iteration on
// T(psi) = T: the converged solve at psi gives dT/dpsi = L_A^T M_AA^-1 L_A with its own factor
// (CoupledContact::TorqueSlope), and T(psi) is continuous and non-decreasing (the convex energy of
// coupled_contact.hpp: the rotation is the torque's conjugate). The search keeps Liu's rules: a
// trial whose torque exceeds T (1 + tol), or that presses a tip corner, is an overshoot and is not
// accepted; the answer is an accepted rotation that the same verdict (LoadProblem::Balanced)
// finds balanced. The safeguard: once a trial has overshot, every trial lies strictly inside the
// bracket (last accepted, least overshooting) -- Newton's step from the last trial when it falls
// inside, else regula falsi with the Illinois modification on the bracket (Dahlquist and Bjorck,
// Numerical Methods, 1974, sec. 6.2.3), else its midpoint; before the first overshoot, Newton from
// the accepted rotation. Newton's step is taken on log T against log (psi - psi_0) (psi_0 the first
// contact, where T = 0): exact for a power law T = A (psi - psi_0)^k, the same step as Newton's to
// first order near the root. The first trial beyond first contact is the single-pin bound
// (LoadedRotationRange), or Liu's doubling step from 1/60 arcsec when it is not finite. It
// converges superlinearly where T is smooth and as bisection at worst; 5.4 trials a position on
// average over 301 positions of Liu's pair with the elastic body (7.0 with Newton's step on T from
// Liu's first step, about 74 with the doubling search).
void SolveCoupledSearch(const LoadProblem& problem, double first_contact, const SolverOptions& options, Workspace& workspace,
                        CoupledContact& coupled, LoadResult* result) {
  const double target = problem.torque();
  const double limit = target * (1.0 + options.torque_tolerance);
  const double force_scale = CoupledForceScale(problem);
  const ActiveSetCholmod::Stats before = coupled.stats();
  Buffers buffers;
  std::vector<double> forces, trial_forces;  // forces: the accepted trial's
  const auto fail = [&](const Evaluation& e, int evaluations_done) {
    result->status = SolverStatus::kNumericalFailure;
    result->message = fmt::format("coupled contact at a trial rotation: {}", e.failure);
    result->torque_evaluations = evaluations_done;
  };
  double psi = first_contact;
  Evaluation at = EvaluateCoupled(problem, psi, workspace, coupled, force_scale, &forces, buffers);
  if (!at.failure.empty()) return fail(at, 1);
  int evaluations = 1;
  // The last trial (its rotation, torque and slope): Newton's point.
  double last_psi = psi, last_torque = at.torque, last_slope = coupled.TorqueSlope(buffers.points);
  // The bracket: lo the accepted rotation (psi), hi the least overshooting trial (none yet).
  bool bracketed = false, hi_edge = false;
  double hi = 0.0, hi_torque = 0.0, lo_torque = at.torque;
  int side = 0;  // Illinois: which end moved last (-1 lo, +1 hi)
  double step = units::ArcsecToRad(1.0 / 60.0);  // Liu section 4: 1/60 arcsec, doubled while nothing is loaded
  bool edge_blocked = false, accepted_new = true;
  for (; evaluations < options.max_iterations; ++evaluations) {
    if (accepted_new) {
      if (CannotCarry(at, target, psi, forces, evaluations, options, result)) return;
      if (problem.Balanced(psi, at.torque, options.torque_tolerance, workspace)) break;
    }
    accepted_new = false;
    // Newton's step on log T against log (psi - psi_0), psi_0 the first contact (T = 0 there):
    // exact for T = A (psi - psi_0)^k with k = T' (psi - psi_0) / T from the last trial's value
    // and slope, where Newton's step on T overshoots by about 3.5x from below (T is convex: more
    // pins engage as psi grows); to first order the same step as Newton's near the root.
    double trial_psi = NAN;
    if (last_slope > 0.0) {
      trial_psi = last_psi + (target - last_torque) / last_slope;
      const double x = last_psi - first_contact;
      const double k = x > 0.0 && last_torque > 0.0 ? last_slope * x / last_torque : 0.0;
      if (k > 0.0) {
        const double power = first_contact + x * std::pow(target / last_torque, 1.0 / k);
        if (std::isfinite(power)) trial_psi = power;
      }
    } else if (evaluations == 1) {
      // The first trial beyond first contact: the rotation at which one pin alone would carry T
      // (LoadedRotationRange: T(psi) >= T there, rigorous for linearised kinematics), whose
      // loaded pins give the slope the step above needs, where Liu's 1/60 arcsec step loads one
      // pin barely. Not finite (no pin can carry load) or not beyond: Liu's doubling step.
      const double single_pin = problem.LoadedRotationRange().single_pin;
      if (std::isfinite(single_pin) && single_pin > psi) trial_psi = single_pin;
    }
    if (bracketed) {
      if (!(hi - psi > 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(hi), std::abs(psi)))) break;
      if (!(trial_psi > psi && trial_psi < hi)) {
        trial_psi = 0.5 * (psi + hi);
        if (!hi_edge && hi_torque > lo_torque) {
          const double falsi = psi + (target - lo_torque) * (hi - psi) / (hi_torque - lo_torque);
          if (falsi > psi && falsi < hi) trial_psi = falsi;
        }
      }
    } else if (!(trial_psi > psi)) {
      trial_psi = psi + step;
      step *= 2.0;
    }
    if (!std::isfinite(trial_psi) || trial_psi == psi) break;  // cannot refine further in double
    const Evaluation trial = EvaluateCoupled(problem, trial_psi, workspace, coupled, force_scale,
                                             &(trial_forces = forces), buffers);
    if (!trial.failure.empty()) return fail(trial, evaluations + 1);
    last_psi = trial_psi, last_torque = trial.torque, last_slope = coupled.TorqueSlope(buffers.points);
    if (trial.edge || trial.torque > limit) {
      // A tip corner pressed at this trial is an overshoot: if the load cannot be reached before a
      // corner engages, the answer is edge contact (below).
      if (trial.edge) edge_blocked = true;
      if (!bracketed || trial_psi < hi) hi = trial_psi, hi_torque = trial.torque, hi_edge = trial.edge;
      if (side == 1) lo_torque = target + 0.5 * (lo_torque - target);  // Illinois: halve the end that stays
      side = 1;
      bracketed = true;
      if (trial.edge) last_slope = 0.0;  // no Newton step from a pressed corner
    } else {
      if (side == -1 && bracketed && !hi_edge) hi_torque = target + 0.5 * (hi_torque - target);
      side = -1;
      psi = trial_psi, at = trial, lo_torque = trial.torque;
      forces.swap(trial_forces);
      accepted_new = true;
    }
  }
  result->rotation = psi;
  result->force = forces;
  result->details = {{"final_step_rad", bracketed ? hi - psi : step}};
  AddKernelDetails(before, coupled.stats(), &result->details);
  result->torque_evaluations = evaluations;
  result->iterations = evaluations;
  result->native_code = 0;
  Conclude(problem.Balanced(psi, at.torque, options.torque_tolerance, workspace), edge_blocked, at.torque, target, evaluations,
           options, result);
}

}  // namespace

void BisectionSolver::DoSolve(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                              LoadResult* result) const {
  // A preloaded pair has no first contact to start from: both flanks press at psi = 0.
  if (problem.preloaded()) return SolveTwoFlanks(problem, problem.torque(), options, workspace, result);
  // Start at the unloaded first contact in the load direction (Liu: theta_c1).
  const std::optional<double> first_contact = FirstContactOrFail(problem, result);
  if (!first_contact) return;
  // Coupled, with the dense kernel (the elastic disc body's coupling): the safeguarded Newton
  // search (SolveCoupledSearch). The CHOLMOD and Woodbury kernels (pin bending) keep Liu's
  // doubling search below, so pin bending's numbers do not change.
  if (problem.has_coupling()) {
    CoupledContact& coupled = CoupledContactFor(problem, workspace);
    if (coupled.dense()) return SolveCoupledSearch(problem, *first_contact, options, workspace, coupled, result);
  }
  double psi = *first_contact;
  const double target = problem.torque();
  double step = units::ArcsecToRad(1.0 / 60.0);  // Liu section 4: 1/60 arcsec
  Buffers buffers;
  std::vector<double> forces, trial_forces, hints;  // forces: the accepted trial's
  // Uncoupled, the accepted trial's pins and forces are at hand (Buffers); coupled, evaluated again.
  const auto converged = [&](double psi_now, double torque_now) {
    if (!problem.has_coupling()) return problem.Balanced(psi_now, torque_now, options.torque_tolerance, buffers.accepted_pins, &forces);
    return problem.Balanced(psi_now, torque_now, options.torque_tolerance, workspace);
  };
  // Uncoupled: the forces of the laws at the approaches (the published method, unchanged). Coupled:
  // the coupled complementarity problem at each trial rotation, warm-started from the last accepted one.
  CoupledContact* coupled = problem.has_coupling() ? &CoupledContactFor(problem, workspace) : nullptr;
  const double force_scale = coupled != nullptr ? CoupledForceScale(problem) : 0.0;
  const ActiveSetCholmod::Stats before = coupled != nullptr ? coupled->stats() : ActiveSetCholmod::Stats{};
  const auto evaluate = [&](double at_psi, std::vector<double>* out) {
    if (coupled == nullptr) return Evaluate(problem, at_psi, workspace, out, &hints, buffers);
    if (out != &forces) *out = forces;
    return EvaluateCoupled(problem, at_psi, workspace, *coupled, force_scale, out, buffers);
  };
  const auto fail = [&](const Evaluation& e, int evaluations_done) {
    result->status = SolverStatus::kNumericalFailure;
    result->message = fmt::format("coupled contact at a trial rotation: {}", e.failure);
    result->torque_evaluations = evaluations_done;
  };
  bool edge_blocked = false;
  // Exact kinematics, uncoupled: trials the linearisation about the last exact trial decides
  // (Linearisation). The accepted rotation is then not always one evaluated on the exact
  // geometry (at_exact false), but never one that may have converged; the last exact one
  // (safe_psi, its trial `safe`, its forces and pins in `forces` and `buffers`) is the answer
  // should the loop stop on one that is not and the exact geometry overshoot there.
  const bool modelled = coupled == nullptr && problem.kinematics() == contact::ContactKinematics::kExact;
  Linearisation model;
  int exact_trials = 0;
  const auto evaluate_exact = [&](double at_psi, std::vector<double>* out, const Linearisation::Prediction* predicted) {
    const Evaluation e = evaluate(at_psi, out);
    ++exact_trials;
    if (modelled && e.failure.empty()) {
      if (predicted != nullptr) model.Observe(*predicted, e.torque);
      model.Take(at_psi, e.torque, buffers.pins, buffers.scratch,
                 problem.TorqueResolution(at_psi, buffers.pins, out));
    }
    return e;
  };
  Evaluation at = evaluate_exact(psi, &forces, nullptr);
  if (!at.failure.empty()) return fail(at, 1);
  if (coupled == nullptr) buffers.Accept();
  bool at_exact = true;
  double safe_psi = psi;
  Evaluation safe = at;
  const double limit = target * (1.0 + options.torque_tolerance);
  int evaluations = 1;
  // The check is a function of the accepted trial alone: after an overshoot (nothing accepted) its
  // answer is the last one, so it is asked again only once a trial has been accepted.
  bool accepted_new = true;
  // A trial on the exact geometry at trial_psi: true when it is accepted (psi, at, forces and the
  // last exact rotation move there); false on an overshoot or a pressed tip corner, and on a
  // failure, with *failed set and the result filled.
  const auto exact_trial = [&](double trial_psi, const Linearisation::Prediction* predicted, bool* failed) -> bool {
    const Evaluation trial = evaluate_exact(trial_psi, &trial_forces, predicted);
    if (!trial.failure.empty()) {
      fail(trial, evaluations + 1);
      *failed = true;
      return false;
    }
    if (trial.edge || trial.torque > limit) {
      // A tip corner pressed at this trial is an overshoot: if the load cannot be reached before a
      // corner engages, the answer is edge contact (below).
      if (trial.edge) edge_blocked = true;
      return false;
    }
    psi = trial_psi;
    at = trial;
    forces.swap(trial_forces);
    if (coupled == nullptr) buffers.Accept();
    at_exact = true, safe_psi = psi, safe = at;
    return true;
  };
  bool failed = false;
  bool use_model = modelled;
  // The search; run again, on the exact geometry alone, from the last exact rotation should it
  // stop on a rotation accepted on the linearisation that the exact geometry overshoots.
  for (int pass = 0; pass < 2; ++pass) {
    for (; evaluations < options.max_iterations; ++evaluations) {
      if (accepted_new && at_exact) {
        if (CannotCarry(at, target, psi, forces, evaluations, options, result)) return;
        if (converged(psi, at.torque)) break;
      }
      accepted_new = false;
      const double trial_psi = psi + step;
      Linearisation::Prediction p;
      if (use_model) p = model.At(trial_psi);
      if (p.usable && p.torque - p.bound > limit) {
        step *= 0.5;  // overshoot, on the linearisation
      } else if (p.usable && p.torque + p.bound < target * (1.0 - options.torque_tolerance)) {
        // Below the load and outside the band of convergence, on the linearisation: accepted without
        // a verdict to ask (one inside the band is evaluated on the exact geometry, below).
        psi = trial_psi;
        at = {p.torque, false, false, {}};
        at_exact = false;
        accepted_new = true;
        step *= 2.0;
      } else if (exact_trial(trial_psi, use_model ? &p : nullptr, &failed)) {
        accepted_new = true;
        step *= 2.0;  // increasing steps while below the load
      } else {
        if (failed) return;
        step *= 0.5;  // overshoot: bisect the step
      }
      if (step < 1e-17 * std::max(std::abs(psi), 1e-12)) break;  // cannot refine further in double
    }
    if (at_exact) break;
    // The search stopped on a rotation accepted on the linearisation: the exact verdict there.
    const double accepted = psi;
    psi = safe_psi;
    if (exact_trial(accepted, nullptr, &failed)) break;
    if (failed) return;
    // It overshoots: from the last exact rotation, as an overshoot of the step that led beyond it.
    at = safe, at_exact = true, accepted_new = false;
    step = 0.5 * (accepted - safe_psi);
    use_model = false;
  }
  result->rotation = psi;
  result->force = forces;
  result->details = {{"final_step_rad", step}};
  if (modelled) result->details["exact_trials"] = exact_trials;
  if (coupled != nullptr) AddKernelDetails(before, coupled->stats(), &result->details);
  result->torque_evaluations = evaluations;
  result->iterations = evaluations;
  result->native_code = 0;
  Conclude(converged(psi, at.torque), edge_blocked, at.torque, target, evaluations, options, result);
}

void BisectionSolver::DoSolveReducer(const LoadProblem& problem, const ReducerSystem& system, const SolverOptions& options,
                                   Workspace& workspace, LoadResult* result) const {
  // Liu's search on the output rotation psi (the stage's TE): the torque the stage returns to the
  // output member, M(psi), rises with psi (the energy is convex), and at each trial psi the discs
  // and shafts balance (ReducerSystem::Minimise with psi held). Illinois' regula falsi on a bracket.
  const int psi = system.output_dof();
  const double scale = system.rotation_scale();  // psi = scale * q[psi]
  const double torque = problem.torque();
  Eigen::VectorXd q = ReducerStart(system, workspace, "bisection-stage");
  ReducerSystem::Evaluation last;
  int evaluations = 0, inner = 0;
  ReducerSystem::Outcome outcome = ReducerSystem::Outcome::kConverged;
  const double inner_tolerance = 0.1 * options.torque_tolerance;
  std::vector<double> hints;  // the law inversions' warm starts, kept over every trial rotation
  const auto moment = [&](double rotation) {
    q(psi) = rotation / scale;
    int steps = 0;
    outcome = system.Minimise(&q, true, inner_tolerance, options.max_iterations, &hints, &steps, &last);
    inner += steps;
    ++evaluations;
    return system.OutputTorque(last) - torque;
  };
  // Bracket: lo at no rotation (at the nominal poses no element pulls: M(0) <= T), hi doubled
  // from a micro-radian. About an exact-kinematics iterate (the origin a solution already) the
  // balance may lie below 0: then 0 is hi and lo is doubled downward.
  double lo = 0.0, f_lo = moment(lo), hi = 1e-6, f_hi = 0.0;
  bool bracketed = f_lo == 0.0;
  if (bracketed) hi = lo, f_hi = f_lo;
  if (f_lo > 0.0) {
    hi = 0.0, f_hi = f_lo, lo = -1e-6;
    for (int k = 0; !bracketed && k < 80 && outcome != ReducerSystem::Outcome::kNumerical; ++k, lo *= 2.0) {
      f_lo = moment(lo);
      if (f_lo <= 0.0) bracketed = true;
      else hi = lo, f_hi = f_lo;
      if (bracketed) break;
    }
  }
  for (int k = 0; !bracketed && k < 80 && outcome != ReducerSystem::Outcome::kNumerical; ++k, hi *= 2.0) {
    f_hi = moment(hi);
    if (f_hi >= 0.0) bracketed = true;
    else lo = hi, f_lo = f_hi;
    if (bracketed) break;
  }
  double x = hi, fx = f_hi;
  int side = 0;
  // The torque is balanced to the tolerance, or as closely as the arithmetic resolves the torque
  // the stage returns (the gradient's rounding times R_p, ReducerSystem::Evaluation::rounding).
  const auto balanced = [&](double miss) {
    return std::abs(miss) <= std::max(options.torque_tolerance * torque, last.rounding / scale);
  };
  while (bracketed && !balanced(fx) && evaluations < options.max_iterations &&
         outcome != ReducerSystem::Outcome::kNumerical) {
    if (!(hi - lo > 4.0 * std::numeric_limits<double>::epsilon() * std::abs(hi))) break;
    x = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
    fx = moment(x);
    if (fx > 0.0) {
      hi = x, f_hi = fx;
      if (side == 1) f_lo *= 0.5;  // Illinois: halve the end that stays
      side = 1;
    } else {
      lo = x, f_lo = fx;
      if (side == -1) f_hi *= 0.5;
      side = -1;
    }
  }
  if (!balanced(fx) && outcome == ReducerSystem::Outcome::kConverged) {
    outcome = ReducerSystem::Outcome::kMaxIterations;
  }
  if (x != q(psi) * scale) moment(x);  // the solution at the last trial
  FinishReducer(system, q, outcome, last, result);
  result->iterations = inner;
  result->torque_evaluations = evaluations;
  if (!bracketed) {
    result->status = SolverStatus::kMaxIterations;
    result->message = "no output rotation found at which the stage carries the torque";
  }
  if (result->status == SolverStatus::kSuccess) KeepReducerStart(system, q, workspace, "bisection-stage");
}

}  // namespace ltca::solvers
