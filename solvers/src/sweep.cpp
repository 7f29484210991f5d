#include "ltca/solvers/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace ltca::solvers {
namespace {

int Severity(SolverStatus s) { return s == SolverStatus::kSuccess ? 0 : (s == SolverStatus::kNotSolved ? -1 : 1); }

}  // namespace

SweepResult SolveSweep(const Deck& deck, const SolverOptions& options) {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  const contact::MeshModel model = deck.MakeModel();
  const auto solver = MakeSolver(options.name);
  SweepResult sweep;
  sweep.solver = options.name;
  sweep.options = options;
  double te_sum = 0.0, te_lo = INFINITY, te_hi = -INFINITY;
  sweep.summary.contacts_min = model.pin_count() + 1;
  sweep.summary.status = SolverStatus::kSuccess;
  for (const double crank : deck.sweep.CrankAngles()) {
    const LoadProblem problem(model, crank, deck.contact, deck.RequireMaterial(), deck.RequireLoad().torque,
                              options.kinematics);
    PositionResult pos;
    pos.crank = crank;
    pos.result = solver->Solve(problem, options);
    std::vector<contact::ContactLaw> scratch;
    const auto pins = problem.At(std::isfinite(pos.result.rotation) ? pos.result.rotation : 0.0, &scratch);
    const double f_max = *std::max_element(pos.result.force.begin(), pos.result.force.end());
    pos.angle.resize(pins.size());
    pos.contact_stress.assign(pins.size(), 0.0);
    for (std::size_t i = 0; i < pins.size(); ++i) {
      pos.angle[i] = problem.base_state().pins[i].angle;
      const double f = pos.result.force[i];
      if (f > kContactForceFraction * f_max && f_max > 0.0) ++pos.contacts;
      if (f > 0.0 && pins[i].law != nullptr) pos.contact_stress[i] = pins[i].law->MaxPressure(f);
      sweep.summary.max_pin_force = std::max(sweep.summary.max_pin_force, f);
      sweep.summary.max_contact_stress = std::max(sweep.summary.max_contact_stress, pos.contact_stress[i]);
    }
    te_sum += pos.result.te;
    te_lo = std::min(te_lo, pos.result.te);
    te_hi = std::max(te_hi, pos.result.te);
    sweep.summary.contacts_min = std::min(sweep.summary.contacts_min, pos.contacts);
    sweep.summary.contacts_max = std::max(sweep.summary.contacts_max, pos.contacts);
    if (Severity(pos.result.status) > Severity(sweep.summary.status)) sweep.summary.status = pos.result.status;
    sweep.positions.push_back(std::move(pos));
  }
  const double n = static_cast<double>(sweep.positions.size());
  sweep.summary.mean_te = te_sum / n;
  sweep.summary.pp_te = te_hi - te_lo;
  sweep.summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return sweep;
}

}  // namespace ltca::solvers
