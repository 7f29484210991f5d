#include "ltca/analysis/friction.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::analysis {
namespace {

/// The torque balance with friction converges when the ratio moves by less than this.
constexpr double kBalanceTolerance = 1e-10;
constexpr int kMaxBalanceSolves = 20;
constexpr int kMaxStageBalanceSolves = 40;
/// The step of the stage's motion along a branch of the loop, relative to the torque.
constexpr double kMotionStep = 1e-4;

}  // namespace

const char* ToString(FrictionSettings::Model model) {
  return model == FrictionSettings::Model::kCoulomb ? "coulomb" : "jiang-mixed";
}

void OperationSettings::Validate() const {
  const double rpm = units::RadPerSToRpm(input_speed);
  if (!(std::isfinite(rpm) && rpm > 0.0 && rpm <= kMaxSpeedRpm)) {
    throw std::invalid_argument(fmt::format(
        "[operation] input_speed_rpm = {:g}: expected a crank speed above 0 and at most {:g} rpm", rpm, kMaxSpeedRpm));
  }
  if (!(std::isfinite(viscosity) && viscosity > 0.0 && viscosity <= 10e-6)) {
    throw std::invalid_argument(fmt::format(
        "[operation] oil_viscosity_pa_s = {}: expected a dynamic viscosity above 0 and at most 10 Pa*s (gear oils: "
        "0.01 to 1 Pa*s)",
        units::MPaSToPaS(viscosity)));
  }
  if (!(std::isfinite(pressure_viscosity) && pressure_viscosity >= 0.0 && pressure_viscosity <= 0.1)) {
    throw std::invalid_argument(fmt::format(
        "[operation] pressure_viscosity_per_gpa = {}: expected 0 to 100 1/GPa (mineral oils: 10 to 30)",
        units::PerMPaToPerGPa(pressure_viscosity)));
  }
  if (kinematic_viscosity && !(std::isfinite(*kinematic_viscosity) && *kinematic_viscosity > 0.0 && *kinematic_viscosity <= 1e4)) {
    throw std::invalid_argument(fmt::format(
        "[operation] oil_kinematic_viscosity_mm2_per_s = {}: expected a kinematic viscosity above 0 and at most 10000 mm^2/s "
        "(gear oils at their operating temperature: about 10 to 1000)",
        *kinematic_viscosity));
  }
  for (const auto& [key, value] : {std::pair{"roughness_ra_cycloid_um", roughness_cycloid},
                                   std::pair{"roughness_ra_pin_um", roughness_pin}}) {
    if (!(std::isfinite(value) && value >= 0.0 && value <= 0.01)) {
      throw std::invalid_argument(fmt::format(
          "[operation] {} = {}: expected a roughness Ra from 0 to 10 um (ground flanks: 0.2 to 0.8 um)", key,
          units::MmToUm(value)));
    }
  }
  if (roughness_cycloid == 0.0 && roughness_pin == 0.0) {
    throw std::invalid_argument(
        "[operation] roughness_ra_cycloid_um = roughness_ra_pin_um = 0: expected a rough surface on at least one body "
        "(the film ratio lambda = h / sigma needs sigma > 0)");
  }
}

void FrictionSettings::Validate(const geometry::PairParameters& pair) const {
  const auto check_mu = [](const char* key, double mu) {
    if (!(std::isfinite(mu) && mu >= 0.0 && mu <= 1.0)) {
      throw std::invalid_argument(fmt::format(
          "[friction] {} = {}: expected a friction coefficient from 0 to 1 (lubricated steel: 0.01 to 0.1)", key, mu));
    }
  };
  if (model == Model::kCoulomb || std::isfinite(coefficient)) check_mu("coefficient", coefficient);
  check_mu("boundary_coefficient", boundary_coefficient);
  if (!std::isnan(sleeve_coefficient)) check_mu("sleeve_coefficient", sleeve_coefficient);
  check_mu("output_pin_coefficient", output_pin_coefficient);
  check_mu("bearing_coefficient", bearing_coefficient);
  if (!(std::isfinite(bearing_viscous_factor) && bearing_viscous_factor >= 0.0 && bearing_viscous_factor <= 100.0)) {
    throw std::invalid_argument(fmt::format(
        "[friction] bearing_viscous_factor = {}: expected Palmgren's f_0 from 0 to 100 (needle and cylindrical roller "
        "bearings: about 2 to 12)",
        bearing_viscous_factor));
  }
  if (!std::isnan(bearing_diameter) && !(std::isfinite(bearing_diameter) && bearing_diameter > 0.0 && bearing_diameter <= 1e4)) {
    throw std::invalid_argument(fmt::format(
        "[friction] bearing_diameter_mm = {}: expected the bearing's diameter d of M = mu F d / 2 above 0 and at most "
        "10000 mm",
        bearing_diameter));
  }
  if (!(std::isfinite(limiting_shear_modulus) && limiting_shear_modulus > 0.0 && limiting_shear_modulus <= 1e4)) {
    throw std::invalid_argument(fmt::format(
        "[friction] limiting_shear_modulus_mpa = {}: expected above 0 and at most 10000 MPa (Jiang: 1 MPa)",
        limiting_shear_modulus));
  }
  if (!(std::isfinite(power_law_exponent) && power_law_exponent > 0.0 && power_law_exponent <= 1.0)) {
    throw std::invalid_argument(fmt::format(
        "[friction] power_law_exponent = {}: expected in (0, 1] (1: Newtonian; Jiang: 0.5)", power_law_exponent));
  }
  if (!std::isnan(limiting_shear_coefficient) &&
      !(std::isfinite(limiting_shear_coefficient) && limiting_shear_coefficient > 0.0 && limiting_shear_coefficient <= 1.0)) {
    throw std::invalid_argument(fmt::format(
        "[friction] limiting_shear_stress_coefficient = {}: expected gamma of tau_L = tau_L0 + gamma p above 0 and at "
        "most 1 (mineral oils: 0.03 to 0.1, Bair and Winer 1979)",
        limiting_shear_coefficient));
  }
  if (!(std::isfinite(limiting_shear_stress) && limiting_shear_stress >= 0.0 && limiting_shear_stress <= 1e3)) {
    throw std::invalid_argument(fmt::format(
        "[friction] limiting_shear_stress_mpa = {}: expected tau_L0 of tau_L = tau_L0 + gamma p from 0 to 1000 MPa",
        limiting_shear_stress));
  }
  if (limiting_shear_stress != 0.0 && std::isnan(limiting_shear_coefficient)) {
    throw std::invalid_argument(fmt::format(
        "[friction] limiting_shear_stress_mpa = {}: expected limiting_shear_stress_coefficient too (the limiting shear "
        "stress tau_L = tau_L0 + gamma p needs its pressure coefficient gamma)",
        limiting_shear_stress));
  }
  if (sleeve_bore_radius && !(std::isfinite(*sleeve_bore_radius) && *sleeve_bore_radius > 0.0 &&
                              *sleeve_bore_radius < pair.pin_radius)) {
    throw std::invalid_argument(fmt::format(
        "[friction] sleeve_bore_radius_mm = {}: expected a radius above 0 and below the sleeve's outer radius, [pair] "
        "pin_radius_mm = {}",
        *sleeve_bore_radius, pair.pin_radius));
  }
}

double BearingFrictionDiameter(const FrictionSettings& friction, double pitch) {
  if (!(friction.bearing_coefficient > 0.0 || friction.bearing_viscous_factor > 0.0)) return 0.0;
  const double d = std::isfinite(friction.bearing_diameter) ? friction.bearing_diameter : pitch;
  if (!(d > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "[friction] bearing_coefficient = {:g}, bearing_viscous_factor = {:g}: expected bearing_diameter_mm (d of the "
        "bearing's friction moment M = mu F d / 2 + M_0(d)) or [bearing] pitch_diameter_mm",
        friction.bearing_coefficient, friction.bearing_viscous_factor));
  }
  return d;
}

double PalmgrenViscousMoment(double f0, double nu, double n_rpm, double d) {
  if (f0 == 0.0) return 0.0;
  const double nu_n = nu * std::abs(n_rpm);
  return (nu_n >= 2000.0 ? 1e-7 * f0 * std::cbrt(nu_n * nu_n) : 160e-7 * f0) * d * d * d;
}

// --- the stiffness loop with friction ------------------------------------------------------------
double LoopFrictionCoefficient(const std::optional<FrictionSettings>& friction) {
  if (!friction) return 0.0;
  return friction->model == FrictionSettings::Model::kCoulomb ? friction->coefficient : friction->boundary_coefficient;
}

solvers::StageLoads StageFrictionLoads(const solvers::LoadProblem& problem, const contact::MeshModel& model,
                                       const contact::MeshModel* second, const contact::MeshState& state,
                                       const LoadResult& result, const LoadResult& from, const LoadResult& to,
                                       const StageLoopFriction& friction) {
  const solvers::ReducerSettings& stage = *problem.reducer();
  const int discs = problem.disc_count();
  solvers::StageLoads loads;
  loads.discs.resize(static_cast<std::size_t>(discs));
  if (!result.reducer || !from.reducer || !to.reducer) return loads;
  const auto& now = to.reducer->discs;
  const auto& before = from.reducer->discs;
  const auto& solved = result.reducer->discs;
  // The problem's frame: a rotation in it is s_phys times the counterclockwise angle.
  const double s_phys = model.load_direction() * problem.direction();
  const auto perp = [](const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); };
  const auto sign = [](double v) { return v > 0.0 ? 1.0 : v < 0.0 ? -1.0 : 0.0; };
  if (friction.mesh > 0.0) {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    int centre_disc = -1;
    double centre_z = kNaN;
    for (std::size_t i = 0; i < state.pins.size() && i < result.force.size(); ++i) {
      const double f = result.force[i];
      if (!(f > 0.0)) continue;
      const contact::PinContact& c = state.pins[i];
      const int d = c.disc == 1 && second != nullptr ? 1 : 0;
      const auto at = static_cast<std::size_t>(d);
      if (at >= now.size() || at >= before.size() || at >= solved.size()) continue;
      if (centre_disc != d || !(centre_z == c.z)) {
        const double crank = state.crank + (d == 1 ? contact::kSecondDiscCrankOffset : 0.0);
        centre = (d == 1 ? *second : model).CyclePose(crank, 0.0, c.z).centre;
        centre_disc = d;
        centre_z = c.z;
      }
      // The disc's material at P moves by dt + s_phys dphi perp(P - O) (the pin stays): the
      // friction, mu F along the contact's tangent perp(n), opposes that motion's tangential part.
      const Eigen::Vector2d motion = (now[at].translation - before[at].translation) +
                                     s_phys * (now[at].rotation - before[at].rotation) * perp(c.cycloid_point - centre);
      const Eigen::Vector2d force = -sign(motion.dot(perp(c.normal))) * friction.mesh * f * perp(c.normal);
      const Eigen::Vector2d arm = c.cycloid_point - centre;
      loads.discs[at].force += force;
      loads.discs[at].moment += s_phys * (arm.x() * force.y() - arm.y() * force.x());
    }
  }
  if (friction.bearing > 0.0) {
    const bool cranks = stage.kind == solvers::OutputKind::kCranks;
    const double k = cranks ? stage.cranks.turns_per_output_turn : 0.0;
    const double dpsi = to.rotation - from.rotation;
    for (int d = 0; d < discs && static_cast<std::size_t>(d) < std::min({now.size(), before.size(), solved.size()}); ++d) {
      const auto at = static_cast<std::size_t>(d);
      const double dphi = now[at].rotation - before[at].rotation;
      // The bearing's relative rotation, problem frame: the eccentric (locked, pins) or the
      // crankshaft (turning k psi, cranks) against the disc.
      const double relative = sign((cranks ? k * dpsi : 0.0) - dphi);
      for (const Eigen::Vector2d& f : solved[at].bearing_force) {
        const double m = friction.bearing * f.norm() * friction.bearing_diameter / 2.0;
        loads.discs[at].moment += relative * m;
        if (cranks) loads.output_moment -= relative * m * k;
      }
    }
  }
  return loads;
}

LoadResult SolveStageWithLoopFriction(const contact::MeshModel& model, const contact::MeshState& state,
                                      double torque, double sense, const StageLoopFriction& friction,
                                      const LoadProblemAt& problem, const SolveProblem& solve, int* solves,
                                      const contact::MeshModel* second, LoopFrictionBalance* balance) {
  const auto count = [&] {
    if (solves != nullptr) ++*solves;
  };
  const solvers::LoadProblem at_torque = problem(torque);
  if (!friction.any() || sense == 0.0 || torque == 0.0 || !at_torque.has_reducer()) {
    count();
    return solve(at_torque);
  }
  // The stage's motion along the branch: the frictionless stage at T and a step behind it on the
  // branch (the torque the branch came from, of the same sign, so in the same frame).
  LoadResult r = solve(at_torque);
  count();
  if (r.status != SolverStatus::kSuccess) return r;
  const LoadResult frictionless = r;
  const LoadResult behind = solve(problem(torque - sense * kMotionStep * std::abs(torque)));
  count();
  if (behind.status != SolverStatus::kSuccess) return behind;
  // The loads as one vector (per disc x, y, moment; then the output's moment), forces times R_p so
  // that every entry is a moment (N*mm) and one tolerance judges them.
  const double radius = model.pair().pin_circle_radius;
  const int discs = at_torque.disc_count();
  const auto flat = [&](const solvers::StageLoads& l) {
    Eigen::VectorXd v = Eigen::VectorXd::Zero(3 * discs + 1);
    for (int d = 0; d < discs && static_cast<std::size_t>(d) < l.discs.size(); ++d) {
      v(3 * d) = l.discs[static_cast<std::size_t>(d)].force.x() * radius;
      v(3 * d + 1) = l.discs[static_cast<std::size_t>(d)].force.y() * radius;
      v(3 * d + 2) = l.discs[static_cast<std::size_t>(d)].moment;
    }
    v(3 * discs) = l.output_moment;
    return v;
  };
  const auto loads_of = [&](const Eigen::VectorXd& v) {
    solvers::StageLoads l;
    l.discs.resize(static_cast<std::size_t>(discs));
    for (int d = 0; d < discs; ++d) {
      l.discs[static_cast<std::size_t>(d)].force = Eigen::Vector2d(v(3 * d), v(3 * d + 1)) / radius;
      l.discs[static_cast<std::size_t>(d)].moment = v(3 * d + 2);
    }
    l.output_moment = v(3 * discs);
    return l;
  };
  // The torque friction absorbs along the branch, N*mm: minus the loads' virtual work over the
  // stage's motion (from `behind` to `frictionless`) per radian of the output. Friction resisting
  // the motion absorbs; the stage locks where it absorbs the whole torque on the loading branch
  // (on the way back friction acts with the torque: its work is negative, and so is this over a
  // negative turn of the output).
  const double turn = frictionless.rotation - behind.rotation;
  const auto absorbed = [&](const Eigen::VectorXd& v) {
    if (!(std::abs(turn) > 0.0) || !frictionless.reducer || !behind.reducer) return 0.0;
    double work = v(3 * discs) * turn;
    for (int d = 0; d < discs && static_cast<std::size_t>(d) < frictionless.reducer->discs.size(); ++d) {
      const auto& a = behind.reducer->discs[static_cast<std::size_t>(d)];
      const auto& b = frictionless.reducer->discs[static_cast<std::size_t>(d)];
      work += (v(3 * d) * (b.translation.x() - a.translation.x()) + v(3 * d + 1) * (b.translation.y() - a.translation.y())) / radius +
              v(3 * d + 2) * (b.rotation - a.rotation);
    }
    return -work / turn;
  };
  const double tolerance = kBalanceTolerance * std::abs(torque);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3 * discs + 1);  // the loads r was solved with
  Eigen::VectorXd x_prev, r_prev;
  for (int k = 0; k < kMaxStageBalanceSolves; ++k) {
    if (r.status != SolverStatus::kSuccess) return r;
    const Eigen::VectorXd g = flat(StageFrictionLoads(at_torque, model, second, state, r, behind, frictionless, friction));
    const Eigen::VectorXd residual = g - x;
    if (residual.cwiseAbs().maxCoeff() <= tolerance) {
      if (balance != nullptr) {
        balance->moment = std::abs(absorbed(x));
        balance->direct = false;
        balance->behind = kNaN;
      }
      return r;
    }
    if (absorbed(g) >= std::abs(torque)) {
      LoadResult f;
      f.status = SolverStatus::kMaxIterations;
      f.message = fmt::format(
          "torque balance with friction (mu {:g}, bearings {:g}): no balance at {:g} N*m, the friction on the discs and "
          "the output absorbs {:g} N*m of it along the loading branch: the stage locks under this friction",
          friction.mesh, friction.bearing, units::NmmToNm(torque), units::NmmToNm(absorbed(g)));
      return f;
    }
    // Anderson's method of depth 1 (Walker and Ni, SIAM J. Numer. Anal. 49 (2011) 1715): the
    // combination of the last two steps whose residuals cancel best.
    Eigen::VectorXd next = g;
    if (r_prev.size() == residual.size()) {
      const Eigen::VectorXd dr = residual - r_prev;
      const double dd = dr.squaredNorm();
      if (dd > 0.0) next = g - (residual.dot(dr) / dd) * ((x - x_prev) + dr);
    }
    x_prev = x;
    r_prev = residual;
    x = next;
    r = solve(at_torque.WithStageLoads(loads_of(x)));
    count();
  }
  LoadResult f;
  f.status = SolverStatus::kMaxIterations;
  f.message = fmt::format("torque balance with friction (mu {:g}, bearings {:g}): the stage's friction loads did not "
                          "settle in {} solves at {:g} N*m",
                          friction.mesh, friction.bearing, kMaxStageBalanceSolves, units::NmmToNm(torque));
  return f;
}

LoadResult SolveWithLoopFriction(const contact::MeshModel& model, const contact::MeshState& state, double torque,
                                 double sense, double mu, const LoadProblemAt& problem, const SolveProblem& solve,
                                 int* solves, const contact::MeshModel* second, LoopFrictionWarmStart* warm,
                                 LoopFrictionBalance* balance) {
  const auto count = [&] {
    if (solves != nullptr) ++*solves;
  };
  if (mu == 0.0 || sense == 0.0) {
    count();
    return solve(problem(torque));
  }
  // Turning about its centre (crank locked), the cycloid slides every contact along its tangent;
  // the friction moment about the centre is mu F_i |(P - O_c) x t_i| = mu F_i |(P - O_c) . n_i|.
  // The disc's centre is evaluated once per disc and section (a slice's z), not once per point.
  std::vector<double> arm(state.pins.size(), 0.0);
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  int centre_disc = -1;
  double centre_z = kNaN;
  for (std::size_t i = 0; i < state.pins.size(); ++i) {
    const contact::PinContact& c = state.pins[i];
    const bool on_second = c.disc == 1 && second != nullptr;  // two discs: each about its own centre
    if (centre_disc != (on_second ? 1 : 0) || !(centre_z == c.z)) {
      const contact::MeshModel& disc = on_second ? *second : model;
      const double crank = state.crank + (on_second ? contact::kSecondDiscCrankOffset : 0.0);
      centre = disc.CyclePose(crank, 0.0, c.z).centre;
      centre_disc = on_second ? 1 : 0;
      centre_z = c.z;
    }
    arm[i] = std::abs((c.cycloid_point - centre).dot(c.normal));
  }
  const auto moment = [&](const LoadResult& res) {
    double m = 0.0;
    for (std::size_t i = 0; i < state.pins.size(); ++i) {
      if (res.force[i] > 0.0) m += mu * res.force[i] * arm[i];
    }
    return m;
  };
  const auto converged = [&](double t, double slope) {
    if (warm != nullptr && torque != 0.0) {
      warm->ratio = t / torque;
      warm->slope = slope;
    }
  };
  solvers::LoadProblem at_torque = problem(torque);
  // A preloaded pair (issue 52): both flanks carry load at every torque, so the normal forces carry
  // t = T - sense M_f with M_f = mu sum F_i a_i over the pins of both flanks (each one's friction
  // resists the turning), t may lie on the other side of zero from T (the preload's drag at a
  // small T), and at T = 0 the balance is t = -sense M_f. The one-flank scaling below does not
  // apply (the opposing flank's pins are not one flank's laws); the secant on t does, judged on the
  // scale of the larger of T and the friction moment, with no lock read from the sign of t.
  const bool preloaded = !at_torque.has_reducer() && at_torque.preloaded();
  // Issue 27: the balance in one solve, sum_i F_i (L_i + d sense mu a_i) = |T| as the frictionless
  // balance of the laws scaled by w_i = 1 + d sense mu a_i / L_i (friction.hpp).
  if (!preloaded && at_torque.scalable_laws() && at_torque.base_state().pins.size() == arm.size()) {
    const std::vector<contact::PinContact>& pins = at_torque.base_state().pins;  // arms signed for the flank
    const double k = at_torque.direction() * sense * mu;
    std::vector<double> scales(pins.size(), 1.0);
    // Pins whose friction arm outgrows the normal arm on the way back (w_i <= 0: near the end of
    // the engagement, L_i -> 0), and pins of arm L_i <= 0 (they open as psi grows), keep w_i = 1:
    // the answer leaves out their friction moment mu a_i F_i, which must be below 1e-2 of the
    // balance's tolerance (a pin touching to rounding on a pair without clearance carries a force
    // of rounding's size); else the secant iteration below solves the balance.
    std::vector<std::size_t> must_open;
    double lowest = std::numeric_limits<double>::infinity();  // the least closing rotation c_i / L_i, L_i > 0
    for (std::size_t i = 0; i < pins.size(); ++i) {
      if (pins[i].edge) continue;  // a tip corner carries no force in any solver
      const double w = pins[i].arm > 0.0 ? 1.0 + k * arm[i] / pins[i].arm : kNaN;
      if (pins[i].arm > 0.0) lowest = std::min(lowest, pins[i].clearance / pins[i].arm);
      if (std::isfinite(w) && w > 0.0) {
        scales[i] = w;
      } else {
        must_open.push_back(i);
      }
    }
    LoadResult r = solve(at_torque.WithLawScales(scales));
    count();
    if (r.force.size() != scales.size()) return r;  // not solved (the status says why)
    double left_out = 0.0;
    for (const std::size_t i : must_open) left_out += r.force[i] > 0.0 ? mu * arm[i] * r.force[i] : 0.0;
    if (left_out <= 1e-2 * kBalanceTolerance * std::abs(torque)) {
      const std::vector<contact::ContactLaw>& laws = at_torque.base_laws();
      r.energy = 0.0;
      // A positive torque presses a pin of arm L_i > 0, so every answer of this flank has
      // psi >= lowest, where a pin of arm <= 0 has at most the approach L_i lowest - c_i.
      double behind = 0.0;
      for (std::size_t i = 0; i < scales.size(); ++i) {
        if (pins[i].edge) continue;
        r.force[i] /= scales[i];
        r.energy += laws[i].ComplementaryEnergy(r.force[i]);
        if (pins[i].arm <= 0.0) behind += mu * arm[i] * laws[i].Force(contact::LinearisedApproach(pins[i], lowest));
      }
      if (r.status != SolverStatus::kSuccess) return r;
      const double m = moment(r);
      converged(torque - sense * m, warm != nullptr ? warm->slope : kNaN);
      if (balance != nullptr) {
        balance->moment = m;
        balance->direct = true;
        balance->behind = std::isfinite(lowest) ? behind : kNaN;
      }
      return r;
    }
  }
  // The secant iteration. The normal forces carry t = T + M_f, M_f = -sense mu sum F_i a_i (the
  // friction resists the motion): a fixed point in t, each step the frictionless problem at t.
  // g(t) = T - sense mu sum F_i(t) a_i - t, solved by the secant method. Its first step: the
  // slope of g the last balance of this kind ended with (warm), else -(1 + sense mu M / t), exact
  // when the friction moment M grows in proportion to t (a linear law on a fixed contact set with
  // no clearance).
  const bool warm_ratio = warm != nullptr && std::isfinite(warm->ratio) && warm->ratio > 0.0;
  // The first solve: at T itself, or (warm) where the last balance of this kind ended, t = ratio T.
  double t_prev = warm_ratio ? warm->ratio * torque : torque;
  LoadResult r = solve(warm_ratio ? problem(t_prev) : at_torque);
  count();
  if (r.status != SolverStatus::kSuccess) return r;
  const auto done = [&](LoadResult res) {
    if (balance != nullptr) {
      balance->moment = moment(res);
      balance->direct = false;
      balance->behind = kNaN;
    }
    return res;
  };
  const auto failed = [](std::string message) {
    LoadResult f;
    f.status = SolverStatus::kMaxIterations;
    f.message = std::move(message);
    return f;
  };
  const double m_prev = moment(r);
  double g_prev = torque - sense * m_prev - t_prev;
  // (A preloaded pair: the larger of T and the friction moment, which stays finite at T = 0.)
  const double scale = preloaded ? std::max(std::abs(torque), m_prev) : std::abs(torque);
  if (std::abs(g_prev) <= kBalanceTolerance * scale) {
    converged(t_prev, warm != nullptr ? warm->slope : kNaN);
    return done(std::move(r));
  }
  // A slope >= 0 (sense mu M / t >= 1 on the way back) sends the step to the other sense: the lock
  // below.
  // (A preloaded pair's friction moment is mostly the preload's, not in proportion to t: -1.)
  double slope = warm != nullptr && std::isfinite(warm->slope) && warm->slope != 0.0 ? warm->slope
                 : t_prev != 0.0 && !preloaded                                        ? -(1.0 + sense * m_prev / t_prev)
                                                                                      : -1.0;
  if (!(std::isfinite(slope) && slope != 0.0)) slope = -1.0;
  double t_now = t_prev - g_prev / slope;
  // The normal forces carry torque in the sense of T: a step to the other sense means the friction
  // moment outgrows the torque (the stage locks under this friction), and no balance exists.
  for (int k = 0; k < kMaxBalanceSolves; ++k) {
    if (!std::isfinite(t_now) || (!preloaded && torque != 0.0 && t_now * torque <= 0.0)) {
      return failed(fmt::format(
          "torque balance with friction (mu {:g}): no balance at {:g} N*m, the friction moment reaches the torque the "
          "normal forces carry (step to {:g} N*m): the stage locks under this friction",
          mu, units::NmmToNm(torque), units::NmmToNm(t_now)));
    }
    r = solve(problem(t_now));
    count();
    if (r.status != SolverStatus::kSuccess) return r;
    const double g_now = torque - sense * moment(r) - t_now;
    const double secant = (g_now - g_prev) / (t_now - t_prev);
    if (std::isfinite(secant) && secant != 0.0) slope = secant;
    if (std::abs(g_now) <= kBalanceTolerance * (preloaded ? std::max(std::abs(torque), moment(r)) : scale)) {
      converged(t_now, slope);
      return done(std::move(r));
    }
    t_prev = t_now;
    g_prev = g_now;
    t_now = t_now - g_now / slope;
  }
  return failed(fmt::format("torque balance with friction (mu {:g}) at {:g} N*m: not converged after {} solves", mu,
                            units::NmmToNm(torque), kMaxBalanceSolves));
}

}  // namespace ltca::analysis
