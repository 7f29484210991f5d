#include "ltca/app/stiffness.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/app/efficiency.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"

namespace ltca::app {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The tangent is the central difference over +-this fraction of the torque it is taken at.
constexpr double kTangentStep = 0.01;

}  // namespace

const char* ToString(Branch branch) { return branch == Branch::kIncreasing ? "increasing" : "decreasing"; }

void Spread::Add(double v, bool in_mean) {
  if (!std::isfinite(v)) return;
  if (count == 0) {
    min = max = v;
  } else {
    min = std::min(min, v);
    max = std::max(max, v);
  }
  if (in_mean) {
    mean = in_mean_count == 0 ? v : mean + (v - mean) / static_cast<double>(in_mean_count + 1);
    ++in_mean_count;
  } else if (in_mean_count == 0) {
    mean = v;  // only the repeated state so far: it is the mean
  }
  ++count;
}

struct StiffnessRunner::Impl {
  const Deck& deck;
  SolverOptions options;
  StiffnessSettings settings;
  std::shared_ptr<const contact::MeshModel> model;
  std::shared_ptr<const contact::MeshModel> second;  // [second_disc]: the stage's two discs (issue 13)
  std::unique_ptr<LoadSolver> solver;
  solvers::Workspace workspace;  // shared by every step and position: the warm starts
  const contact::Material& material;
  double rated;  // T, N*mm
  std::vector<double> cranks;
  solvers::LoadProblem::CheckedCoupling coupling;
  StiffnessSummary summary;
  std::vector<double> curve_sum;
  std::vector<std::int64_t> curve_count;
  std::vector<Spread> readoff_spread;
  Clock::duration elapsed{};
  // issue 14: Coulomb friction in the loop (0 without [friction]); sense of the twist's motion on
  // the branch being solved (+1 increasing, -1 decreasing, 0: the loop's midpoint, both).
  bool closed = false;
  double friction_mu = LoopFrictionCoefficient(deck);
  double sense = 0.0;

  Impl(const Deck& d, const SolverOptions& o, const StiffnessSettings& s)
      : deck(d), options(o), settings(s), model(std::make_shared<const contact::MeshModel>(d.MakeModel())),
        second(d.MakeSecondModel()),
        solver(solvers::MakeSolver(o.name)), material(d.RequireMaterial()), rated(std::abs(d.RequireLoad().torque)),
        cranks(s.crank ? std::vector<double>{*s.crank} : d.sweep.CrankAngles()) {
    if (rated == 0.0) {
      throw std::invalid_argument(
          "[load] torque_nm = 0: expected the rated torque of the stiffness loop, not zero (the loop runs from "
          "-|T| to +|T|)");
    }
    // Nothing is solved for a pair that interferes at any crank (as `solve` and `backlash` reject it).
    for (const double crank : cranks) contact::RequireNoInterference(State(crank), crank, Tolerance());
    // The last crank repeats the first's state (a closed period): the means weigh it once (issue 26).
    closed = cranks.size() > 1 && contact::SameMesh(State(cranks.front()), State(cranks.back()));
    coupling = deck.MakeCoupling(*model);
  }

  /// Every contact point of the stage at a crank: one disc, or both.
  contact::MeshState State(double crank) const { return deck.EvaluateDiscs(*model, second.get(), crank); }
  double Tolerance() const {
    return std::max(model->interference_tolerance(), second ? second->interference_tolerance() : 0.0);
  }

  solvers::LoadProblem Problem(const contact::MeshState& state, double torque) const {
    if (second) return {model, second, state, deck.contact, material, torque, options.kinematics};
    solvers::LoadProblem problem(model, state, deck.contact, material, torque, options.kinematics);
    if (!coupling.matrix) return problem;
    return problem.WithCoupling(coupling);
  }

  /// The twist at a non-zero torque (rad, -TE), NaN when the solve fails (counted in pos).
  double Twist(const contact::MeshState& state, double torque, StiffnessPosition* pos, SolverStatus* status) {
    if (friction_mu > 0.0 && sense == 0.0) {  // issue 14: the loop's midpoint, both branches solved
      sense = 1.0;
      const double up = Twist(state, torque, pos, status);
      sense = -1.0;
      const double down = Twist(state, torque, pos, status);
      sense = 0.0;
      return 0.5 * (up + down);
    }
    int solves = 0;
    const LoadResult r = SolveWithLoopFriction(
        *model, state, torque, sense, friction_mu,
        [&](double t) { return solver->Solve(Problem(state, t), options, workspace); }, &solves, second.get());
    pos->solves += solves;
    if (status != nullptr) *status = r.status;
    if (second && r.status == SolverStatus::kSuccess && std::abs(torque) == rated) {
      // Two discs (issue 13): the split at +-T; with friction, of the last branch solved.
      const std::vector<double> parts = Problem(state, torque).DiscTorques(r.rotation, r.force, workspace);
      (torque > 0.0 ? pos->first_disc_share_drive : pos->first_disc_share_coast) = parts[0] / (parts[0] + parts[1]);
    }
    if (r.status == SolverStatus::kSuccess) return -r.te;
    ++pos->failed;
    if (pos->first_failure.empty()) {
      pos->first_failure = fmt::format("torque {:g} N*m: {}: {}", units::NmmToNm(torque), solvers::ToString(r.status), r.message);
    }
    return kNaN;
  }
};

StiffnessRunner::StiffnessRunner(const Deck& deck, const SolverOptions& options, const StiffnessSettings& settings) {
  const auto start = Clock::now();
  options.Validate();
  settings.Validate();
  impl_ = std::make_unique<Impl>(deck, options, settings);
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
  contact::RequireNoInterference(state, crank, m.Tolerance());
  const double t = m.rated;

  // The free play: where the output rests at zero torque, coming from either flank.
  pos.first_contact_drive = m.Problem(state, t).FirstContactRotation();
  pos.first_contact_coast = m.Problem(state, -t).FirstContactRotation();
  if (!std::isfinite(pos.first_contact_drive) || !std::isfinite(pos.first_contact_coast)) {
    pos.first_contact_drive = std::isfinite(pos.first_contact_drive) ? pos.first_contact_drive : kNaN;
    pos.first_contact_coast = std::isfinite(pos.first_contact_coast) ? pos.first_contact_coast : kNaN;
    ++pos.failed;
    pos.first_failure = "zero torque: no pin can close its gap on one of the flanks";
  }
  pos.backlash = pos.first_contact_drive + pos.first_contact_coast;
  const CurvePoint at_drive{0.0, pos.first_contact_drive, Branch::kIncreasing,
                            std::isfinite(pos.first_contact_drive) ? SolverStatus::kSuccess : SolverStatus::kNumericalFailure};
  const CurvePoint at_coast{0.0, -pos.first_contact_coast, Branch::kIncreasing,
                            std::isfinite(pos.first_contact_coast) ? SolverStatus::kSuccess : SolverStatus::kNumericalFailure};

  // The loop: up from -T to +T, then down again; each step starts from the workspace the previous
  // one left.
  const std::vector<double> levels = Levels();
  std::vector<double> up(levels.size(), kNaN), down(levels.size(), kNaN);
  for (const Branch branch : {Branch::kIncreasing, Branch::kDecreasing}) {
    const bool increasing = branch == Branch::kIncreasing;
    m.sense = increasing ? 1.0 : -1.0;  // issue 14: friction resists the twist's motion
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

  // The read-offs, each solved at its own torque (the levels need not contain it). Without
  // friction a torque has one twist, so each midpoint of the loop is that twist.
  const auto twist = [&](double torque) {
    CurvePoint p{torque, kNaN, Branch::kIncreasing, SolverStatus::kNotSolved};
    p.twist = m.Twist(state, torque, &pos, &p.status);
    pos.readoffs.push_back(p);
    return p.twist;
  };
  if (m.settings.rigidity == StiffnessSettings::Rigidity::kSecant) {
    const double full = twist(t), half = twist(0.5 * t), coast_half = twist(-0.5 * t), coast_full = twist(-t);
    const double drive = full - half, coast = coast_half - coast_full;  // a on either flank
    pos.rigidity_drive = 0.5 * t / drive;
    pos.rigidity_coast = 0.5 * t / coast;
    pos.rigidity = t / (drive + coast);
  } else {
    const double at = m.settings.tangent_torque, h = kTangentStep * std::abs(at);
    const double above = twist(at + h), below = twist(at - h);
    pos.rigidity = 2.0 * h / (above - below);
  }
  const double f = m.settings.lost_motion_fraction;
  const double plus = twist(f * t), minus = twist(-f * t);
  pos.lost_motion = plus - minus;

  // The summary.
  StiffnessSummary& s = m.summary;
  s.closed_period = m.closed;
  const bool in_mean = !(m.closed && crank == m.cranks.back());
  (pos.succeeded() ? s.succeeded : s.failed) += 1;
  s.solves += pos.solves;
  if (!pos.succeeded() && s.first_failure.empty()) {
    s.first_failure = fmt::format("crank {:.6g} deg, {}", units::RadToDeg(crank), pos.first_failure);
  }
  s.rigidity.Add(pos.rigidity, in_mean);
  s.rigidity_drive.Add(pos.rigidity_drive, in_mean);
  s.rigidity_coast.Add(pos.rigidity_coast, in_mean);
  s.lost_motion.Add(pos.lost_motion, in_mean);
  s.backlash.Add(pos.backlash, in_mean);
  s.branch_difference.Add(pos.branch_difference, in_mean);
  s.first_disc_share_drive.Add(pos.first_disc_share_drive, in_mean);
  s.first_disc_share_coast.Add(pos.first_disc_share_coast, in_mean);
  if (s.curve.empty()) {
    s.curve = pos.curve;
    s.curve_min.assign(pos.curve.size(), kNaN);
    s.curve_max.assign(pos.curve.size(), kNaN);
    m.curve_sum.assign(pos.curve.size(), 0.0);
    m.curve_count.assign(pos.curve.size(), 0);
  }
  for (std::size_t i = 0; i < pos.curve.size(); ++i) {
    const double v = pos.curve[i].twist;
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

StiffnessSummary StiffnessRunner::Summary() const {
  StiffnessSummary s = impl_->summary;
  for (std::size_t i = 0; i < s.curve.size(); ++i) {
    const std::int64_t n = impl_->curve_count[i];
    s.curve[i].twist = n > 0 ? impl_->curve_sum[i] / static_cast<double>(n) : kNaN;
    s.curve[i].status = n > 0 ? SolverStatus::kSuccess : SolverStatus::kNumericalFailure;
  }
  for (std::size_t i = 0; i < s.readoffs.size(); ++i) {
    s.readoffs[i].twist = impl_->readoff_spread[i].mean;
    s.readoffs[i].status = impl_->readoff_spread[i].count > 0 ? SolverStatus::kSuccess : SolverStatus::kNumericalFailure;
  }
  s.wall_seconds = std::chrono::duration<double>(impl_->elapsed).count();
  return s;
}

}  // namespace ltca::app
