#include "ltca/analysis/friction.hpp"

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
  if (!(std::isfinite(limiting_shear_modulus) && limiting_shear_modulus > 0.0 && limiting_shear_modulus <= 1e4)) {
    throw std::invalid_argument(fmt::format(
        "[friction] limiting_shear_modulus_mpa = {}: expected above 0 and at most 10000 MPa (Jiang: 1 MPa)",
        limiting_shear_modulus));
  }
  if (!(std::isfinite(power_law_exponent) && power_law_exponent > 0.0 && power_law_exponent <= 1.0)) {
    throw std::invalid_argument(fmt::format(
        "[friction] power_law_exponent = {}: expected in (0, 1] (1: Newtonian; Jiang: 0.5)", power_law_exponent));
  }
  if (sleeve_bore_radius && !(std::isfinite(*sleeve_bore_radius) && *sleeve_bore_radius > 0.0 &&
                              *sleeve_bore_radius < pair.pin_radius)) {
    throw std::invalid_argument(fmt::format(
        "[friction] sleeve_bore_radius_mm = {}: expected a radius above 0 and below the sleeve's outer radius, [pair] "
        "pin_radius_mm = {}",
        *sleeve_bore_radius, pair.pin_radius));
  }
}

// --- the stiffness loop with friction ------------------------------------------------------------
double LoopFrictionCoefficient(const std::optional<FrictionSettings>& friction) {
  if (!friction) return 0.0;
  return friction->model == FrictionSettings::Model::kCoulomb ? friction->coefficient : friction->boundary_coefficient;
}

LoadResult SolveWithLoopFriction(const contact::MeshModel& model, const contact::MeshState& state, double torque,
                                 double sense, double mu, const std::function<LoadResult(double)>& solve, int* solves,
                                 const contact::MeshModel* second, LoopFrictionWarmStart* warm) {
  const bool warm_ratio = warm != nullptr && std::isfinite(warm->ratio) && warm->ratio > 0.0 && mu != 0.0 && sense != 0.0;
  // The first solve: at T itself, or (warm) where the last balance of this kind ended, t = ratio T.
  double t_prev = warm_ratio ? warm->ratio * torque : torque;
  LoadResult r = solve(t_prev);
  if (solves != nullptr) ++*solves;
  if (mu == 0.0 || sense == 0.0 || r.status != SolverStatus::kSuccess) return r;
  // Turning about its centre (crank locked), the cycloid slides every contact along its tangent;
  // the friction moment about the centre is mu F_i |(P - O_c) x t_i| = mu F_i |(P - O_c) . n_i|.
  std::vector<double> arm(state.pins.size(), 0.0);
  for (std::size_t i = 0; i < state.pins.size(); ++i) {
    const contact::PinContact& c = state.pins[i];
    const bool on_second = c.disc == 1 && second != nullptr;  // issue 13: each disc about its own centre
    const contact::MeshModel& disc = on_second ? *second : model;
    const double crank = state.crank + (on_second ? contact::kSecondDiscCrankOffset : 0.0);
    arm[i] = std::abs((c.cycloid_point - disc.CyclePose(crank, 0.0, c.z).centre).dot(c.normal));
  }
  // The normal forces carry t = T + M_f, M_f = -sense mu sum F_i a_i (the friction resists the
  // motion): a fixed point in t, each step the frictionless problem at t.
  // g(t) = T - sense mu sum F_i(t) a_i - t, solved by the secant method. Its first step: the
  // slope of g the last balance of this kind ended with (warm), else -(1 + sense mu M / t), exact
  // when the friction moment M grows in proportion to t (a linear law on a fixed contact set with
  // no clearance).
  const auto moment = [&](const LoadResult& res) {
    double m = 0.0;
    for (std::size_t i = 0; i < state.pins.size(); ++i) {
      if (res.force[i] > 0.0) m += mu * res.force[i] * arm[i];
    }
    return m;
  };
  const auto failed = [](std::string message) {
    LoadResult f;
    f.status = SolverStatus::kMaxIterations;
    f.message = std::move(message);
    return f;
  };
  const auto converged = [&](double t, double slope) {
    if (warm != nullptr && torque != 0.0) {
      warm->ratio = t / torque;
      warm->slope = slope;
    }
  };
  const double m_prev = moment(r);
  double g_prev = torque - sense * m_prev - t_prev;
  if (std::abs(g_prev) <= kBalanceTolerance * std::abs(torque)) {
    converged(t_prev, warm != nullptr ? warm->slope : kNaN);
    return r;
  }
  // A slope >= 0 (sense mu M / t >= 1 on the way back) sends the step to the other sense: the lock
  // below.
  double slope = warm != nullptr && std::isfinite(warm->slope) && warm->slope != 0.0 ? warm->slope
                 : t_prev != 0.0                                                      ? -(1.0 + sense * m_prev / t_prev)
                                                                                      : -1.0;
  if (!(std::isfinite(slope) && slope != 0.0)) slope = -1.0;
  double t_now = t_prev - g_prev / slope;
  // The normal forces carry torque in the sense of T: a step to the other sense means the friction
  // moment outgrows the torque (the stage locks under this friction), and no balance exists.
  for (int k = 0; k < kMaxBalanceSolves; ++k) {
    if (!std::isfinite(t_now) || (torque != 0.0 && t_now * torque <= 0.0)) {
      return failed(fmt::format(
          "torque balance with friction (mu {:g}): no balance at {:g} N*m, the friction moment reaches the torque the "
          "normal forces carry (step to {:g} N*m): the stage locks under this friction",
          mu, units::NmmToNm(torque), units::NmmToNm(t_now)));
    }
    r = solve(t_now);
    if (solves != nullptr) ++*solves;
    if (r.status != SolverStatus::kSuccess) return r;
    const double g_now = torque - sense * moment(r) - t_now;
    const double secant = (g_now - g_prev) / (t_now - t_prev);
    if (std::isfinite(secant) && secant != 0.0) slope = secant;
    if (std::abs(g_now) <= kBalanceTolerance * std::abs(torque)) {
      converged(t_now, slope);
      return r;
    }
    t_prev = t_now;
    g_prev = g_now;
    t_now = t_now - g_now / slope;
  }
  return failed(fmt::format("torque balance with friction (mu {:g}) at {:g} N*m: not converged after {} solves", mu,
                            units::NmmToNm(torque), kMaxBalanceSolves));
}

}  // namespace ltca::analysis
