#include "two_flanks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "coupled_contact.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::solvers {
namespace {

struct Moment {
  double torque = 0.0;  // sum F_i L_i, N*mm
  double flank = 0.0;   // half of sum F_i |L_i|, N*mm
  bool edge = false, saturated = false;
  std::string failure;  // coupled: the complementarity problem did not converge
};

}  // namespace

void SolveTwoFlanks(const LoadProblem& problem, double torque, const SolverOptions& options, Workspace& workspace,
                    LoadResult* result) {
  std::vector<LoadProblem::PinAt> pins;
  std::vector<contact::ContactLaw> scratch;
  std::vector<CoupledPoint> points;
  Loading loading;
  CoupledContact* coupled = problem.has_coupling() ? &CoupledContactFor(problem, workspace) : nullptr;
  // A typical point force for the coupled problem's tolerances: the torque's, or at zero torque
  // a newton (the coupled solve scales its own tolerance with it).
  const double force_scale = coupled != nullptr ? std::max(CoupledForceScale(problem), 1.0) : 0.0;
  std::vector<double> forces(static_cast<std::size_t>(problem.point_count()), 0.0);
  int evaluations = 0;
  const auto moment = [&](double psi, std::vector<double>* f) {
    ++evaluations;
    problem.At(psi, workspace, &scratch, &pins);
    Moment m;
    if (coupled == nullptr) {
      LoadAt(pins, nullptr, &loading);
      *f = loading.force;
      m.torque = loading.torque, m.edge = loading.edge, m.saturated = loading.saturated;
    } else {
      CoupledPoints(pins, &points);
      const CoupledOutcome o = coupled->AtRotation(points, force_scale, f);
      m.torque = o.torque, m.edge = o.edge, m.saturated = o.saturated;
      if (!o.converged && !o.saturated) m.failure = o.failure;
    }
    for (std::size_t i = 0; i < pins.size() && i < f->size(); ++i) m.flank += 0.5 * (*f)[i] * std::abs(pins[i].arm);
    return m;
  };
  const auto balanced = [&](double psi, const Moment& m, const std::vector<double>& f) {
    const double miss = std::abs(m.torque - torque);
    const double allowed = torque > 0.0 ? options.torque_tolerance * std::max(torque, m.flank)
                                        : std::min(options.torque_tolerance * m.flank, 1e-7);
    if (miss <= allowed) return true;
    return coupled == nullptr && miss <= problem.TorqueResolution(psi, pins, &f);
  };
  const auto finish = [&](SolverStatus status, std::string message, double psi, const std::vector<double>& f) {
    result->status = status;
    result->message = std::move(message);
    result->rotation = psi;
    result->force = f;
    result->torque_evaluations = evaluations;
    result->iterations = evaluations;
    result->details["two_flanks"] = 1.0;
  };
  const double window = contact::RotationWindow(problem.model());
  double lo = 0.0, hi = 0.0;
  std::vector<double> f_lo_forces, f_hi_forces;
  Moment at0 = moment(0.0, &forces);
  if (!at0.failure.empty()) return finish(SolverStatus::kNumericalFailure, "coupled contact: " + at0.failure, 0.0, forces);
  if (balanced(0.0, at0, forces) && !at0.edge) {
    return finish(SolverStatus::kSuccess, fmt::format("two flanks: torque balanced at the theoretical position"), 0.0,
                  forces);
  }
  double g_lo = at0.torque - torque, g_hi = g_lo;
  Moment m_lo = at0, m_hi = at0;
  // Bracket: from psi = 0 in doubling steps (Liu's first step, 1/60 arcsec) toward the root.
  const double sign = g_lo < 0.0 ? 1.0 : -1.0;
  double step = units::ArcsecToRad(1.0 / 60.0);
  bool bracketed = false;
  std::vector<double> trial(forces.size(), 0.0);
  double last = 0.0;
  Moment m_last = at0;
  std::vector<double> last_forces = forces;
  for (int k = 0; k < 200 && evaluations < options.max_iterations; ++k, step *= 2.0) {
    const double x = std::clamp(sign * step, -window, window);
    if (coupled != nullptr) trial = last_forces;
    const Moment m = moment(x, &trial);
    if (!m.failure.empty()) return finish(SolverStatus::kNumericalFailure, "coupled contact: " + m.failure, x, trial);
    const double g = m.torque - torque;
    if ((sign > 0.0 && g >= 0.0) || (sign < 0.0 && g <= 0.0)) {
      if (sign > 0.0) lo = last, g_lo = m_last.torque - torque, m_lo = m_last, hi = x, g_hi = g, m_hi = m;
      else hi = last, g_hi = m_last.torque - torque, m_hi = m_last, lo = x, g_lo = g, m_lo = m;
      if (sign > 0.0) f_lo_forces = last_forces, f_hi_forces = trial;
      else f_hi_forces = last_forces, f_lo_forces = trial;
      bracketed = true;
      break;
    }
    last = x, m_last = m, last_forces = trial;
    if (std::abs(x) >= window) break;
  }
  if (!bracketed) {
    const bool cannot = m_last.saturated;
    return finish(cannot ? SolverStatus::kLawCannotCarry : SolverStatus::kMaxIterations,
                  cannot ? fmt::format("two flanks: a pin reached the largest force its contact law can carry at {:.6g} "
                                       "N*m of {:.6g}", units::NmmToNm(m_last.torque), units::NmmToNm(torque))
                         : fmt::format("two flanks: no rotation within a quarter tooth pitch ({:.6g} deg) balances "
                                       "{:.6g} N*m (at the end {:.6g} N*m)", units::RadToDeg(window),
                                       units::NmmToNm(torque), units::NmmToNm(m_last.torque)),
                  last, last_forces);
  }
  // Illinois' regula falsi on [lo, hi], g(lo) < 0 <= g(hi) (or the reverse at the bracket's end).
  double x = g_hi == 0.0 ? hi : lo;
  Moment mx = g_hi == 0.0 ? m_hi : m_lo;
  std::vector<double> fx = g_hi == 0.0 ? f_hi_forces : f_lo_forces;
  if (std::abs(g_hi) <= std::abs(g_lo)) x = hi, mx = m_hi, fx = f_hi_forces;
  int side = 0;
  bool converged = false;
  // The bracket's ends were evaluated last at psi = hi or lo; re-evaluated once for the judge's pins.
  trial = fx;
  mx = moment(x, &trial);
  fx = trial;
  while (evaluations < options.max_iterations) {
    if (!mx.failure.empty()) return finish(SolverStatus::kNumericalFailure, "coupled contact: " + mx.failure, x, fx);
    if (balanced(x, mx, fx)) {
      converged = true;
      break;
    }
    if (!(hi - lo > 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(hi), std::abs(lo)))) break;
    double next = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    trial = fx;
    const Moment m = moment(next, &trial);
    const double g = m.torque - torque;
    if (g > 0.0) {
      hi = next, g_hi = g;
      if (side == 1) g_lo *= 0.5;  // Illinois: halve the end that stays
      side = 1;
    } else {
      lo = next, g_lo = g;
      if (side == -1) g_hi *= 0.5;
      side = -1;
    }
    x = next, mx = m, fx = trial;
  }
  const double miss = std::abs(mx.torque - torque);
  if (mx.edge) {
    return finish(SolverStatus::kEdgeContact, "two flanks: a tip corner is pressed at the balance (edge contact; "
                                               "line-contact laws do not apply)", x, fx);
  }
  if (mx.saturated) {
    return finish(SolverStatus::kLawCannotCarry,
                  "two flanks: a pin is beyond the largest force its contact law can carry at the balance", x, fx);
  }
  if (!converged) {
    return finish(SolverStatus::kMaxIterations,
                  fmt::format("two flanks: the torque did not balance after {} evaluations: off by {:.3g} N*mm",
                              evaluations, miss), x, fx);
  }
  finish(SolverStatus::kSuccess,
         fmt::format("two flanks: torque balanced to {:.3g} N*mm after {} evaluations", miss, evaluations), x, fx);
}

}  // namespace ltca::solvers
