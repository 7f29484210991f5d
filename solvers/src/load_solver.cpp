#include "ltca/solvers/load_solver.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "coupled_contact.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"
#include "reducer_system.hpp"
#include "two_flanks.hpp"

namespace ltca::solvers {
namespace {

// The residual cannot tell a rotation whole tooth pitches off (the exact geometry repeats every
// pitch), so a success must also lie where the physical answer lies:
// first contact <= psi <= single-pin bound, and |psi| within a quarter tooth pitch. The range is
// met to the torque tolerance; under exact kinematics the single-pin bound is a first-order
// estimate, allowed 5 % of the range. Both ends lie within a quarter pitch of the linearised
// answer, which lies in the linearised range, so a success is within one pitch of it.
void JudgeRange(const LoadProblem& problem, const SolverOptions& options, LoadResult* result) {
  const LoadProblem::RotationRange range = problem.LoadedRotationRange();
  const double psi = result->rotation;
  const double width = std::isfinite(range.single_pin) ? range.single_pin - range.first_contact : 0.0;
  const bool exact = problem.kinematics() == contact::ContactKinematics::kExact;
  const double slack = (2.0 * options.torque_tolerance + (exact ? 0.05 : 1e-9)) * width +
                       8.0 * std::numeric_limits<double>::epsilon() * std::abs(psi);
  std::string why;
  if (std::abs(psi) > range.window) {
    why = fmt::format("beyond a quarter tooth pitch ({:.6g} deg)", units::RadToDeg(range.window));
  } else if (psi < range.first_contact - slack) {
    why = fmt::format("before first contact at {:.6g} arcsec", units::RadToArcsec(range.first_contact));
  } else if (psi > range.single_pin + slack) {
    why = fmt::format("beyond the single-pin bound {:.6g} arcsec", units::RadToArcsec(range.single_pin));
  }
  if (why.empty()) return;
  result->status = SolverStatus::kRotationOutOfRange;
  result->message += fmt::format("; the rotation {:.6g} arcsec lies {}", units::RadToArcsec(psi), why);
}

// A solved result whose figures lie beyond the material or the law's idealisation keeps its
// status and carries warnings (one per kind, naming the worst pin).
// A point as the warnings name it: its pin, and its disc when there are two.
std::string PointName(const LoadProblem& problem, int point) {
  const contact::PinContact& p = problem.base_state().pins[static_cast<std::size_t>(point)];
  if (problem.disc_count() == 1) return fmt::format("pin {}", p.pin + 1);
  return fmt::format("pin {} of disc {}", p.pin + 1, p.disc + 1);
}

// laws: each point's law (nullptr for an edge point).
void JudgeValidity(const LoadProblem& problem, const std::vector<const contact::ContactLaw*>& laws, LoadResult* result) {
  double worst_stress = 0.0, worst_ratio = 0.0, worst_seat = 0.0;
  int stress_pin = -1, width_pin = -1, seat_pin = -1;
  for (std::size_t i = 0; i < laws.size() && i < result->force.size(); ++i) {
    const double f = result->force[i];
    if (!(f > 0.0) || laws[i] == nullptr) continue;
    const double p = laws[i]->MaxPressure(f);
    if (p > worst_stress) worst_stress = p, stress_pin = static_cast<int>(i);
    const double ratio = laws[i]->HalfWidth(f) / laws[i]->valid_half_width();
    if (ratio > worst_ratio) worst_ratio = ratio, width_pin = static_cast<int>(i);
    const double seat = laws[i]->SeatHalfWidth(f) / laws[i]->seat_valid_half_width();
    if (seat > worst_seat) worst_seat = seat, seat_pin = static_cast<int>(i);
  }
  if (worst_seat > 1.0) {
    const auto k = static_cast<std::size_t>(seat_pin);
    result->warnings.push_back(fmt::format(
        "the groove's Hertz half-width {:.4g} mm at {} exceeds a tenth of the pin radius ({:.4g} mm): a conformal "
        "contact beyond the validity of the line-contact law ([pins] groove_radius_mm)",
        laws[k]->SeatHalfWidth(result->force[k]), PointName(problem, seat_pin), laws[k]->seat_valid_half_width()));
  }
  const double limit = problem.material().contact_stress_limit;
  if (worst_stress > limit) {
    result->warnings.push_back(fmt::format(
        "contact stress {:.6g} MPa at {} exceeds the material limit {:.6g} MPa ([material] contact_stress_limit_mpa)",
        worst_stress, PointName(problem, stress_pin), limit));
  }
  if (worst_ratio > 1.0) {
    const double b = laws[static_cast<std::size_t>(width_pin)]->HalfWidth(result->force[static_cast<std::size_t>(width_pin)]);
    result->warnings.push_back(fmt::format(
        "Hertz half-width {:.4g} mm at {} exceeds a tenth of the smaller radius of curvature ({:.4g} mm): "
        "beyond the validity of the line-contact law", b, PointName(problem, width_pin), b / worst_ratio));
  }
}

// The output pins of a stage: the largest contact stress of a pin in its hole (the conformal law the
// stage solves with, contact::OutputPinLaw) against the material's limit, named like the pin ring's.
void JudgeOutputPins(const LoadProblem& problem, LoadResult* result) {
  const ReducerSettings* stage = problem.reducer();
  if (stage == nullptr || stage->kind != OutputKind::kPins || !result->reducer) return;
  const contact::ContactLaw law = ReducerSystem::OutputPinLaw(problem);
  double worst = 0.0;
  int worst_pin = -1, worst_disc = -1;
  for (std::size_t d = 0; d < result->reducer->discs.size(); ++d) {
    const std::vector<double>& forces = result->reducer->discs[d].output_force;
    for (std::size_t j = 0; j < forces.size(); ++j) {
      if (!(forces[j] > 0.0)) continue;
      const double p = law.MaxPressure(forces[j]);
      if (p > worst) worst = p, worst_pin = static_cast<int>(j), worst_disc = static_cast<int>(d);
    }
  }
  const double limit = problem.material().contact_stress_limit;
  if (worst > limit) {
    result->warnings.push_back(fmt::format(
        "contact stress {:.6g} MPa at output pin {}{} in its hole exceeds the material limit {:.6g} MPa ([material] "
        "contact_stress_limit_mpa)",
        worst, worst_pin + 1, problem.disc_count() > 1 ? fmt::format(" of disc {}", worst_disc + 1) : std::string(), limit));
  }
}

}  // namespace

const char* ToString(SolverStatus status) {
  switch (status) {
    case SolverStatus::kNotSolved: return "not-solved";
    case SolverStatus::kSuccess: return "success";
    case SolverStatus::kMaxIterations: return "max-iterations";
    case SolverStatus::kLawCannotCarry: return "law-cannot-carry";
    case SolverStatus::kEdgeContact: return "edge-contact";
    case SolverStatus::kTooManyGroups: return "too-many-groups";
    case SolverStatus::kNumericalFailure: return "numerical-failure";
    case SolverStatus::kResidualTooLarge: return "residual-too-large";
    case SolverStatus::kInterference: return "interference";
    case SolverStatus::kRotationOutOfRange: return "rotation-out-of-range";
    case SolverStatus::kCouplingUnsupported: return "coupling-unsupported";
    case SolverStatus::kReducerUnsupported: return "stage-unsupported";
    case SolverStatus::kCannotAssemble: return "cannot-assemble";
    case SolverStatus::kPreloadUnsupported: return "preload-unsupported";
  }
  return "?";
}

const char* ToString(Flank flank) {
  switch (flank) {
    case Flank::kNone: return "none";
    case Flank::kDrive: return "drive";
    case Flank::kCoast: return "coast";
  }
  return "?";
}

namespace {
/// The torque tolerances SolverOptions accepts (relative |T_out - T| / T).
constexpr double kMinTorqueTolerance = 1e-15, kMaxTorqueTolerance = 0.05;
}  // namespace

void SolverOptions::Validate() const {
  // Above 5 % the load that is balanced is not the torque that was asked for (Liu 2021 section 3
  // stops at 1 %); below 1e-15 no rotation in double precision can resolve it (Balanced() then
  // falls back to the resolution anyway).
  if (!(torque_tolerance >= kMinTorqueTolerance && torque_tolerance <= kMaxTorqueTolerance)) {
    throw std::invalid_argument(fmt::format(
        "[solver] torque_tolerance = {}: expected a relative tolerance from {:g} to {:g} (|T_out - T| / T: above 5 % the "
        "balanced load is no longer the given torque; Liu 2021 section 3 uses 1 %)",
        torque_tolerance, kMinTorqueTolerance, kMaxTorqueTolerance));
  }
  if (max_iterations < 1) {
    throw std::invalid_argument(fmt::format("[solver] max_iterations = {}: expected >= 1", max_iterations));
  }
  if (!(residual_tolerance > 0.0)) {
    throw std::invalid_argument(
        fmt::format("[solver] residual_tolerance = {}: expected > 0", residual_tolerance));
  }
}

SolverOptions ApplyPreset(SolverOptions options, const std::string& preset) {
  if (preset == "liu2021") {
    options.name = "bisection";
    options.torque_tolerance = 1e-2;  // Liu section 3: stop when torque and load agree within 1 %
    options.residual_tolerance = 2e-2;
    return options;
  }
  throw std::invalid_argument(fmt::format("[solver] preset = \"{}\": expected \"liu2021\"", preset));
}

void LoadSolver::DoSolveReducer(const LoadProblem&, const ReducerSystem&, const SolverOptions&, Workspace&,
                              LoadResult* result) const {
  result->status = SolverStatus::kReducerUnsupported;
  result->message = fmt::format("solver \"{}\" does not solve the reducer stage", name());
}

// The shared part of a stage solve: the refusals, the zero torque, the backend, and the
// judge of every balance (ReducerSystem::Judge). No range judge: the output rotation includes the
// mechanism's and the bearings' compliance, which the pin ring's single-pin bound does not see.
Eigen::VectorXd LoadSolver::SolveReducerExact(const LoadProblem& problem, const ReducerSystem& nominal,
                                            const SolverOptions& options, Workspace& workspace, LoadResult* result) const {
  // Exact kinematics (docs/stage.md): the stage linearised about the poses of the last
  // iterate, every element re-evaluated where the discs and the output member are, solved by the
  // backend; repeated until an iterate moves no coordinate by more than 1e-12 of the largest
  // (rotations times R_p) or than the geometry's resolution, a Newton iteration on the geometry.
  // The first iterate is the linearised solution.
  constexpr int kMaxOuter = 30;
  // The geometry re-evaluated at the poses resolves them to a few eps of the pin-circle radius
  // (positions of that size subtracted): no iterate can settle closer than that.
  const double resolution = 16.0 * std::numeric_limits<double>::epsilon() * problem.model().pair().pin_circle_radius;
  Eigen::VectorXd origin = Eigen::VectorXd::Zero(nominal.coordinate_count());
  double last_change = std::numeric_limits<double>::infinity(), size = 0.0;
  for (int outer = 0; outer < kMaxOuter; ++outer) {
    LoadResult iterate;
    iterate.force.assign(static_cast<std::size_t>(problem.point_count()), 0.0);
    const ReducerSystem system(problem, origin, nominal.coupled());
    DoSolveReducer(problem, system, options, workspace, &iterate);
    iterate.iterations += result->iterations;
    iterate.torque_evaluations += result->torque_evaluations;
    if (iterate.status != SolverStatus::kSuccess) {
      // A re-linearisation that no longer solves (near the arithmetic's limit, at a vanishing load)
      // after one that did, with the poses settled to 1e-6 of their size: the last iterate stands,
      // and the shared judge at its poses decides. Otherwise the failure is the result.
      if (outer > 0 && last_change <= 1e-6 * size) return origin;
      *result = std::move(iterate);
      return origin;
    }
    *result = std::move(iterate);
    const Eigen::VectorXd next = system.CoordinatesOf(*result);
    last_change = system.Distance(next, origin);
    size = system.Distance(next, Eigen::VectorXd::Zero(next.size()));
    origin = next;
    if (last_change <= std::max(1e-12 * size, resolution)) return origin;
  }
  result->status = SolverStatus::kMaxIterations;
  result->message = fmt::format("exact kinematics of the stage: the poses still moved after {} re-linearisations", kMaxOuter);
  return origin;
}

/// Whether a stage's bearing or output pins are pressed at no load (a negative radial clearance, holes
/// smaller than pin + 2 e): the stage is then preloaded whether its pins overlap the cycloid or not.
bool StageElementsPreloaded(const LoadProblem& problem);

void LoadSolver::SolveReducer(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                            LoadResult* result) const {
  const LoadSolver& solver = *this;
  if (!solver.supports_reducer()) {
    result->status = SolverStatus::kReducerUnsupported;
    result->message = fmt::format("solver \"{}\" does not solve the reducer stage ([output]); solvers that do: "
                                  "{} (docs/stage.md)", solver.name(), fmt::join(ReducerSolverNames(), ", "));
  } else if (problem.overlapping()) {
    // Pins overlap the cycloid: the floating discs find their preload state at zero torque (the
    // stage's energy takes every element of either flank), the loaded balance starts from it.
    SolveReducerPreloaded(problem, options, workspace, result, StageElementsPreloaded(problem));
  } else if (StageElementsPreloaded(problem)) {
    // A preloaded bearing (negative radial clearance) or output pins in holes smaller than pin + 2 e:
    // the same preload state, pressed by those elements.
    SolveReducerPreloaded(problem, options, workspace, result, true);
  } else {
    SolveReducerBody(problem, options, workspace, result);
  }
  FinishReducerResult(problem, result);
}

bool StageElementsPreloaded(const LoadProblem& problem) {
  const ReducerSettings& s = *problem.reducer();
  if (s.bearing.kind != contact::BearingKind::kRigid) {
    for (int d = 0; d < problem.disc_count(); ++d) {
      if (s.BearingOf(d).radial_clearance < 0.0) return true;
    }
  }
  if (s.kind != OutputKind::kPins) return false;
  // An output pin overlaps its hole at no load only where the hole's deviations can make up its
  // clearance hole - pin - e: then the stage's own gaps decide (the holes as built).
  double reach = 0.0;
  for (int d = 0; d < problem.disc_count(); ++d) {
    for (const Eigen::Vector2d& dev : s.Holes(d)) reach = std::max(reach, dev.norm());
  }
  const double tolerance = problem.model().interference_tolerance();
  if (s.pins.hole_radius - s.pins.pin_radius - problem.model().pair().eccentricity - reach >= -tolerance) return false;
  return ReducerSystem(problem).ElementsPreloaded(tolerance);
}

void LoadSolver::SolveReducerPreloaded(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                                       LoadResult* result, bool elements) const {
  // The preload state: the stage under 1e-7 of its torque (as the free play of ltca stiffness),
  // where the stage's minimisation keeps a scale; its forces are the zero-torque preload's to 1e-7
  // of the torque's share. A torque of at most 1 N*mm, the judge's floor of a moment (e.g. a free
  // play's 1e-7 T), is already zero to the judge: that problem is its own preload state (1e-7 of
  // it would lie below what the stage's rotation resolves). A problem at zero torque is solved there.
  const bool vanishing = std::abs(problem.torque()) <= 1.0;
  LoadResult zero;
  zero.force.assign(result->force.size(), 0.0);
  SolveReducerBody(vanishing ? problem : problem.Unloaded(1e-7), options, workspace, &zero, true);
  LoadResult::Preload preload;
  preload.rotation = zero.rotation;
  preload.force = zero.force;
  double worst_stress = 0.0;
  int stress_point = -1;
  for (std::size_t i = 0; i < zero.force.size(); ++i) {
    const double f = zero.force[i];
    if (!(f > 0.0)) continue;
    ++preload.contacts;
    preload.max_force_n = std::max(preload.max_force_n, f);
    const contact::PinContact& pin = problem.base_state().pins[i];
    if (pin.arm < 0.0) preload.opposing_torque_nmm += f * -pin.arm;
    if (pin.edge) continue;
    const double p = problem.base_laws()[i].MaxPressure(f);
    if (p > worst_stress) worst_stress = p, stress_point = static_cast<int>(i);
  }
  preload.max_stress_mpa = worst_stress;
  const double limit = problem.material().contact_stress_limit;
  std::string overlaps = contact::InterferenceReport(problem.base_state(), problem.model().interference_tolerance());
  if (elements) {
    overlaps += fmt::format("{}the stage's elements: a bearing with a negative radial clearance or output pins in holes "
                            "smaller than pin + 2 e", overlaps.empty() ? "" : "; ");
  }
  if (zero.status != SolverStatus::kSuccess) {
    // Beyond the laws (a pin past its largest force, a pressed tip corner): the disc cannot be
    // seated. Any other failure is the solve's, said as such.
    const bool beyond = zero.status == SolverStatus::kLawCannotCarry || zero.status == SolverStatus::kEdgeContact;
    *result = std::move(zero);
    result->preload.reset();  // no valid solve produced the preload's figures
    if (beyond) result->status = SolverStatus::kCannotAssemble;
    result->message = fmt::format("{}the stage is preloaded ({}); the preload state (the stage at 1e-7 of its torque): {}",
                                  beyond ? "cannot assemble: " : "", overlaps, result->message);
    result->rotation = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  if (preload.contacts > 0 && worst_stress > limit) {
    *result = std::move(zero);
    result->preload = preload;
    result->status = SolverStatus::kCannotAssemble;
    result->message = fmt::format("cannot assemble: the preload at zero torque presses {} to {:.6g} MPa, beyond the "
                                  "material limit {:.6g} MPa ([material] contact_stress_limit_mpa; the overlap: {})",
                                  PointName(problem, stress_point), worst_stress, limit, overlaps);
    result->rotation = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  if (problem.torque() == 0.0 || vanishing) {
    *result = std::move(zero);
    result->message = fmt::format("{}: the preload state, {} points pressed ({})", problem.torque() == 0.0 ? "zero torque" : "a vanishing torque",
                                  preload.contacts, result->message);
  } else {
    SolveReducerBody(problem, options, workspace, result);
  }
  // A preload presses both flanks: a floating disc that seats itself (translating) off every
  // overlap rests on one flank under the vanishing torque and carries no preload.
  // A preloaded bearing or output pin is pressed whatever the disc does.
  if (preload.opposing_torque_nmm > 0.0 || elements) result->preload = preload;
}

void LoadSolver::SolveReducerBody(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                                  LoadResult* result, bool solve_zero) const {
  const LoadSolver& solver = *this;
  {
    // Pin bending: the coupled contact solver kept in the workspace (its analysis reused over a sweep).
    CoupledContact* coupled = problem.has_coupling() ? &CoupledContactFor(problem, workspace) : nullptr;
    const ReducerSystem nominal(problem, coupled);
    std::unique_ptr<ReducerSystem> judge;  // exact kinematics: the system about the reported poses
    if (problem.torque() == 0.0 && !solve_zero) {
      nominal.Fill(nominal.Zero(), result);
      result->status = SolverStatus::kSuccess;
      result->message = "zero torque: no rotation, no forces";
    } else if (problem.kinematics() != contact::ContactKinematics::kExact) {
      solver.DoSolveReducer(problem, nominal, options, workspace, result);
    } else {
      judge = std::make_unique<ReducerSystem>(problem, SolveReducerExact(problem, nominal, options, workspace, result), coupled);
    }
    if (std::isfinite(result->rotation) && result->reducer) {
      (judge ? *judge : nominal).Judge(result);
      const double accepted = std::max(options.residual_tolerance, 2.0 * options.torque_tolerance);
      if (result->status == SolverStatus::kSuccess && !(result->residuals.Normalised() <= accepted)) {
        result->status = SolverStatus::kResidualTooLarge;
        result->message += fmt::format("; shared residual {:.3g} exceeds {:.3g}", result->residuals.Normalised(), accepted);
      }
      if (result->status == SolverStatus::kSuccess) {  // the pin ring's stresses and laws, as for the mesh alone
        const auto& base = problem.base_laws();
        std::vector<const contact::ContactLaw*> laws(base.size());
        for (std::size_t i = 0; i < base.size(); ++i) laws[i] = problem.base_state().pins[i].edge ? nullptr : &base[i];
        JudgeValidity(problem, laws, result);
        JudgeOutputPins(problem, result);
      }
    }
  }
}

void LoadSolver::FinishReducerResult(const LoadProblem& problem, LoadResult* result) const {
  result->te = -problem.direction() * result->rotation;
  result->flank = problem.torque() == 0.0 ? Flank::kNone : (problem.direction() > 0.0 ? Flank::kDrive : Flank::kCoast);
  if (!std::isfinite(result->rotation)) return;
  // The energy of a stage is its strain energy (the potential's elastic part).
  result->active.clear();
  result->energy = 0.0;
  for (std::size_t i = 0; i < result->force.size(); ++i) {
    if (result->force[i] > 0.0) result->active.push_back(static_cast<int>(i));
  }
  if (result->reducer) {
    for (const double e : result->reducer->group_energy) result->energy += e;
  }
}

Residuals ComputeResiduals(const LoadProblem& problem, const LoadResult& result) {
  if (!problem.has_reducer()) return ComputeResiduals(problem, result.rotation, result.force);
  LoadResult judged = result;
  const ReducerSystem nominal(problem);
  const Eigen::VectorXd reported = nominal.CoordinatesOf(result);
  if (problem.kinematics() == contact::ContactKinematics::kExact && reported.allFinite()) {
    // Exact kinematics: judged with the geometry at the poses the result reports (a result without
    // finite poses has nothing to judge: the nominal system's judge says so).
    ReducerSystem(problem, reported).Judge(&judged);
  } else {
    nominal.Judge(&judged);
  }
  return judged.residuals;
}

void LoadSolver::SolvePreloaded(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                                LoadResult* result) const {
  // The preload state: the two-flank balance at zero torque, shared by every backend (it is the
  // assembly, not a backend's answer), judged against the laws and the material's stress limit.
  LoadResult zero;
  zero.force.assign(result->force.size(), 0.0);
  SolveTwoFlanks(problem, 0.0, options, workspace, &zero);
  LoadResult::Preload preload;
  preload.rotation = zero.rotation;
  preload.force = zero.force;
  double worst_stress = 0.0;
  int stress_point = -1;
  if (std::isfinite(zero.rotation)) {
    std::vector<contact::ContactLaw> scratch;
    const auto pins = problem.At(zero.rotation, workspace, &scratch);
    for (std::size_t i = 0; i < pins.size() && i < zero.force.size(); ++i) {
      const double f = zero.force[i];
      if (!(f > 0.0)) continue;
      ++preload.contacts;
      preload.max_force_n = std::max(preload.max_force_n, f);
      if (pins[i].arm < 0.0) preload.opposing_torque_nmm += f * -pins[i].arm;
      if (pins[i].law == nullptr) continue;
      const double p = pins[i].law->MaxPressure(f);
      if (p > worst_stress) worst_stress = p, stress_point = static_cast<int>(i);
    }
  }
  preload.max_stress_mpa = worst_stress;
  // The preload's figures where its balance was found; none from a failed solve.
  if (zero.status == SolverStatus::kSuccess) result->preload = preload;
  const double limit = problem.material().contact_stress_limit;
  if (zero.status != SolverStatus::kSuccess) {
    result->status = SolverStatus::kCannotAssemble;
    result->message = fmt::format("cannot assemble: pins overlap the cycloid on both flanks ({}) and the disc finds no "
                                  "preload balance within its contact laws: {}",
                                  contact::InterferenceReport(problem.base_state(), problem.model().interference_tolerance()),
                                  zero.message);
  } else if (worst_stress > limit) {
    result->status = SolverStatus::kCannotAssemble;
    result->message = fmt::format("cannot assemble: the preload at zero torque presses {} to {:.6g} MPa, beyond the "
                                  "material limit {:.6g} MPa ([material] contact_stress_limit_mpa; the overlap: {})",
                                  PointName(problem, stress_point), worst_stress, limit,
                                  contact::InterferenceReport(problem.base_state(), problem.model().interference_tolerance()));
  } else if (problem.torque() == 0.0) {
    result->status = SolverStatus::kSuccess;
    result->message = fmt::format("zero torque: the preload state, {} points pressed on both flanks ({})",
                                  preload.contacts, zero.message);
    result->rotation = zero.rotation;
    result->force = zero.force;
    result->torque_evaluations = zero.torque_evaluations;
    result->iterations = zero.iterations;
    result->details = zero.details;
  } else if (!supports_two_flanks()) {
    result->status = SolverStatus::kPreloadUnsupported;
    result->message = fmt::format("solver \"{}\" searches one flank from first contact; this pair is preloaded (pins "
                                  "overlap on both flanks: {}), solved by the registered backends, e.g. bisection (docs/solvers.md, \"Two flanks\")",
                                  name(), contact::InterferenceReport(problem.base_state(), problem.model().interference_tolerance()));
  } else {
    DoSolve(problem, options, workspace, result);
  }
}

LoadResult LoadSolver::Solve(const LoadProblem& problem, const SolverOptions& options) const {
  Workspace workspace;
  return Solve(problem, options, workspace);
}

namespace {
std::atomic<std::uint64_t> solve_calls{0};
}  // namespace

std::uint64_t SolveCallCount() { return solve_calls.load(std::memory_order_relaxed); }

LoadResult LoadSolver::Solve(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace) const {
  solve_calls.fetch_add(1, std::memory_order_relaxed);
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  LoadResult result;
  result.force.assign(static_cast<std::size_t>(problem.point_count()), 0.0);
  if (problem.has_reducer()) {
    SolveReducer(problem, options, workspace, &result);
    result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }
  const double capacity = problem.TorqueCapacity();
  if (problem.has_coupling() && !supports_coupling()) {
    // Judged before anything else: this backend would answer the uncoupled problem.
    result.status = SolverStatus::kCouplingUnsupported;
    result.message = fmt::format("solver \"{}\" does not support a compliance coupling, which this problem has "
                                 "(docs/solvers.md, \"Coupled compliance\")", name());
  } else if (problem.preloaded()) {
    // Pins overlap on both flanks and no rotation frees them all: a preloaded pair. Its zero-torque
    // balance over both flanks is the assembly (the preload state); the loaded balance starts from
    // it (docs/solvers.md "Two flanks").
    SolvePreloaded(problem, options, workspace, &result);
  } else if (problem.torque() == 0.0) {
    // No load: the cycloid stays at its theoretical position, no pin carries force.
    result.status = SolverStatus::kSuccess;
    result.message = "zero torque: no rotation, no forces";
    result.rotation = 0.0;
  } else if (problem.torque() > capacity) {
    // Shared by every backend: even with every pin at its law's largest force the torque is short.
    result.status = SolverStatus::kLawCannotCarry;
    result.message = fmt::format("the contact laws can carry at most {:.6g} N*m here (every loaded pin at its "
                                 "largest force), less than the load {:.6g} N*m",
                                 units::NmmToNm(capacity), units::NmmToNm(problem.torque()));
  } else {
    DoSolve(problem, options, workspace, &result);
  }
  result.te = -problem.direction() * result.rotation;
  result.flank = problem.torque() == 0.0 ? Flank::kNone : (problem.direction() > 0.0 ? Flank::kDrive : Flank::kCoast);
  // Shared part: approaches, active set, energy, and the judge's residuals.
  std::vector<contact::ContactLaw> scratch;
  const auto pins = problem.At(std::isfinite(result.rotation) ? result.rotation : 0.0, workspace, &scratch);
  result.approach.resize(pins.size());
  result.energy = 0.0;
  result.active.clear();
  for (std::size_t i = 0; i < pins.size(); ++i) {
    result.approach[i] = pins[i].approach;
    if (result.force[i] > 0.0) {
      result.active.push_back(static_cast<int>(i));
      if (pins[i].law != nullptr) result.energy += pins[i].law->ComplementaryEnergy(result.force[i]);
    }
  }
  if (problem.has_coupling()) {  // plus the coupling's 1/2 F^T C F
    const Eigen::Map<const Eigen::VectorXd> f(result.force.data(), static_cast<Eigen::Index>(result.force.size()));
    result.energy += 0.5 * f.dot(*problem.coupling() * f);
  }
  if (std::isfinite(result.rotation)) {
    result.residuals = ComputeResiduals(problem, result.rotation, result.force, workspace);
    // Judged at the accuracy that was asked for: a loose torque tolerance allows a like residual.
    const double accepted = std::max(options.residual_tolerance, 2.0 * options.torque_tolerance);
    if (result.status == SolverStatus::kSuccess && !(result.residuals.Normalised() <= accepted)) {
      result.status = SolverStatus::kResidualTooLarge;
      result.message += fmt::format("; shared residual {:.3g} exceeds {:.3g}", result.residuals.Normalised(), accepted);
    }
    if (result.status == SolverStatus::kSuccess && problem.torque() != 0.0) {
      if (!result.preload) {
        JudgeRange(problem, options, &result);
      } else if (std::abs(result.rotation) > contact::RotationWindow(problem.model())) {
        result.status = SolverStatus::kRotationOutOfRange;
        result.message += fmt::format("; the rotation {:.6g} arcsec lies beyond a quarter tooth pitch",
                                      units::RadToArcsec(result.rotation));
      }
    }
    if (result.status == SolverStatus::kSuccess) {
      std::vector<const contact::ContactLaw*> laws(pins.size());
      for (std::size_t i = 0; i < pins.size(); ++i) laws[i] = pins[i].law;
      JudgeValidity(problem, laws, &result);
      // A balance the arithmetic cannot resolve (a torque so small that its rotation is below what
      // the geometry resolves in double precision) is the best there is, and said to be that coarse.
      if (result.residuals.torque_miss_relative > accepted) {
        result.warnings.push_back(fmt::format(
            "resolution-limited balance: the forces miss the torque by {:.4g} % of it, below what the geometry resolves "
            "in double precision at this rotation; the forces are that coarse",
            100.0 * result.residuals.torque_miss_relative));
      }
    }
  }
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace ltca::solvers
