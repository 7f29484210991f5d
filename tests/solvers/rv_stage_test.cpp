// The RV stage as it is built (issue 49): the first stage with the input locked. Independent
// references: the planetary kinematics of the first stage by hand, and the stage's stiffness
// matrix assembled here from hand-placed cranks and solved directly (Eigen).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <doctest/doctest.h>

#include "ltca/contact/cranks.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/registry.hpp"
#include "ltca/solvers/reducer.hpp"
#include "pairs.hpp"
#include "one_sided_network.hpp"
#include "problems.hpp"

namespace rv_stage_test {

using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::ReducerSettings;
using ltca::solvers::SolverStatus;

constexpr double kLawStiffness = 2e4;  // N/mm per mm of contact length (tests/problems.hpp LinearLaw)

/// RV-40E's first stage as its ratio 121 = 1 + (z_spur / z_sun) z_p with z_p = 40 gives it:
/// z_spur / z_sun = 3, e.g. a 15-tooth sun and 45-tooth spur gears.
constexpr int kSun = 15, kSpur = 45;
/// By hand: with the sun held, one carrier turn rolls each spur gear once round the sun, which
/// turns it z_sun / z_spur = 1/3 of a turn relative to the carrier (the pitch arcs rolled on each
/// other are equal: r_s 2 pi = r_p 2 pi (1/3)), on top of the carrier's own turn: 4/3 turns in the
/// fixed frame, in the carrier's sense (the coin-rotation count).
constexpr double kHandTurns = 4.0 / 3.0;

/// Three crankshafts on R_c 45 mm in linear needle bearings (3e5 N/mm), shafts of 1e5 N/mm.
ReducerSettings Cranks(double turns) {
  ReducerSettings s;
  s.kind = ltca::solvers::OutputKind::kCranks;
  s.cranks.count = 3;
  s.cranks.circle_radius = 45.0;
  s.cranks.phase = 0.3;
  s.cranks.shaft_stiffness = 1e5;
  s.cranks.turns_per_output_turn = turns;
  s.bearing.kind = ltca::contact::BearingKind::kLinear;
  s.bearing.radial_stiffness = 3e5;
  return s;
}

LoadProblem TwoDiscs(const ReducerSettings& stage, double crank, double torque,
                     ltca::contact::ContactKinematics kinematics = ltca::contact::ContactKinematics::kLinearised) {
  const auto model = std::make_shared<const ltca::contact::MeshModel>(ltca::test::LiuPair(), ltca::geometry::Modification{});
  const LoadProblem mesh(model, model, crank, ltca::test::LinearLaw(kLawStiffness), {}, torque, kinematics);
  return mesh.WithReducer(std::make_shared<const ReducerSettings>(stage));
}

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }

/// The stage as a linear network (dofs x, y, phi per disc, then psi; counterclockwise = the
/// problem's frame for T > 0 and d = 1). Each crank's needle bearing and shaft are one spring
/// k_b k_s / (k_b + k_s) on the eccentric's displacement in its hole, placed by hand: crank j's
/// centre C_j = R_c (cos, sin)(alpha_j + psi_0) on the carrier, the eccentric E_j = C_j + R(k psi) D
/// (D the disc's nominal centre, turned by the first stage), the hole H_j = D + t + R(phi) (C_j - 0)
/// in the disc: du/dpsi = perp(C_j) + k perp(D), du/dphi = -perp(C_j), du/dt = -I. The pin ring's
/// linear springs on each point's normal and arm (the contact layer's, as in stage_test.cpp).
/// With `holes` (per disc, per crank: the hole's radial and tangential deviation in the disc, mm;
/// empty: none) the hole sits at C_j + dev_j (dev_j = dr u_j + dt t_j, u_j and t_j the radial and
/// tangential unit vectors at alpha_j), the eccentric off it by o_j = -dev_j at q = 0: the spring
/// stores k |g q + o_j|^2 / 2, a preload -k g^T o_j, and the disc's turn moves the hole by
/// perp(C_j + dev_j).
Eigen::VectorXd Network(const LoadProblem& problem, double turns, double torque,
                        const std::vector<std::vector<Eigen::Vector2d>>& holes = {}) {
  const int n = 7;
  Eigen::MatrixXd fixed = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd load = Eigen::VectorXd::Zero(n);
  const double k = 3e5 * 1e5 / (3e5 + 1e5);
  const double out = problem.model().kinematics().CycloidPose(problem.crank()).rotation;
  for (int d = 0; d < 2; ++d) {
    const Eigen::Vector2d centre = problem.DiscModel(d).real_pair().CycloidPose(problem.DiscCrank(d)).centre;
    for (int j = 0; j < 3; ++j) {
      const double alpha = 2.0 * ltca::units::kPi * j / 3 + 0.3 + out;
      const Eigen::Vector2d u(std::cos(alpha), std::sin(alpha));
      const Eigen::Vector2d c = 45.0 * u;
      const Eigen::Vector2d dev = holes.empty() ? Eigen::Vector2d::Zero()
                                                : Eigen::Vector2d(holes[static_cast<std::size_t>(d)][static_cast<std::size_t>(j)].x() * u +
                                                                  holes[static_cast<std::size_t>(d)][static_cast<std::size_t>(j)].y() * Perp(u));
      Eigen::MatrixXd g = Eigen::MatrixXd::Zero(2, n);
      g.block(0, 3 * d, 2, 2) = -Eigen::Matrix2d::Identity();
      g.col(3 * d + 2) = -Perp(c + dev);
      g.col(6) = Perp(c) + turns * Perp(centre);
      fixed += k * g.transpose() * g;
      load -= k * g.transpose() * (-dev);
    }
  }
  struct Spring {
    Eigen::VectorXd a;
    double gap, k;
  };
  std::vector<Spring> springs;
  for (const auto& p : problem.base_state().pins) {
    Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
    a(3 * p.disc) = p.normal.x();
    a(3 * p.disc + 1) = p.normal.y();
    a(3 * p.disc + 2) = p.arm;
    springs.push_back({a, p.clearance, kLawStiffness * p.length});
  }
  const std::optional<Eigen::VectorXd> q = ltca::test::SolveOneSided(fixed, springs, n - 1, torque, load);
  if (!q) throw std::runtime_error("the hand-assembled network's active set did not settle");
  return *q;
}

/// Every solver of the stage on `problem` against the network's q: the output's and each disc's
/// rotation and translation to 1e-9.
void SolversMatchNetwork(const LoadProblem& problem, const Eigen::VectorXd& q) {
  for (const std::string& name : ltca::solvers::ReducerSolverNames()) {
    CAPTURE(name);
    const LoadResult r = ltca::test::SolveTight(name, problem);
    INFO(r.message);
    REQUIRE(r.status == SolverStatus::kSuccess);
    CHECK(r.rotation == doctest::Approx(q(6)).epsilon(1e-9));
    for (int d = 0; d < 2; ++d) {
      const auto& disc = r.reducer->discs[static_cast<std::size_t>(d)];
      CHECK(disc.rotation == doctest::Approx(q(3 * d + 2)).epsilon(1e-9));
      CHECK((disc.translation - q.segment<2>(3 * d)).norm() <= 1e-9 * q.segment<2>(3 * d).norm());
    }
  }
}

// The tests sit in the namespace: a unity build puts other files' helpers of the same names beside them.

TEST_CASE("contact: the first stage turns each crankshaft 1 + z_sun / z_spur times the carrier, as the planetary kinematics by hand") {
  CHECK(ltca::contact::FirstStageTurns(kSun, kSpur) == doctest::Approx(kHandTurns).epsilon(1e-15));
  CHECK(ltca::contact::FirstStageTurns(20, 20) == 2.0);  // equal gears: the spur gear turns twice per carrier turn
  CHECK_THROWS_WITH_AS(ltca::contact::FirstStageTurns(0, 45), doctest::Contains("[output] first_stage_teeth = [0, 45]"),
                       std::invalid_argument);
  // The eccentric's motion with those turns: E_j(psi) = R(psi) C_j + R(k psi) D, by central
  // differences of the hand positions, against the contact layer's gradient of the eccentric's
  // offset in its (unmoved) hole.
  ltca::contact::Cranks cranks;
  cranks.count = 3;
  cranks.circle_radius = 35.0;
  cranks.phase = 0.4;
  cranks.turns_per_output_turn = ltca::contact::FirstStageTurns(kSun, kSpur);
  const Eigen::Vector2d centre = 1.3 * Eigen::Vector2d(std::cos(0.7), std::sin(0.7));
  const ltca::geometry::Pose disc{centre, 0.0};
  const auto at = ltca::contact::EvaluateCranks(cranks, disc, 0.0);
  const double h = 1e-6;
  for (int j = 0; j < 3; ++j) {
    const double alpha = 2.0 * ltca::units::kPi * j / 3 + 0.4;
    const auto eccentric = [&](double psi) -> Eigen::Vector2d {
      return 35.0 * Eigen::Vector2d(std::cos(alpha + psi), std::sin(alpha + psi)) +
             Eigen::Rotation2Dd(kHandTurns * psi) * centre;
    };
    const Eigen::Vector2d hand = (eccentric(h) - eccentric(-h)) / (2.0 * h);
    CHECK((at[static_cast<std::size_t>(j)].output_gradient - hand).norm() <= 1e-8 * hand.norm());
  }
}

TEST_CASE("solvers: the first stage: two discs on three cranks with the input locked are the hand-assembled linear network (1e-9)") {
  // Linear laws and no clearance: the stage is a linear network whose crank rows carry the
  // first stage's k perp(D); every solver of the stage against it, at two cranks. Without the
  // first stage (k = 0, the old model) the same network with k = 0, and the first stage stiffens
  // the stage: the eccentrics, turned with the carrier, take up part of the disc's translation.
  const double torque = 4.12e5;
  for (const double crank : {0.3, 1.1}) {
    CAPTURE(crank);
    for (const double turns : {0.0, ltca::contact::FirstStageTurns(kSun, kSpur)}) {
      CAPTURE(turns);
      const LoadProblem problem = TwoDiscs(Cranks(turns), crank, torque);
      const Eigen::VectorXd q = Network(problem, turns, torque);
      SolversMatchNetwork(problem, q);
    }
    const double old_rotation = Network(TwoDiscs(Cranks(0.0), crank, torque), 0.0, torque)(6);
    const double first_stage = Network(TwoDiscs(Cranks(kHandTurns), crank, torque), kHandTurns, torque)(6);
    CHECK(first_stage < old_rotation);
  }
}

TEST_CASE("solvers: two discs with their own crank holes are the hand network with each disc's hole offsets (1e-9)") {
  // Discs are machined one by one: disc 1's crank holes off by one set of deviations, disc 2's by
  // another (ReducerSettings::second_disc_holes). Linear laws, no clearance: the hand network with
  // each disc's offsets, every solver of the stage, with and without the first stage. Disc 2 given
  // the common holes is the stage without second_disc_holes, bit for bit.
  const double torque = 4.12e5, crank = 0.3;
  const std::vector<std::vector<Eigen::Vector2d>> holes = {
      {Eigen::Vector2d(0.006, -0.004), Eigen::Vector2d(0.0, 0.005), Eigen::Vector2d(-0.003, 0.0)},
      {Eigen::Vector2d(-0.005, 0.002), Eigen::Vector2d(0.004, 0.0), Eigen::Vector2d(0.0, -0.006)}};
  for (const double turns : {0.0, ltca::contact::FirstStageTurns(kSun, kSpur)}) {
    CAPTURE(turns);
    ReducerSettings stage = Cranks(turns);
    stage.cranks.hole_deviation = holes[0];
    stage.second_disc_holes = holes[1];
    const LoadProblem problem = TwoDiscs(stage, crank, torque);
    const Eigen::VectorXd q = Network(problem, turns, torque, holes);
    const Eigen::VectorXd shared = Network(problem, turns, torque, {holes[0], holes[0]});
    REQUIRE(std::abs(q(6) - shared(6)) > 1e-6 * std::abs(q(6)));  // disc 2's own holes matter
    SolversMatchNetwork(problem, q);
    ReducerSettings common = stage;
    common.second_disc_holes = holes[0];
    ReducerSettings none = stage;
    none.second_disc_holes.reset();
    const LoadResult a = ltca::test::SolveTight("compatibility", TwoDiscs(common, crank, torque));
    const LoadResult b = ltca::test::SolveTight("compatibility", TwoDiscs(none, crank, torque));
    CHECK(a.rotation == b.rotation);
    CHECK(a.force == b.force);
  }
}

TEST_CASE("solvers: the first stage under exact kinematics moves the stage as under linearised kinematics, both discs alike") {
  // Exact kinematics turns each disc's eccentric by k psi at every re-linearisation: the first
  // stage's effect on the output rotation (k = 4/3 against k = 0) is the linearised one up to the
  // geometry's second order, the rotation (8.5e-4 rad here) times the effect (measured: 1.3 times
  // that; bound 10 times); a path that dropped the first stage would show no effect at all. Every
  // solver.
  const double torque = 4.12e5, crank = 0.3, turns = ltca::contact::FirstStageTurns(kSun, kSpur);
  const auto solve = [&](const std::string& name, double k, ltca::contact::ContactKinematics kinematics) {
    const LoadResult r = ltca::test::SolveTight(name, TwoDiscs(Cranks(k), crank, torque, kinematics));
    INFO(r.message);
    REQUIRE(r.status == SolverStatus::kSuccess);
    return r.rotation;
  };
  using ltca::contact::ContactKinematics;
  const double linear = solve("compatibility", 0.0, ContactKinematics::kLinearised) -
                        solve("compatibility", turns, ContactKinematics::kLinearised);
  CHECK(linear > 1e-2 * solve("compatibility", 0.0, ContactKinematics::kLinearised));
  for (const std::string& name : ltca::solvers::ReducerSolverNames()) {
    CAPTURE(name);
    const double rotation = solve(name, 0.0, ContactKinematics::kExact);
    const double exact = rotation - solve(name, turns, ContactKinematics::kExact);
    CHECK(std::abs(exact - linear) <= 10.0 * std::abs(rotation) * linear);
  }
}


constexpr double kYoung = 206000.0, kPoisson = 0.3;  // tests' default [material]: steel

/// The crankshaft of the beam tests: d 20 mm, supports 40 mm apart, eccentrics at 15 and 27 mm,
/// support bearings of 5e5 N/mm.
ltca::contact::CrankshaftBeam Shaft() {
  ltca::contact::CrankshaftBeam b;
  b.diameter = 20.0;
  b.span = 40.0;
  b.eccentric = {15.0, 27.0};
  b.support_stiffness = 5e5;
  return b;
}

/// Maxwell-Mohr's unit-load method, independent of the closed form: C_ij = int M_i M_j / (E I) dx
/// + int V_i V_j / (kappa G A) dx + sum over the supports of R_i R_j / k_s, with M, V and R of a
/// unit load at a_i and at a_j on the simply supported span. M_i M_j is quadratic between the
/// breakpoints 0, a_1, a_2, L, so Simpson's rule on each piece is exact. kappa typed for nu = 0.3:
/// 6 x 1.3 / (7 + 1.8) = 7.8 / 8.8 (Cowper 1966, solid circle). `supports` false: the beam alone.
Eigen::Matrix2d MohrCompliance(const ltca::contact::CrankshaftBeam& b, bool beam, bool supports) {
  const double l = b.span, d = b.diameter;
  const double ei = kYoung * ltca::units::kPi * std::pow(d, 4) / 64.0;
  const double kga = (7.8 / 8.8) * (kYoung / 2.6) * ltca::units::kPi * d * d / 4.0;
  const auto moment = [l](double a, double x) { return x <= a ? (l - a) * x / l : a * (l - x) / l; };
  const auto shear = [l](double a, double x) { return x < a ? (l - a) / l : -a / l; };
  std::vector<double> cuts{0.0, std::min(b.eccentric[0], b.eccentric[1]), std::max(b.eccentric[0], b.eccentric[1]), l};
  Eigen::Matrix2d c = Eigen::Matrix2d::Zero();
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      const double ai = b.eccentric[static_cast<std::size_t>(i)], aj = b.eccentric[static_cast<std::size_t>(j)];
      if (beam) {
        for (std::size_t s = 0; s + 1 < cuts.size(); ++s) {
          const double x0 = cuts[s], x1 = cuts[s + 1], xm = 0.5 * (x0 + x1), h = x1 - x0;
          if (h <= 0.0) continue;
          c(i, j) += h / 6.0 *
                     (moment(ai, x0) * moment(aj, x0) + 4.0 * moment(ai, xm) * moment(aj, xm) + moment(ai, x1) * moment(aj, x1)) / ei;
          c(i, j) += h * shear(ai, xm) * shear(aj, xm) / kga;
        }
      }
      if (supports) c(i, j) += ((l - ai) * (l - aj) / (l * l) + ai * aj / (l * l)) / b.support_stiffness;
    }
  }
  return c;
}

TEST_CASE("contact: a crankshaft's 2 x 2 compliance is Maxwell-Mohr's unit-load integral, and a centre load gives L^3 / (48 E I) + L / (4 kappa G A) (1e-12)") {
  const ltca::contact::CrankshaftBeam b = Shaft();
  const ltca::contact::ShaftCompliance c = ltca::contact::CrankshaftCompliance(b, kYoung, kPoisson);
  const Eigen::Matrix2d beam = MohrCompliance(b, true, false), supports = MohrCompliance(b, false, true);
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      CAPTURE(i);
      CAPTURE(j);
      CHECK(c.beam(i, j) == doctest::Approx(beam(i, j)).epsilon(1e-12));
      CHECK(c.supports(i, j) == doctest::Approx(supports(i, j)).epsilon(1e-12));
    }
  }
  CHECK(c.beam(0, 1) == doctest::Approx(c.beam(1, 0)).epsilon(1e-13));  // Maxwell's reciprocity, from two branches
  // The textbook centre load: bending L^3 / (48 E I), shear L / (4 kappa G A); the supports
  // (1/2 each) add 1 / (2 k_s).
  ltca::contact::CrankshaftBeam centre = b;
  centre.eccentric = {20.0, 10.0};
  const double ei = kYoung * ltca::units::kPi * std::pow(20.0, 4) / 64.0;
  const double kga = (7.8 / 8.8) * (kYoung / 2.6) * ltca::units::kPi * 100.0;
  const ltca::contact::ShaftCompliance m = ltca::contact::CrankshaftCompliance(centre, kYoung, kPoisson);
  CHECK(m.beam(0, 0) == doctest::Approx(std::pow(40.0, 3) / (48.0 * ei) + 40.0 / (4.0 * kga)).epsilon(1e-12));
  CHECK(m.supports(0, 0) == doctest::Approx(0.5 / 5e5).epsilon(1e-12));
}

TEST_CASE("solvers: a crankshaft compliance diag(1/k, 1/k) is today's shaft spring k: the single-spring limit (1e-12)") {
  const double torque = 4.12e5, crank = 0.3;
  ReducerSettings spring = Cranks(0.0);  // shafts of 1e5 N/mm, one spring per shaft and disc
  ReducerSettings diagonal = spring;
  diagonal.cranks.shaft_stiffness = std::numeric_limits<double>::infinity();
  diagonal.cranks.shaft_compliance = Eigen::Matrix2d(Eigen::Vector2d(1e-5, 1e-5).asDiagonal());
  for (const std::string& name : ltca::solvers::ReducerSolverNames()) {
    CAPTURE(name);
    const LoadResult a = ltca::test::SolveTight(name, TwoDiscs(spring, crank, torque));
    const LoadResult b = ltca::test::SolveTight(name, TwoDiscs(diagonal, crank, torque));
    REQUIRE(a.status == SolverStatus::kSuccess);
    REQUIRE(b.status == SolverStatus::kSuccess);
    CHECK(b.rotation == doctest::Approx(a.rotation).epsilon(1e-12));
    for (std::size_t d = 0; d < 2; ++d) {
      for (std::size_t j = 0; j < 3; ++j) {
        CHECK((b.reducer->discs[d].bearing_force[j] - a.reducer->discs[d].bearing_force[j]).norm() <=
              1e-12 * a.reducer->discs[d].bearing_force[j].norm());
        CHECK((b.reducer->discs[d].shaft_deflection[j] - a.reducer->discs[d].shaft_deflection[j]).norm() <=
              1e-12 * a.reducer->discs[d].shaft_deflection[j].norm());
      }
    }
    const auto shafts = static_cast<std::size_t>(ltca::solvers::StageGroup::kShafts);
    CHECK(b.reducer->group_energy[shafts] == doctest::Approx(a.reducer->group_energy[shafts]).epsilon(1e-12));
  }
}

TEST_CASE("solvers: crankshafts as beams, the first stage and the carrier: a linear stage is the directly assembled stiffness matrix (1e-9)") {
  // Two discs, linear laws, no clearance: the network of tests above with each crank's needle
  // bearing (3e5 N/mm) on u + v, v the shaft's deflection at that disc's eccentric (12 more dofs),
  // and per crank and direction the beam's stiffness, the inverse of Maxwell-Mohr's compliance,
  // coupling both discs' v; the eccentrics turned by the first stage (4/3); the output turned
  // T / k_c further by the carrier. Every solver: the output rotation, each disc's pose, every
  // pin-ring force, every crank bearing's force, every shaft deflection and the budget's shaft,
  // support-bearing and carrier energies.
  const double torque = 4.12e5, crank = 0.3, kc = 2e9;
  ReducerSettings stage = Cranks(kHandTurns);
  stage.cranks.shaft_stiffness = std::numeric_limits<double>::infinity();
  stage.cranks.beam = Shaft();
  stage.carrier_stiffness = kc;
  const LoadProblem problem = TwoDiscs(stage, crank, torque);
  const int n = 19;
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  const double kb = 3e5;
  const double out = problem.model().kinematics().CycloidPose(crank).rotation;
  std::vector<Eigen::MatrixXd> rows;  // per disc and crank: u + v = G x
  for (int d = 0; d < 2; ++d) {
    const Eigen::Vector2d centre = problem.DiscModel(d).real_pair().CycloidPose(problem.DiscCrank(d)).centre;
    for (int j = 0; j < 3; ++j) {
      const double alpha = 2.0 * ltca::units::kPi * j / 3 + 0.3 + out;
      const Eigen::Vector2d c = 45.0 * Eigen::Vector2d(std::cos(alpha), std::sin(alpha));
      Eigen::MatrixXd g = Eigen::MatrixXd::Zero(2, n);
      g.block(0, 3 * d, 2, 2) = -Eigen::Matrix2d::Identity();
      g.col(3 * d + 2) = -Perp(c);
      g.col(6) = Perp(c) + kHandTurns * Perp(centre);
      g.block(0, 7 + 2 * (3 * d + j), 2, 2) = Eigen::Matrix2d::Identity();
      k += kb * g.transpose() * g;
      rows.push_back(g);
    }
  }
  const Eigen::Matrix2d compliance = MohrCompliance(Shaft(), true, true);
  const Eigen::Matrix2d beam = compliance.inverse();
  for (int j = 0; j < 3; ++j) {
    for (int a = 0; a < 2; ++a) {
      const int i0 = 7 + 2 * j + a, i1 = 7 + 2 * (3 + j) + a;
      k(i0, i0) += beam(0, 0);
      k(i0, i1) += beam(0, 1);
      k(i1, i0) += beam(1, 0);
      k(i1, i1) += beam(1, 1);
    }
  }
  struct Spring {
    Eigen::VectorXd a;
    double gap, k;
    int index;
  };
  std::vector<Spring> springs;
  for (std::size_t i = 0; i < problem.base_state().pins.size(); ++i) {
    const auto& p = problem.base_state().pins[i];
    Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
    a(3 * p.disc) = p.normal.x();
    a(3 * p.disc + 1) = p.normal.y();
    a(3 * p.disc + 2) = p.arm;
    springs.push_back({a, p.clearance, kLawStiffness * p.length, static_cast<int>(i)});
  }
  const std::optional<Eigen::VectorXd> solved = ltca::test::SolveOneSided(k, springs, 6, torque);  // psi
  REQUIRE(solved.has_value());
  const Eigen::VectorXd& q = *solved;
  // The beams' energy split: P^T C_beam P / 2 for the shafts, the rest for the support bearings.
  const Eigen::Matrix2d beam_part = MohrCompliance(Shaft(), true, false);
  double shafts = 0.0, supports = 0.0, force_max = 0.0;
  for (int j = 0; j < 3; ++j) {
    for (int a = 0; a < 2; ++a) {
      const Eigen::Vector2d v(q(7 + 2 * j + a), q(7 + 2 * (3 + j) + a));
      const Eigen::Vector2d load = beam * v;
      shafts += 0.5 * load.dot(beam_part * load);
      supports += 0.5 * load.dot(v) - 0.5 * load.dot(beam_part * load);
    }
  }
  for (const auto& g : rows) force_max = std::max(force_max, kb * (g * q).norm());
  for (const std::string& name : ltca::solvers::ReducerSolverNames()) {
    CAPTURE(name);
    const LoadResult r = ltca::test::SolveTight(name, problem);
    INFO(r.message);
    REQUIRE(r.status == SolverStatus::kSuccess);
    CHECK(r.rotation == doctest::Approx(q(6) + torque / kc).epsilon(1e-9));
    double scale = force_max;
    for (const double x : r.force) scale = std::max(scale, x);
    for (int d = 0; d < 2; ++d) {
      const auto& disc = r.reducer->discs[static_cast<std::size_t>(d)];
      CHECK(disc.rotation == doctest::Approx(q(3 * d + 2)).epsilon(1e-9));
      CHECK((disc.translation - q.segment<2>(3 * d)).norm() <= 1e-9 * q.segment<2>(3 * d).norm());
      for (int j = 0; j < 3; ++j) {
        const Eigen::Vector2d bearing = kb * (rows[static_cast<std::size_t>(3 * d + j)] * q);
        CHECK((disc.bearing_force[static_cast<std::size_t>(j)] - bearing).norm() <= 1e-9 * force_max);
        const Eigen::Vector2d v = q.segment<2>(7 + 2 * (3 * d + j));
        CHECK((disc.shaft_deflection[static_cast<std::size_t>(j)] - v).norm() <= 1e-9 * q.segment(7, 12).cwiseAbs().maxCoeff());
      }
    }
    for (const Spring& s : springs) {
      CHECK(std::abs(r.force[static_cast<std::size_t>(s.index)] - s.k * std::max(0.0, s.a.dot(q) - s.gap)) <= 1e-9 * scale);
    }
    const auto& e = r.reducer->group_energy;
    CHECK(e[static_cast<std::size_t>(ltca::solvers::StageGroup::kShafts)] == doctest::Approx(shafts).epsilon(1e-9));
    CHECK(e[static_cast<std::size_t>(ltca::solvers::StageGroup::kSupports)] == doctest::Approx(supports).epsilon(1e-9));
    CHECK(e[static_cast<std::size_t>(ltca::solvers::StageGroup::kCarrier)] == doctest::Approx(0.5 * torque * torque / kc).epsilon(1e-12));
    CHECK(r.residuals.balance_relative < 1e-9);
  }
}

}  // namespace rv_stage_test
