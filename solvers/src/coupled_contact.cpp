#include "coupled_contact.hpp"

#include "active_set_dense.hpp"
#include "beam_woodbury.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <fmt/format.h>

namespace ltca::solvers {
namespace {

constexpr int kMaxIterations = 200;
constexpr int kSemismoothIterations = 40;  // then the monotone primal active-set method
constexpr double kStepTolerance = 1e-12;   // of the largest force
constexpr double kRefresh = 1e-2;          // relative change of a tangent compliance that refactorises
constexpr double kEps = std::numeric_limits<double>::epsilon();

struct BackendCoupled final : Workspace::BackendState {
  std::unique_ptr<CoupledContact> solver;
};

}  // namespace

std::vector<CoupledPoint> CoupledPoints(const std::vector<LoadProblem::PinAt>& pins) {
  std::vector<CoupledPoint> out;
  CoupledPoints(pins, &out);
  return out;
}

void CoupledPoints(const std::vector<LoadProblem::PinAt>& pins, std::vector<CoupledPoint>* points) {
  std::vector<CoupledPoint>& out = *points;
  out.resize(pins.size());
  for (std::size_t i = 0; i < pins.size(); ++i) out[i] = {pins[i].edge ? nullptr : pins[i].law, pins[i].approach, pins[i].arm};
}

void AddKernelDetails(const ActiveSetCholmod::Stats& before, const ActiveSetCholmod::Stats& now, BackendDetails* details) {
  (*details)["factorisations"] = now.factorisations - before.factorisations;
  (*details)["rowadds"] = now.rowadds - before.rowadds;
  (*details)["rowdels"] = now.rowdels - before.rowdels;
  (*details)["solves"] = now.solves - before.solves;
}

double CoupledForceScale(const LoadProblem& problem) {
  double arms = 0.0;
  for (const auto& p : problem.base_state().pins) arms += std::max(p.arm, 0.0);
  return arms > 0.0 && problem.torque() > 0.0 ? problem.torque() / arms : 1.0;
}

CoupledContact& CoupledContactFor(const LoadProblem& problem, Workspace& workspace) {
  auto* state = static_cast<BackendCoupled*>(workspace.Backend("coupled-contact"));
  if (state == nullptr) {
    state = static_cast<BackendCoupled*>(workspace.SetBackend("coupled-contact", std::make_unique<BackendCoupled>()));
  }
  // An elastic disc body on a stage's output pins: the coupled set holds them too (its matrix only).
  const LoadProblem::StageBodyCoupling* body = problem.stage_body_coupling();
  const Eigen::SparseMatrix<double>& coupling = body != nullptr ? *body->total : *problem.coupling();
  static const std::shared_ptr<const LoadProblem::CouplingFactors> kNone;
  const std::shared_ptr<const LoadProblem::CouplingFactors>& factors = body != nullptr ? kNone : problem.coupling_factors();
  const Eigen::MatrixXd* dense = body != nullptr ? nullptr : problem.coupling_dense();
  if (state->solver == nullptr ||
      (!state->solver->Matches(coupling, factors) && !state->solver->Reload(coupling, factors, dense))) {
    state->solver = std::make_unique<CoupledContact>(coupling, factors, dense);
  }
  return *state->solver;
}

CoupledContact::CoupledContact(const Eigen::SparseMatrix<double>& coupling,
                               std::shared_ptr<const LoadProblem::CouplingFactors> factors, const Eigen::MatrixXd* dense) {
  if (factors != nullptr) {
    auto beam = std::make_unique<BeamWoodbury>(std::move(factors));
    beam_kernel_ = beam.get();
    kernel_ = std::move(beam);
  } else if (ActiveSetDense::Suits(coupling)) {
    auto kernel = std::make_unique<ActiveSetDense>(coupling, dense);
    dense_kernel_ = kernel.get();
    kernel_ = std::move(kernel);
  } else {
    auto matrix = std::make_unique<ActiveSetCholmod>(coupling);
    matrix_kernel_ = matrix.get();
    kernel_ = std::move(matrix);
  }
}

CoupledContact::~CoupledContact() = default;

bool CoupledContact::Matches(const Eigen::SparseMatrix<double>& coupling,
                             const std::shared_ptr<const LoadProblem::CouplingFactors>& factors) const {
  if (factors != nullptr) return beam_kernel_ != nullptr && beam_kernel_->Matches(factors);
  if (dense_kernel_ != nullptr) return dense_kernel_->Matches(coupling);
  return matrix_kernel_ != nullptr && matrix_kernel_->Matches(coupling);
}

bool CoupledContact::Reload(const Eigen::SparseMatrix<double>& coupling,
                            const std::shared_ptr<const LoadProblem::CouplingFactors>& factors, const Eigen::MatrixXd* dense) {
  if (factors != nullptr || dense_kernel_ == nullptr || !ActiveSetDense::Suits(coupling) ||
      coupling.rows() != dense_kernel_->size()) {
    return false;
  }
  dense_kernel_->Load(coupling, dense);
  return true;
}

CoupledOutcome CoupledContact::AtRotation(const std::vector<CoupledPoint>& points, double force_scale,
                                          std::vector<double>* force) {
  return Solve(points, false, 0.0, force_scale, force);
}

CoupledOutcome CoupledContact::ForTorque(const std::vector<CoupledPoint>& points, double torque,
                                         std::vector<double>* force) {
  double arms = 0.0;
  for (const auto& p : points) arms += std::max(p.arm, 0.0);
  return Solve(points, true, torque, arms > 0.0 ? torque / arms : 1.0, force);
}

double CoupledContact::TorqueSlope(const std::vector<CoupledPoint>& points) {
  ActiveSetKernel& kernel = *kernel_;
  const int n = kernel.size();
  if (static_cast<int>(points.size()) != n) return 0.0;
  const std::vector<char>& active = kernel.active_set();
  Eigen::MatrixXd& rhs = buffers_.rhs;
  Eigen::MatrixXd& sol = buffers_.sol;
  rhs.setZero(n, 1);
  bool any = false;
  for (int i = 0; i < n; ++i) {
    if (!active[static_cast<std::size_t>(i)]) continue;
    rhs(i, 0) = points[static_cast<std::size_t>(i)].arm;
    any = true;
  }
  if (!any || !kernel.Solve(rhs, &sol)) return 0.0;
  double slope = 0.0;
  for (int i = 0; i < n; ++i) {
    if (active[static_cast<std::size_t>(i)]) slope += rhs(i, 0) * sol(i, 0);
  }
  return std::isfinite(slope) ? slope : 0.0;
}

CoupledOutcome CoupledContact::Solve(const std::vector<CoupledPoint>& points, bool for_torque, double torque,
                                     double force_scale, std::vector<double>* force) {
  ActiveSetKernel& kernel = *kernel_;
  const int n = kernel.size();
  CoupledOutcome out;
  if (static_cast<int>(points.size()) != n) {
    out.failure = fmt::format("{} contact points for a coupling of {}", points.size(), n);
    return out;
  }
  std::vector<double>& f = *force;
  f.resize(points.size(), 0.0);
  const auto u = [](int i) { return static_cast<std::size_t>(i); };
  std::vector<char>& free = buffers_.free;
  free.assign(points.size(), 0);
  for (int i = 0; i < n; ++i) {
    if (points[u(i)].law == nullptr || !(f[u(i)] > 0.0) || !std::isfinite(f[u(i)])) f[u(i)] = 0.0;
    free[u(i)] = f[u(i)] > 0.0;
  }
  // Secant compliance of an entering point (F = 0): w(f) / f at the force scale.
  const auto secant = [&](const contact::ContactLaw& law) {
    const double fs = std::min(force_scale, 0.5 * law.max_force());
    return law.Approach(fs) / fs;
  };
  // For a given torque the start carries it: scaled, or (cold) the uncoupled answer of the secant
  // stiffnesses, sum k_i L_i max(0, a_i + L_i psi) = T (increasing in psi; bisection on psi).
  const auto carry_torque = [&]() -> bool {
    double t = 0.0;
    for (int i = 0; i < n; ++i) t += f[u(i)] * points[u(i)].arm;
    if (t > 0.0) {
      for (double& x : f) x *= torque / t;
      return true;
    }
    std::vector<double> k(points.size(), 0.0);
    double lo = INFINITY;
    for (int i = 0; i < n; ++i) {
      const CoupledPoint& p = points[u(i)];
      if (p.law == nullptr || !(p.arm > 0.0)) continue;
      k[u(i)] = 1.0 / secant(*p.law);
      lo = std::min(lo, -p.approach / p.arm);
    }
    if (!std::isfinite(lo)) return false;
    const auto carried = [&](double at) {
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += k[u(i)] * points[u(i)].arm * std::max(0.0, points[u(i)].approach + points[u(i)].arm * at);
      return sum;
    };
    double width = 1e-9, hi = lo + width;
    for (int grow = 0; grow < 200 && carried(hi) < torque; ++grow) width *= 2.0, hi = lo + width;
    for (int halve = 0; halve < 100; ++halve) {
      const double mid = 0.5 * (lo + hi);
      (carried(mid) < torque ? lo : hi) = mid;
    }
    for (int i = 0; i < n; ++i) {
      f[u(i)] = k[u(i)] * std::max(0.0, points[u(i)].approach + points[u(i)].arm * hi);
      free[u(i)] = f[u(i)] > 0.0;
    }
    t = 0.0;
    for (int i = 0; i < n; ++i) t += f[u(i)] * points[u(i)].arm;
    if (!(t > 0.0)) return false;
    for (double& x : f) x *= torque / t;
    return true;
  };
  if (for_torque && !carry_torque()) {
    out.failure = "no contact point with a law and a positive arm can carry the torque";
    return out;
  }
  const Eigen::Map<Eigen::VectorXd> fv(f.data(), n);
  Eigen::VectorXd& fcopy = buffers_.f;  // f as the kernels take it
  Eigen::VectorXd& cf = buffers_.cf;
  Eigen::VectorXd& d = buffers_.d;
  Eigen::VectorXd& df = buffers_.df;
  Eigen::MatrixXd& rhs = buffers_.rhs;
  Eigen::MatrixXd& sol = buffers_.sol;
  cf.resize(n);
  d.setZero(n);
  df.resize(n);
  rhs.setZero(n, for_torque ? 2 : 1);
  const bool newton = kernel.refactorisation_is_cheap();
  double psi = 0.0, last_step = INFINITY, previous_step = INFINITY, mismatch = 0.0;
  bool settled = false, monotone = false, last_full = false;
  int saturated = -1;  // a point held below its law's largest force in the last step
  for (int it = 0; it < kMaxIterations; ++it) {
    out.iterations = it + 1;
    // C F (the matrix kernel: over the loaded columns only).
    fcopy = fv;
    kernel.Apply(fcopy, &cf);
    // The largest force (every f_i is finite and >= 0 here), reduced in registers: a running
    // maximum kept in f_max's own memory (the lambdas below capture it) cost a store-to-load
    // chain through 40 points every step.
    const double f_max = n > 0 ? std::max(0.0, fv.maxCoeff()) : 0.0;
    // The points held at zero: the gap with the last full step's psi; violators enter.
    int worst = -1;
    double worst_gap = 0.0;
    bool entered = false;
    // At a given rotation the gaps of the start are known: its points may enter at once.
    if ((it > 0 && last_full) || (it == 0 && !for_torque)) {
      for (int i = 0; i < n; ++i) {
        const CoupledPoint& p = points[u(i)];
        if (free[u(i)] || p.law == nullptr) continue;
        const double gap = cf(i) - p.approach - psi * p.arm;
        const double tol = 64.0 * kEps * (std::abs(cf(i)) + std::abs(p.approach) + std::abs(psi * p.arm));
        if (!(gap < -tol)) continue;
        if (!monotone) {
          free[u(i)] = 1;
          entered = true;
        } else if (gap < worst_gap) {
          worst_gap = gap, worst = i;
        }
      }
      if (monotone && worst >= 0 && last_step <= 1e-6 * f_max) {
        free[u(worst)] = 1;  // one at a time, once the free set is nearly solved
        entered = true;
      }
      // Converged when the error left after the last step, estimated from the chord's compliance
      // mismatch (linear) and the law's curvature (quadratic, F |w''| / w' < 1 below the largest
      // force), is below the tolerance.
      const double left = mismatch * last_step + last_step * last_step / std::max(f_max, 1e-300);
      if (!entered && settled && left <= kStepTolerance * std::max(f_max, 1e-300)) {
        out.converged = true;
        break;
      }
    }
    // Tangent compliances and residuals on the free set.
    bool refresh = false;
    double pending = 0.0;  // largest relative mismatch of a factorised compliance
    const std::vector<char>& in_factor = kernel.active_set();
    for (int i = 0; i < n; ++i) {
      if (!free[u(i)]) {
        rhs.row(i).setZero();
        continue;
      }
      const contact::ContactLaw& law = *points[u(i)].law;
      double w = 0.0;
      if (f[u(i)] > 0.0) {
        w = law.Approach(f[u(i)], &d(i));
      } else {
        d(i) = secant(law);
      }
      if (in_factor[u(i)]) pending = std::max(pending, std::abs(d(i) - kernel.diagonal(i)) / kernel.diagonal(i));
      rhs(i, 0) = w + cf(i) - points[u(i)].approach;
      if (for_torque) rhs(i, 1) = points[u(i)].arm;
    }
    // A chord step that contracted poorly: refactorise with the current tangents.
    if (pending > kRefresh || (previous_step < INFINITY && last_step > 0.05 * previous_step)) refresh = true;
    if (newton && pending > 0.0) refresh = true;  // a Newton step: the factor holds the current tangents
    if (refresh) kernel.SetDiagonal(d);
    bool any_free = false;
    for (int i = 0; i < n; ++i) {
      if (free[u(i)] == in_factor[u(i)]) {
        any_free = any_free || free[u(i)];
        continue;
      }
      if (free[u(i)]) {
        kernel.Add(i, d(i));
        any_free = true;
      } else {
        kernel.Remove(i);
      }
    }
    if (!any_free) {  // nothing can carry load: every force is zero (at a rotation)
      if (for_torque) {
        out.failure = "no contact point is left to carry the torque";
        return out;
      }
      std::fill(f.begin(), f.end(), 0.0);
      last_step = 0.0, last_full = true, settled = true;
      continue;
    }
    if (!kernel.Solve(rhs, &sol)) {
      out.failure = "the factorisation of D + C on the active set failed";
      return out;
    }
    df = -sol.col(0);
    double psi_new = psi;
    if (for_torque) {
      double lx = 0.0, ly = 0.0, t = 0.0;
      for (int i = 0; i < n; ++i) {
        t += f[u(i)] * points[u(i)].arm;
        if (!free[u(i)]) continue;
        lx += points[u(i)].arm * sol(i, 1);
        ly += points[u(i)].arm * sol(i, 0);
      }
      if (!(lx > 0.0)) {
        out.failure = "the loaded points cannot take up a rotation (no positive arm)";
        return out;
      }
      psi_new = (torque - t + ly) / lx;  // [M, -L; L^T, 0] [dF; psi] = [-g; T - L^T F]
      df += psi_new * sol.col(1);
    }
    // Step length: full (semismooth Newton), or ratio test and Armijo (monotone).
    double alpha = 1.0;
    int blocking = -1;
    if (monotone) {
      for (int i = 0; i < n; ++i) {
        if (free[u(i)] && df(i) < 0.0 && -f[u(i)] / df(i) < alpha) alpha = -f[u(i)] / df(i), blocking = i;
      }
      const auto energy = [&](double a) {
        Eigen::VectorXd trial = fv;
        for (int i = 0; i < n; ++i) if (free[u(i)]) trial(i) = std::max(0.0, f[u(i)] + a * df(i));
        Eigen::VectorXd ct;
        kernel.Apply(trial, &ct);
        double e = 0.5 * trial.dot(ct);
        for (int i = 0; i < n; ++i) {
          if (trial(i) > 0.0) e += points[u(i)].law->ComplementaryEnergy(trial(i)) - points[u(i)].approach * trial(i);
        }
        return e;
      };
      double slope = 0.0;
      for (int i = 0; i < n; ++i) if (free[u(i)]) slope += rhs(i, 0) * df(i);
      if (alpha * df.cwiseAbs().maxCoeff() > 1e-6 * std::max(f_max, 1e-300) && slope < 0.0) {
        const double e0 = energy(0.0);
        for (int k = 0; k < 30 && energy(alpha) > e0 + 1e-4 * alpha * slope; ++k) alpha *= 0.5, blocking = -1;
      }
    }
    double step = 0.0;
    bool clipped = false;
    for (int i = 0; i < n; ++i) {
      if (!free[u(i)]) continue;
      f[u(i)] += alpha * df(i);
      step = std::max(step, std::abs(alpha * df(i)));
      if (i == blocking || f[u(i)] <= 0.0) {
        if (monotone && i != blocking && f[u(i)] > -1e-9 * std::max(f_max, 1e-300)) {
          f[u(i)] = 0.0;  // rounding at the boundary the ratio test stopped at
          continue;
        }
        f[u(i)] = 0.0;
        free[u(i)] = 0;
        clipped = true;
      }
    }
    // A force beyond the law's range (an overshooting step, or a load the law cannot carry):
    // held just below it; reported when the iteration does not settle.
    saturated = -1;
    for (int i = 0; i < n; ++i) {
      if (free[u(i)] && f[u(i)] >= points[u(i)].law->max_force()) {
        f[u(i)] = (1.0 - 1e-6) * points[u(i)].law->max_force();
        saturated = i;
      }
    }
    last_full = alpha == 1.0;
    if (last_full) psi = psi_new;
    previous_step = refresh ? INFINITY : last_step;
    last_step = step;
    mismatch = refresh ? 0.0 : pending;
    settled = !clipped && !entered && saturated < 0;
    if (!monotone && it + 1 == kSemismoothIterations) {
      // Not settled: continue monotone from a feasible point.
      monotone = true;
      previous_step = last_step = INFINITY;
      if (for_torque && !carry_torque()) {
        out.failure = "no contact point with a law and a positive arm can carry the torque";
        return out;
      }
    }
  }
  out.rotation = psi;
  out.torque = 0.0;
  for (int i = 0; i < n; ++i) {
    out.torque += f[u(i)] * points[u(i)].arm;
    const CoupledPoint& p = points[u(i)];
    if (p.law == nullptr) {
      const double gap = cf(i) - p.approach - psi * p.arm;
      if (gap < -64.0 * kEps * (std::abs(cf(i)) + std::abs(p.approach) + std::abs(psi * p.arm))) out.edge = true;
    }
  }
  if (!out.converged && saturated >= 0) {
    out.saturated = true;
    out.failure = fmt::format("point {} needs more force than its contact law can carry", saturated + 1);
  } else if (!out.converged) {
    out.failure = fmt::format("the active set did not settle in {} Newton steps", kMaxIterations);
  }
  return out;
}

}  // namespace ltca::solvers
