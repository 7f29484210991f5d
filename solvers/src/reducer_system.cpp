#include "reducer_system.hpp"

#include <algorithm>
#include <optional>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <fmt/format.h>

#include "coupled_contact.hpp"
#include "ltca/contact/cranks.hpp"
#include "ltca/contact/output_pins.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::solvers {

void ReducerSystem::Row::Add(int i, double v) {
  if (v == 0.0 || i < 0) return;
  for (int k = 0; k < n; ++k) {
    if (index[static_cast<std::size_t>(k)] == i) {
      value[static_cast<std::size_t>(k)] += v;
      return;
    }
  }
  if (n == static_cast<int>(index.size())) throw std::logic_error("ReducerSystem::Row: more than 6 non-zeros");
  index[static_cast<std::size_t>(n)] = i;
  value[static_cast<std::size_t>(n)] = v;
  ++n;
}

double ReducerSystem::Row::Dot(const Eigen::VectorXd& x) const {
  double s = 0.0;
  for (int k = 0; k < n; ++k) s += value[static_cast<std::size_t>(k)] * x(index[static_cast<std::size_t>(k)]);
  return s;
}

ReducerSystem::Row ReducerSystem::ToDofs(const Row& coordinates) const {
  Row out;
  for (int k = 0; k < coordinates.n; ++k) {
    const auto c = static_cast<std::size_t>(coordinates.index[static_cast<std::size_t>(k)]);
    out.Add(coordinate_dof_[c], coordinates.value[static_cast<std::size_t>(k)] * coordinate_scale_[c]);
  }
  return out;
}

Eigen::VectorXd ReducerSystem::Coordinates(const Eigen::VectorXd& q) const {
  Eigen::VectorXd c = Eigen::VectorXd::Zero(coordinate_count());
  for (std::size_t i = 0; i < coordinate_dof_.size(); ++i) {
    if (coordinate_dof_[i] >= 0) c(static_cast<Eigen::Index>(i)) = coordinate_scale_[i] * q(coordinate_dof_[i]);
  }
  return c;
}

bool ReducerSystem::ElementsPreloaded(double tolerance) const {
  for (const Scalar& e : scalars_) {
    if (e.group == StageGroup::kOutput && e.gap < -tolerance) return true;
    // A needle roller on the elastic body: its bearing preloaded, as the planar element's test.
    if (e.group == StageGroup::kBearings && Bearing(e.disc).radial_clearance < 0.0) return true;
  }
  for (const Planar& p : planars_) {
    if (!p.shaft && Bearing(p).kind != contact::BearingKind::kRigid && Bearing(p).radial_clearance < 0.0) return true;
  }
  return false;
}

contact::ContactLaw ReducerSystem::OutputPinLaw(const LoadProblem& problem) {
  // An elastic disc body condensed at its holes: the hole's term is the local field beyond the
  // body's patch, as the flank's (the same w0: contact::DiscFlankCompliance::cycloid_log_radius_mm).
  const double hole_log_radius =
      problem.stage_body_coupling() != nullptr ? problem.contact_settings().cycloid_log_radius : 0.0;
  return contact::OutputPinLaw(problem.contact_settings(), problem.material(), problem.reducer()->pins,
                               problem.model().pair().face_width, problem.log_radius_cap(), hole_log_radius);
}

contact::ContactLaw ReducerSystem::CrankRollerLaw(const LoadProblem& problem) {
  // The bearing's own law, Palmgren's for both raceways, and with an elastic disc body condensed
  // at its crank holes the raceway's local field beyond the body's patches in place of the one a
  // rigid law's reference depth holds (docs/fe_disc.md "The RV disc"): the disc side's Hertz term
  // C (ln(4 r_h / b) - 1/2) of a concave raceway of radius r_h = (d_m + D_w) / 2 becomes C (ln(4
  // rho_e / b) - 1/2), rho_e = w0 / sqrt(e), as for the flank and the output-pin holes: a linear
  // term (2 / (pi B)) C ln(rho_e / r_h) Q, C = (1 - nu^2) / E of the disc, B its face width.
  const contact::BearingSettings& b = problem.reducer()->bearing;
  double linear = 0.0;
  if (problem.stage_body_coupling() != nullptr) {
    const double rho_e = problem.contact_settings().cycloid_log_radius;
    const double hole = 0.5 * (b.pitch_diameter + b.roller_diameter);
    const contact::Material& m = problem.material();
    const double c = (1.0 - m.poisson_ratio * m.poisson_ratio) / m.young_modulus;
    linear = 2.0 / (units::kPi * problem.model().pair().face_width) * c * std::log(rho_e / hole);
  }
  return contact::ContactLaw::Roller(b.roller_length, linear);
}

Eigen::Vector2d ReducerSystem::Displacement(const Planar& p, const Eigen::VectorXd& q) {
  return Eigen::Vector2d(p.row[0].Dot(q), p.row[1].Dot(q)) + p.offset;
}

Eigen::Vector2d ReducerSystem::DisplacementAt(const Planar& p, const Eigen::VectorXd& c) {
  return Eigen::Vector2d(p.coordinates[0].Dot(c), p.coordinates[1].Dot(c)) + p.offset;
}

ReducerSystem::ReducerSystem(const LoadProblem& problem, CoupledContact* coupled) : problem_(&problem), coupled_(coupled) {
  Build(problem, nullptr);
}

ReducerSystem::ReducerSystem(const LoadProblem& problem, const Eigen::VectorXd& origin, CoupledContact* coupled)
    : problem_(&problem), coupled_(coupled) {
  Build(problem, &origin);
}

void ReducerSystem::Build(const LoadProblem& problem, const Eigen::VectorXd* origin) {
  if (problem.reducer() == nullptr) throw std::invalid_argument("ReducerSystem: the problem has no reducer");
  settings_ = *problem.reducer();
  second_bearing_ = settings_.BearingOf(1);
  discs_ = problem.disc_count();
  radius_ = problem.model().pair().pin_circle_radius;
  torque_ = problem.torque();
  // The problem's frame: a rotation in it is s times the counterclockwise angle.
  const double s = problem.model().load_direction() * problem.direction();
  const bool cranks = settings_.kind == OutputKind::kCranks;
  crank_count_ = cranks ? settings_.cranks.count : 0;
  const bool bearing_compliant = settings_.bearing.kind != contact::BearingKind::kRigid;
  const bool shaft_compliant = cranks && std::isfinite(settings_.cranks.shaft_stiffness);
  shaft_beam_ = cranks && (settings_.cranks.beam.given() || settings_.cranks.shaft_compliance.has_value());
  if (shaft_beam_) {
    if (!bearing_compliant || discs_ != 2) {
      throw std::invalid_argument("[output] shaft_diameter_mm: a crankshaft as a beam carries both discs' eccentrics in "
                                  "their needle bearings; expected [second_disc] and a linear or rollers [bearing]");
    }
    contact::ShaftCompliance parts;
    if (settings_.cranks.shaft_compliance) {
      parts.beam = *settings_.cranks.shaft_compliance;
    } else {
      parts = contact::CrankshaftCompliance(settings_.cranks.beam, problem.material().young_modulus,
                                            problem.material().poisson_ratio);
    }
    beam_compliance_ = parts.total();
    beam_part_ = parts.beam;
    const Eigen::LDLT<Eigen::Matrix2d> ldlt(beam_compliance_);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || !(ldlt.vectorD().minCoeff() > 0.0)) {
      throw std::invalid_argument("[output] shaft_diameter_mm: the crankshaft's compliance is not positive definite");
    }
    beam_stiffness_ = ldlt.solve(Eigen::Matrix2d::Identity());
  }
  shaft_coordinates_ = bearing_compliant && (shaft_compliant || shaft_beam_);
  if (shaft_compliant) {
    shaft_.kind = contact::BearingKind::kLinear;
    shaft_.radial_stiffness = settings_.cranks.shaft_stiffness;
  }

  // Coordinates and dofs: a rigid eccentric bearing holds its disc's centre.
  psi_coordinate_ = 3 * discs_;
  const int coordinates = psi_coordinate_ + 1 + (shaft_coordinates_ ? 2 * discs_ * crank_count_ : 0);
  coordinate_dof_.assign(static_cast<std::size_t>(coordinates), -1);
  coordinate_scale_.assign(static_cast<std::size_t>(coordinates), 1.0);
  for (int c = 0; c < coordinates; ++c) {
    const bool translation = c < psi_coordinate_ && c % 3 != 2;
    const bool rotation = c == psi_coordinate_ || (c < psi_coordinate_ && c % 3 == 2);
    if (translation && !cranks && !bearing_compliant) continue;
    coordinate_dof_[static_cast<std::size_t>(c)] = dofs_++;
    coordinate_scale_[static_cast<std::size_t>(c)] = rotation ? 1.0 / radius_ : 1.0;
  }
  // Loads besides T (StageLoads): each disc's force on x, y and moment on phi, the output's on psi.
  applied_ = Eigen::VectorXd::Zero(coordinates);
  if (const StageLoads* loads = problem.stage_loads()) {
    for (std::size_t d = 0; d < loads->discs.size() && static_cast<int>(d) < discs_; ++d) {
      const auto at = static_cast<Eigen::Index>(3 * d);
      applied_(at) = loads->discs[d].force.x();
      applied_(at + 1) = loads->discs[d].force.y();
      applied_(at + 2) = loads->discs[d].moment;
    }
    applied_(psi_coordinate_) = loads->output_moment;
  }
  origin_ = Eigen::VectorXd::Zero(coordinates);
  exact_ = origin != nullptr;
  if (origin != nullptr) {
    if (origin->size() != coordinates) throw std::invalid_argument("ReducerSystem: the origin has another layout");
    origin_ = *origin;
  }
  const auto translation_of = [&](int d) { return Eigen::Vector2d(origin_(3 * d), origin_(3 * d + 1)); };
  const double psi0 = origin_(psi_coordinate_);

  // The pin ring: today's points; the disc's translation t closes a gap by n . t.
  const contact::MeshState& base = problem.base_state();
  laws_.reserve(base.pins.size() + static_cast<std::size_t>(discs_ * std::max(settings_.pins.count, 0)));
  for (std::size_t i = 0; i < base.pins.size(); ++i) {
    // Exact kinematics: the point where the disc is (its rotation and its moved centre).
    const int d = base.pins[i].disc;
    const contact::PinContact pin = origin == nullptr ? base.pins[i]
                                                      : problem.EvaluatePin(base.pins[i], origin_(3 * d + 2), translation_of(d));
    Scalar e;
    e.coordinates.Add(3 * d, pin.normal.x());
    e.coordinates.Add(3 * d + 1, pin.normal.y());
    e.coordinates.Add(3 * d + 2, pin.arm);
    e.gap = pin.clearance;
    e.direction = pin.normal;
    if (!pin.edge) {
      e.law = static_cast<int>(laws_.size());
      laws_.push_back(origin == nullptr ? problem.base_laws()[i] : problem.LawOf(pin));
    }
    e.group = StageGroup::kMesh;
    e.disc = d;
    e.index = static_cast<int>(i);
    scalars_.push_back(e);
  }
  mesh_points_ = static_cast<int>(base.pins.size());
  coupled_points_ = mesh_points_;
  if (problem.has_coupling()) {
    coupling_ = problem.coupling();
    force_scale_ = CoupledForceScale(problem);
    if (const LoadProblem::StageBodyCoupling* body = problem.stage_body_coupling()) {
      // The elastic disc body: its holes' contacts (every disc's output pins in pin order, or
      // every disc's needle rollers, added below) join the coupled set after the problem's points.
      coupling_ = body->total.get();
      body_coupling_ = body->body.get();
      coupled_points_ += body->output_points;
    }
  }
  if (coupling_ != nullptr && coupled_ != nullptr) {
    // Pin bending: C couples the points of one pin's beam. Its blocks are the connected
    // sets of its non-zeros (one pin's slices), each kept dense for the Hessian's condensation;
    // only a system that evaluates needs them (a judge's system has no coupled solver).
    std::vector<int> parent(static_cast<std::size_t>(coupled_points_));
    for (int i = 0; i < coupled_points_; ++i) parent[static_cast<std::size_t>(i)] = i;
    const auto root = [&](int i) {
      while (parent[static_cast<std::size_t>(i)] != i) i = parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
      return i;
    };
    for (int k = 0; k < coupling_->outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(*coupling_, k); it; ++it) {
        const int a = root(static_cast<int>(it.row())), b = root(static_cast<int>(it.col()));
        if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
      }
    }
    std::vector<int> block_of(static_cast<std::size_t>(coupled_points_), -1);
    for (int i = 0; i < coupled_points_; ++i) {
      const int r = root(i);
      if (block_of[static_cast<std::size_t>(r)] < 0) {
        block_of[static_cast<std::size_t>(r)] = static_cast<int>(blocks_.size());
        blocks_.emplace_back();
      }
      blocks_[static_cast<std::size_t>(block_of[static_cast<std::size_t>(r)])].points.push_back(i);
    }
    for (Block& b : blocks_) {
      const auto m = static_cast<Eigen::Index>(b.points.size());
      b.c.resize(m, m);
      for (Eigen::Index x = 0; x < m; ++x) {
        for (Eigen::Index y = 0; y < m; ++y) b.c(x, y) = coupling_->coeff(b.points[static_cast<std::size_t>(x)], b.points[static_cast<std::size_t>(y)]);
      }
    }
  }

  // The output member's nominal rotation: the first disc's (the holes and cranks of every disc
  // sit where the output member's pins and cranks are at the nominal poses).
  const double output_rotation = problem.model().kinematics().CycloidPose(problem.crank()).rotation;
  // The output pins' law, one for every pin of every disc.
  const std::optional<contact::ContactLaw> pin_law = cranks ? std::nullopt : std::optional(OutputPinLaw(problem));
  // An elastic disc body on the crank holes: every needle roller a scalar contact of the coupled
  // set, on its hole's wall (disc by disc, crank by crank, roller by roller after the pin ring),
  // in place of the bearing's planar element.
  const bool rollers_coupled = cranks && coupled_points_ > mesh_points_;
  int roller_law = -1;
  if (rollers_coupled) {
    if (settings_.bearing.kind != contact::BearingKind::kRollers) {
      throw std::logic_error("ReducerSystem: an elastic disc body on crank holes needs roller bearings");
    }
    roller_law = static_cast<int>(laws_.size());
    laws_.push_back(CrankRollerLaw(problem));
  }
  // Roller k of the crank bearing p (its u rows and offset set) as a scalar: approach u . e_k - c.
  const auto add_rollers = [&](const Planar& p) {
    const contact::BearingSettings& bearing = Bearing(p);
    const int z = bearing.roller_count;
    for (int k = 0; k < z; ++k) {
      const double angle = p.phase + 2.0 * units::kPi * k / z;
      const Eigen::Vector2d e(std::cos(angle), std::sin(angle));
      Scalar r;
      for (int a = 0; a < 2; ++a) {
        const Row& row = p.coordinates[static_cast<std::size_t>(a)];
        for (int i = 0; i < row.n; ++i) {
          r.coordinates.Add(row.index[static_cast<std::size_t>(i)], e(a) * row.value[static_cast<std::size_t>(i)]);
        }
      }
      r.gap = bearing.radial_clearance - p.offset.dot(e);
      r.law = roller_law;
      r.direction = e;  // the roller's force on the disc (the hole's outward normal there)
      r.group = StageGroup::kBearings;
      r.disc = p.disc;
      r.index = p.index * z + k;
      scalars_.push_back(r);
    }
  };
  for (int d = 0; d < discs_; ++d) {
    const geometry::Pose real = problem.DiscModel(d).real_pair().CycloidPose(problem.DiscCrank(d));
    // The disc where it is (nominal, or the origin's pose: its centre moved, its rotation added in
    // the problem's frame), and the output member turned by the origin's psi.
    const geometry::Pose holes{real.centre + translation_of(d), output_rotation + s * origin_(3 * d + 2)};
    const double output_at = output_rotation + s * psi0;
    const double eccentric_direction = std::atan2(real.centre.y(), real.centre.x());
    if (!cranks) {
      const contact::OutputPins pins = settings_.PinsOf(d);  // this disc's holes
      for (const contact::OutputPinContact& c : contact::EvaluateOutputPins(pins, holes, output_at)) {
        Scalar e;
        e.coordinates.Add(3 * d, c.translation_gradient.x());
        e.coordinates.Add(3 * d + 1, c.translation_gradient.y());
        e.coordinates.Add(3 * d + 2, s * c.disc_arm);
        e.coordinates.Add(psi_coordinate_, s * c.output_arm);
        e.gap = c.gap;
        e.law = static_cast<int>(laws_.size());
        laws_.push_back(*pin_law);
        e.direction = c.normal;
        e.group = StageGroup::kOutput;
        e.disc = d;
        e.index = c.pin;
        scalars_.push_back(e);
      }
      if (bearing_compliant) {
        // The eccentric (inner member) relative to the disc's bore (outer): u = -t.
        Planar p;
        p.coordinates[0].Add(3 * d, -1.0);
        p.coordinates[1].Add(3 * d + 1, -1.0);
        p.offset = -translation_of(d);
        p.phase = eccentric_direction;
        p.group = StageGroup::kBearings;
        p.disc = d;
        planars_.push_back(p);
      }
      continue;
    }
    // The eccentric keeps its direction, or turns k times the output member's rotation.
    const double turn = settings_.cranks.turns_per_output_turn * s * psi0;
    const Eigen::Vector2d eccentric = Eigen::Rotation2Dd(turn) * real.centre;
    for (const contact::CrankContact& c : contact::EvaluateCranks(settings_.CranksOf(d), holes, output_at, eccentric)) {
      std::array<Row, 2> u;
      for (int a = 0; a < 2; ++a) {
        u[static_cast<std::size_t>(a)].Add(3 * d + a, -1.0);
        u[static_cast<std::size_t>(a)].Add(3 * d + 2, s * c.disc_rotation_gradient(a));
        u[static_cast<std::size_t>(a)].Add(psi_coordinate_, s * c.output_gradient(a));
      }
      Planar p;
      p.offset = c.offset;
      p.phase = eccentric_direction;
      p.disc = d;
      p.index = c.crank;
      if (shaft_coordinates_) {
        // The needle bearing sees u + v, v the shaft's deflection at the eccentric; the shaft
        // stores k |v|^2 / 2.
        const int v = psi_coordinate_ + 1 + 2 * (d * crank_count_ + c.crank);
        const Eigen::Vector2d v0(origin_(v), origin_(v + 1));
        p.offset += v0;
        Planar shaft = p;
        shaft.offset = v0;
        shaft.shaft = true;
        shaft.group = StageGroup::kShafts;
        for (int a = 0; a < 2; ++a) {
          u[static_cast<std::size_t>(a)].Add(v + a, 1.0);
          shaft.coordinates[static_cast<std::size_t>(a)].Add(v + a, 1.0);
        }
        p.coordinates = u;
        p.group = StageGroup::kBearings;
        if (rollers_coupled) add_rollers(p);
        else planars_.push_back(p);
        if (!shaft_beam_) planars_.push_back(shaft);  // a beam's energy couples both discs' (EvaluateBeams)
      } else {
        p.coordinates = u;
        p.shaft = !bearing_compliant;
        p.group = bearing_compliant ? StageGroup::kBearings : StageGroup::kShafts;
        if (rollers_coupled) add_rollers(p);
        else planars_.push_back(p);
      }
    }
  }
  if (coupled_points_ > mesh_points_) {
    // The body's hole rows are every disc's output pins (disc, pin) or needle rollers (disc,
    // crank, roller), right after the pin ring.
    if (static_cast<int>(scalars_.size()) < coupled_points_) {
      throw std::logic_error("ReducerSystem: the disc body's coupled set is larger than the stage's elements");
    }
    int expected = 0, disc = 0;
    for (int i = mesh_points_; i < coupled_points_; ++i) {
      const Scalar& e = scalars_.at(static_cast<std::size_t>(i));
      if (e.disc == disc + 1) disc = e.disc, expected = 0;
      const StageGroup group = rollers_coupled ? StageGroup::kBearings : StageGroup::kOutput;
      if (e.group != group || e.index != expected++ || e.disc != disc) {
        throw std::logic_error("ReducerSystem: the disc body's coupled hole contacts are not in order");
      }
    }
  }
  for (Scalar& e : scalars_) e.row = ToDofs(e.coordinates);
  for (Planar& p : planars_) {
    p.row[0] = ToDofs(p.coordinates[0]);
    p.row[1] = ToDofs(p.coordinates[1]);
  }
}

void ReducerSystem::Evaluate(const Eigen::VectorXd& q, bool with_hessian, std::vector<double>* hints,
                           Evaluation* out) const {
  const Eigen::Index n = dofs_;
  out->gradient.setZero(n);
  if (with_hessian) out->hessian.setZero(n, n);
  out->saturated = false;
  out->edge = false;
  out->energy_rounding = 0.0;
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const int psi = output_dof();
  out->energy = -torque_ * q(psi) / radius_;
  out->gradient(psi) = -torque_ / radius_;
  if (hints != nullptr && hints->size() != scalars_.size()) hints->assign(scalars_.size(), 0.0);
  out->failure.clear();
  Eigen::VectorXd magnitude = Eigen::VectorXd::Zero(n);
  magnitude(psi) = torque_ / radius_;
  for (std::size_t c = 0; c < coordinate_dof_.size(); ++c) {  // the loads besides T: their work
    const double f = applied_(static_cast<Eigen::Index>(c));
    const int k = coordinate_dof_[c];
    if (f == 0.0 || k < 0) continue;
    out->energy -= f * coordinate_scale_[c] * q(k);
    out->gradient(k) -= f * coordinate_scale_[c];
    magnitude(k) += std::abs(f) * coordinate_scale_[c];
  }
  if (coupling_ != nullptr) {
    EvaluateCoupled(q, with_hessian, hints, out, &magnitude);
    if (!out->failure.empty()) return;
  }
  for (std::size_t i = coupling_ != nullptr ? static_cast<std::size_t>(coupled_points_) : 0; i < scalars_.size(); ++i) {
    const Scalar& e = scalars_[i];
    const double delta = e.row.Dot(q) - e.gap;
    if (!(delta > 0.0)) continue;
    if (e.law < 0) {
      out->edge = true;
      continue;
    }
    const contact::ContactLaw& law = laws_[static_cast<std::size_t>(e.law)];
    const double f = hints != nullptr ? law.Force(delta, &(*hints)[i]) : law.Force(delta);
    double k = 0.0;
    if (f >= law.max_force()) {
      out->saturated = true;
    } else {
      const double compliance = law.Compliance(f);
      k = compliance > 0.0 && std::isfinite(compliance) ? 1.0 / compliance : 0.0;
    }
    out->energy += law.StrainEnergy(delta, f);  // F delta - E^c(F), f the law's force at delta
    // The approach is resolved to eps times the terms it sums: a force to k times that.
    double reach = std::abs(e.gap);
    for (int a = 0; a < e.row.n; ++a) reach += std::abs(e.row.value[static_cast<std::size_t>(a)] * q(e.row.index[static_cast<std::size_t>(a)]));
    out->energy_rounding += kEps * std::abs(f) * reach;
    for (int a = 0; a < e.row.n; ++a) {
      const auto ia = static_cast<std::size_t>(a);
      out->gradient(e.row.index[ia]) += f * e.row.value[ia];
      magnitude(e.row.index[ia]) += (std::abs(f) + k * reach) * std::abs(e.row.value[ia]);
      if (!with_hessian) continue;
      for (int b = 0; b < e.row.n; ++b) {
        const auto ib = static_cast<std::size_t>(b);
        out->hessian(e.row.index[ia], e.row.index[ib]) += k * e.row.value[ia] * e.row.value[ib];
      }
    }
  }
  for (const Planar& p : planars_) {
    const Eigen::Vector2d u = Displacement(p, q);
    // A preloaded roller bearing (radial_clearance < 0): its force and energy are sums of roller
    // loads of K_n p^(10/9) each even where the net force vanishes; their sum is the size the
    // rounding scales with (docs/stage.md "Preload"). Without a preload the net force, as before.
    const bool preloaded_rollers = Bearing(p).kind == contact::BearingKind::kRollers && Bearing(p).radial_clearance < 0.0;
    const contact::BearingResponse r = contact::BearingAt(Bearing(p), u, p.phase, preloaded_rollers);
    double carried = r.force.lpNorm<1>();
    if (preloaded_rollers) {
      carried = 0.0;
      for (const double load : r.roller_load) carried += load;
    }
    out->energy += r.energy;
    double reach = p.offset.lpNorm<1>() + std::abs(Bearing(p).radial_clearance);
    for (const Row& row : p.row) {
      for (int a = 0; a < row.n; ++a) reach += std::abs(row.value[static_cast<std::size_t>(a)] * q(row.index[static_cast<std::size_t>(a)]));
    }
    out->energy_rounding += kEps * carried * reach;
    const Eigen::Vector2d du = -r.force;  // dE/du
    for (int a = 0; a < 2; ++a) {
      const Row& ra = p.row[static_cast<std::size_t>(a)];
      for (int i = 0; i < ra.n; ++i) {
        const auto ii = static_cast<std::size_t>(i);
        out->gradient(ra.index[ii]) += du(a) * ra.value[ii];
        magnitude(ra.index[ii]) += preloaded_rollers ? carried * std::abs(ra.value[ii]) : std::abs(du(a) * ra.value[ii]);
        if (!with_hessian) continue;
        for (int b = 0; b < 2; ++b) {
          const Row& rb = p.row[static_cast<std::size_t>(b)];
          for (int j = 0; j < rb.n; ++j) {
            const auto jj = static_cast<std::size_t>(j);
            out->hessian(ra.index[ii], rb.index[jj]) += r.stiffness(a, b) * ra.value[ii] * rb.value[jj];
          }
        }
      }
    }
  }
  if (shaft_beam_) {
    // Crankshafts as beams: per crank and direction v = (v_1, v_2), the two discs' deflections at
    // their eccentrics (absolute: the origin's and the step's), energy v^T K v / 2.
    for (int j = 0; j < crank_count_; ++j) {
      for (int a = 0; a < 2; ++a) {
        const std::array<int, 2> c{ShaftCoordinate(0, j) + a, ShaftCoordinate(1, j) + a};
        const std::array<int, 2> i{coordinate_dof_[static_cast<std::size_t>(c[0])], coordinate_dof_[static_cast<std::size_t>(c[1])]};
        const Eigen::Vector2d v(origin_(c[0]) + q(i[0]), origin_(c[1]) + q(i[1]));
        const Eigen::Vector2d f = beam_stiffness_ * v;
        out->energy += 0.5 * v.dot(f);
        out->energy_rounding += kEps * (f.cwiseAbs().dot(v.cwiseAbs()));
        for (int x = 0; x < 2; ++x) {
          out->gradient(i[static_cast<std::size_t>(x)]) += f(x);
          magnitude(i[static_cast<std::size_t>(x)]) += std::abs(beam_stiffness_(x, 0) * v(0)) + std::abs(beam_stiffness_(x, 1) * v(1));
          if (!with_hessian) continue;
          for (int y = 0; y < 2; ++y) out->hessian(i[static_cast<std::size_t>(x)], i[static_cast<std::size_t>(y)]) += beam_stiffness_(x, y);
        }
      }
    }
  }
  out->rounding = 16.0 * std::numeric_limits<double>::epsilon() * magnitude.maxCoeff();
}

ReducerSystem::CoupledForces ReducerSystem::SolveCoupled(const std::vector<double>& approach, std::vector<double>* force) const {
  if (coupled_ == nullptr) throw std::logic_error("ReducerSystem: pin bending's coupling needs the coupled contact solver");
  std::vector<CoupledPoint> points(static_cast<std::size_t>(coupled_points_));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int law = scalars_[i].law;
    points[i].law = law >= 0 ? &laws_[static_cast<std::size_t>(law)] : nullptr;
    points[i].approach = approach[i];
  }
  const CoupledOutcome o = coupled_->AtRotation(points, force_scale_, force);
  return {o.converged, o.saturated, o.edge,
          o.converged ? std::string()
                      : fmt::format("the pins' coupled contact problem ({}): {}",
                                    body_coupling_ != nullptr ? "the elastic disc body" : "pin bending",
                                    o.failure.empty() ? "did not converge" : o.failure)};
}

// Pin bending in the stage (the stage with the pin-bending coupling). The deformed gap of pin-ring point
// i is w_i(F_i) + (C F)_i - delta_i(q), with delta_i = row_i . q - gap_i its approach under the
// poses. The pin ring's energy at q is the condensed one,
//   E(delta) = max over F >= 0 of  F . delta - sum_i W*_i(F_i) - F^T C F / 2,
// (W*_i the complementary energy of point i's law): convex in delta, its maximiser the coupled
// contact solution at those approaches (CoupledContact::AtRotation), its gradient F (Danskin) and,
// on the loaded set A, its Hessian (D_A + C_AA)^-1 with D_i = w_i'(F_i) the tangent compliance.
// C couples the slices of one pin only, so the Hessian's condensation is a dense solve per pin.
void ReducerSystem::EvaluateCoupled(const Eigen::VectorXd& q, bool with_hessian, std::vector<double>* hints,
                                  Evaluation* out, Eigen::VectorXd* magnitude) const {
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const auto points = static_cast<std::size_t>(coupled_points_);
  std::vector<double> approach(points), force(points, 0.0);
  for (std::size_t i = 0; i < points; ++i) {
    approach[i] = scalars_[i].row.Dot(q) - scalars_[i].gap;
    if (hints != nullptr) force[i] = (*hints)[i];  // the last evaluation's forces: a warm start
  }
  const CoupledForces solved = SolveCoupled(approach, &force);
  if (!solved.converged) {
    out->failure = solved.failure;
    out->energy = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  if (hints != nullptr) std::copy(force.begin(), force.end(), hints->begin());
  out->saturated = out->saturated || solved.saturated;
  out->edge = out->edge || solved.edge;
  const Eigen::Map<const Eigen::VectorXd> f(force.data(), static_cast<Eigen::Index>(points));
  const Eigen::VectorXd cf = *coupling_ * f;
  out->energy -= 0.5 * f.dot(cf);
  for (std::size_t i = 0; i < points; ++i) {
    const Scalar& e = scalars_[i];
    const double fi = force[i];
    if (!(fi > 0.0) || e.law < 0) continue;
    const contact::ContactLaw& law = laws_[static_cast<std::size_t>(e.law)];
    out->energy += fi * approach[i] - law.ComplementaryEnergy(fi);
    const double compliance = law.Compliance(fi) + coupling_->coeff(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i));
    const double k = compliance > 0.0 && std::isfinite(compliance) ? 1.0 / compliance : 0.0;
    double reach = std::abs(e.gap) + std::abs(cf(static_cast<Eigen::Index>(i)));
    for (int a = 0; a < e.row.n; ++a) reach += std::abs(e.row.value[static_cast<std::size_t>(a)] * q(e.row.index[static_cast<std::size_t>(a)]));
    out->energy_rounding += kEps * fi * reach;
    for (int a = 0; a < e.row.n; ++a) {
      const auto ia = static_cast<std::size_t>(a);
      out->gradient(e.row.index[ia]) += fi * e.row.value[ia];
      (*magnitude)(e.row.index[ia]) += (fi + k * reach) * std::abs(e.row.value[ia]);
    }
  }
  if (!with_hessian) return;
  for (const Block& b : blocks_) {
    std::vector<Eigen::Index> loaded;  // positions in the block
    for (std::size_t x = 0; x < b.points.size(); ++x) {
      const auto i = static_cast<std::size_t>(b.points[x]);
      if (force[i] > 0.0 && scalars_[i].law >= 0) loaded.push_back(static_cast<Eigen::Index>(x));
    }
    if (loaded.empty()) continue;
    const auto m = static_cast<Eigen::Index>(loaded.size());
    Eigen::MatrixXd compliance(m, m), rows = Eigen::MatrixXd::Zero(m, dofs_);
    for (Eigen::Index x = 0; x < m; ++x) {
      const auto i = static_cast<std::size_t>(b.points[static_cast<std::size_t>(loaded[static_cast<std::size_t>(x)])]);
      for (Eigen::Index y = 0; y < m; ++y) compliance(x, y) = b.c(loaded[static_cast<std::size_t>(x)], loaded[static_cast<std::size_t>(y)]);
      compliance(x, x) += laws_[static_cast<std::size_t>(scalars_[i].law)].Compliance(force[i]);
      const Row& row = scalars_[i].row;
      for (int a = 0; a < row.n; ++a) rows(x, row.index[static_cast<std::size_t>(a)]) += row.value[static_cast<std::size_t>(a)];
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(compliance);
    if (ldlt.info() != Eigen::Success) continue;  // an infinite tangent compliance: no stiffness
    const Eigen::MatrixXd stiff = ldlt.solve(rows);
    if (stiff.allFinite()) out->hessian.noalias() += rows.transpose() * stiff;
  }
}

ReducerSystem::Outcome ReducerSystem::Minimise(Eigen::VectorXd* q, bool hold_output, double tolerance, int max_iterations,
                                           std::vector<double>* hints, int* iterations, Evaluation* last) const {
  const int psi = output_dof();
  // The free dofs, in order.
  std::vector<int> free;
  for (int i = 0; i < dofs_; ++i) {
    if (!(hold_output && i == psi)) free.push_back(i);
  }
  const auto m = static_cast<Eigen::Index>(free.size());
  const double force_tolerance = tolerance * torque_ / radius_;  // N (T > 0: zero torque never gets here)
  Evaluation& cur = *last;
  Evaluate(*q, true, hints, &cur);
  Eigen::VectorXd g(m), dq(m);
  Eigen::MatrixXd h(m, m);
  const auto gather = [&](const Evaluation& e) {
    for (Eigen::Index a = 0; a < m; ++a) {
      g(a) = e.gradient(free[static_cast<std::size_t>(a)]);
      for (Eigen::Index b = 0; b < m; ++b) h(a, b) = e.hessian(free[static_cast<std::size_t>(a)], free[static_cast<std::size_t>(b)]);
    }
  };
  gather(cur);
  *iterations = 0;
  if (m == 0) return Outcome::kConverged;
  // A trust region of radius `radius` (mm): the Newton step when the Hessian is positive definite
  // and the step fits, else (H + mu I) dq = -g with mu = |g| / radius, whose step is no longer
  // than the radius (H is positive semidefinite). The radius starts at a micrometre, grows 4x
  // after a step that the energy confirms, and shrinks 4x after one it does not.
  double radius = 1e-3;
  Evaluation trial, second;
  Eigen::LDLT<Eigen::MatrixXd> ldlt;
  // The finest step that still moves a position. About an origin (exact kinematics) the gaps are
  // positions of the size of R_p re-evaluated there, known to a few eps of it; in the nominal
  // system they are the solve's own, and a step resolves to a few eps of the largest dof or gap.
  double gap_scale = 0.0;
  for (const Scalar& e : scalars_) gap_scale = std::max(gap_scale, std::abs(e.gap));
  for (const Planar& p : planars_) gap_scale = std::max(gap_scale, p.offset.cwiseAbs().maxCoeff());
  const auto resolution = [&](const Eigen::VectorXd& at) {
    return 4.0 * std::numeric_limits<double>::epsilon() *
           (exact_ ? radius_ : std::max(gap_scale, at.size() > 0 ? at.cwiseAbs().maxCoeff() : 0.0));
  };
  // The free part of a gradient.
  const auto free_gradient = [&](const Evaluation& e, Eigen::VectorXd* out) {
    out->resize(m);
    for (Eigen::Index a = 0; a < m; ++a) (*out)(a) = e.gradient(free[static_cast<std::size_t>(a)]);
  };
  // The step of the model (g, h) within the trust region: Newton's when h is positive definite
  // and its step fits, else Levenberg-Marquardt's (h + mu I) dq = -g with mu = |g| / radius.
  const auto model_step = [&](const Eigen::MatrixXd& hm, const Eigen::VectorXd& gm, double within, Eigen::VectorXd* step) {
    const double scale = hm.diagonal().cwiseAbs().maxCoeff();
    ldlt.compute(hm);
    bool newton = ldlt.info() == Eigen::Success && ldlt.isPositive() && ldlt.vectorD().minCoeff() > 1e-13 * scale;
    if (newton) {
      *step = ldlt.solve(-gm);
      newton = step->allFinite() && step->norm() <= within;
    }
    if (!newton) {
      const double mu = std::max(gm.norm() / within, 1e-13 * scale);
      ldlt.compute(hm + mu * Eigen::MatrixXd::Identity(m, m));
      *step = ldlt.solve(-gm);
    }
    return newton;
  };
  Eigen::VectorXd gt(m), g2(m);
  Eigen::MatrixXd ht(m, m);
  for (int it = 0; it < max_iterations; ++it) {
    if (!g.allFinite() || !std::isfinite(cur.energy)) return Outcome::kNumerical;
    const double g_max = g.cwiseAbs().maxCoeff();
    if (g_max <= std::max(force_tolerance, cur.rounding)) return Outcome::kConverged;
    *iterations = it + 1;
    model_step(h, g, radius, &dq);
    if (!dq.allFinite()) return Outcome::kNumerical;
    const double predicted = -(g.dot(dq) + 0.5 * dq.dot(h * dq));
    Eigen::VectorXd next = *q;
    for (Eigen::Index a = 0; a < m; ++a) next(free[static_cast<std::size_t>(a)]) += dq(a);
    Evaluate(next, true, hints, &trial);
    free_gradient(trial, &gt);
    const double actual = cur.energy - trial.energy;
    // Near the minimum the energies agree to rounding: there a step counts when it lowers the
    // gradient (its 2-norm, which the model's step lowers wherever the model holds).
    const double rounding = 64.0 * std::numeric_limits<double>::epsilon() *
                                (std::abs(cur.energy) + torque_ * std::abs(next(psi)) / radius_) +
                            16.0 * std::max(cur.energy_rounding, trial.energy_rounding);
    const bool decisive = predicted > rounding || std::abs(actual) > rounding;
    const bool accept = std::isfinite(trial.energy) &&
                        (decisive ? predicted > 0.0 && actual >= 0.1 * predicted : gt.norm() < g.norm());
    if (accept) {
      *q = next;
      std::swap(cur, trial);
      gather(cur);
      if (!decisive || actual >= 0.75 * predicted) radius = std::max(radius, 4.0 * dq.norm());
      continue;
    }
    // The step closed or opened contacts the model at q did not see. The trial point's own step
    // (its Hessian has them) lands on the minimum of the trial's active set, exactly for linear
    // laws: an active-set Newton step. Taken when it lowers the energy below q's, or, where the
    // energy cannot tell (a free-play solve at 1e-7 T), the gradient.
    const double step = dq.norm();
    if (std::isfinite(trial.energy)) {
      for (Eigen::Index a = 0; a < m; ++a) {
        for (Eigen::Index b = 0; b < m; ++b) ht(a, b) = trial.hessian(free[static_cast<std::size_t>(a)], free[static_cast<std::size_t>(b)]);
      }
      Eigen::VectorXd d2;
      // (Newton's step unbounded, as the minimum of the trial's active set; where the energy cannot
      // tell, Levenberg-Marquardt's within the region the step just crossed, judged by the gradient.)
      const bool trial_newton =
          model_step(ht, gt, decisive ? std::numeric_limits<double>::infinity() : std::max(radius, step), &d2);
      if ((trial_newton || !decisive) && d2.allFinite()) {
        Eigen::VectorXd candidate = next;
        for (Eigen::Index a = 0; a < m; ++a) candidate(free[static_cast<std::size_t>(a)]) += d2(a);
        Evaluate(candidate, true, hints, &second);
        free_gradient(second, &g2);
        const bool better = std::isfinite(second.energy) &&
                            (decisive ? cur.energy - second.energy > rounding : g2.norm() < g.norm());
        if (better) {
          radius = std::max(radius, (candidate - *q).norm());
          *q = candidate;
          std::swap(cur, second);
          gather(cur);
          continue;
        }
      }
    }
    radius = 0.25 * step;
    if (!(radius > 0.0)) return Outcome::kNumerical;
    // A trust region below the resolution of a position: no step can tell the model from the
    // arithmetic's rounding any more. The arithmetic's limit; the shared judge decides.
    if (radius < resolution(*q)) return Outcome::kConverged;
  }
  return g.cwiseAbs().maxCoeff() <= std::max(force_tolerance, cur.rounding) ? Outcome::kConverged
                                                                             : Outcome::kMaxIterations;
}

void ReducerSystem::Fill(const Eigen::VectorXd& q, LoadResult* result) const {
  const Eigen::VectorXd relative = Coordinates(q);
  const Eigen::VectorXd c = origin_ + relative;
  // The carrier in series: the output turns T / k beyond the output member's elements.
  result->rotation = c(psi_coordinate_) + CarrierTwist();
  result->force.assign(static_cast<std::size_t>(problem_->point_count()), 0.0);
  result->approach.assign(static_cast<std::size_t>(problem_->point_count()), 0.0);
  ReducerSolution stage;
  stage.discs.resize(static_cast<std::size_t>(discs_));
  const int bearings = settings_.kind == OutputKind::kPins ? 1 : crank_count_;
  for (int d = 0; d < discs_; ++d) {
    ReducerSolution::Disc& disc = stage.discs[static_cast<std::size_t>(d)];
    disc.translation = Eigen::Vector2d(c(3 * d), c(3 * d + 1));
    disc.rotation = c(3 * d + 2);
    if (settings_.kind == OutputKind::kPins) {
      disc.output_force.assign(static_cast<std::size_t>(settings_.pins.count), 0.0);
      disc.output_direction.assign(static_cast<std::size_t>(settings_.pins.count), Eigen::Vector2d::Zero());
    }
    disc.bearing_force.assign(static_cast<std::size_t>(bearings), Eigen::Vector2d::Zero());
    disc.roller_load.assign(static_cast<std::size_t>(bearings), {});
    if (shaft_coordinates_) {
      for (int j = 0; j < crank_count_; ++j) {
        const int v = psi_coordinate_ + 1 + 2 * (d * crank_count_ + j);
        disc.shaft_deflection.emplace_back(c(v), c(v + 1));
      }
    }
  }
  std::vector<Eigen::Vector2d> mesh_force(static_cast<std::size_t>(discs_), Eigen::Vector2d::Zero());
  // Pin bending: the pin-ring forces of the coupled contact problem at these approaches; the
  // beams' strain energy F^T C F / 2, each contact's its own.
  std::vector<double> coupled;
  if (coupling_ != nullptr) {
    std::vector<double> approach(static_cast<std::size_t>(coupled_points_));
    for (std::size_t i = 0; i < approach.size(); ++i) approach[i] = scalars_[i].coordinates.Dot(relative) - scalars_[i].gap;
    coupled.assign(approach.size(), 0.0);
    if (!SolveCoupled(approach, &coupled).converged) std::fill(coupled.begin(), coupled.end(), 0.0);
    const Eigen::Map<const Eigen::VectorXd> f(coupled.data(), static_cast<Eigen::Index>(coupled.size()));
    const double coupled_energy = 0.5 * f.dot(*coupling_ * f);
    if (body_coupling_ != nullptr) {
      // The elastic body's complementary energy f^T C_body f / 2 (its share of the work); the
      // rest of the coupling's is the pins' bending.
      const double body = 0.5 * f.dot(*body_coupling_ * f);
      stage.group_energy.resize(static_cast<std::size_t>(kStageGroupsWithBody), 0.0);
      stage.group_energy[static_cast<std::size_t>(StageGroup::kDiscBody)] += body;
      stage.group_energy[static_cast<std::size_t>(StageGroup::kPinBending)] += coupled_energy - body;
    } else {
      stage.group_energy[static_cast<std::size_t>(StageGroup::kPinBending)] += coupled_energy;
    }
  }
  for (std::size_t i = 0; i < scalars_.size(); ++i) {
    const Scalar& e = scalars_[i];
    const double delta = e.coordinates.Dot(relative) - e.gap;
    if (e.group == StageGroup::kMesh) result->approach[static_cast<std::size_t>(e.index)] = delta;
    const bool is_coupled = i < coupled.size();
    if (!(is_coupled || delta > 0.0) || e.law < 0) continue;
    const contact::ContactLaw& law = laws_[static_cast<std::size_t>(e.law)];
    const double f = is_coupled ? coupled[i] : law.Force(delta);
    if (!(f > 0.0)) continue;
    // A seated pin's strain energy splits between its contact and its seat: each part's
    // F w_part(F) - (complementary energy of the part). The contact's approach is w(F) (with
    // pin bending, delta less the beam's deflection).
    const double seat = f * law.SeatApproach(f) - law.SeatComplementaryEnergy(f);
    const double contact_approach = is_coupled ? law.Approach(f) : delta;
    stage.group_energy[static_cast<std::size_t>(e.group)] += f * contact_approach - law.ComplementaryEnergy(f) - seat;
    stage.group_energy[static_cast<std::size_t>(StageGroup::kSeats)] += seat;
    ReducerSolution::Disc& disc = stage.discs[static_cast<std::size_t>(e.disc)];
    if (e.group == StageGroup::kMesh) {
      result->force[static_cast<std::size_t>(e.index)] = f;
      // The pin pushes the cycloid along -n (n from the cycloid toward the pin).
      mesh_force[static_cast<std::size_t>(e.disc)] -= f * e.direction;
    } else if (e.group == StageGroup::kBearings) {
      // A needle roller on the elastic body: its load on its crank hole's wall (outward).
      const int z = Bearing(e.disc).roller_count;
      const auto crank = static_cast<std::size_t>(e.index / z);
      std::vector<double>& loads = disc.roller_load[crank];
      if (loads.empty()) loads.assign(static_cast<std::size_t>(z), 0.0);
      loads[static_cast<std::size_t>(e.index % z)] = f;
      disc.bearing_force[crank] += f * e.direction;
    } else {
      disc.output_force[static_cast<std::size_t>(e.index)] = f;
      disc.output_direction[static_cast<std::size_t>(e.index)] = e.direction;
    }
  }
  for (const Planar& p : planars_) {
    const contact::BearingResponse r = contact::BearingAt(Bearing(p), DisplacementAt(p, relative), p.phase);
    stage.group_energy[static_cast<std::size_t>(p.group)] += r.energy;
    ReducerSolution::Disc& disc = stage.discs[static_cast<std::size_t>(p.disc)];
    // The force on the outer member (the disc) is the opposite of that on the eccentric. A shaft
    // in series with a bearing carries the bearing's force: the bearing's own element reports it.
    if (p.shaft && shaft_coordinates_) continue;
    disc.bearing_force[static_cast<std::size_t>(p.index)] = -r.force;
    if (!p.shaft) disc.roller_load[static_cast<std::size_t>(p.index)] = r.roller_load;
  }
  if (settings_.kind == OutputKind::kPins && settings_.bearing.kind == contact::BearingKind::kRigid) {
    // A rigid eccentric bearing holds the disc's centre: its force is the reaction to the others.
    for (int d = 0; d < discs_; ++d) {
      ReducerSolution::Disc& disc = stage.discs[static_cast<std::size_t>(d)];
      Eigen::Vector2d others = mesh_force[static_cast<std::size_t>(d)] + applied_.segment<2>(3 * d);
      for (std::size_t j = 0; j < disc.output_force.size(); ++j) others += disc.output_force[j] * disc.output_direction[j];
      disc.bearing_force[0] = -others;
    }
  }
  if (shaft_beam_) {
    // Each beam's strain energy P^T C P / 2 at its eccentrics' loads P = K v splits into the
    // shaft's (bending and shear) and the support bearings' parts of C.
    for (int j = 0; j < crank_count_; ++j) {
      for (int a = 0; a < 2; ++a) {
        const Eigen::Vector2d v(c(ShaftCoordinate(0, j) + a), c(ShaftCoordinate(1, j) + a));
        const Eigen::Vector2d load = beam_stiffness_ * v;
        const double shaft = 0.5 * load.dot(beam_part_ * load);
        stage.group_energy[static_cast<std::size_t>(StageGroup::kShafts)] += shaft;
        stage.group_energy[static_cast<std::size_t>(StageGroup::kSupports)] += 0.5 * load.dot(v) - shaft;
      }
    }
  }
  stage.group_energy[static_cast<std::size_t>(StageGroup::kCarrier)] = 0.5 * torque_ * CarrierTwist();
  result->reducer = std::move(stage);
}

void ReducerSystem::Judge(LoadResult* result) const {
  Residuals r;
  if (!result->reducer || !std::isfinite(result->rotation)) {
    result->residuals = r;
    return;
  }
  ReducerSolution& stage = *result->reducer;
  // The coordinates as the result reports them, relative to the origin the system is built about.
  const Eigen::VectorXd c = CoordinatesOf(*result) - origin_;
  // Generalised forces dPi/dc with the reported forces: each disc's force (N) and moment (N*mm),
  // the output member's moment minus T, each shaft's force.
  Eigen::VectorXd balance = Eigen::VectorXd::Zero(coordinate_count());
  balance(psi_coordinate_) = -torque_;
  // The largest single contribution of an element force to each coordinate's balance (N, N*mm):
  // the size of what the balance is a difference of. A preloaded stage near zero torque carries
  // element moments far beyond T on its discs and output member (docs/stage.md "Preload").
  Eigen::VectorXd carried = Eigen::VectorXd::Zero(coordinate_count());
  const auto add = [&](int i, double v) {
    balance(i) += v;
    carried(i) = std::max(carried(i), std::abs(v));
  };
  // The loads besides T (StageLoads) on the discs and the output member.
  for (int i = 0; i < coordinate_count(); ++i) {
    if (applied_(i) != 0.0) add(i, -applied_(i));
  }
  double f_max = 0.0, w_max = 0.0;
  const double geometry_resolution = 16.0 * std::numeric_limits<double>::epsilon() * radius_;
  const auto reported = [&](const Scalar& e) -> double {
    if (e.group == StageGroup::kMesh) {
      return static_cast<std::size_t>(e.index) < result->force.size() ? result->force[static_cast<std::size_t>(e.index)] : 0.0;
    }
    if (e.group == StageGroup::kBearings) {  // a needle roller on the elastic body
      const int z = Bearing(e.disc).roller_count;
      const auto& loads = stage.discs[static_cast<std::size_t>(e.disc)].roller_load;
      const auto crank = static_cast<std::size_t>(e.index / z), k = static_cast<std::size_t>(e.index % z);
      return crank < loads.size() && k < loads[crank].size() ? loads[crank][k] : 0.0;
    }
    const auto& forces = stage.discs[static_cast<std::size_t>(e.disc)].output_force;
    return static_cast<std::size_t>(e.index) < forces.size() ? forces[static_cast<std::size_t>(e.index)] : 0.0;
  };
  // Pin bending (and an elastic disc body): each coupled point's deflection (C F)_i under the
  // reported forces.
  Eigen::VectorXd beam;
  if (coupling_ != nullptr) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(coupled_points_);
    for (int i = 0; i < coupled_points_; ++i) f(i) = reported(scalars_[static_cast<std::size_t>(i)]);
    beam = *coupling_ * f;
  }
  for (std::size_t i = 0; i < scalars_.size(); ++i) {
    const Scalar& e = scalars_[i];
    const double f = reported(e);
    const double delta = e.coordinates.Dot(c) - e.gap;
    for (int k = 0; k < e.coordinates.n; ++k) {
      add(e.coordinates.index[static_cast<std::size_t>(k)], f * e.coordinates.value[static_cast<std::size_t>(k)]);
    }
    f_max = std::max(f_max, std::abs(f));
    if (f > 0.0) w_max = std::max(w_max, std::abs(delta));
    double deflection = e.law >= 0 ? laws_[static_cast<std::size_t>(e.law)].Approach(f) : 0.0;
    if (static_cast<Eigen::Index>(i) < beam.size()) deflection += beam(static_cast<Eigen::Index>(i));
    // About a moved origin (exact kinematics) the gaps are the geometry re-evaluated there, each
    // resolved to a few eps of the pin-circle radius (positions of that size subtracted): a gap
    // within that of the solve's is the same gap. The nominal system's gaps are the solve's own.
    const double raw = deflection - delta;
    const double gap = exact_ ? std::copysign(std::max(0.0, std::abs(raw) - geometry_resolution), raw) : raw;
    r.force_violation_n = std::max(r.force_violation_n, std::max(0.0, -f));
    r.gap_violation_mm = std::max(r.gap_violation_mm, std::max(0.0, -gap));
    r.complementarity_nmm = std::max(r.complementarity_nmm, std::max(f, 0.0) * std::abs(gap));
  }
  // Planar elements: the reported force (on the disc) must be the law's at the displacement.
  double planar_miss = 0.0;
  for (const Planar& p : planars_) {
    const contact::BearingResponse law = contact::BearingAt(Bearing(p), DisplacementAt(p, c), p.phase, false);
    Eigen::Vector2d du = -law.force;  // dE/du by the law
    if (!(p.shaft && shaft_coordinates_)) {
      const auto& forces = stage.discs[static_cast<std::size_t>(p.disc)].bearing_force;
      const Eigen::Vector2d f = static_cast<std::size_t>(p.index) < forces.size()
                                    ? forces[static_cast<std::size_t>(p.index)]
                                    : Eigen::Vector2d::Zero();
      planar_miss = std::max(planar_miss, (f - du).norm());
      du = f;
    }
    f_max = std::max(f_max, du.norm());
    // A preloaded roller bearing (radial_clearance < 0): its net force is a difference of roller
    // loads of K_n p^(10/9) each even at no load, the size of what its balance is a difference of
    // (the net force alone, ~0 at zero torque, made rounding a residual of 1.9e-5).
    if (Bearing(p).kind == contact::BearingKind::kRollers && Bearing(p).radial_clearance < 0.0) {
      const contact::BearingResponse rollers = contact::BearingAt(Bearing(p), DisplacementAt(p, c), p.phase, true);
      for (const double q : rollers.roller_load) f_max = std::max(f_max, q);
    }
    for (int a = 0; a < 2; ++a) {
      const Row& row = p.coordinates[static_cast<std::size_t>(a)];
      for (int k = 0; k < row.n; ++k) add(row.index[static_cast<std::size_t>(k)], du(a) * row.value[static_cast<std::size_t>(k)]);
    }
  }
  if (shaft_beam_) {
    // The beams' forces at the reported deflections (the law is the beam's: nothing else reports them).
    const Eigen::VectorXd absolute = c + origin_;
    for (int j = 0; j < crank_count_; ++j) {
      for (int a = 0; a < 2; ++a) {
        const std::array<int, 2> k{ShaftCoordinate(0, j) + a, ShaftCoordinate(1, j) + a};
        const Eigen::Vector2d f = beam_stiffness_ * Eigen::Vector2d(absolute(k[0]), absolute(k[1]));
        add(k[0], f(0));
        add(k[1], f(1));
        f_max = std::max(f_max, f.cwiseAbs().maxCoeff());
      }
    }
  }
  if (settings_.kind == OutputKind::kPins && settings_.bearing.kind == contact::BearingKind::kRigid) {
    // The rigid eccentric bearing's reaction, as reported, on the disc's translation.
    for (int d = 0; d < discs_; ++d) {
      const Eigen::Vector2d f = stage.discs[static_cast<std::size_t>(d)].bearing_force.at(0);
      add(3 * d, -f.x());
      add(3 * d + 1, -f.y());
      f_max = std::max(f_max, f.norm());
    }
  }
  const double f_scale = std::max(f_max, 1e-300), w_scale = std::max(w_max, 1e-12);
  // Moments are judged against the largest of T, 1 N*mm and the largest moment an element force
  // contributes to a disc's or the output member's balance: a loaded stage's element moments are
  // shares of T (the scale is T's, as before), a preloaded stage's near zero torque are its preload's,
  // whose balance is then judged on the same relative footing.
  const auto is_moment = [&](int i) { return i == psi_coordinate_ || (i < psi_coordinate_ && i % 3 == 2); };
  double m_carried = 0.0;
  for (int i = 0; i < coordinate_count(); ++i) {
    if (is_moment(i)) m_carried = std::max(m_carried, carried(i));
  }
  const double t_scale = std::max({torque_, 1.0, m_carried});
  double force_balance = planar_miss / f_scale, moment_balance = 0.0;
  for (int i = 0; i < coordinate_count(); ++i) {
    const bool moment = is_moment(i);
    if (moment) {
      moment_balance = std::max(moment_balance, std::abs(balance(i)) / t_scale);
    } else {
      force_balance = std::max(force_balance, std::abs(balance(i)) / f_scale);
    }
  }
  r.torque_relative = std::abs(balance(psi_coordinate_)) / t_scale;
  r.balance_relative = std::max(force_balance, moment_balance);
  r.normalised = std::max({r.balance_relative, r.force_violation_n / f_scale, r.gap_violation_mm / w_scale,
                           r.complementarity_nmm / (f_scale * w_scale)});
  stage.force_balance_relative = force_balance;
  stage.moment_balance_relative = moment_balance;
  result->residuals = r;
}

Eigen::VectorXd ReducerSystem::CoordinatesOf(const LoadResult& result) const {
  Eigen::VectorXd c = Eigen::VectorXd::Zero(coordinate_count());
  if (!result.reducer) return c;
  const ReducerSolution& stage = *result.reducer;
  for (int d = 0; d < discs_ && d < static_cast<int>(stage.discs.size()); ++d) {
    const ReducerSolution::Disc& disc = stage.discs[static_cast<std::size_t>(d)];
    c(3 * d) = disc.translation.x();
    c(3 * d + 1) = disc.translation.y();
    c(3 * d + 2) = disc.rotation;
    for (int j = 0; shaft_coordinates_ && j < crank_count_ && j < static_cast<int>(disc.shaft_deflection.size()); ++j) {
      const int v = psi_coordinate_ + 1 + 2 * (d * crank_count_ + j);
      c(v) = disc.shaft_deflection[static_cast<std::size_t>(j)].x();
      c(v + 1) = disc.shaft_deflection[static_cast<std::size_t>(j)].y();
    }
  }
  c(psi_coordinate_) = result.rotation - CarrierTwist();
  return c;
}

Eigen::VectorXd ReducerSystem::OriginDofs() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(dofs_);
  for (std::size_t i = 0; i < coordinate_dof_.size(); ++i) {
    if (coordinate_dof_[i] >= 0) q(coordinate_dof_[i]) = origin_(static_cast<Eigen::Index>(i)) / coordinate_scale_[i];
  }
  return q;
}

double ReducerSystem::Distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
  double d = 0.0;
  for (Eigen::Index i = 0; i < a.size() && i < b.size(); ++i) {
    const bool rotation = i == psi_coordinate_ || (i < psi_coordinate_ && i % 3 == 2);
    d = std::max(d, std::abs(a(i) - b(i)) * (rotation ? radius_ : 1.0));
  }
  return d;
}

void FinishReducer(const ReducerSystem& system, const Eigen::VectorXd& q, ReducerSystem::Outcome outcome,
                 const ReducerSystem::Evaluation& last, LoadResult* result) {
  system.Fill(q, result);
  if (outcome == ReducerSystem::Outcome::kNumerical) {
    result->status = SolverStatus::kNumericalFailure;
    result->message = last.failure.empty() ? "the stage's minimisation failed (no step lowers the energy)" : last.failure;
  } else if (last.edge) {
    result->status = SolverStatus::kEdgeContact;
    result->message = "a loaded pin sits on a tip corner: edge contact, not solved as line contact";
  } else if (last.saturated) {
    result->status = SolverStatus::kLawCannotCarry;
    result->message = "an element needs more force than its contact law can represent";
  } else if (outcome == ReducerSystem::Outcome::kMaxIterations) {
    result->status = SolverStatus::kMaxIterations;
    result->message = "the stage's balance did not converge within [solver] max_iterations";
  } else {
    result->status = SolverStatus::kSuccess;
    result->message = "converged";
  }
}

namespace {
struct ReducerStartState final : Workspace::BackendState {
  Eigen::VectorXd q;
};
}  // namespace

Eigen::VectorXd ReducerStart(const ReducerSystem& system, Workspace& workspace, const std::string& key) {
  const auto* state = dynamic_cast<const ReducerStartState*>(workspace.Backend(key));
  if (state != nullptr && state->q.size() == system.dof_count() && state->q.allFinite()) {
    return state->q - system.OriginDofs();
  }
  return system.Zero();
}

void KeepReducerStart(const ReducerSystem& system, const Eigen::VectorXd& q, Workspace& workspace, const std::string& key) {
  auto state = std::make_unique<ReducerStartState>();
  state->q = q + system.OriginDofs();
  workspace.SetBackend(key, std::move(state));
}

}  // namespace ltca::solvers
