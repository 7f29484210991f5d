#include "ltca/analysis/efficiency.hpp"
#include "ltca/analysis/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/contact/sliding.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"

namespace ltca::analysis {
namespace {

using Clock = std::chrono::steady_clock;
using units::kPi;

/// z component of a x b.
double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }
using geometry::Perp;

/// The torque balance with friction converges when the friction moment ratio moves by less than
/// this, within at most kMaxRatioSolves solves.
constexpr double kRatioTolerance = 1e-10;
constexpr int kMaxRatioSolves = 20;
/// An interpolated secant step is accepted when its ratio residual is below this.
constexpr double kInterpolatedTolerance = 1e-8;
/// At most this many secant steps on the interpolated forces after each solve.
constexpr int kInterpolatedSteps = 8;

/// A failed position: its status and message (and the warnings so far) and no figure at all, so
/// that nothing a failed balance computed reaches the output as a number (null in JSON, n/a in
/// text, no CSV rows).
EfficiencyPosition Failed(EfficiencyPosition pos, SolverStatus status, std::string message) {
  EfficiencyPosition failed;
  failed.crank = pos.crank;
  failed.status = status;
  failed.message = std::move(message);
  failed.balance_solves = pos.balance_solves;
  failed.balance_residual = std::numeric_limits<double>::quiet_NaN();
  failed.warnings = std::move(pos.warnings);
  return failed;
}

/// The warning's name: the text before the first ':'.
std::string WarningName(const std::string& w) { return w.substr(0, w.find(':')); }

}  // namespace

double SensingerEfficiency(const geometry::PairParameters& pair, double mu) {
  const double arm = pair.eccentricity * pair.tooth_count / std::abs(pair.ToothDifference());  // |O_c I|
  return 1.0 / (1.0 + 4.0 * mu * (pair.pin_circle_radius - pair.pin_radius) / (kPi * arm));
}

struct EfficiencyRunner::Impl {
  Stage stage;
  const StageDesign& design;
  const contact::Material& material;
  SolverOptions options;
  std::unique_ptr<LoadSolver> solver;
  solvers::Workspace workspace;
  FrictionSettings friction;
  OperationSettings operation;
  double torque;  // signed, N*mm
  std::vector<double> cranks;
  bool closed = false;
  contact::Lubrication lubrication;
  double crank_speed = 0.0;  // rad/s, signed (set by the first position)
  double bearing_diameter = 0.0;  // mm, d of the bearings' friction moment (bearing_coefficient > 0)
  EfficiencySummary summary;
  double mp_sum = 0.0;
  std::int64_t mp_count = 0;
  std::map<std::string, std::string> warnings;
  Clock::duration elapsed{}, solving{};

  Impl(const Stage& st, const SolverOptions& o, double t, const FrictionSettings& f, const OperationSettings& op)
      : stage(st), design(st.design()), material(st.material()), options(o), solver(solvers::MakeSolver(o.name)), friction(f), operation(op),
        torque(t), cranks(st.cranks()) {
    // At zero torque only a preloaded pair loses power (its preload's drag, issue 52): the mesh
    // alone whose pins overlap the cycloid on both flanks at the first crank.
    if (torque == 0.0 && (stage.design().reducer || cranks.empty() || !stage.Problem(cranks.front(), 0.0).preloaded())) {
      throw std::invalid_argument("[load] torque_nm = 0: expected a non-zero torque (efficiency has no output power "
                                  "at zero torque; only a preloaded pair, the mesh alone, loses power there: its "
                                  "preload's drag, docs/efficiency.md \"A preloaded pair\")");
    }
    // The last crank repeats the first's state (a closed period): the means weigh it once.
    closed = stage.closed_period();
    lubrication.viscosity = operation.viscosity;
    lubrication.pressure_viscosity = operation.pressure_viscosity;
    lubrication.roughness_cycloid = operation.roughness_cycloid;
    lubrication.roughness_pin = operation.roughness_pin;
    lubrication.boundary_coefficient = friction.boundary_coefficient;
    lubrication.limiting_shear_modulus = friction.limiting_shear_modulus;
    lubrication.power_law_exponent = friction.power_law_exponent;
    if (friction.bearing_viscous_factor > 0.0 && !operation.kinematic_viscosity) {
      throw std::invalid_argument(fmt::format(
          "[friction] bearing_viscous_factor = {:g}: expected [operation] oil_kinematic_viscosity_mm2_per_s (nu of "
          "Palmgren's viscous moment 1e-7 f_0 (nu n)^(2/3) d^3)",
          friction.bearing_viscous_factor));
    }
    bearing_diameter = BearingFrictionDiameter(friction, design.reducer ? design.reducer->bearing.pitch_diameter : 0.0);
    lubrication.limiting_shear_coefficient = friction.limiting_shear_coefficient;
    lubrication.limiting_shear_stress = friction.limiting_shear_stress;
  }

  solvers::LoadProblem Problem(const contact::MeshState& state, double t) const { return stage.Problem(state, t); }

  LoadResult Solve(const contact::MeshState& state, double t) {
    const auto start = Clock::now();
    LoadResult r = solver->Solve(Problem(state, t), options, workspace);
    solving += Clock::now() - start;
    return r;
  }

  /// Where a pin's contact is a point contact (Jiang eq. 15-19): lead crowning (relative
  /// curvature 8 c / B^2 along the width) or a misalignment (the pin axis crossing the flank's),
  /// when the ellipse fits within the face width; otherwise the line contact holds.
  bool PointCurvature(const contact::PinContact& c, contact::RelativeCurvature* curvature) const {
    const double across = c.cycloid_curvature + 1.0 / c.pin_radius;
    const double crowning = design.errors.lead_crowning;
    const double tilt = std::hypot(design.assembly.misalignment_xz, design.assembly.misalignment_yz);
    if (crowning > 0.0) {
      *curvature = {8.0 * crowning / (design.pair.face_width * design.pair.face_width), across};
      return true;
    }
    if (tilt > 0.0 && c.cycloid_curvature > 0.0) {
      *curvature = contact::CrossedCylinders(c.cycloid_curvature, 1.0 / c.pin_radius, tilt);
      return curvature->a > 0.0;
    }
    return false;
  }

  struct PointKinematics {
    Eigen::Vector2d lever;  // P - O_c, mm
    contact::ContactVelocities v;  // per second
  };

  /// jiang-mixed's largest full-film coefficient without the cap (with the Hertz pressure there)
  /// and its largest mixed coefficient at one evaluation.
  struct MixedRange {
    double full_film = 0.0;
    double max_pressure = 0.0;
    double coefficient = 0.0;
  };

  /// Without a limiting shear stress, eq. 23's power-law shear grows as exp(n alpha p): a
  /// coefficient above 1, or a lock that comes from a full-film coefficient above the boundary
  /// one, is the fluid model beyond its range (not the stage's friction). The message names the
  /// inputs that put it there; empty when the model is within range.
  std::string OutsideRange(const MixedRange& range, bool locked) const {
    if (friction.model != FrictionSettings::Model::kJiangMixed || lubrication.capped()) return {};
    if (!(range.coefficient > 1.0 || (locked && range.full_film > friction.boundary_coefficient))) return {};
    return fmt::format(
        "jiang.full_film_outside_range: the power-law fluid of Jiang eq. 23 without a limiting shear stress gives a "
        "full-film coefficient f_e = {:.3g} (mixed coefficient up to {:.3g}) at a Hertz pressure of {:.4g} MPa with "
        "[operation] pressure_viscosity_per_gpa = {:g} and oil_viscosity_pa_s = {:g}{}: the lubrication model is "
        "outside its range; expected [friction] limiting_shear_stress_coefficient (gamma of tau_L = gamma p, 0.03 to "
        "0.1 for mineral oils, Bair and Winer 1979) or a lower pressure-viscosity coefficient",
        range.full_film, range.coefficient, range.max_pressure, units::PerMPaToPerGPa(lubrication.pressure_viscosity),
        units::MPaSToPaS(lubrication.viscosity), locked ? " (the torque balance found no state: not a lock of the stage)" : "");
  }

  /// mu at each loaded point for the forces f; fills the contact records. Returns the friction
  /// moment ratio sigma M_f / |T| with the effective coefficients.
  double Evaluate(const contact::MeshState& state, const std::vector<PointKinematics>& kin,
                  const std::vector<double>& f, double sigma, std::vector<ContactFrictionPoint>* out,
                  std::vector<std::string>* warn, MixedRange* range = nullptr) const {
    out->clear();
    const double e_star = material.EquivalentModulus();
    // Each disc's force on a pin (two discs touch a pin at two places along it).
    const auto pins = static_cast<std::size_t>(stage.model().pin_count());
    std::vector<double> pin_force(pins * static_cast<std::size_t>(stage.disc_count()), 0.0);
    const auto pin_of = [pins](const contact::PinContact& c) { return static_cast<std::size_t>(c.disc) * pins + static_cast<std::size_t>(c.pin); };
    for (std::size_t i = 0; i < f.size(); ++i) pin_force[pin_of(state.pins[i])] += std::max(0.0, f[i]);
    // A point carries load above kContactForceFraction of the largest (the rule of ltca solve):
    // below it the force is numerical zero, whose "coefficient" (viscous drag over a vanishing
    // load) means nothing.
    const double floor = kContactForceFraction * *std::max_element(f.begin(), f.end());
    double moment = 0.0;
    const double ratio = friction.sleeve_bore_radius ? *friction.sleeve_bore_radius / design.pair.pin_radius : 1.0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (!(f[i] > floor)) continue;
      const contact::PinContact& c = state.pins[i];
      ContactFrictionPoint p;
      p.disc = c.disc;
      p.pin = c.pin;
      p.slice = c.slice;
      p.force = f[i];
      p.sliding = kin[i].v.sliding;
      p.entrainment = kin[i].v.entrainment;
      const double across = c.cycloid_curvature + 1.0 / c.pin_radius;
      const double rho = across > 0.0 ? 1.0 / across : kNaN;
      contact::RelativeCurvature curvature;
      contact::ContactShape shape = contact::LineShape(f[i], c.length, rho, e_star);
      if (PointCurvature(c, &curvature)) {
        const contact::ContactShape ellipse = contact::EllipseShape(curvature, pin_force[pin_of(c)], e_star);
        if (2.0 * ellipse.semi_major <= design.pair.face_width) {
          shape = ellipse;
          // The pin's ellipse carries the pin's force: this point's share of its area.
          shape.area *= f[i] / pin_force[pin_of(c)];
          p.point_contact = true;
        }
      }
      p.max_pressure = shape.max_pressure;
      if (friction.model == FrictionSettings::Model::kCoulomb) {
        p.coefficient = friction.coefficient;
      } else {
        const contact::MixedFriction m = contact::MixedCoefficient(lubrication, f[i], shape, c.length, rho, e_star,
                                                                   p.entrainment, p.sliding);
        p.coefficient = m.coefficient;
        if (range != nullptr && m.full_film_uncapped > range->full_film) *range = {m.full_film_uncapped, shape.max_pressure, m.coefficient};
        if (range != nullptr) range->coefficient = std::max(range->coefficient, m.coefficient);
        p.film_thickness = m.film_thickness;
        p.lambda = m.lambda;
        if (warn != nullptr) warn->insert(warn->end(), m.warnings.begin(), m.warnings.end());
      }
      // Jiang eq. 34: with a sleeve rolling on the cycloid, the sliding is at its bore, slower by
      // r_bore / r_sleeve; the tangential force at the cycloid is what turns the sleeve against
      // the bore's friction, mu_bore F r_bore / r_sleeve.
      const double bore = std::isnan(friction.sleeve_coefficient) ? p.coefficient : friction.sleeve_coefficient;
      p.effective_coefficient = friction.sleeve_bore_radius ? bore * ratio : p.coefficient;
      p.loss_first_order = units::NmmPerSToW(p.coefficient * f[i] * std::abs(p.sliding));
      p.loss = units::NmmPerSToW(p.effective_coefficient * f[i] * std::abs(p.sliding));
      // The friction force on the cycloid opposes its sliding over the pin.
      const double direction = p.sliding > 0.0 ? 1.0 : p.sliding < 0.0 ? -1.0 : 0.0;
      moment += Cross(kin[i].lever, -p.effective_coefficient * f[i] * direction * Perp(c.normal));
      out->push_back(p);
    }
    return sigma * moment / std::abs(torque != 0.0 ? torque : drag_reference);
  }
  /// At zero torque (a preloaded pair): the friction moment at the preload state, N*mm, the scale
  /// of the ratio s in place of |T| (the normal forces then carry sigma drag_reference s).
  double drag_reference = 1.0;

  /// The stage's losses at its reducer's forces (W) and the friction moments they put on the discs
  /// (N*mm, a bound: each output pin's friction force at the arm R_w + r_h, the largest its
  /// contact point can have about the disc's centre). Each disc turns at omega_d = phi' omega_c
  /// (phi' = d(rotation) / d(crank), PoseRatePerCrank), its centre at v_O = O' omega_c; the output
  /// member turns with it (the W mechanism or the carrier), so the disc's material moves over the
  /// output member's at the one velocity v_rel = omega_c (O' - phi' perp(O)) everywhere (the
  /// rotations cancel): an output pin slides at |t_j . v_rel|, t_j = perp(n_j), and loses
  /// mu_w F_j |t_j . v_rel| (nominally e omega_c z_p / z_c, docs/efficiency.md). A bearing's inner
  /// member (the eccentric, or the crankshaft's) turns with the crank at omega_c, the disc's bore
  /// at omega_d: its friction moment mu_b |F| d / 2 (SKF's simplified model) loses
  /// mu_b |F| (d / 2) |omega_c (1 - phi')|.
  struct StageLosses {
    double output = 0.0, bearings = 0.0, moment = 0.0;
    /// The losses a fraction w of the way from a to b (the forces interpolated so, the losses are
    /// linear in them).
    static StageLosses Between(const StageLosses& a, const StageLosses& b, double w) {
      return {a.output + w * (b.output - a.output), a.bearings + w * (b.bearings - a.bearings), a.moment + w * (b.moment - a.moment)};
    }
  };
  StageLosses StageLoss(const LoadResult& r, double crank) const {
    StageLosses loss;
    if (!design.reducer || !r.reducer || !friction.stage_friction()) return loss;
    const solvers::ReducerSettings& reducer = *design.reducer;
    for (std::size_t k = 0; k < r.reducer->discs.size(); ++k) {
      const auto& disc = r.reducer->discs[k];
      const contact::MeshModel& model = stage.model(static_cast<int>(k));
      const double at = k == 0 ? crank : crank + contact::kSecondDiscCrankOffset;
      const geometry::Pose pose = model.CyclePose(at, 0.0, 0.0);
      const contact::PoseRate rate = contact::PoseRatePerCrank(model, at, 0.0, 0.0);
      if (friction.bearing_coefficient > 0.0 || friction.bearing_viscous_factor > 0.0) {
        const double relative = std::abs(crank_speed * (1.0 - rate.angular_velocity));  // rad/s
        const double viscous = PalmgrenViscousMoment(friction.bearing_viscous_factor, operation.kinematic_viscosity.value_or(0.0),
                                                     units::RadPerSToRpm(relative), bearing_diameter);
        for (const Eigen::Vector2d& f : disc.bearing_force) {
          const double moment = friction.bearing_coefficient * f.norm() * bearing_diameter / 2.0 + viscous;
          loss.bearings += moment * relative;
          loss.moment += moment;
        }
      }
      if (friction.output_pin_coefficient > 0.0 && reducer.kind == solvers::OutputKind::kPins) {
        const Eigen::Vector2d v = crank_speed * (rate.centre_velocity - rate.angular_velocity * Perp(pose.centre));
        const double arm = reducer.pins.circle_radius + reducer.pins.hole_radius;
        for (std::size_t j = 0; j < disc.output_force.size(); ++j) {
          if (!(disc.output_force[j] > 0.0)) continue;
          const double force = friction.output_pin_coefficient * disc.output_force[j];
          loss.output += force * std::abs(Perp(disc.output_direction[j]).dot(v));
          loss.moment += force * arm;
        }
      }
    }
    loss.output = units::NmmPerSToW(loss.output);
    loss.bearings = units::NmmPerSToW(loss.bearings);
    return loss;
  }

  EfficiencyPosition SolvePosition(double crank) {
    EfficiencyPosition pos;
    pos.crank = crank;
    const contact::MeshState state = stage.State(crank);
    LoadResult r = Solve(state, torque);
    ++summary.solves;
    pos.status = r.status;
    pos.message = r.message;
    if (r.status != SolverStatus::kSuccess) return pos;
    pos.warnings = r.warnings;
    const bool idle = torque == 0.0;  // a preloaded pair's drag at zero torque (issue 52)
    if (idle && !(r.preload && r.preload->contacts > 0)) {
      return Failed(std::move(pos), SolverStatus::kNumericalFailure,
                    "zero torque: no pin is pressed at this crank (no preload), so nothing is lost and nothing delivered");
    }

    // Kinematics per point, per radian of crank first; then the crank's sense that drives the load.
    // Two discs: each point turns about its own disc's centre, the second disc's half a
    // crank turn on; both turn the output together, so the friction moments add.
    const std::size_t n = state.pins.size();
    std::vector<PointKinematics> kin(n);
    std::vector<contact::PoseRate> rates(n);
    double reaction = 0.0;  // moment of the normal forces on the cycloids about their centres
    for (std::size_t i = 0; i < n; ++i) {
      const contact::PinContact& c = state.pins[i];
      const contact::MeshModel& model = stage.model(c.disc);
      const double at = c.disc == 0 ? crank : crank + contact::kSecondDiscCrankOffset;
      const geometry::Pose pose = model.CyclePose(at, 0.0, c.z);
      rates[i] = contact::PoseRatePerCrank(model, at, 0.0, c.z);
      kin[i].lever = c.cycloid_point - pose.centre;
      kin[i].v = contact::Velocities(c, pose, rates[i]);
      reaction += Cross(kin[i].lever, -r.force[i] * c.normal);
    }
    // The cycloid turns against the load torque: omega_c has the sign -sigma. At zero torque the
    // preload's normal moments cancel: the crank turns forward and the friction, which resists the
    // cycloid's turning, is the load (sigma = -sign(omega_c)).
    const double per_crank = rates.front().angular_velocity;
    const double sigma = idle ? (per_crank > 0.0 ? -1.0 : 1.0) : reaction < 0.0 ? 1.0 : -1.0;  // the load's sense
    const double crank_sign = idle ? 1.0 : (-sigma * per_crank) > 0.0 ? 1.0 : -1.0;
    crank_speed = crank_sign * operation.input_speed;
    for (std::size_t i = 0; i < n; ++i) {
      auto& v = kin[i].v;
      v.sliding *= crank_speed;
      v.normal *= crank_speed;
      v.point_over_pin *= crank_speed;
      v.point_over_cycloid *= crank_speed;
      v.entrainment *= crank_speed;
      v.point_velocity *= crank_speed;
    }
    const double omega_c = std::abs(per_crank * crank_speed);
    pos.output_power = units::NmmPerSToW(std::abs(torque) * omega_c);

    // First order: the frictionless forces.
    std::vector<ContactFrictionPoint> first;
    MixedRange range;
    if (idle) {
      // The scale of s: the preload's friction moment (the ratio at the preload's forces over
      // 1 N*mm), so that s = 1 at the preload's forces and the balance t = sigma M_f(t) is
      // t = sigma drag_reference s, s = ratio(t).
      drag_reference = 1.0;
      std::vector<ContactFrictionPoint> probe;
      std::vector<std::string> ignored;
      drag_reference = std::abs(Evaluate(state, kin, r.force, sigma, &probe, &ignored));
      if (!(drag_reference > 0.0)) drag_reference = 1.0;
    }
    pos.friction_moment_ratio_first_order = Evaluate(state, kin, r.force, sigma, &first, &pos.warnings, &range);
    if (std::string outside = OutsideRange(range, false); !outside.empty()) {
      return Failed(std::move(pos), SolverStatus::kNumericalFailure, std::move(outside));
    }
    pos.friction_moment_ratio = pos.friction_moment_ratio_first_order;  // "bound": the accepted forces
    pos.power_loss_first_order = 0.0;
    double mu_force = 0.0, force_sum = 0.0;
    for (const auto& p : first) {
      pos.power_loss_first_order += p.loss_first_order;
      mu_force += p.coefficient * p.force;
      force_sum += p.force;
    }
    pos.mean_coefficient = force_sum > 0.0 ? mu_force / force_sum : kNaN;
    const StageLosses frictionless = StageLoss(r, crank);
    pos.power_loss_first_order += frictionless.output + frictionless.bearings;
    pos.efficiency_first_order = pos.output_power / (pos.output_power + pos.power_loss_first_order);
    // The stage's losses at the accepted state: the frictionless forces ("bound", no mesh friction),
    // a balance solve's, or interpolated between two solves as the mesh's forces are (linear in them).
    StageLosses accepted = frictionless;

    // The full model: the friction moment in the torque balance, solved to a fixed point (the
    // approach of every pin depends on psi alone, so re-solving the frictionless problem at the
    // torque the normal forces must carry, T (1 + ratio), is exact within the model), or bounded.
    pos.contacts = first;
    if (friction.torque_balance == FrictionSettings::TorqueBalance::kSolve && pos.friction_moment_ratio != 0.0) {
      // Secant on g(s) = ratio(forces solved at T (1 + s)) - s, from s = 0 (g = the frictionless
      // ratio). The forces are nearly linear in s over this range, so after one solve at s_1 the
      // secant root s_2 is taken with the forces interpolated linearly between s = 0 and s_1, and
      // accepted when its residual is below kInterpolatedTolerance (second order in g(s_1));
      // otherwise more solves follow.
      std::vector<double> f_prev = r.force;
      StageLosses stage_prev = frictionless;
      double s_prev = 0.0, g_prev = pos.friction_moment_ratio_first_order, s_now = pos.friction_moment_ratio_first_order;
      bool converged = false;
      std::vector<std::string> ignored;
      for (int k = 0; k < kMaxRatioSolves; ++k) {
        const LoadResult rk = Solve(state, idle ? sigma * drag_reference * s_now : torque * (1.0 + s_now));
        ++pos.balance_solves;
        if (rk.status != SolverStatus::kSuccess) return Failed(std::move(pos), rk.status, "torque balance with friction: " + rk.message);
        const double g_now = Evaluate(state, kin, rk.force, sigma, &pos.contacts, &ignored, &range) - s_now;
        const StageLosses stage_now = StageLoss(rk, crank);
        pos.balance_residual = std::abs(g_now);
        if (std::abs(g_now) < kRatioTolerance) {
          converged = true;
          accepted = stage_now;
          pos.friction_moment_ratio = g_now + s_now;  // the ratio of the solved forces: the accepted state
          break;
        }
        // Secant steps on the interpolated forces, F(s) = F(s_prev) + w (F(s_now) - F(s_prev)),
        // w = (s - s_prev) / (s_now - s_prev): each costs one evaluation of the friction, no solve.
        // With Coulomb friction the ratio is linear in the forces, so the first step is the root;
        // with a coefficient that depends on the force (jiang-mixed) a few more steps find it.
        std::vector<double> f_next(rk.force.size());
        std::vector<ContactFrictionPoint> interpolated;
        double s_a = s_prev, g_a = g_prev, s_b = s_now, g_b = g_now, s_next = s_now;
        for (int step = 0; step < kInterpolatedSteps; ++step) {
          const double slope = (g_b - g_a) / (s_b - s_a);
          s_next = slope != 0.0 && std::isfinite(slope) ? s_b - g_b / slope : s_b + g_b;
          const double w = (s_next - s_prev) / (s_now - s_prev);
          for (std::size_t i = 0; i < f_next.size(); ++i) f_next[i] = f_prev[i] + w * (rk.force[i] - f_prev[i]);
          // The interpolation stands only while every force keeps its sign (no contact lost or
          // gained beyond the two solves) and the torque its sense; otherwise the next solve decides.
          bool keeps_contacts = std::isfinite(s_next) && s_next > -1.0;
          for (std::size_t i = 0; i < f_next.size() && keeps_contacts; ++i) {
            keeps_contacts = rk.force[i] > 0.0 ? f_next[i] > 0.0 : f_next[i] >= 0.0;
          }
          if (!keeps_contacts) break;
          const double g_next = Evaluate(state, kin, f_next, sigma, &interpolated, &ignored) - s_next;
          if (std::abs(g_next) < kInterpolatedTolerance) {
            converged = true;
            accepted = StageLosses::Between(stage_prev, stage_now, w);
            // The accepted state is this step's: its ratio and its own residual (not the last solve's).
            pos.friction_moment_ratio = g_next + s_next;
            pos.balance_residual = std::abs(g_next);
            break;
          }
          if (s_next == s_b) break;
          s_a = s_b;
          g_a = g_b;
          s_b = s_next;
          g_b = g_next;
        }
        if (converged) {
          pos.contacts = std::move(interpolated);
          break;
        }
        // The friction moment opposes the load, so the balance lies at s >= 0; a secant step
        // below it means the friction moment grows as fast as the torque the forces carry (a
        // ratio that reaches 1: the stage locks), and no balance exists.
        if (!std::isfinite(s_next) || s_next < 0.0) {
          if (std::string outside = OutsideRange(range, true); !outside.empty()) {
            return Failed(std::move(pos), SolverStatus::kNumericalFailure, std::move(outside));
          }
          return Failed(std::move(pos), SolverStatus::kMaxIterations,
                        fmt::format("efficiency.torque_balance_not_converged: no torque balance with friction (the "
                                    "friction moment reaches the torque the normal forces carry; ratio {:.3g} at "
                                    "s = {:.3g}): the stage locks under this friction",
                                    g_now + s_now, s_now));
        }
        f_prev = rk.force;
        stage_prev = stage_now;
        s_prev = s_now;
        g_prev = g_now;
        s_now = s_next;
      }
      if (!converged) {
        return Failed(std::move(pos), SolverStatus::kMaxIterations,
                      fmt::format("efficiency.torque_balance_not_converged: the friction moment ratio moved by {:.3g} "
                                  "(more than {:g}) after {} solves",
                                  pos.balance_residual, kRatioTolerance, kMaxRatioSolves));
      }
    } else if (friction.torque_balance == FrictionSettings::TorqueBalance::kBound && pos.friction_moment_ratio != 0.0 && idle) {
      pos.warnings.push_back(fmt::format(
          "efficiency.torque_balance_bounded: the preload's frictionless forces; the friction moment, {:.6g} N*m, is "
          "left out of the balance", units::NmmToNm(drag_reference)));
    } else if (friction.torque_balance == FrictionSettings::TorqueBalance::kBound && pos.friction_moment_ratio != 0.0) {
      pos.warnings.push_back(fmt::format(
          "efficiency.torque_balance_bounded: frictionless forces; the friction moment is {:.3g} of the torque, "
          "the bound on the relative change of the forces and the loss",
          std::abs(pos.friction_moment_ratio)));
    }
    pos.power_loss = 0.0;
    pos.pin_coefficient.assign(static_cast<std::size_t>(stage.model().pin_count()), kNaN);
    pos.pin_loss.assign(static_cast<std::size_t>(stage.model().pin_count()), 0.0);
    std::vector<double> pin_mu_force(pos.pin_loss.size(), 0.0), pin_force(pos.pin_loss.size(), 0.0);
    for (const auto& p : pos.contacts) {
      pos.power_loss += p.loss;
      const auto j = static_cast<std::size_t>(p.pin);
      pos.pin_loss[j] += p.loss;
      pin_mu_force[j] += p.coefficient * p.force;
      pin_force[j] += p.force;
    }
    for (std::size_t j = 0; j < pin_force.size(); ++j) {
      if (pin_force[j] > 0.0) pos.pin_coefficient[j] = pin_mu_force[j] / pin_force[j];
    }
    // By source: with a pin sleeve the sliding of the pin ring is at the sleeve's bore (eq. 34).
    (friction.sleeve_bore_radius ? pos.power_loss_by_source.seats : pos.power_loss_by_source.mesh) = pos.power_loss;
    (friction.sleeve_bore_radius ? pos.power_loss_by_source.mesh : pos.power_loss_by_source.seats) = 0.0;
    pos.power_loss_by_source.output = accepted.output;
    pos.power_loss_by_source.bearings = accepted.bearings;
    pos.power_loss = pos.power_loss_by_source.total();
    pos.stage_friction_moment_ratio = accepted.moment / std::abs(torque);
    pos.efficiency = pos.output_power / (pos.output_power + pos.power_loss);
    if (idle) {
      // No torque to compare the friction moment with: the ratios are null, the efficiencies 0
      // (nothing delivered), the classical estimates (of a loaded half ring) do not apply.
      pos.friction_moment_ratio = pos.friction_moment_ratio_first_order = pos.stage_friction_moment_ratio = kNaN;
      return pos;
    }

    // The classical estimates with the same (mean) mu: F_i ~ L_i over the pins of the loaded half
    // of the nominal pair (Malhotra-Parameswaran's distribution), and its continuum limit.
    const geometry::Kinematics& k = stage.model().kinematics();
    const geometry::PairParameters& pair = design.pair;
    const double pitch = pair.eccentricity * pair.pin_count / pair.ToothDifference();
    const Eigen::Vector2d u(std::cos(crank), std::sin(crank));
    const Eigen::Vector2d centre = pair.eccentricity * u, ip = pitch * u;
    double loaded_side = 0.0;
    // (The first disc's: with two discs the classical figures are the first disc's at its crank.)
    for (const auto& p : first) {
      if (p.disc == 0) loaded_side += p.force * std::sin(k.AngleFromLineOfCentres(p.pin, crank));
    }
    double num = 0.0, den = 0.0;
    for (int j = 0; j < pair.pin_count; ++j) {
      if (std::sin(k.AngleFromLineOfCentres(j, crank)) * loaded_side <= 0.0) continue;
      const Eigen::Vector2d ci = k.PinCentre(j) - ip;
      const double l = ci.norm();
      const double arm = std::abs(Cross(ci / l, centre - ip));  // O_c to the normal line C_j I
      num += arm * (l - pair.pin_radius);
      den += arm * arm;
    }
    if (den > 0.0 && std::isfinite(pos.mean_coefficient)) {
      pos.efficiency_malhotra_parameswaran = 1.0 / (1.0 + pos.mean_coefficient * num / den);
      pos.efficiency_sensinger = SensingerEfficiency(pair, pos.mean_coefficient);
    }
    return pos;
  }
};

EfficiencyRunner::EfficiencyRunner(const Stage& stage, const SolverOptions& options, double torque,
                                   const FrictionSettings& friction, const OperationSettings& operation) {
  const auto start = Clock::now();
  options.Validate();
  impl_ = std::make_unique<Impl>(stage, options, torque, friction, operation);
  impl_->elapsed = Clock::now() - start;
}
EfficiencyRunner::~EfficiencyRunner() = default;
EfficiencyRunner::EfficiencyRunner(EfficiencyRunner&&) noexcept = default;
EfficiencyRunner& EfficiencyRunner::operator=(EfficiencyRunner&&) noexcept = default;
const std::vector<double>& EfficiencyRunner::cranks() const { return impl_->cranks; }
double EfficiencyRunner::crank_speed() const { return impl_->crank_speed; }

EfficiencyPosition EfficiencyRunner::Solve(double crank) {
  const auto start = Clock::now();
  Impl& m = *impl_;
  EfficiencyPosition pos = m.SolvePosition(crank);
  EfficiencySummary& s = m.summary;
  s.balance_solves += pos.balance_solves;
  s.closed_period = m.closed;
  if (pos.succeeded()) {
    const bool in_mean = !(m.closed && crank == m.cranks.back());
    ++s.succeeded;
    s.power_loss.Add(pos.power_loss, in_mean);
    s.power_loss_first_order.Add(pos.power_loss_first_order, in_mean);
    s.power_loss_mesh.Add(pos.power_loss_by_source.mesh, in_mean);
    s.power_loss_output.Add(pos.power_loss_by_source.output, in_mean);
    s.power_loss_bearings.Add(pos.power_loss_by_source.bearings, in_mean);
    s.power_loss_seats.Add(pos.power_loss_by_source.seats, in_mean);
    s.stage_friction_moment_ratio.Add(pos.stage_friction_moment_ratio, in_mean);
    s.output_power.Add(pos.output_power, in_mean);
    s.friction_moment_ratio.Add(pos.friction_moment_ratio, in_mean);
    s.friction_moment_ratio_first_order.Add(pos.friction_moment_ratio_first_order, in_mean);
    s.mean_coefficient.Add(pos.mean_coefficient, in_mean);
    if (in_mean && std::isfinite(pos.efficiency_malhotra_parameswaran)) {
      m.mp_sum += pos.efficiency_malhotra_parameswaran;
      ++m.mp_count;
    }
    for (const std::string& w : pos.warnings) m.warnings.emplace(WarningName(w), w);
  } else {
    s.Fail(fmt::format("crank {:.6g} deg: {}: {}", units::RadToDeg(crank), solvers::ToString(pos.status), pos.message));
  }
  m.elapsed += Clock::now() - start;
  return pos;
}

EfficiencySummary EfficiencyRunner::Summary() const {
  const Impl& m = *impl_;
  EfficiencySummary s = m.summary;
  if (s.succeeded > 0) {
    s.efficiency = s.output_power.mean / (s.output_power.mean + s.power_loss.mean);
    s.efficiency_first_order = s.output_power.mean / (s.output_power.mean + s.power_loss_first_order.mean);
    if (m.mp_count > 0) s.efficiency_malhotra_parameswaran = m.mp_sum / static_cast<double>(m.mp_count);
    if (std::isfinite(s.mean_coefficient.mean) && m.torque != 0.0) {  // (a loaded half ring's estimate)
      s.efficiency_sensinger = SensingerEfficiency(m.design.pair, s.mean_coefficient.mean);
    }
    s.energy_loss_per_revolution = s.power_loss.mean * 2.0 * kPi / m.operation.input_speed;
  }
  for (const auto& [name, text] : m.warnings) s.warnings.push_back(text);
  if (std::string note = m.stage.SamplingNote(); !note.empty()) s.warnings.push_back(std::move(note));
  s.wall_seconds = std::chrono::duration<double>(m.elapsed).count();
  s.loaded_solve_seconds = std::chrono::duration<double>(m.solving).count();
  return s;
}

bool EfficiencySpectrum::all_succeeded() const {
  for (const Bin& b : bins) {
    if (!b.summary.all_succeeded()) return false;
  }
  return true;
}

EfficiencySpectrum CombineEfficiency(std::vector<EfficiencySpectrum::Bin> bins) {
  EfficiencySpectrum out;
  out.bins = std::move(bins);
  if (out.bins.empty() || !out.all_succeeded()) return out;  // a failed bin leaves the spectrum's figures null
  const auto weighted = [&](auto figure) {
    double sum = 0.0;
    for (const EfficiencySpectrum::Bin& b : out.bins) sum += b.bin.time_share * figure(b.summary);
    return std::isfinite(sum) ? sum : kEfficiencyNaN;
  };
  out.output_power = weighted([](const EfficiencySummary& s) { return s.output_power.mean; });
  out.power_loss = weighted([](const EfficiencySummary& s) { return s.power_loss.mean; });
  out.power_loss_mesh = weighted([](const EfficiencySummary& s) { return s.power_loss_mesh.mean; });
  out.power_loss_output = weighted([](const EfficiencySummary& s) { return s.power_loss_output.mean; });
  out.power_loss_bearings = weighted([](const EfficiencySummary& s) { return s.power_loss_bearings.mean; });
  out.power_loss_seats = weighted([](const EfficiencySummary& s) { return s.power_loss_seats.mean; });
  out.efficiency = out.output_power / (out.output_power + out.power_loss);
  if (!std::isfinite(out.efficiency)) out.efficiency = kEfficiencyNaN;
  return out;
}

}  // namespace ltca::analysis
