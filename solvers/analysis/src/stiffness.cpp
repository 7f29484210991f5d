#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"

namespace ltca::analysis {
namespace {

using Clock = std::chrono::steady_clock;

/// The tangent is the central difference over +-this fraction of the torque it is taken at.
constexpr double kTangentStep = 0.01;

/// The stick after a reversal ends where the other sense's twist equals the held twist: found to
/// this fraction of the held twist, or of T in torque, in at most kStickIterations solves.
constexpr double kStickTolerance = 1e-10;
constexpr int kStickIterations = 40;

/// The key of the stick-end searches' friction warm start (their torques move from step to step).
constexpr double kStickKey = std::numeric_limits<double>::infinity();

/// The integral of T d(twist) once round the curve, closed from its last point to its first
/// (trapezoids), N*mm*rad; NaN when any point is.
double LoopWork(const std::vector<CurvePoint>& curve) {
  double work = 0.0;
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const CurvePoint& a = curve[i];
    const CurvePoint& b = curve[(i + 1) % curve.size()];
    work += 0.5 * (a.torque + b.torque) * (b.twist - a.twist);
  }
  return work;
}

/// Inserts p into the run of points of its branch, in torque order (rising on the increasing
/// branch, falling on the decreasing one); returns its index.
std::size_t InsertInOrder(std::vector<CurvePoint>& curve, const CurvePoint& p) {
  const bool increasing = p.branch == Branch::kIncreasing;
  std::size_t i = 0;
  while (i < curve.size() && curve[i].branch != p.branch) ++i;
  if (i < curve.size()) ++i;  // the reversal point stays first
  while (i < curve.size() && curve[i].branch == p.branch &&
         (increasing ? curve[i].torque < p.torque : curve[i].torque > p.torque)) {
    ++i;
  }
  curve.insert(curve.begin() + static_cast<std::ptrdiff_t>(i), p);
  return i;
}

}  // namespace

void StiffnessSettings::Validate() const {
  if (steps < 3 || steps > kMaxSteps || steps % 2 == 0) {
    throw std::invalid_argument(fmt::format(
        "[stiffness] steps_per_branch = {}: expected an odd integer from 3 to {} (torque levels from -T to +T, "
        "zero among them)",
        steps, kMaxSteps));
  }
  if (rigidity == Rigidity::kTangent && !(std::isfinite(tangent_torque) && tangent_torque != 0.0)) {
    throw std::invalid_argument(fmt::format(
        "[stiffness] tangent_torque_nm = {}: expected a finite torque other than 0 in N*m with rigidity = \"tangent\" "
        "(the free play at zero torque has no slope)",
        units::NmmToNm(tangent_torque)));
  }
  if (!(lost_motion_fraction > 0.0 && lost_motion_fraction < 1.0)) {
    throw std::invalid_argument(fmt::format(
        "[stiffness] lost_motion_fraction = {}: expected a fraction of the rated torque between 0 and 1 "
        "(exclusive; catalogues use 0.03)",
        lost_motion_fraction));
  }
  const double max_crank = units::DegToRad(kMaxCrankDeg);
  if (crank && !(std::isfinite(*crank) && std::abs(*crank) <= max_crank)) {
    throw std::invalid_argument(fmt::format(
        "[stiffness] crank_deg = {}: expected a finite crank angle within +-{} deg (docs/decks.md, Limits)",
        units::RadToDeg(*crank), kMaxCrankDeg));
  }
}

const char* ToString(Branch branch) { return branch == Branch::kIncreasing ? "increasing" : "decreasing"; }


struct StiffnessRunner::Impl {
  Stage stage;
  SolverOptions options;
  StiffnessSettings settings;
  std::unique_ptr<LoadSolver> solver;
  solvers::Workspace workspace;  // shared by every step and position: the warm starts
  double rated;  // T, N*mm
  std::vector<double> cranks;
  StiffnessSummary summary;
  std::vector<double> curve_sum;
  std::vector<std::int64_t> curve_count;
  std::vector<Spread> readoff_spread;
  Spread stick_torque[2], stick_twist[2];  // the stick_end points over the positions: [increasing, decreasing]
  Clock::duration elapsed{};
  // Coulomb friction in the loop (0 without [friction]); sense of the twist's motion on
  // the branch being solved (+1 increasing, -1 decreasing, 0: the loop's midpoint, both).
  bool closed = false;
  double friction_mu = 0.0;
  // A stage: its friction in the loop, the mesh's (friction_mu) and the bearings' (StageLoopFriction).
  StageLoopFriction stage_friction;
  bool with_friction() const { return friction_mu > 0.0 || stage_friction.bearing > 0.0; }
  double sense = 0.0;
  // Issue 27: the friction balance of each (torque, sense) warm-started from where it ended at the
  // previous crank; the stick-end searches' torques move, one warm start per sense.
  std::map<std::pair<double, double>, LoopFrictionWarmStart> friction_warm;
  bool searching = false;  // within StickEnd

  Impl(const Stage& st, const SolverOptions& o, const StiffnessSettings& s, double torque,
       const std::optional<FrictionSettings>& friction)
      : stage(st), options(o), settings(s), solver(solvers::MakeSolver(o.name)), rated(std::abs(torque)),
        cranks(s.crank ? std::vector<double>{*s.crank} : st.cranks()), friction_mu(LoopFrictionCoefficient(friction)) {
    if (rated == 0.0) {
      throw std::invalid_argument(
          "[load] torque_nm = 0: expected the rated torque of the stiffness loop, not zero (the loop runs from "
          "-|T| to +|T|)");
    }
    if (friction && stage.design().reducer) {
      // The stage's loop: the mesh's friction and the bearings' on the discs (StageLoopFriction).
      stage_friction.mesh = friction_mu;
      stage_friction.bearing = friction->bearing_coefficient;
      if (stage_friction.bearing > 0.0) {  // the loop takes the load term only (the viscous one runs)
        stage_friction.bearing_diameter = BearingFrictionDiameter(*friction, stage.design().reducer->bearing.pitch_diameter);
      }
    }
    // The last crank repeats the first's state (a closed period): the means weigh it once.
    closed = !s.crank && stage.closed_period();
  }

  /// Counts a solved position in the summary's run record; returns whether the means weigh it
  /// (the last crank of a closed period repeats the first).
  bool Record(const StiffnessPosition& pos) {
    summary.closed_period = closed;
    summary.solves += pos.solves;
    if (pos.succeeded()) {
      ++summary.succeeded;
    } else {
      summary.Fail(fmt::format("crank {:.6g} deg, {}", units::RadToDeg(pos.crank), pos.first_failure));
    }
    return !(closed && pos.crank == cranks.back());
  }

  /// Every contact point of the stage at a crank: one disc, or both.
  contact::MeshState State(double crank) const { return stage.State(crank); }

  solvers::LoadProblem Problem(const contact::MeshState& state, double torque) const {
    return stage.Problem(state, torque);
  }

  // Issue 27: the problems of one crank angle's lost motion by torque, built once (its four
  // balances with friction ask for two torques, each on both passes); empty outside it.
  bool keep_problems = false;
  std::vector<std::pair<double, solvers::LoadProblem>> kept_problems;
  struct KeepProblems {
    Impl& impl;
    explicit KeepProblems(Impl& m) : impl(m) {
      impl.kept_problems.clear();
      impl.keep_problems = true;
    }
    ~KeepProblems() {
      impl.keep_problems = false;
      impl.kept_problems.clear();
    }
    KeepProblems(const KeepProblems&) = delete;
    KeepProblems& operator=(const KeepProblems&) = delete;
  };
  solvers::LoadProblem KeptProblem(const contact::MeshState& state, double torque) {
    if (!keep_problems) return Problem(state, torque);
    for (const auto& [t, p] : kept_problems) {
      if (t == torque) return p;
    }
    kept_problems.emplace_back(torque, Problem(state, torque));
    return kept_problems.back().second;
  }

  /// The free play at a crank: where the output rests at zero torque, coming from either flank
  /// (first_contact_drive, first_contact_coast, backlash; NaN where it cannot be found).
  void FreePlay(const contact::MeshState& state, StiffnessPosition* pos) {
    const auto first_contact = [&](double torque) {
      const solvers::LoadProblem problem = Problem(state, torque);
      if (!problem.has_reducer() && problem.preloaded()) {
        // A preloaded pair rests where both flanks balance at zero torque (the preload state): the
        // loop runs through it without free play, from either flank (in the frame of `torque`).
        ++pos->solves;
        const LoadResult r = solver->Solve(Problem(state, 0.0), options, workspace);
        if (r.status == SolverStatus::kSuccess) return torque > 0.0 ? r.rotation : -r.rotation;
        ++pos->failed;
        if (pos->first_failure.empty()) {
          pos->first_failure = fmt::format("zero torque (the preload): {}: {}", solvers::ToString(r.status), r.message);
        }
        return kNaN;
      }
      if (!problem.has_reducer()) return problem.FirstContactRotation();
      // A reducer stage: its free play takes up the clearances of every element (holes,
      // bearings), not the mesh's alone: the output's rotation under a vanishing torque, 1e-7 T,
      // whose elastic part is below 1e-6 of the twist at T (Hertz and Palmgren contacts stiffen:
      // their approach grows as F^0.9, so (1e-7)^0.9 = 5e-7 of it). NaN when that solve fails.
      ++pos->solves;
      const LoadResult r = solver->Solve(Problem(state, 1e-7 * torque), options, workspace);
      if (r.status == SolverStatus::kSuccess) return r.rotation;
      ++pos->failed;
      if (pos->first_failure.empty()) {
        pos->first_failure = fmt::format("torque {:g} N*m (the free play): {}: {}", units::NmmToNm(1e-7 * torque),
                                        solvers::ToString(r.status), r.message);
      }
      return kNaN;
    };
    pos->first_contact_drive = first_contact(rated);
    pos->first_contact_coast = first_contact(-rated);
    if (!std::isfinite(pos->first_contact_drive) || !std::isfinite(pos->first_contact_coast)) {
      pos->first_contact_drive = std::isfinite(pos->first_contact_drive) ? pos->first_contact_drive : kNaN;
      pos->first_contact_coast = std::isfinite(pos->first_contact_coast) ? pos->first_contact_coast : kNaN;
      if (pos->first_failure.empty()) {  // the mesh alone; a stage's failed solve has counted and named itself
        ++pos->failed;
        pos->first_failure = "zero torque: no pin can close its gap on one of the flanks";
      }
    }
    pos->backlash = pos->first_contact_drive + pos->first_contact_coast;
  }

  /// The twist at a non-zero torque (rad, -TE) with friction resisting the motion of the current
  /// sense, NaN when the solve fails (counted in pos). on_loop: false for a probe that is not a
  /// point of the loop (it does not set the two discs' split).
  double Twist(const contact::MeshState& state, double torque, StiffnessPosition* pos, SolverStatus* status,
               bool on_loop = true, LoopFrictionBalance* balance = nullptr) {
    int solves = 0;
    LoopFrictionWarmStart* warm = nullptr;
    if (friction_mu > 0.0 && sense != 0.0) {
      warm = &friction_warm[{searching ? kStickKey : torque, sense}];
    }
    const auto problem = [&](double t) { return KeptProblem(state, t); };
    const auto solve = [&](const solvers::LoadProblem& p) { return solver->Solve(p, options, workspace); };
    const contact::MeshModel* second = stage.disc_count() == 2 ? &stage.model(1) : nullptr;
    const LoadResult r =
        stage.design().reducer
            ? SolveStageWithLoopFriction(stage.model(), state, torque, sense, stage_friction, problem, solve, &solves,
                                         second, balance)
            : SolveWithLoopFriction(stage.model(), state, torque, sense, friction_mu, problem, solve, &solves, second,
                                    warm, balance);
    pos->solves += solves;
    if (with_friction() && sense != 0.0 && r.preload && r.preload->contacts > 0 && stage.design().reducer) {
      // A preloaded stage: friction at the preload's forces holds the twist at zero torque, and the
      // stage's loop (a stick ends by zero torque) does not model a stick through zero. (The mesh
      // alone does: FrictionLoop, docs/stiffness.md "Preload".)
      ++pos->failed;
      if (pos->first_failure.empty()) {
        pos->first_failure = fmt::format(
            "torque {:g} N*m: the loop with friction of a preloaded pair ({} points pressed at zero torque) is not "
            "modelled: its stick would run through zero torque; expected the loop without [friction]",
            units::NmmToNm(torque), r.preload->contacts);
      }
      if (status != nullptr) *status = SolverStatus::kPreloadUnsupported;
      return kNaN;
    }
    if (status != nullptr) *status = r.status;
    if (stage.disc_count() == 2 && on_loop && r.status == SolverStatus::kSuccess && std::abs(torque) == rated) {
      // Two discs: the split at +-T; with friction, of the loop's pass through it.
      const std::vector<double> parts = Problem(state, torque).DiscTorques(r.rotation, r.force, workspace);
      (torque > 0.0 ? pos->first_disc_share_drive : pos->first_disc_share_coast) = parts[0] / (parts[0] + parts[1]);
    }
    if (r.reducer && on_loop && torque == rated) {  // a stage: the compliance budget at +T
      double total = 0.0;
      for (const double e : r.reducer->group_energy) total += e;
      pos->compliance_share.clear();
      for (const double e : r.reducer->group_energy) {
        pos->compliance_share.push_back(r.status == SolverStatus::kSuccess && total > 0.0 ? e / total : kNaN);
      }
    }
    if (r.status == SolverStatus::kSuccess) return -r.te;
    ++pos->failed;
    if (pos->first_failure.empty()) {
      pos->first_failure = fmt::format("torque {:g} N*m: {}: {}", units::NmmToNm(torque), solvers::ToString(r.status), r.message);
    }
    return kNaN;
  }

  /// The torque at which the stick after a reversal ends, the root of
  /// h(t) = sense (twist_sense(t) - held) between t_a (h_a < 0: still stuck) and t_b (h_b >= 0),
  /// by regula falsi with the Illinois modification (each step one solve of the current sense).
  /// Under the linear law h is linear in t and the first step is the root. NaN when a solve fails.
  double StickEnd(const contact::MeshState& state, double held, double t_a, double h_a, double t_b, double h_b,
                  StiffnessPosition* pos) {
    if (h_b == 0.0) return t_b;
    const double twist_tol = kStickTolerance * std::max(std::abs(held), 1e-9);
    int kept = 0;  // which end was kept last: -1 a, +1 b
    double t = t_b;
    for (int it = 0; it < kStickIterations; ++it) {
      t = (t_a * h_b - t_b * h_a) / (h_b - h_a);
      if (std::abs(t_b - t_a) <= kStickTolerance * rated) return t;
      SolverStatus status = SolverStatus::kNotSolved;
      searching = true;
      const double h = sense * (Twist(state, t, pos, &status, false) - held);
      searching = false;
      if (!std::isfinite(h)) return kNaN;
      if (std::abs(h) <= twist_tol) return t;
      if (h < 0.0) {
        t_a = t, h_a = h;
        if (kept == -1) h_b *= 0.5;
        kept = -1;
      } else {
        t_b = t, h_b = h;
        if (kept == 1) h_a *= 0.5;
        kept = 1;
      }
    }
    return t;
  }

  /// The loop with Coulomb friction, path dependent. It starts at -T with
  /// the twist the decreasing pass arrives with (that branch solved at -T); on each branch the
  /// twist holds at its reversal value over the levels where the branch of the new sense (friction
  /// resisting that motion) stays short of it, up to the stick_end point (StickEnd), then follows
  /// that branch; the decreasing pass ends at -T on the twist the loop began with. Fills pos->curve,
  /// the stick ends, and the loop's twist per level (up, down). Returns the held twists at -T, +T.
  std::pair<double, double> FrictionLoop(const contact::MeshState& state, const std::vector<double>& levels,
                                         const CurvePoint& at_coast, const CurvePoint& at_drive, StiffnessPosition* pos,
                                         std::vector<double>* up, std::vector<double>* down) {
    const std::size_t n = levels.size();
    // A preloaded pair (the mesh alone, issue 52): both flanks carry load at zero torque, so the
    // friction resists there too; zero is a level of the loop like any other (solved with the
    // friction of its pass), and a stick may run through it.
    const bool preloaded = !stage.design().reducer && Problem(state, rated).preloaded();
    SolverStatus low_status = SolverStatus::kNotSolved;
    sense = -1.0;
    const double held_low = Twist(state, levels.front(), pos, &low_status);
    double held = held_low, held_high = kNaN;
    SolverStatus held_status = low_status;
    for (const Branch branch : {Branch::kIncreasing, Branch::kDecreasing}) {
      const bool increasing = branch == Branch::kIncreasing;
      sense = increasing ? 1.0 : -1.0;
      std::vector<double>& loop = increasing ? *up : *down;
      double& stick_end = increasing ? pos->stick_end_coast : pos->stick_end_drive;
      const std::size_t first = increasing ? 0 : n - 1;
      pos->curve.push_back({levels[first], held, branch, held_status});  // the reversal
      loop[first] = held;
      // The branch of this sense at the reversal torque lies behind the held twist (h < 0).
      double t_prev = levels[first], h_prev = kNaN;
      bool stuck = std::isfinite(held);
      if (stuck) {
        SolverStatus status = SolverStatus::kNotSolved;
        h_prev = sense * (Twist(state, levels[first], pos, &status, false) - held);
        stuck = std::isfinite(h_prev);
      }
      for (std::size_t i = 1; i < n; ++i) {
        const std::size_t k = increasing ? i : n - 1 - i;
        const double torque = levels[k];
        if (torque == 0.0 && !preloaded) {  // no force, no friction: a stick cannot outlast zero torque
          // With few levels the stick may reach the last level before zero: it ends between that
          // level and zero, where the branch arrives at the first contact of the flank it leaves.
          const CurvePoint& leaving = increasing ? at_coast : at_drive;
          const double h_zero = sense * (leaving.twist - held);
          if (stuck && std::isfinite(h_zero) && h_zero >= 0.0) {
            stick_end = StickEnd(state, held, t_prev, h_prev, 0.0, h_zero, pos);
            CurvePoint end{stick_end, std::isfinite(stick_end) ? held : kNaN, branch,
                           std::isfinite(stick_end) ? held_status : SolverStatus::kNumericalFailure};
            end.stick_end = true;
            pos->curve.push_back(end);
          }
          stuck = false;
          for (CurvePoint p : increasing ? std::vector<CurvePoint>{at_coast, at_drive} : std::vector<CurvePoint>{at_drive, at_coast}) {
            p.branch = branch;
            pos->curve.push_back(p);
          }
          continue;
        }
        CurvePoint p{torque, kNaN, branch, SolverStatus::kNotSolved};
        if (!increasing && k == 0 && !stuck) {
          p.twist = held_low;  // the loop closes where it began (the same solve)
          p.status = low_status;
        } else {
          p.twist = Twist(state, torque, pos, &p.status);
        }
        if (stuck) {
          const double h = sense * (p.twist - held);
          if (!std::isfinite(h)) {
            stuck = false;  // a failed solve: the point stays unsolved
          } else if (h < 0.0) {  // still stuck: the twist holds
            t_prev = torque;
            h_prev = h;
            p.twist = held;
            p.status = held_status;
          } else {
            stick_end = StickEnd(state, held, t_prev, h_prev, torque, h, pos);
            CurvePoint end{stick_end, std::isfinite(stick_end) ? held : kNaN, branch,
                           std::isfinite(stick_end) ? held_status : SolverStatus::kNumericalFailure};
            end.stick_end = true;
            pos->curve.push_back(end);
            stuck = false;
          }
        }
        loop[k] = p.twist;
        pos->curve.push_back(p);
      }
      if (stuck && preloaded) {
        // The preload's friction held the output from one end of the loop to the other: the
        // friction moment at the preload exceeds the torque, and the output never turns.
        ++pos->failed;
        if (pos->first_failure.empty()) {
          pos->first_failure = fmt::format(
              "the loop with friction of a preloaded pair: the output sticks from {:g} N*m to {:g} N*m (the preload's "
              "friction moment exceeds the torque): no loop",
              units::NmmToNm(levels[first]), units::NmmToNm(levels[increasing ? n - 1 : 0]));
        }
      }
      held = loop[increasing ? n - 1 : 0];
      held_status = pos->curve.back().status;
      if (increasing) held_high = held;
    }
    sense = 0.0;
    return {held_low, held_high};
  }
};

StiffnessRunner::StiffnessRunner(const Stage& stage, const SolverOptions& options, const StiffnessSettings& settings,
                                 double torque, const std::optional<FrictionSettings>& friction) {
  const auto start = Clock::now();
  options.Validate();
  settings.Validate();
  impl_ = std::make_unique<Impl>(stage, options, settings, torque, friction);
  impl_->elapsed = Clock::now() - start;
}
StiffnessRunner::~StiffnessRunner() = default;
StiffnessRunner::StiffnessRunner(StiffnessRunner&&) noexcept = default;
StiffnessRunner& StiffnessRunner::operator=(StiffnessRunner&&) noexcept = default;

const std::vector<double>& StiffnessRunner::cranks() const { return impl_->cranks; }
double StiffnessRunner::rated_torque() const { return impl_->rated; }

std::vector<double> StiffnessRunner::Levels() const {
  const int n = impl_->settings.steps;
  const int half = (n - 1) / 2;
  std::vector<double> levels(static_cast<std::size_t>(n));
  // Symmetric by construction: level half + k is exactly minus level half - k, the middle one 0.
  for (int k = 0; k <= half; ++k) {
    const double t = impl_->rated * static_cast<double>(k) / static_cast<double>(half);
    levels[static_cast<std::size_t>(half + k)] = t;
    levels[static_cast<std::size_t>(half - k)] = -t;
  }
  return levels;
}

StiffnessPosition StiffnessRunner::Solve(double crank) {
  const auto start = Clock::now();
  Impl& m = *impl_;
  StiffnessPosition pos;
  pos.crank = crank;
  const contact::MeshState state = m.State(crank);
  const double t = m.rated;

  m.FreePlay(state, &pos);
  const CurvePoint at_drive{0.0, pos.first_contact_drive, Branch::kIncreasing,
                            std::isfinite(pos.first_contact_drive) ? SolverStatus::kSuccess : SolverStatus::kNumericalFailure};
  const CurvePoint at_coast{0.0, -pos.first_contact_coast, Branch::kIncreasing,
                            std::isfinite(pos.first_contact_coast) ? SolverStatus::kSuccess : SolverStatus::kNumericalFailure};

  // The loop: up from -T to +T, then down again; each step starts from the workspace the previous
  // one left.
  const std::vector<double> levels = Levels();
  std::vector<double> up(levels.size(), kNaN), down(levels.size(), kNaN);
  double held_low = kNaN, held_high = kNaN;  // with friction: the twist held after the reversal at -T, +T
  if (m.with_friction()) std::tie(held_low, held_high) = m.FrictionLoop(state, levels, at_coast, at_drive, &pos, &up, &down);
  for (const Branch branch : {Branch::kIncreasing, Branch::kDecreasing}) {
    if (m.with_friction()) break;  // the loop above
    const bool increasing = branch == Branch::kIncreasing;
    m.sense = increasing ? 1.0 : -1.0;  // friction resists the twist's motion
    for (std::size_t i = 0; i < levels.size(); ++i) {
      const std::size_t k = increasing ? i : levels.size() - 1 - i;
      const double torque = levels[k];
      if (torque == 0.0) {  // the flank it comes from, then the one it goes to
        for (CurvePoint p : increasing ? std::vector<CurvePoint>{at_coast, at_drive} : std::vector<CurvePoint>{at_drive, at_coast}) {
          p.branch = branch;
          pos.curve.push_back(p);
        }
        continue;
      }
      CurvePoint p{torque, kNaN, branch, SolverStatus::kNotSolved};
      p.twist = m.Twist(state, torque, &pos, &p.status);
      (increasing ? up : down)[k] = p.twist;
      pos.curve.push_back(p);
    }
  }
  m.sense = 0.0;
  pos.branch_difference = 0.0;
  for (std::size_t k = 0; k < levels.size(); ++k) {
    if (levels[k] == 0.0) continue;
    pos.branch_difference = std::max(pos.branch_difference, std::abs(up[k] - down[k]));  // NaN stays NaN
    if (!std::isfinite(up[k] - down[k])) pos.branch_difference = kNaN;
  }

  pos.hysteresis = LoopWork(pos.curve);

  // The read-offs, each solved at its own torque (the levels need not contain it). Without
  // friction a torque has one twist. With friction the loop has two there:
  //  - the rigidity (secant or tangent) is read on the loading pass, the twist moving away from
  //    zero in the sense of the torque (the increasing pass for T > 0, the decreasing one for
  //    T < 0), the curve a catalogue's test traces from 50 % to 100 % of the rated torque (Harmonic
  //    Drive: the slope of the torque-torsion curve loaded from zero); the loop's midline would
  //    take the reversal's twist at +-T against both passes' mean at +-T / 2, a secant that grows
  //    without bound with friction (K (1 - r^2) / (1 - 2 r) under the linear law);
  //  - the lost motion at the midpoints of the loop's width at +-f T, as the catalogue defines it:
  //    the mean of the loop's twist on either pass, the branch of that sense or the held twist
  //    where the torque lies within that pass's stick.
  const auto twist = [&](double torque, bool loading) {
    CurvePoint p{torque, kNaN, Branch::kIncreasing, SolverStatus::kNotSolved};
    if (m.with_friction() && loading) {
      m.sense = torque > 0.0 ? 1.0 : -1.0;
      p.branch = torque > 0.0 ? Branch::kIncreasing : Branch::kDecreasing;
      p.twist = m.Twist(state, torque, &pos, &p.status);
      m.sense = 0.0;
    } else if (m.with_friction()) {
      SolverStatus on_up = SolverStatus::kSuccess, on_down = SolverStatus::kSuccess;
      double rising = held_low, falling = held_high;
      if (!(torque < pos.stick_end_coast)) {
        m.sense = 1.0;
        rising = m.Twist(state, torque, &pos, &on_up);
      }
      if (!(torque > pos.stick_end_drive)) {
        m.sense = -1.0;
        falling = m.Twist(state, torque, &pos, &on_down);
      }
      m.sense = 0.0;
      p.twist = 0.5 * (rising + falling);
      p.status = on_up != SolverStatus::kSuccess ? on_up : on_down;
    } else {
      p.twist = m.Twist(state, torque, &pos, &p.status);
    }
    pos.readoffs.push_back(p);
    return p.twist;
  };
  if (m.settings.rigidity == StiffnessSettings::Rigidity::kSecant) {
    const double full = twist(t, true), half = twist(0.5 * t, true), coast_half = twist(-0.5 * t, true),
                 coast_full = twist(-t, true);
    const double drive = full - half, coast = coast_half - coast_full;  // a on either flank
    pos.rigidity_drive = 0.5 * t / drive;
    pos.rigidity_coast = 0.5 * t / coast;
    pos.rigidity = t / (drive + coast);
  } else {
    const double at = m.settings.tangent_torque, h = kTangentStep * std::abs(at);
    const double above = twist(at + h, true), below = twist(at - h, true);
    pos.rigidity = 2.0 * h / (above - below);
  }
  const double f = m.settings.lost_motion_fraction;
  const double plus = twist(f * t, false), minus = twist(-f * t, false);
  pos.lost_motion = plus - minus;

  // The summary.
  StiffnessSummary& s = m.summary;
  const bool in_mean = m.Record(pos);
  s.rigidity.Add(pos.rigidity, in_mean);
  s.rigidity_drive.Add(pos.rigidity_drive, in_mean);
  s.rigidity_coast.Add(pos.rigidity_coast, in_mean);
  s.lost_motion.Add(pos.lost_motion, in_mean);
  s.backlash.Add(pos.backlash, in_mean);
  s.branch_difference.Add(pos.branch_difference, in_mean);
  s.first_disc_share_drive.Add(pos.first_disc_share_drive, in_mean);
  s.first_disc_share_coast.Add(pos.first_disc_share_coast, in_mean);
  if (s.compliance_share.size() < pos.compliance_share.size()) s.compliance_share.resize(pos.compliance_share.size());
  for (std::size_t g = 0; g < pos.compliance_share.size(); ++g) s.compliance_share[g].Add(pos.compliance_share[g], in_mean);
  s.hysteresis.Add(pos.hysteresis, in_mean);
  s.stick_end_drive.Add(pos.stick_end_drive, in_mean);
  s.stick_end_coast.Add(pos.stick_end_coast, in_mean);
  // The curve's layout over the positions: the levels and zero-torque points (the same at every
  // position); the stick_end points, whose torque differs by position, apart.
  std::vector<CurvePoint> layout;
  for (const CurvePoint& c : pos.curve) {
    if (!c.stick_end) {
      layout.push_back(c);
      continue;
    }
    const int b = c.branch == Branch::kIncreasing ? 0 : 1;
    if (std::isfinite(c.twist)) m.stick_torque[b].Add(c.torque, in_mean);
    m.stick_twist[b].Add(c.twist, in_mean);
  }
  if (s.curve.empty()) {
    s.curve = layout;
    s.curve_min.assign(layout.size(), kNaN);
    s.curve_max.assign(layout.size(), kNaN);
    m.curve_sum.assign(layout.size(), 0.0);
    m.curve_count.assign(layout.size(), 0);
  }
  for (std::size_t i = 0; i < layout.size(); ++i) {
    const double v = layout[i].twist;
    if (!std::isfinite(v)) continue;
    s.curve_min[i] = std::isnan(s.curve_min[i]) ? v : std::min(s.curve_min[i], v);
    s.curve_max[i] = std::isnan(s.curve_max[i]) ? v : std::max(s.curve_max[i], v);
    if (!in_mean) continue;
    m.curve_sum[i] += v;
    ++m.curve_count[i];
  }
  if (s.readoffs.empty()) {
    s.readoffs = pos.readoffs;
    m.readoff_spread.assign(pos.readoffs.size(), Spread{});
  }
  for (std::size_t i = 0; i < pos.readoffs.size(); ++i) m.readoff_spread[i].Add(pos.readoffs[i].twist, in_mean);
  m.elapsed += Clock::now() - start;
  return pos;
}

StiffnessPosition StiffnessRunner::SolveLostMotion(double crank) {
  const auto start = Clock::now();
  Impl& m = *impl_;
  StiffnessPosition pos;
  pos.crank = crank;
  const contact::MeshState state = m.State(crank);
  const double t = m.rated, ft = m.settings.lost_motion_fraction * t;
  // One twist of the sense `sense` (0 without friction), not a point of a drawn loop.
  const auto twist = [&](double torque, double sense, LoopFrictionBalance* balance = nullptr) {
    m.sense = sense;
    SolverStatus status = SolverStatus::kNotSolved;
    const double v = m.Twist(state, torque, &pos, &status, false, balance);
    m.sense = 0.0;
    return v;
  };
  double plus = kNaN, minus = kNaN;  // the loop's midpoints at +f T and -f T
  if (!m.with_friction()) {
    plus = twist(ft, 0.0);
    minus = twist(-ft, 0.0);
  } else {
    // The loop starts at -T on the decreasing pass and reverses at +T; the reversals hold the
    // twists held_low and held_high, so the way back at +f T reads min(falling_plus, held_high)
    // and the way up at -f T max(rising_minus, held_low). Issue 27: the held twist is solved only
    // when it can be the nearer. On the way back at +f T the normal forces carry
    // t_fp = f T + M_fp, at the reversal t_hh = T - M(t_hh). Were t_hh < t_fp, the rotation would
    // be no larger there (it grows with t), so M(t_hh) <= M_+(t_fp) + B <= M_fp + B
    // (LoopFrictionBalance: M_+ the pins of arm > 0, non-decreasing; B behind), and
    // T - M_fp - B <= t_hh < f T + M_fp. So f T + 2 M_fp + B <= T gives t_fp <= t_hh, and
    // falling_plus <= held_high. The same on the other flank with rising_minus and held_low.
    LoopFrictionBalance falling, rising;
    double rising_plus = kNaN, falling_plus = kNaN, falling_minus = kNaN, rising_minus = kNaN;
    {
      const Impl::KeepProblems keep(m);  // this state's problems, dropped on leaving (also by an exception)
      rising_plus = twist(ft, 1.0), falling_plus = twist(ft, -1.0, &falling);
      falling_minus = twist(-ft, -1.0), rising_minus = twist(-ft, 1.0, &rising);
    }
    const auto held_needed = [&](const LoopFrictionBalance& b) { return !(b.direct && ft + 2.0 * b.moment + b.behind <= t); };
    const double held_high = held_needed(falling) ? twist(t, 1.0) : std::numeric_limits<double>::infinity();
    const double held_low = held_needed(rising) ? twist(-t, -1.0) : -std::numeric_limits<double>::infinity();
    if (pos.failed == 0) {
      plus = 0.5 * (rising_plus + std::min(falling_plus, held_high));
      minus = 0.5 * (std::max(rising_minus, held_low) + falling_minus);
    }
  }
  pos.lost_motion = pos.failed == 0 ? plus - minus : kNaN;
  pos.readoffs.push_back({ft, plus, Branch::kIncreasing, pos.failed == 0 ? SolverStatus::kSuccess : SolverStatus::kNumericalFailure});
  pos.readoffs.push_back({-ft, minus, Branch::kIncreasing, pos.failed == 0 ? SolverStatus::kSuccess : SolverStatus::kNumericalFailure});

  m.summary.lost_motion.Add(pos.lost_motion, m.Record(pos));
  m.elapsed += Clock::now() - start;
  return pos;
}

StiffnessPosition StiffnessRunner::SolveFreePlay(double crank) {
  const auto start = Clock::now();
  Impl& m = *impl_;
  StiffnessPosition pos;
  pos.crank = crank;
  m.FreePlay(m.State(crank), &pos);
  m.summary.backlash.Add(pos.backlash, m.Record(pos));
  m.elapsed += Clock::now() - start;
  return pos;
}

StiffnessSummary StiffnessRunner::Summary() const {
  StiffnessSummary s = impl_->summary;
  for (std::size_t i = 0; i < s.curve.size(); ++i) {
    const std::int64_t n = impl_->curve_count[i];
    s.curve[i].twist = n > 0 ? impl_->curve_sum[i] / static_cast<double>(n) : kNaN;
    s.curve[i].status = n > 0 ? SolverStatus::kSuccess : SolverStatus::kNumericalFailure;
  }
  for (const Branch branch : {Branch::kIncreasing, Branch::kDecreasing}) {  // friction: the mean stick ends
    const int b = branch == Branch::kIncreasing ? 0 : 1;
    const Spread& twist = impl_->stick_twist[b];
    if (impl_->stick_torque[b].count == 0) continue;
    CurvePoint end{impl_->stick_torque[b].mean, twist.mean, branch, SolverStatus::kSuccess};
    end.stick_end = true;
    const auto at = static_cast<std::ptrdiff_t>(InsertInOrder(s.curve, end));
    s.curve_min.insert(s.curve_min.begin() + at, twist.min);
    s.curve_max.insert(s.curve_max.begin() + at, twist.max);
  }
  for (std::size_t i = 0; i < s.readoffs.size(); ++i) {
    s.readoffs[i].twist = impl_->readoff_spread[i].mean;
    s.readoffs[i].status = impl_->readoff_spread[i].count > 0 ? SolverStatus::kSuccess : SolverStatus::kNumericalFailure;
  }
  s.wall_seconds = std::chrono::duration<double>(impl_->elapsed).count();
  return s;
}

StiffnessResult StiffnessRunner::Run(const StiffnessSink& sink) {
  StiffnessResult result;
  result.settings = impl_->settings;
  result.rated_torque = impl_->rated;
  result.friction_coefficient = impl_->friction_mu;
  result.bearing_friction_coefficient = impl_->stage_friction.bearing;
  result.cranks = impl_->cranks;
  for (const double crank : impl_->cranks) {
    StiffnessPosition p = Solve(crank);
    if (sink) {
      sink(p);
    } else {
      result.positions.push_back(std::move(p));
    }
  }
  result.summary = Summary();
  return result;
}

StiffnessResult Stiffness(const Stage& stage, const SolverOptions& options, const StiffnessSettings& settings, double torque,
                          const std::optional<FrictionSettings>& friction) {
  return StiffnessRunner(stage, options, settings, torque, friction).Run();
}

}  // namespace ltca::analysis
