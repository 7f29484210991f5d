#include "ltca/analysis/sweep.hpp"

#include "ltca/analysis/stage.hpp"
#include "ltca/contact/bearing.hpp"
#include "ltca/geometry/kinematics.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"

namespace ltca::analysis {

void LoadCase::Validate() const {
  if (!std::isfinite(torque)) {
    throw std::invalid_argument(fmt::format(
        "[load] torque_nm = {}: expected a finite torque in N*m (its sign picks the flank, "
        "docs/conventions.md)",
        units::NmmToNm(torque)));
  }
}

namespace {

int Severity(SolverStatus s) { return s == SolverStatus::kSuccess ? 0 : (s == SolverStatus::kNotSolved ? -1 : 1); }

using Clock = std::chrono::steady_clock;

}  // namespace

void Sweep::Validate(int tooth_count) const {
  if (positions < 1 || positions > kMaxPositions) {
    throw std::invalid_argument(fmt::format(
        "[sweep] positions = {}: expected an integer from 1 to {} (docs/decks.md, Limits)",
        positions, kMaxPositions));
  }
  const double max_deg = MaxCrankDeg(tooth_count);
  const double max_crank = units::DegToRad(max_deg);
  for (const auto& [key, value] : {std::pair{"crank_start_deg", crank_start}, std::pair{"crank_end_deg", crank_end}}) {
    if (!std::isfinite(value) || std::abs(value) > max_crank) {
      throw std::invalid_argument(fmt::format(
          "[sweep] {} = {}: expected a finite crank angle within +-{} deg ({} x {} crank turns, {} turns of the disc: at least "
          "two output turns; at least 10 crank turns; docs/decks.md, Limits)",
          key, units::RadToDeg(value), max_deg, kMaxOutputTurns, std::abs(tooth_count), kMaxOutputTurns));
    }
  }
  if (positions > 1 && crank_end <= crank_start) {
    throw std::invalid_argument(fmt::format(
        "[sweep] crank_end_deg = {}: expected an angle above crank_start_deg = {} when "
        "positions > 1",
        units::RadToDeg(crank_end), units::RadToDeg(crank_start)));
  }
}

std::vector<double> Sweep::CrankAngles() const {
  std::vector<double> angles(static_cast<std::size_t>(positions));
  for (int i = 0; i < positions; ++i) {
    angles[static_cast<std::size_t>(i)] =
        positions == 1 ? crank_start
                       : crank_start + (crank_end - crank_start) * i / (positions - 1);
  }
  return angles;
}

void SummaryAccumulator::Add(const PositionResult& p, bool in_mean) {
  if (Severity(p.result.status) > Severity(s_.status)) s_.status = p.result.status;
  if (p.result.status == SolverStatus::kCannotAssemble) ++s_.cannot_assemble;
  if (const auto& pre = p.result.preload; pre) {
    ++s_.preloaded;
    const auto larger = [](double a, double b) { return std::isfinite(a) ? std::max(a, b) : b; };
    s_.max_preload_force = larger(s_.max_preload_force, pre->max_force_n);
    s_.max_preload_stress = larger(s_.max_preload_stress, pre->max_stress_mpa);
  }
  if (added_++ == 0) first_crank_ = p.crank;
  last_crank_ = p.crank;
  if (!p.succeeded()) {
    ++s_.failed;
    cycles_.Fail();
    return;
  }
  if (p.disc_torque.size() == 2) discs_ = 2;
  cycles_.Add(p.contact_stress);
  if (s_.succeeded == 0) {
    s_.contacts_min = p.contacts;
    s_.contacts_max = p.contacts;
    s_.max_pin_force = 0.0;
    s_.max_contact_stress = 0.0;
  }
  ++s_.succeeded;
  if (!p.result.warnings.empty()) {
    if (s_.warned == 0) s_.first_warning = fmt::format("crank {:.6g} deg: {}", units::RadToDeg(p.crank), p.result.warnings.front());
    ++s_.warned;
  }
  if (in_mean) {
    te_sum_ += p.result.te;
    ++te_count_;
  }
  te_lo_ = std::min(te_lo_, p.result.te);
  te_hi_ = std::max(te_hi_, p.result.te);
  s_.contacts_min = std::min(s_.contacts_min, p.contacts);
  s_.contacts_max = std::max(s_.contacts_max, p.contacts);
  for (const double f : p.pin_force) s_.max_pin_force = std::max(s_.max_pin_force, f);
  for (const double q : p.contact_stress) s_.max_contact_stress = std::max(s_.max_contact_stress, q);
  if (p.result.reducer) {  // a reducer stage: its element and bearing forces
    const solvers::ReducerSolution& st = *p.result.reducer;
    if (!s_.reducer) {
      s_.reducer = ReducerSummary{};
      s_.reducer->max_output_force = 0.0;
      s_.reducer->max_bearing_load = 0.0;
    }
    ReducerSummary& g = *s_.reducer;
    std::size_t b = 0;
    double energy = 0.0;
    for (const double e : st.group_energy) energy += e;
    if (share_sums_.size() != st.group_energy.size()) share_sums_.assign(st.group_energy.size(), 0.0);
    for (const auto& disc : st.discs) {
      for (const double f : disc.output_force) g.max_output_force = std::max(g.max_output_force, f);
      for (std::size_t k = 0; k < disc.bearing_force.size(); ++k, ++b) {
        const double load = disc.bearing_force[k].norm();
        g.max_bearing_load = std::max(g.max_bearing_load, load);
        if (bearing_power_sum_.size() <= b) bearing_power_sum_.resize(b + 1, 0.0);
        if (in_mean) bearing_power_sum_[b] += std::pow(load, contact::kRollerLifeExponent);
        if (g.bearing_max_load.size() <= b) {
          g.bearing_max_load.resize(b + 1, 0.0);
          g.bearing_max_roller_load.resize(b + 1, std::numeric_limits<double>::quiet_NaN());
        }
        g.bearing_max_load[b] = std::max(g.bearing_max_load[b], load);
        for (const double q : disc.roller_load[k]) {
          g.max_roller_load = std::isnan(g.max_roller_load) ? q : std::max(g.max_roller_load, q);
          g.bearing_max_roller_load[b] = std::isnan(g.bearing_max_roller_load[b]) ? q : std::max(g.bearing_max_roller_load[b], q);
        }
        if (in_mean && !disc.roller_load[k].empty()) {  // the load-zone life's load state
          if (g.roller_moments.size() <= b) g.roller_moments.resize(b + 1);
          g.roller_moments[b].push_back(contact::LoadMoments(disc.roller_load[k]));
        }
      }
    }
    if (in_mean) {
      for (std::size_t k = 0; k < share_sums_.size(); ++k) share_sums_[k] += energy > 0.0 ? st.group_energy[k] / energy : 0.0;
      ++stage_count_;
    }
  }
  if (p.disc_torque.size() == 2 && p.disc_torque[0] + p.disc_torque[1] != 0.0) {
    const double share = p.disc_torque[0] / (p.disc_torque[0] + p.disc_torque[1]);
    s_.first_disc_share_min = shares_ == 0 ? share : std::min(s_.first_disc_share_min, share);
    s_.first_disc_share_max = shares_ == 0 ? share : std::max(s_.first_disc_share_max, share);
    if (in_mean) {
      share_sum_ += share;
      ++share_count_;
    }
    ++shares_;
  }
}

namespace {

/// The least (or greatest) finite entry; NaN when none is finite.
double Extreme(const std::vector<double>& values, bool least) {
  double best = std::numeric_limits<double>::quiet_NaN();
  for (const double v : values) {
    if (std::isfinite(v) && !(least ? v >= best : v <= best)) best = v;
  }
  return best;
}

}  // namespace

double BearingLife::ShortestHours() const { return Extreme(hours, true); }
double BearingLife::ShortestLoadZoneHours() const { return Extreme(load_zone_hours, true); }
double BearingLife::SmallestStaticSafety() const { return Extreme(static_safety, true); }
double BearingLife::LargestRollerStress() const { return Extreme(max_roller_stress, false); }
double BearingLife::ShortestModifiedHours() const { return Extreme(modified_hours, true); }
double BearingLife::ShortestLoadZoneModifiedHours() const { return Extreme(load_zone_modified_hours, true); }

BearingLife BearingLives(const StageDesign& design, const ReducerSummary& summary, const Sweep& sweep, bool closed_period,
                         double input_speed, double kinematic_viscosity) {
  BearingLife life;
  // Positions evenly spaced over a turn cover it whether or not the last repeats the first.
  const double swept = std::abs(sweep.crank_end - sweep.crank_start);
  const double covered = sweep.positions > 1 ? swept * sweep.positions / (sweep.positions - 1) : 0.0;
  if (std::max(swept, covered) >= 2.0 * units::kPi * (1.0 - 1e-12)) {
    life.basis = "a whole crank turn";
  } else if (closed_period) {
    life.basis = "one mesh period, which repeats over the crank turn";
  } else {
    life.basis = fmt::format("the swept {:.6g} deg of crank only, not a whole turn", units::RadToDeg(swept));
  }
  const double rating = design.reducer ? design.reducer->bearing.dynamic_load_rating : 0.0;
  const double ratio = geometry::Kinematics(design.pair).TransmissionRatio();
  const double rpm = std::isfinite(input_speed) ? units::RadPerSToRpm(input_speed) * std::abs(1.0 - 1.0 / ratio)
                                                : std::numeric_limits<double>::quiet_NaN();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  // An unloaded bearing's life is infinite (no damage: a spectrum's idle bin), not missing.
  const auto hours = [&](double l) {
    if (!std::isfinite(rpm) || std::isnan(l)) return kNaN;
    return std::isinf(l) && l > 0.0 ? std::numeric_limits<double>::infinity() : contact::RatingLifeHours(l, rpm);
  };
  for (const double load : summary.mean_equivalent_load) {
    const double l10 = rating > 0.0 ? contact::RatingLife(rating, load) : kNaN;
    life.million_revolutions.push_back(l10);
    life.hours.push_back(hours(l10));
  }
  // The load-zone life, from each position's roller loads (contact/bearing.hpp). Which raceway
  // turns against the load follows from the element: the eccentric bearing of a cycloidal drive
  // carries the disc's whole reaction (mesh and output pins), which turns with the eccentric, the
  // inner ring, so the outer ring (the disc's bore) turns against it; a crank's needle bearing
  // carries the disc's share of the torque to the carrier, which holds the crank's axis, so the
  // load stands in the carrier's frame, as the disc's bore does (the disc translates on its
  // orbit), and the crankshaft's eccentric, the inner ring, turns against it. (Measured: over a
  // crank turn the eccentric bearing's load turns 356.7 deg, a crank bearing's -6.8 to -14.0 deg;
  // docs/derivations/load_zone_life.py.)
  const contact::BearingSettings* bearing = design.reducer ? &design.reducer->bearing : nullptr;
  const bool cranks = design.reducer && design.reducer->kind == solvers::OutputKind::kCranks;
  const contact::Raceway turning = cranks ? contact::Raceway::kInner : contact::Raceway::kOuter;
  life.turning_basis = cranks ? "the crank bearing's load goes to the carrier, which holds the crank's axis: it stands in the "
                                "carrier's frame with the disc's bore (the disc translates), and the crankshaft's eccentric, the "
                                "inner ring, turns against it"
                              : "the eccentric bearing's load, the disc's whole reaction, turns with the eccentric (the inner "
                                "ring): the outer ring, the disc's bore, turns against it";
  const bool rollers = bearing != nullptr && bearing->kind == contact::BearingKind::kRollers;
  const bool has_geometry = rollers && bearing->pitch_diameter > bearing->roller_diameter;
  const double reference = has_geometry && rating > 0.0 ? contact::LoadZoneReferenceDamage(*bearing) : kNaN;
  const double capacity_ratio = has_geometry ? contact::RacewayCapacityRatio(bearing->roller_diameter, bearing->pitch_diameter) : kNaN;
  for (std::size_t b = 0; b < summary.mean_equivalent_load.size(); ++b) {
    life.turning_raceway.push_back(turning);
    double load = kNaN;
    if (std::isfinite(reference) && b < summary.roller_moments.size() && !summary.roller_moments[b].empty()) {
      double damage = 0.0;  // Palmgren-Miner: the mean damage per revolution over the positions
      for (const contact::RollerLoadMoments& m : summary.roller_moments[b]) {
        damage += contact::LundbergPalmgrenDamage(m, capacity_ratio, turning);
      }
      load = contact::LoadZoneEquivalentLoad(damage / static_cast<double>(summary.roller_moments[b].size()), reference);
    }
    const double l = std::isfinite(load) ? contact::RatingLife(rating, load) : kNaN;
    life.load_zone_equivalent_load.push_back(load);
    life.load_zone_million_revolutions.push_back(l);
    life.load_zone_hours.push_back(hours(l));
    // Static: ISO 76's P_0 of a radial roller bearing is its radial load.
    const double p0 = b < summary.bearing_max_load.size() ? summary.bearing_max_load[b] : kNaN;
    const double c0 = bearing != nullptr ? bearing->static_load_rating : 0.0;
    life.static_safety.push_back(c0 > 0.0 && std::isfinite(p0) && p0 > 0.0 ? c0 / p0 : kNaN);
    const double q = b < summary.bearing_max_roller_load.size() ? summary.bearing_max_roller_load[b] : kNaN;
    life.max_roller_stress.push_back(has_geometry && std::isfinite(q) ? contact::RollerContactStress(*bearing, q) : kNaN);
  }
  // ISO 281:2007's modified rating life (9.3): a_ISO from kappa = nu / nu_1, e_C and C_u / P, on
  // each life with the load that gives it by ISO 281's formula (P the mean equivalent load, P_lz:
  // ISO/TS 16281's modified reference life a_ISO L_10r takes a_ISO at this equivalent reference load).
  if (!std::isnan(kinematic_viscosity) && bearing != nullptr) {
    life.modified = true;
    life.kinematic_viscosity = kinematic_viscosity;
    life.reference_viscosity = contact::ReferenceViscosity(rpm, bearing->pitch_diameter);
    life.viscosity_ratio = kinematic_viscosity / life.reference_viscosity;
    life.contamination_factor = bearing->contamination_factor;
    const bool given = bearing->fatigue_load_limit > 0.0;
    life.fatigue_load_limit = given ? bearing->fatigue_load_limit
                                    : contact::FatigueLoadLimitEstimate(bearing->static_load_rating, bearing->pitch_diameter);
    life.fatigue_load_limit_basis = given ? "given ([bearing] fatigue_load_limit_n)"
                                          : "ISO 281:2007 Annex B (B.20): C_0r / 8.2";
    const auto modify = [&](double load, double million_revolutions, std::vector<double>& ratio, std::vector<double>& a,
                            std::vector<double>& h) {
      // P = 0 (an idle bin): e_C C_u / P is infinite and a_ISO its cap; the life stays infinite.
      const double r = std::isnan(load) ? kNaN
                                        : (load > 0.0 ? life.contamination_factor * life.fatigue_load_limit / load
                                                      : std::numeric_limits<double>::infinity());
      const double factor = contact::LifeModificationFactor(life.viscosity_ratio, r);
      ratio.push_back(r);
      a.push_back(factor);
      h.push_back(hours(factor * million_revolutions));
    };
    for (std::size_t b = 0; b < summary.mean_equivalent_load.size(); ++b) {
      modify(summary.mean_equivalent_load[b], life.million_revolutions[b], life.load_ratio, life.life_modification,
             life.modified_hours);
      modify(life.load_zone_equivalent_load[b], life.load_zone_million_revolutions[b], life.load_zone_load_ratio,
             life.load_zone_life_modification, life.load_zone_modified_hours);
    }
  }
  return life;
}

SweepSummary SummaryAccumulator::Summary() const {
  SweepSummary s = s_;
  s.closed_period = closed_period;
  {
    Sweep swept;
    swept.crank_start = first_crank_;
    swept.crank_end = last_crank_;
    swept.positions = static_cast<int>(std::min<std::int64_t>(added_, Sweep::kMaxPositions));
    s.contact_cycles = cycles_.Finish(swept, closed_period, static_cast<int>(discs_));
  }
  if (s.succeeded > 0) {
    // A sweep's only success may be the repeated last state: it is the mean then.
    s.mean_te = te_count_ > 0 ? te_sum_ / static_cast<double>(te_count_) : te_lo_;
    s.pp_te = te_hi_ - te_lo_;
  }
  if (s.reducer && stage_count_ > 0) {
    const double n = static_cast<double>(stage_count_);
    for (const double sum : bearing_power_sum_) {
      s.reducer->mean_equivalent_load.push_back(std::pow(sum / n, 1.0 / contact::kRollerLifeExponent));
    }
    for (const double sum : share_sums_) s.reducer->energy_share.push_back(sum / n);
  }
  if (shares_ > 0) {
    s.first_disc_share_mean = share_count_ > 0 ? share_sum_ / static_cast<double>(share_count_) : s.first_disc_share_min;
  }
  return s;
}

namespace {

/// A hint that [load] torque_nm was typed in N*mm (issue 54: 412,000 for 412 N*m ended as
/// law-cannot-carry naming no unit): when every position fails because the law cannot carry the
/// load, or the largest Hertz stress is beyond kImplausible times the material's limit (a steel
/// contact yields long before; a 1000x torque raises the stress about sqrt(1000) = 32x).
std::string UnitHint(double torque, const SweepSummary& s, const contact::Material& material) {
  constexpr double kImplausible = 5.0;
  const bool cannot_carry = s.succeeded == 0 && s.status == SolverStatus::kLawCannotCarry;
  const double ratio = s.max_contact_stress / material.contact_stress_limit;
  if (!cannot_carry && !(ratio > kImplausible)) return {};
  const double nm = units::NmmToNm(torque);
  return fmt::format("[load] torque_nm = {:g} N*m {}: if it was meant in N*mm, it is {:g} N*m (units are in the keys' "
                     "names, docs/units.md)",
                     nm,
                     cannot_carry ? "is more than the contact law can carry at every position"
                                  : fmt::format("gives {:.3g} times [material] contact_stress_limit_mpa", ratio),
                     nm / 1000.0);
}

}  // namespace

struct SweepRunner::Impl {
  Stage stage;
  SolverOptions options;
  std::unique_ptr<LoadSolver> solver;
  solvers::Workspace workspace;  // this sweep's warm starts: one runner per thread
  double torque;
  SummaryAccumulator summary;
  Clock::duration elapsed{};
  // The last crank's state repeats the first's (a closed period, contact::SameMesh): the mean
  // weights it once.
  double last_crank = 0.0;

  Impl(const Stage& s, const SolverOptions& o, double t)
      : stage(s), options(o), solver(solvers::MakeSolver(o.name)), torque(t) {
    summary.closed_period = stage.closed_period();
    if (!stage.cranks().empty()) last_crank = stage.cranks().back();
  }
};

SweepRunner::SweepRunner(const Stage& stage, const SolverOptions& options, double torque) {
  const auto start = Clock::now();
  options.Validate();
  impl_ = std::make_unique<Impl>(stage, options, torque);
  impl_->elapsed = Clock::now() - start;
}
SweepRunner::~SweepRunner() = default;
SweepRunner::SweepRunner(SweepRunner&&) noexcept = default;
SweepRunner& SweepRunner::operator=(SweepRunner&&) noexcept = default;

const SolverOptions& SweepRunner::options() const { return impl_->options; }

PositionResult SweepRunner::Solve(double crank) {
  const auto start = Clock::now();
  Impl& m = *impl_;
  const solvers::LoadProblem problem = m.stage.Problem(crank, m.torque);
  PositionResult pos;
  pos.crank = crank;
  pos.result = m.solver->Solve(problem, m.options, m.workspace);
  std::vector<contact::ContactLaw> scratch;
  const auto points = problem.At(std::isfinite(pos.result.rotation) ? pos.result.rotation : 0.0, m.workspace, &scratch);
  const auto& base = problem.base_state().pins;
  // Per pin of every disc: disc 1's pins, then disc 2's.
  const contact::MeshModel& model = m.stage.model();
  const auto pins = static_cast<std::size_t>(model.pin_count() * problem.disc_count());
  const auto per_disc = static_cast<std::size_t>(model.pin_count());
  pos.slices = model.slice_count();
  pos.angle.assign(pins, 0.0);
  pos.pin_force.assign(pins, 0.0);
  pos.contact_stress.assign(pins, 0.0);
  pos.point_stress.assign(points.size(), 0.0);
  pos.load_centroid.assign(pins, std::numeric_limits<double>::quiet_NaN());
  std::vector<double> moment(pins, 0.0);  // sum F z per pin, N*mm
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto j = static_cast<std::size_t>(base[i].disc) * per_disc + static_cast<std::size_t>(base[i].pin);
    if (base[i].slice == 0) pos.angle[j] = base[i].angle;
    const double f = i < pos.result.force.size() ? pos.result.force[i] : 0.0;
    pos.pin_force[j] += f;
    moment[j] += f * base[i].z;
    if (f > 0.0 && points[i].law != nullptr) pos.point_stress[i] = points[i].law->MaxPressure(f);
    pos.contact_stress[j] = std::max(pos.contact_stress[j], pos.point_stress[i]);
  }
  const double f_max = pos.pin_force.empty() ? 0.0 : *std::max_element(pos.pin_force.begin(), pos.pin_force.end());
  for (std::size_t j = 0; j < pins; ++j) {
    if (pos.pin_force[j] > kContactForceFraction * f_max && f_max > 0.0) ++pos.contacts;
    if (pos.pin_force[j] > 0.0) pos.load_centroid[j] = moment[j] / pos.pin_force[j];
  }
  // A relieved tip that carries load is reported as such: the user's relief is used as
  // given, and its contact (a small convex radius: a high stress) is a fact the user must see.
  const bool relieved = model.profile().tip_cap().active() ||
                        (m.stage.disc_count() == 2 && m.stage.model(1).profile().tip_cap().active());
  if (relieved && pos.succeeded()) {
    const bool exact = problem.kinematics() == contact::ContactKinematics::kExact;
    for (std::size_t i = 0; i < points.size() && i < pos.result.force.size(); ++i) {
      const double f = pos.result.force[i];
      if (!(f > kContactForceFraction * f_max)) continue;
      const geometry::SurfacePart part = exact ? problem.EvaluatePin(base[i], pos.result.rotation).part : base[i].part;
      if (part == geometry::SurfacePart::kFlank) continue;
      pos.result.warnings.push_back(fmt::format("{}pin {} bears {:.4g} N on the {} of a relieved tip ({:.4g} MPa)",
                                                problem.disc_count() == 2 ? fmt::format("disc {} ", base[i].disc + 1) : "",
                                                base[i].pin + 1, f, geometry::SurfacePartName(part), pos.point_stress[i]));
    }
  }
  if (problem.disc_count() == 2) {
    pos.disc_torque = pos.succeeded() ? problem.DiscTorques(pos.result.rotation, pos.result.force, m.workspace)
                                      : std::vector<double>(2, std::numeric_limits<double>::quiet_NaN());
  }
  m.summary.Add(pos, !(m.summary.closed_period && crank == m.last_crank));
  m.elapsed += Clock::now() - start;
  return pos;
}

SweepSummary SweepRunner::Summary() const {
  SweepSummary s = impl_->summary.Summary();
  s.wall_seconds = std::chrono::duration<double>(impl_->elapsed).count();
  if (std::string note = impl_->stage.SamplingNote(); !note.empty()) s.notes.push_back(std::move(note));
  if (std::string note = UnitHint(impl_->torque, s, impl_->stage.material()); !note.empty()) s.notes.push_back(std::move(note));
  return s;
}

SweepResult SolveSweep(const Stage& stage, const SolverOptions& options, double torque, const SweepCallbacks& callbacks) {
  SweepRunner runner(stage, options, torque);
  SweepResult sweep;
  sweep.solver = options.name;
  sweep.options = options;
  for (const double crank : stage.cranks()) {
    PositionResult pos = runner.Solve(crank);
    if (callbacks.on_position) callbacks.on_position(pos);
    if (callbacks.keep_positions) sweep.positions.push_back(std::move(pos));
  }
  sweep.summary = runner.Summary();
  return sweep;
}

}  // namespace ltca::analysis
