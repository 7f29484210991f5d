#include "energy_groups_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "coupled_contact.hpp"

namespace ltca::solvers {
namespace {

constexpr double kGapTolerance = 1e-12;  // mm: rounding of an exactly touching pin

/// A pin already pressed at the linearisation point whose arm is not positive (arm <= min_arm):
/// the rotation does not close it (it opens it), so it is no group member and no first contact;
/// it carries the force its law gives at its linearised approach (zero once it opens) in every
/// group, which is complementary by construction. Its torque F L (<= 0) pushes back against the
/// load, and d(F L)/dpsi = F' L^2 >= 0 keeps the group torque non-decreasing in psi.
/// A departure from Li (docs/solvers.md).
struct PressedPin {
  std::size_t pin = 0;
  double approach0 = 0.0, arm = 0.0;
  const contact::ContactLaw* law = nullptr;
};

struct Linearised {  // points about the current rotation psi0: approach = L (psi - psi0) + a0
  std::vector<double> approach0, arm;
  std::vector<int> pin;                         ///< the pin (tooth) of every point
  std::vector<const contact::ContactLaw*> law;  ///< nullptr: no group member (edge, or arm <= min_arm)
  std::vector<PressedPin> pressed;               ///< in every group, see PressedPin
  double psi0 = 0.0;
  double Approach(std::size_t i, double psi) const { return approach0[i] + arm[i] * (psi - psi0); }
  double Approach(const PressedPin& p, double psi) const { return p.approach0 + p.arm * (psi - psi0); }
};

struct GroupSolution {
  bool feasible = false;
  double psi = 0.0;
  double energy = std::numeric_limits<double>::infinity();
  std::vector<double> force;
};

// Every member tooth in contact: solve sum_{G} F_i(approach_i(psi)) L_i = T by bisection on psi
// (the left side is non-decreasing), then check feasibility. A tooth is a pin with its slices:
// the slices of a member carry the force of their law (none where the slice is open:
// complementary by construction), and a member must have a pressed slice.
GroupSolution SolveGroup(const Linearised& lin, const std::vector<std::size_t>& group, int pins, double torque,
                         double tolerance) {
  GroupSolution s;
  const auto torque_at = [&](double psi) {
    double t = 0.0;
    for (const std::size_t i : group) t += lin.law[i]->Force(lin.Approach(i, psi)) * lin.arm[i];
    for (const auto& p : lin.pressed) t += p.law->Force(lin.Approach(p, psi)) * p.arm;
    return t;
  };
  double lo = std::numeric_limits<double>::infinity();
  for (const std::size_t i : group) lo = std::min(lo, lin.psi0 - lin.approach0[i] / lin.arm[i]);
  double step = 1e-7, hi = lo + step;
  int guard = 0;
  while (torque_at(hi) < torque && guard++ < 200) lo = hi, step *= 2.0, hi = lo + step;
  if (guard >= 200) return s;
  for (int it = 0; it < 200 && hi - lo > 1e-16 * std::max(std::abs(hi), 1e-12); ++it) {
    const double mid = 0.5 * (lo + hi);
    const double t = torque_at(mid);
    if (std::abs(t - torque) <= tolerance * torque) lo = hi = mid;
    else (t < torque ? lo : hi) = mid;
  }
  s.psi = 0.5 * (lo + hi);
  s.force.assign(lin.arm.size(), 0.0);
  s.feasible = true;
  s.energy = 0.0;
  std::vector<bool> member(lin.arm.size(), false), pressed_tooth(static_cast<std::size_t>(pins), false);
  for (const std::size_t i : group) member[i] = true;
  for (std::size_t i = 0; i < lin.arm.size(); ++i) {
    const double delta = lin.Approach(i, s.psi);
    if (member[i]) {
      if (delta > 0.0) pressed_tooth[static_cast<std::size_t>(lin.pin[i])] = true;
      s.force[i] = lin.law[i]->Force(delta);
      if (delta > 0.0) s.energy += s.force[i] * delta;  // Li eq. 14: NE = sum F_i delta_i
    } else if (lin.law[i] != nullptr && delta > kGapTolerance) {
      s.feasible = false;                        // a non-member would penetrate
    }
  }
  for (const std::size_t i : group) {
    if (!pressed_tooth[static_cast<std::size_t>(lin.pin[i])]) s.feasible = false;  // a member would have to pull
  }
  for (const auto& p : lin.pressed) {  // complementary by construction: no feasibility check
    const double delta = lin.Approach(p, s.psi);
    s.force[p.pin] = p.law->Force(delta);
    if (delta > 0.0) s.energy += s.force[p.pin] * delta;
  }
  return s;
}

// Coupled (pin bending): the group's points, and the pressed points of non-positive arm,
// are the only ones allowed to carry force; among them the coupled complementarity problem with
// the torque balance is solved (CoupledContact::ForTorque, the compatibility backend's kernel:
// members may open, as the slices of a member do uncoupled). Feasible when it converges, every
// member tooth carries load and every other usable point stays open; the energy is Li's
// NE = sum F_i delta_i with delta_i the total approach.
GroupSolution SolveGroupCoupled(const Linearised& lin, const std::vector<std::size_t>& group, int teeth, double torque,
                                const Eigen::SparseMatrix<double>& matrix, CoupledContact& coupled) {
  GroupSolution s;
  const std::size_t n = lin.arm.size();
  std::vector<CoupledPoint> points(n, CoupledPoint{nullptr, -1.0, 0.0});  // non-members: far open, no law
  std::vector<bool> member(n, false);
  for (const std::size_t i : group) {
    member[i] = true;
    points[i] = {lin.law[i], lin.approach0[i], lin.arm[i]};
  }
  for (const auto& p : lin.pressed) {
    member[p.pin] = true;
    points[p.pin] = {p.law, p.approach0, p.arm};
  }
  std::vector<double> force;
  const CoupledOutcome o = coupled.ForTorque(points, torque, &force);
  if (!o.converged || o.edge || o.saturated) return s;
  s.psi = lin.psi0 + o.rotation;
  s.force = std::move(force);
  s.feasible = true;
  s.energy = 0.0;
  // A non-member's gap: (C F)_i - delta_i (no force of its own; a coupling across pins moves it).
  const Eigen::VectorXd moved =
      matrix * Eigen::Map<const Eigen::VectorXd>(s.force.data(), static_cast<Eigen::Index>(s.force.size()));
  std::vector<bool> loaded_tooth(static_cast<std::size_t>(teeth), false);
  for (std::size_t i = 0; i < n; ++i) {
    const double delta = points[i].approach + points[i].arm * o.rotation;
    if (member[i]) {
      if (s.force[i] > 0.0) loaded_tooth[static_cast<std::size_t>(lin.pin[i])] = true;
      s.energy += s.force[i] * delta;
    } else if (lin.law[i] != nullptr && lin.Approach(i, s.psi) - moved(static_cast<Eigen::Index>(i)) > kGapTolerance) {
      s.feasible = false;  // a non-member would penetrate
    }
  }
  for (const std::size_t i : group) {
    if (!loaded_tooth[static_cast<std::size_t>(lin.pin[i])]) s.feasible = false;
  }
  return s;
}

}  // namespace

void EnergyGroupsSolver::DoSolve(const LoadProblem& problem, const SolverOptions& options, Workspace& workspace,
                                 LoadResult* result) const {
  const int n = problem.point_count();
  // A tooth: a pin with its slices, of one disc (two discs: tooth = disc z_p + pin).
  const int pins_per_disc = problem.model().pin_count();
  const int teeth = pins_per_disc * problem.disc_count();
  const auto& points = problem.base_state().pins;
  const auto tooth_of = [&](const contact::PinContact& p) { return p.disc * pins_per_disc + p.pin; };
  // The tooth k places further round the pin ring from tooth t, on the same disc.
  const auto along = [&](int t, int k) {
    const int pin = ((t % pins_per_disc + k) % pins_per_disc + pins_per_disc) % pins_per_disc;
    return t - t % pins_per_disc + pin;
  };
  // The points of every tooth (pin-major: a contiguous range).
  std::vector<std::vector<std::size_t>> points_of(static_cast<std::size_t>(teeth));
  for (std::size_t i = 0; i < points.size(); ++i) points_of[static_cast<std::size_t>(tooth_of(points[i]))].push_back(i);
  const double min_arm = 1e-9 * problem.model().pair().pin_circle_radius;
  std::vector<contact::ContactLaw> scratch;
  // A preloaded pair (result->preload set by LoadSolver::SolvePreloaded) is linearised about its
  // preload state: under T > 0 the balance lies at a larger rotation (M is non-decreasing), so the
  // opposing flank's pressed pins (arm < 0) only open, each a PressedPin in every group, and its
  // open pins stay open; the closing flank's pressed pins close "before" the preload state, so the
  // first of them is the first contact and every group holds them all (a pressed non-member is
  // infeasible).
  const bool two_flanks = result->preload.has_value();
  double psi = two_flanks ? result->preload->rotation : 0.0;
  // What the first pin alone may have to carry: T plus the opposing flank's push-back, at most its
  // preload moment (its pins open as psi grows past the preload state).
  const double carried = problem.torque() + (two_flanks ? result->preload->opposing_torque_nmm : 0.0);
  int groups_evaluated = 0;
  BackendDetails details;
  const int outer_limit = problem.kinematics() == contact::ContactKinematics::kExact ? 50 : 1;
  if (problem.has_coupling() && problem.disc_count() > 1) {
    // Two discs' groups are the candidate teeth in closing order (below), the loaded set only
    // without a coupling: each disc's elastic body (the mesh alone with two discs) moves the
    // closing of one tooth by its neighbours' loads, and the loaded set need not be a prefix of
    // that order (docs/fe_disc.md "Two discs"). Refused by name rather than answered from a wrong
    // set or a failure.
    result->status = SolverStatus::kCouplingUnsupported;
    result->message = "solver \"energy-groups\" with two discs takes the tooth groups in closing order, which a "
                      "coupling (each disc's elastic body) does not keep: expected bisection, compatibility or energy-qp "
                      "(docs/fe_disc.md, \"Two discs\")";
    return;
  }
  CoupledContact* coupled = problem.has_coupling() ? &CoupledContactFor(problem, workspace) : nullptr;
  const auto solve_group = [&](const Linearised& lin, const std::vector<std::size_t>& group) {
    return coupled != nullptr ? SolveGroupCoupled(lin, group, teeth, problem.torque(), *problem.coupling(), *coupled)
                              : SolveGroup(lin, group, teeth, problem.torque(), 0.01 * options.torque_tolerance);
  };
  for (int outer = 0; outer < outer_limit; ++outer) {
    const auto pins = problem.At(psi, workspace, &scratch);
    Linearised lin;
    lin.psi0 = psi;
    for (std::size_t i = 0; i < pins.size(); ++i) {
      const auto& p = pins[i];
      const bool usable = p.arm > min_arm && p.law != nullptr;
      lin.approach0.push_back(p.approach);
      lin.pin.push_back(tooth_of(points[i]));
      lin.arm.push_back(usable ? p.arm : 0.0);
      lin.law.push_back(usable ? p.law : nullptr);
      // Under exact kinematics the pin at the far end of the line of centres can be pressed at
      // second order with a tiny negative arm (Liu Table 1, crank 0.018 deg: pin 21 = index 20,
      // arm -0.004 mm, pressed 5e-8 mm); left out, the answer leaves it penetrating. PressedPin.
      if (!usable && p.law != nullptr && p.approach > kGapTolerance) {
        lin.pressed.push_back({i, p.approach, p.arm, p.law});
      }
    }
    // 1. First contact (smallest closing rotation) about the current linearisation.
    int first = -1;
    double first_psi = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i) {
      if (lin.law[static_cast<std::size_t>(i)] == nullptr) continue;
      const double close = psi - lin.approach0[static_cast<std::size_t>(i)] / lin.arm[static_cast<std::size_t>(i)];
      if (close < first_psi) first_psi = close, first = i;
    }
    if (first < 0) {
      result->status = SolverStatus::kNumericalFailure;
      result->message = "no pin can close its gap in the load direction";
      return;
    }
    // 2. Maximum deformation: the first pin alone carries the torque (Li Fig. 5).
    const auto* first_law = lin.law[static_cast<std::size_t>(first)];
    const double first_arm = lin.arm[static_cast<std::size_t>(first)];
    double psi_max = first_psi + first_law->Approach(carried / first_arm) / first_arm;
    // Coupled, more loaded points can turn the cycloid further than one alone: the problem's
    // coupled bound (LoadProblem::LoadedRotationRange) widens the candidates.
    if (coupled != nullptr) psi_max = std::max(psi_max, problem.LoadedRotationRange().single_pin);
    std::vector<bool> candidate(static_cast<std::size_t>(teeth), false);  // per tooth: a slice can close
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (lin.law[k] != nullptr && lin.Approach(k, psi_max) > 0.0) candidate[static_cast<std::size_t>(lin.pin[k])] = true;
    }
    ++details["relinearisations"];
    details["candidates"] = static_cast<int>(std::count(candidate.begin(), candidate.end(), true));
    // 3. Contiguous runs of candidate teeth (cyclic pin order) containing the first one. Two discs
    // load two runs, one per disc: there the groups in closing order below are the groups.
    const int first_tooth = lin.pin[static_cast<std::size_t>(first)];
    int left = 0, right = 0;  // how far the run of candidates extends each way from `first_tooth`
    if (problem.disc_count() == 1) {
      while (left < teeth - 1 && candidate[static_cast<std::size_t>(along(first_tooth, -left - 1))]) ++left;
      while (right < teeth - 1 - left && candidate[static_cast<std::size_t>(along(first_tooth, right + 1))]) ++right;
    }
    const long groups = problem.disc_count() == 1 ? static_cast<long>(left + 1) * (right + 1) : 0;
    if (groups > kMaxGroups) {
      result->status = SolverStatus::kTooManyGroups;
      result->message = fmt::format("{} candidate tooth groups exceed the limit of {}", groups, kMaxGroups);
      result->rotation = psi;
      return;
    }
    // 4-5. Solve every group, keep the feasible one of minimum energy.
    GroupSolution best;
    for (int a = 0; a <= left && groups > 0; ++a) {
      for (int b = 0; b <= right; ++b) {
        std::vector<std::size_t> group;  // the usable points of the teeth first_tooth - a .. first_tooth + b
        for (int j = -a; j <= b; ++j) {
          for (const std::size_t i : points_of[static_cast<std::size_t>(along(first_tooth, j))]) {
            if (lin.law[i] != nullptr) group.push_back(i);
          }
        }
        GroupSolution s = solve_group(lin, group);
        ++groups_evaluated;
        if (s.feasible && s.energy < best.energy) best = std::move(s);
      }
    }
    if (!best.feasible) {
      // Li's groups are contiguous runs of teeth, as the loaded set of a pair without errors is.
      // Pitch or position errors of single pins can load a set with gaps (Liu 2021 section 5.2).
      // Then the groups are the candidate teeth in the order they close (uncoupled and
      // linearised, the loaded set is exactly the teeth closing before the loaded rotation): a
      // departure from Li (docs/solvers.md).
      std::vector<std::pair<double, int>> closing;  // (closing rotation, tooth) of the candidates
      std::vector<double> tooth_closing(static_cast<std::size_t>(teeth), std::numeric_limits<double>::infinity());
      for (int i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (lin.law[k] == nullptr || !candidate[static_cast<std::size_t>(lin.pin[k])]) continue;
        double& c = tooth_closing[static_cast<std::size_t>(lin.pin[k])];
        c = std::min(c, psi - lin.approach0[k] / lin.arm[k]);
      }
      for (int t = 0; t < teeth; ++t) {
        if (std::isfinite(tooth_closing[static_cast<std::size_t>(t)])) closing.emplace_back(tooth_closing[static_cast<std::size_t>(t)], t);
      }
      std::sort(closing.begin(), closing.end());
      std::vector<std::size_t> group;
      for (const auto& [unused, tooth] : closing) {
        for (const std::size_t i : points_of[static_cast<std::size_t>(tooth)]) {
          if (lin.law[i] != nullptr) group.push_back(i);
        }
        GroupSolution s = solve_group(lin, group);
        ++groups_evaluated;
        if (s.feasible && s.energy < best.energy) best = std::move(s);
      }
      details["closing_order_groups"] = 1;
    }
    if (!best.feasible) {
      result->status = SolverStatus::kNumericalFailure;
      result->message = fmt::format("none of the {} contiguous tooth groups nor the groups in closing order is feasible",
                                    groups);
      result->rotation = psi;
      result->iterations = groups_evaluated;
      return;
    }
    const double change = best.psi - psi;
    psi = best.psi;
    result->force = best.force;
    result->status = SolverStatus::kSuccess;
    if (std::abs(change) <= options.torque_tolerance * std::max(std::abs(psi), 1e-12)) break;
  }
  result->rotation = psi;
  result->iterations = groups_evaluated;
  details["groups_evaluated"] = groups_evaluated;
  result->details = details;
  result->message = fmt::format("{} tooth groups evaluated (Li eq. 14)", groups_evaluated);
  for (const auto& pin : problem.At(psi, workspace, &scratch)) {
    if (pin.law == nullptr && pin.approach > 0.0) {
      result->status = SolverStatus::kEdgeContact;
      result->message = "a loaded pin sits on a tip corner (edge contact); line-contact laws do not apply";
    }
  }
}

}  // namespace ltca::solvers
