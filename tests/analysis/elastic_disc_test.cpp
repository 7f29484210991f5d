// The disc as an elastic body (contact/disc_body.hpp, docs/fe_disc.md): the split of the local
// Hertz field from the body's far field counts nothing twice, and every solver that takes a
// coupling agrees on the elastic body, under both kinematics.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/SparseCore>
#include <doctest/doctest.h>

#include "ltca/analysis/stage.hpp"
#include "ltca/contact/disc_body.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "ltca/solvers/registry.hpp"
#include "helpers.hpp"
#include "pairs.hpp"
#include "problems.hpp"

namespace elastic_disc_test {

using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::SolverStatus;
using ltca::test::MaxAbs;
using ltca::test::MaxDifference;

constexpr double kTorque = 206000.0;  // N*mm, Liu's section 5.2

/// Liu's section 5.2 pair as made (cases/liu2021_sec52_base.toml) with signed rho.
ltca::analysis::StageDesign Sec52Design() {
  ltca::analysis::StageDesign d;
  d.name = "Liu 2021 section 5.2";
  d.pair = ltca::test::LiuPair();
  d.modification.pin_radius = -0.004;
  d.modification.pin_circle_radius = -0.017;
  d.contact.rho_convention = ltca::contact::RhoConvention::kSigned;
  d.material = ltca::contact::Material{};
  d.material->young_modulus = d.material->pin_young_modulus = 206000.0;
  d.material->poisson_ratio = d.material->pin_poisson_ratio = 0.3;
  return d;
}

TEST_CASE("analysis: an elastic body that is a half-plane down to the rigid law's reference depth returns the rigid disc's answer (the split counts nothing twice)") {
  // The rigid disc's hertz-line law takes the cycloid's approach as C (ln(4 rho/b) - 1/2), rho =
  // min(|rho_c|, cap): on a half-plane, the Hertz contact's centre relative to the point at depth
  // d = 2 rho exp(-(1 - 2 nu) / (2 (1 - nu))) below it (Johnson, Contact Mechanics, 1985, sec. 5.6:
  // (2F/(pi B)) C (ln(2d/b) - nu/(2(1 - nu)))). An elastic body that is exactly that half-plane,
  // rigid beyond the depth d, has at each contact the uniform patch's mean displacement relative
  // to depth d, (2F/(pi B)) C (ln(d/(2 w0)) + 1 - nu/(2(1 - nu))) = (2F/(pi B)) C (ln(rho/w0) + 1/2),
  // and no coupling between contacts. With it as the body's coupling and the elastic law's
  // cycloid term (rho = w0/sqrt(e)), the elastic model must give the rigid model's forces and TE
  // to the solvers' tolerance (1e-9), in every solver that takes a coupling, at crank 0 and 4.5 deg.
  const ltca::analysis::StageDesign design = Sec52Design();
  const ltca::contact::MeshModel model = design.MakeModel();
  const double w0 = 0.2;  // mm
  ltca::contact::ContactSettings elastic = design.contact;
  elastic.cycloid_log_radius = w0 / std::sqrt(std::numbers::e);
  const double c = (1.0 - 0.3 * 0.3) / 206000.0;
  int compared = 0;
  for (const double crank_deg : {0.0, 4.5}) {
    const double crank = crank_deg * std::numbers::pi / 180.0;
    const LoadProblem rigid(model, crank, design.contact, *design.material, kTorque,
                            ltca::contact::ContactKinematics::kLinearised);
    const LoadProblem plain(model, crank, elastic, *design.material, kTorque, ltca::contact::ContactKinematics::kLinearised);
    const std::vector<ltca::contact::PinContact>& pins = plain.base_state().pins;
    Eigen::SparseMatrix<double> body(static_cast<Eigen::Index>(pins.size()), static_cast<Eigen::Index>(pins.size()));
    for (std::size_t i = 0; i < pins.size(); ++i) {
      const double rho = std::min(1.0 / std::abs(pins[i].cycloid_curvature), rigid.log_radius_cap());
      body.insert(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) =
          2.0 / (std::numbers::pi * pins[i].length) * c * (std::log(rho / w0) + 0.5);
    }
    const LoadProblem half_plane = plain.WithCoupling(body);
    for (const std::string& name : ltca::solvers::SolverNames()) {
      CAPTURE(name);
      CAPTURE(crank_deg);
      const LoadResult a = ltca::test::SolveWith(name, rigid);
      const LoadResult b = ltca::test::SolveWith(name, half_plane);
      REQUIRE(a.status == SolverStatus::kSuccess);
      if (b.status == SolverStatus::kCouplingUnsupported) continue;
      REQUIRE(b.status == SolverStatus::kSuccess);
      CHECK(std::abs(a.te - b.te) <= 1e-9 * std::abs(a.te));
      CHECK(MaxDifference(a.force, b.force) <= 1e-9 * MaxAbs(a.force));
      ++compared;
    }
    // Without the body the elastic law alone is stiffer (its TE smaller by more than 1 arcsec =
    // 4.8e-6 rad, of about 11 arcsec loaded rotation): the split moved compliance into the body.
    const LoadResult alone = ltca::test::SolveWith("bisection", plain);
    REQUIRE(alone.status == SolverStatus::kSuccess);
    CHECK(std::abs(alone.te) < std::abs(ltca::test::SolveWith("bisection", rigid).te) - 4.8e-6);
  }
  CHECK(compared >= 2);
}

TEST_CASE("analysis: every solver agrees on Liu's pair with the elastic disc body, both kinematics") {
  // The FE body of Liu's section 5.2 disc (22 mm bore, plane strain; a coarser grid than the
  // default to keep the set-up short): every solver that takes a coupling gives bisection's TE and
  // forces to 1e-9 (linearised) at crank 0 and 4.5 deg, and under exact kinematics to 1e-9 as well;
  // the body turns the disc further than the rigid disc (TE larger in magnitude) and loads more pins.
  // Labelled slow (one FE set-up).
  ltca::analysis::StageDesign design = Sec52Design();
  const ltca::analysis::StageDesign rigid_design = design;
  design.disc.body = ltca::contact::DiscBodySettings::Body::kElastic;
  design.disc.bore_radius = 22.0;
  design.disc.element_size = 4.0;
  design.disc.grid.points_per_space = 16;
  const double crank = 4.5 * std::numbers::pi / 180.0;
  const ltca::analysis::Stage linear(design, {0.0, crank});
  const ltca::analysis::Stage rigid(rigid_design, {0.0, crank});
  REQUIRE(linear.disc_body() != nullptr);
  int compared = 0;
  for (const auto kinematics : {ltca::contact::ContactKinematics::kLinearised, ltca::contact::ContactKinematics::kExact}) {
    const ltca::analysis::Stage stage = linear.WithKinematics(kinematics);
    for (const double at : {0.0, crank}) {
      CAPTURE(at);
      const LoadProblem problem = stage.Problem(at, kTorque);
      REQUIRE(problem.has_coupling());
      const LoadResult reference = ltca::test::SolveWith("bisection", problem);
      REQUIRE(reference.status == SolverStatus::kSuccess);
      // Issue 48: with the dense kernel bisection searches psi by the safeguarded Newton iteration
      // (bisection_solver.hpp): 7 to 8 trials a position on this pair (ltca solve, 301 linearised
      // and 101 exact positions of cases/liu2021_sec52_base.toml), where Liu's doubling search
      // takes about 70; 15 leaves room for a harder position and fails if the doubling search runs.
      CHECK(reference.torque_evaluations <= 15);
      const LoadResult stiff = ltca::test::SolveWith("bisection", rigid.WithKinematics(kinematics).Problem(at, kTorque));
      CHECK(std::abs(reference.te) > 1.2 * std::abs(stiff.te));
      for (const std::string& name : ltca::solvers::SolverNames()) {
        CAPTURE(name);
        const LoadResult r = ltca::test::SolveWith(name, problem);
        if (r.status == SolverStatus::kCouplingUnsupported) continue;
        REQUIRE(r.status == SolverStatus::kSuccess);
        CHECK(std::abs(r.te - reference.te) <= 1e-9 * std::abs(reference.te));
        CHECK(MaxDifference(r.force, reference.force) <= 1e-9 * MaxAbs(reference.force));
        ++compared;
      }
    }
  }
  CHECK(compared >= 8);
}

/// Liu's pair as two identical discs half a crank turn apart on one pin ring, the mesh alone (issue
/// 48: the mesh alone with two discs, each disc its own cyclic body clamped at its bore).
ltca::analysis::StageDesign TwoDiscDesign() {
  ltca::analysis::StageDesign d = Sec52Design();
  d.name = "Liu 2021 section 5.2, two discs";
  d.second_disc = ltca::analysis::SecondDisc{};
  d.second_disc->modification = d.modification;
  return d;
}

TEST_CASE("analysis: with two discs in the mesh alone an elastic body that is a half-plane down to the rigid law's reference depth returns the rigid two-disc answer in every solver that takes a coupling, to 1e-9") {
  // As the one-disc test above (Johnson, Contact Mechanics, 1985, sec. 5.6): the half-plane body
  // rigid beyond the law's reference depth, (2F/(pi B)) C (ln(rho/w0) + 1/2) at each contact and no
  // coupling, given as the coupling over both discs' points (a body per disc), with the elastic
  // law's cycloid term: every solver that takes a coupling returns the rigid two-disc problem's TE
  // and forces (both discs) to 1e-9, at crank 0 and 4.5 deg.
  const ltca::analysis::StageDesign design = TwoDiscDesign();
  ltca::analysis::StageDesign elastic_design = design;
  const double w0 = 0.2;  // mm
  elastic_design.contact.cycloid_log_radius = w0 / std::sqrt(std::numbers::e);
  const double c = (1.0 - 0.3 * 0.3) / 206000.0;
  const double crank = 4.5 * std::numbers::pi / 180.0;
  const ltca::analysis::Stage rigid_stage(design, {0.0, crank});
  const ltca::analysis::Stage elastic_stage(elastic_design, {0.0, crank});
  int compared = 0;
  for (const double at : {0.0, crank}) {
    const LoadProblem rigid = rigid_stage.Problem(at, kTorque);
    const LoadProblem plain = elastic_stage.Problem(at, kTorque);
    REQUIRE(plain.disc_count() == 2);
    REQUIRE(!plain.has_coupling());
    const std::vector<ltca::contact::PinContact>& pins = plain.base_state().pins;
    Eigen::SparseMatrix<double> body(static_cast<Eigen::Index>(pins.size()), static_cast<Eigen::Index>(pins.size()));
    for (std::size_t i = 0; i < pins.size(); ++i) {
      if (pins[i].edge || !(pins[i].length > 0.0)) continue;
      const double rho = std::min(1.0 / std::abs(pins[i].cycloid_curvature), rigid.log_radius_cap());
      body.insert(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) =
          2.0 / (std::numbers::pi * pins[i].length) * c * (std::log(rho / w0) + 0.5);
    }
    const LoadProblem half_plane = plain.WithCoupling(body);
    for (const std::string& name : ltca::solvers::SolverNames()) {
      CAPTURE(name);
      CAPTURE(at);
      const LoadResult a = ltca::test::SolveWith(name, rigid);
      const LoadResult b = ltca::test::SolveWith(name, half_plane);
      REQUIRE(a.status == SolverStatus::kSuccess);
      if (b.status == SolverStatus::kCouplingUnsupported) continue;
      INFO(b.message);
      REQUIRE(b.status == SolverStatus::kSuccess);
      CHECK(std::abs(a.te - b.te) <= 1e-9 * std::abs(a.te));
      CHECK(MaxDifference(a.force, b.force) <= 1e-9 * MaxAbs(a.force));
      ++compared;
    }
  }
  CHECK(compared >= 4);
  // A coupling between the two discs' points is refused, naming the points (pin bending is not
  // supported with two discs: its beams would couple both discs' contacts on one pin).
  const LoadProblem plain = elastic_stage.Problem(0.0, kTorque);
  const auto n = static_cast<Eigen::Index>(plain.point_count());
  Eigen::SparseMatrix<double> across(n, n);
  for (Eigen::Index i = 0; i < n; ++i) across.insert(i, i) = 1e-6;
  across.insert(0, n - 1) = across.insert(n - 1, 0) = 1e-7;
  CHECK_THROWS_WITH_AS(plain.WithCoupling(across), doctest::Contains("two discs take a coupling within each disc only"),
                       std::invalid_argument);
}

TEST_CASE("analysis: with two discs in the mesh alone each disc is its own cyclic body, every solver agrees to 1e-9 and the half-turn symmetry holds to 1e-9, both kinematics") {
  // Liu's pair twice, 180 deg apart, the FE body (22 mm bore, plane strain; the coarse grid of the
  // one-disc test above). (1) The coupling is block-diagonal: disc 2's block is its body's
  // coefficients of its own points (the one cyclic body: without holes both discs are one design,
  // one set-up), nothing between the discs. (2) Every solver that takes a coupling gives
  // bisection's TE and forces to 1e-9 at crank 0 and 4.5 deg, both kinematics. (3) The half-turn
  // symmetry: turned by pi about the pin circle's centre, disc 2 at crank theta (its eccentric at
  // theta + pi) is disc 1 at theta (z_p = 40 even: ring pin j onto j + 20; its profile turned
  // (theta + pi) d / z_c + pi, a whole number of tooth pitches, 19 here, onto disc 1's), and the
  // cyclic body (one tooth space's sector turned z_c times) is the same under that turn: disc 2's
  // pin j + 20 carries disc 1's pin j's force, to 1e-9 of the largest, and each disc T / 2.
  ltca::analysis::StageDesign design = TwoDiscDesign();
  const ltca::analysis::StageDesign rigid_design = design;
  design.disc.body = ltca::contact::DiscBodySettings::Body::kElastic;
  design.disc.bore_radius = 22.0;
  design.disc.element_size = 4.0;
  design.disc.grid.points_per_space = 16;
  const double crank = 4.5 * std::numbers::pi / 180.0;
  const ltca::analysis::Stage linear(design, {0.0, crank});
  const ltca::analysis::Stage rigid(rigid_design, {0.0, crank});
  REQUIRE(linear.disc_body(0) != nullptr);
  CHECK(linear.disc_body(1) == linear.disc_body(0));  // one design, one set-up
  CHECK(linear.disc_body(0)->cyclic());
  int compared = 0;
  for (const auto kinematics : {ltca::contact::ContactKinematics::kLinearised, ltca::contact::ContactKinematics::kExact}) {
    const ltca::analysis::Stage stage = linear.WithKinematics(kinematics);
    for (const double at : {0.0, crank}) {
      CAPTURE(at);
      CAPTURE(static_cast<int>(kinematics));
      const LoadProblem problem = stage.Problem(at, kTorque);
      REQUIRE(problem.has_coupling());
      REQUIRE(problem.disc_count() == 2);
      const std::vector<ltca::contact::PinContact>& pins = problem.base_state().pins;
      {
        const Eigen::MatrixXd c = Eigen::MatrixXd(*problem.coupling());
        std::vector<Eigen::Index> second_rows;
        std::vector<ltca::contact::PinContact> second_points;
        double across = 0.0;
        for (std::size_t i = 0; i < pins.size(); ++i) {
          for (std::size_t j = 0; j < pins.size(); ++j) {
            if (pins[i].disc != pins[j].disc) across = std::max(across, std::abs(c(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j))));
          }
          if (pins[i].disc != 1) continue;
          second_rows.push_back(static_cast<Eigen::Index>(i));
          second_points.push_back(pins[i]);
          second_points.back().disc = 0;
        }
        CHECK(across == 0.0);
        const Eigen::MatrixXd own = linear.disc_body(1)->Coupling(second_points);
        double worst = 0.0;
        for (std::size_t x = 0; x < second_rows.size(); ++x) {
          for (std::size_t y = 0; y < second_rows.size(); ++y) {
            worst = std::max(worst, std::abs(c(second_rows[x], second_rows[y]) -
                                             own(static_cast<Eigen::Index>(x), static_cast<Eigen::Index>(y))));
          }
        }
        CHECK(own.maxCoeff() > 0.0);
        CHECK(worst <= 1e-12 * own.maxCoeff());
      }
      const LoadResult reference = ltca::test::SolveTight("bisection", problem);
      REQUIRE(reference.status == SolverStatus::kSuccess);
      const LoadResult stiff = ltca::test::SolveWith("bisection", rigid.WithKinematics(kinematics).Problem(at, kTorque));
      REQUIRE(stiff.status == SolverStatus::kSuccess);
      CHECK(std::abs(reference.te) > 1.2 * std::abs(stiff.te));
      // The half turn: disc 2's pin j + 20 against disc 1's pin j.
      std::vector<std::vector<double>> by_pin(2, std::vector<double>(40, 0.0));
      for (std::size_t i = 0; i < pins.size(); ++i) {
        by_pin.at(static_cast<std::size_t>(pins[i].disc)).at(static_cast<std::size_t>(pins[i].pin)) += reference.force.at(i);
      }
      double half_turn = 0.0;
      for (std::size_t j = 0; j < 40; ++j) half_turn = std::max(half_turn, std::abs(by_pin[0][j] - by_pin[1][(j + 20) % 40]));
      MESSAGE("two discs, mesh alone, crank ", at, ", kinematics ", static_cast<int>(kinematics),
              ": half-turn departure ", half_turn / MaxAbs(reference.force), " of the largest pin force");
      CHECK(half_turn <= 1e-9 * MaxAbs(reference.force));
      // Li's tooth groups take two discs' groups in closing order, which the coupling does not
      // keep: refused by name (energy_groups_solver.cpp), never a number from a wrong set.
      CHECK(ltca::test::SolveWith("energy-groups", problem).status == SolverStatus::kCouplingUnsupported);
      for (const std::string& name : ltca::solvers::SolverNames()) {
        CAPTURE(name);
        const LoadResult r = ltca::test::SolveTight(name, problem);
        if (r.status == SolverStatus::kCouplingUnsupported) continue;
        INFO(r.message);
        REQUIRE(r.status == SolverStatus::kSuccess);
        CHECK(std::abs(r.te - reference.te) <= 1e-9 * std::abs(reference.te));
        CHECK(MaxDifference(r.force, reference.force) <= 1e-9 * MaxAbs(reference.force));
        ++compared;
      }
    }
  }
  CHECK(compared >= 8);
}

TEST_CASE("contact: the hole grid of the elastic body is a direct condensation at its grid points and interpolates between them within 2 %") {
  // Liu's disc (unmodified) with a 28 mm bore clamped and the cycloidal drive's 8 output-pin holes
  // (r_h 6.32 mm on a 40 mm circle, cases/stage/cycloidal_drive.toml), 3 mm elements, the default
  // grids (32 points a tooth space, 48 around each hole, 0.2 mm patches). The same body built
  // directly (DiscBody: the same outline, refinement points and so the same mesh) and condensed at
  // chosen points: (1) at grid points of two holes and of the flank, along the grid's directions,
  // its compliance is the flank's K and the Coupling's entries to 1e-9 relative (the hole rings are
  // where they say, loaded along the hole's outward normal, in the flank's one condensation), and
  // so is K at every 16th grid point (the set-up's sparse forward solves against the direct
  // condensation's full solves); (2)
  // half-way between two hole grid points the interpolated coupling (diagonal and the coefficient
  // to another hole's contact) is within 2 % of the direct one, relative to sqrt(C_ii C_jj).
  // Labelled slow (two whole-disc set-ups).
  const ltca::geometry::PairParameters pair = ltca::test::LiuPair();
  const ltca::geometry::CycloidProfile profile(pair);
  ltca::contact::DiscBodyDesign body;
  body.bore_radius_mm = 28.0;
  body.thickness_mm = pair.face_width;
  body.element_size_mm = 3.0;
  body.refine_radius_mm = 6.0;
  for (int j = 0; j < 8; ++j) {
    const double a = 2.0 * std::numbers::pi * j / 8;
    body.holes.push_back({40.0 * Eigen::Vector2d(std::cos(a), std::sin(a)), 6.32});
  }
  const ltca::contact::DiscFlankGrid grid;
  const ltca::contact::DiscFlankCompliance flank(profile, body, grid);
  REQUIRE(!flank.cyclic());
  REQUIRE(flank.hole_count() == 8);
  const int hp = grid.points_per_hole;
  REQUIRE(flank.grid_points() == pair.tooth_count * grid.points_per_space + 8 * hp);
  // The body as DiscFlankCompliance builds it.
  ltca::contact::DiscBodyDesign direct = body;
  direct.outline_mm = ltca::contact::DiscOutline(profile, 2 * grid.points_per_space);
  direct.refine_near_mm = direct.outline_mm;
  for (const ltca::contact::DiscHole& hole : body.holes) {
    for (int j = 0; j < 2 * hp; ++j) {
      const double a = std::numbers::pi * j / hp;
      direct.refine_near_mm.emplace_back(hole.centre_mm + hole.radius_mm * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
  }
  direct.refined_size_mm = grid.patch_half_width_mm;
  const ltca::contact::DiscBody fe(direct);
  const auto at = [&](int h, double a) {  // a point on hole h's wall at angle a, along its outward normal
    const Eigen::Vector2d d(std::cos(a), std::sin(a));
    return ltca::contact::DiscLoadPoint{body.holes[static_cast<std::size_t>(h)].centre_mm + 6.32 * d, d, grid.patch_half_width_mm};
  };
  const double step = 2.0 * std::numbers::pi / hp;
  const int g_flank = 5 * grid.points_per_space + 11;  // tooth space 5, grid point 11
  const std::vector<ltca::contact::DiscLoadPoint> points{
      at(0, 5 * step), at(3, 17 * step),
      {flank.grid_point(g_flank), flank.grid_normal(g_flank), grid.patch_half_width_mm},
      at(0, 5.5 * step), at(1, 30.5 * step)};
  const Eigen::MatrixXd c = fe.Condense(points).compliance_mm_per_n;
  const std::vector<int> g{flank.hole_grid_start(0) + 5, flank.hole_grid_start(3) + 17, g_flank};
  const Eigen::MatrixXd& k = flank.grid_compliance();
  double grid_miss = 0.0;
  for (int x = 0; x < 3; ++x) {
    for (int y = 0; y < 3; ++y) {
      grid_miss = std::max(grid_miss, std::abs(c(x, y) - k(g[static_cast<std::size_t>(x)], g[static_cast<std::size_t>(y)])) /
                                          std::sqrt(c(x, x) * c(y, y)));
    }
  }
  MESSAGE("hole grid against a direct condensation at grid points: largest relative difference " << grid_miss);
  CHECK(grid_miss < 1e-9);
  // Every 16th grid point of the flank and the holes (102 of 1,632): the body's K (the sparse
  // forward solves, Y^T Y) against the direct condensation's full solves (F^T K^-1 F).
  std::vector<int> every;
  std::vector<ltca::contact::DiscLoadPoint> spread;
  for (int i = 0; i < flank.grid_points(); i += 16) {
    every.push_back(i);
    spread.push_back({flank.grid_point(i), flank.grid_normal(i), grid.patch_half_width_mm});
  }
  const Eigen::MatrixXd cs = fe.Condense(spread).compliance_mm_per_n;
  double spread_miss = 0.0;
  for (std::size_t x = 0; x < every.size(); ++x) {
    for (std::size_t y = 0; y < every.size(); ++y) {
      const auto ix = static_cast<Eigen::Index>(x), iy = static_cast<Eigen::Index>(y);
      spread_miss = std::max(spread_miss, std::abs(cs(ix, iy) - k(every[x], every[y])) / std::sqrt(cs(ix, ix) * cs(iy, iy)));
    }
  }
  MESSAGE("the body's K at every 16th grid point against a direct condensation: largest relative difference " << spread_miss);
  CHECK(spread_miss < 1e-9);
  // The Coupling at grid points: a flank contact at the grid's u (whole face width) and two hole contacts.
  ltca::contact::PinContact p;
  p.cycloid_point = p.pin_point = p.normal = Eigen::Vector2d::Zero();
  p.tooth_space = 5;
  p.u = flank.grid_u(11);
  p.length = pair.face_width;
  p.part = ltca::geometry::SurfacePart::kFlank;
  const Eigen::MatrixXd coupled = flank.Coupling(
      {p}, {{0, Eigen::Vector2d(std::cos(5 * step), std::sin(5 * step))}, {3, Eigen::Vector2d(std::cos(17 * step), std::sin(17 * step))}});
  const std::vector<int> order{2, 0, 1};  // Coupling's order: the flank point, then the holes
  double coupling_miss = 0.0;
  for (int x = 0; x < 3; ++x) {
    for (int y = 0; y < 3; ++y) {
      const int cx = order[static_cast<std::size_t>(x)], cy = order[static_cast<std::size_t>(y)];
      coupling_miss = std::max(coupling_miss, std::abs(coupled(x, y) - c(cx, cy)) / std::sqrt(c(cx, cx) * c(cy, cy)));
    }
  }
  CHECK(coupling_miss < 1e-9);
  // Between grid points.
  const Eigen::MatrixXd between = flank.Coupling(
      {}, {{0, Eigen::Vector2d(std::cos(5.5 * step), std::sin(5.5 * step))}, {1, Eigen::Vector2d(std::cos(30.5 * step), std::sin(30.5 * step))}});
  double interpolation_miss = 0.0;
  for (int x = 0; x < 2; ++x) {
    for (int y = 0; y < 2; ++y) {
      interpolation_miss = std::max(interpolation_miss, std::abs(between(x, y) - c(3 + x, 3 + y)) / std::sqrt(c(3 + x, 3 + x) * c(3 + y, 3 + y)));
    }
  }
  MESSAGE("hole grid between grid points: largest relative difference " << interpolation_miss << ", C_hole " << c(3, 3) * 1e6
                                                                       << " nm/N, C_hole,hole " << c(3, 4) * 1e6 << " nm/N");
  CHECK(interpolation_miss < 0.02);
}

}  // namespace elastic_disc_test
