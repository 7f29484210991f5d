// The disc as an elastic body (contact/src/fe, ltca/contact/disc_body.hpp): the T6 plane
// elasticity against closed forms on gmsh meshes, and the condensed compliance's properties.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "fe/disc_mesh.hpp"
#include "fe/gmsh_library.hpp"
#include "fe/t6_elasticity.hpp"
#include "ltca/contact/disc_body.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "pairs.hpp"

namespace disc_body_test {

using ltca::contact::DiscBodyDesign;
using ltca::contact::DiscHole;
using ltca::contact::DiscLoadPoint;
using ltca::contact::PlaneModel;
namespace fe = ltca::contact::fe;

constexpr double kPi = std::numbers::pi;

DiscBodyDesign Annulus(double inner, double outer, double size) {
  DiscBodyDesign d;
  d.outer_radius_mm = outer;
  d.bore_radius_mm = inner;
  d.element_size_mm = size;
  d.refined_size_mm = size;
  d.young_modulus_mpa = 206000.0;
  d.poisson_ratio = 0.3;
  d.thickness_mm = 10.0;
  return d;
}

std::vector<char> BoundaryNodes(const fe::T6Mesh& mesh, bool bore_only) {
  std::vector<char> on(mesh.nodes.size(), 0);
  for (const fe::BoundaryEdge& e : mesh.edges) {
    if (bore_only && e.boundary != fe::Boundary::kBore) continue;
    for (const int n : e.nodes) on[n] = 1;
  }
  return on;
}

std::vector<int> DofsOf(const std::vector<char>& on) {
  std::vector<int> dofs;
  for (std::size_t n = 0; n < on.size(); ++n) {
    if (on[n]) {
      dofs.push_back(2 * static_cast<int>(n));
      dofs.push_back(2 * static_cast<int>(n) + 1);
    }
  }
  return dofs;
}

// The patch test on a mesh (Irons; Zienkiewicz, Taylor and Zhu 2005, ch. 9): u = c + A x imposed
// on every boundary node, the largest error at the interior nodes relative to the largest
// displacement; *interior receives their count.
double PatchTestError(const fe::T6Mesh& mesh, PlaneModel plane, double thickness, int* interior) {
  const std::vector<char> boundary = BoundaryNodes(mesh, false);
  const fe::Elasticity el{plane, 206000.0, 0.3, thickness};
  const fe::ElasticModel model(mesh, el, DofsOf(boundary));
  Eigen::Matrix2d a;
  a << 1.2e-3, -0.7e-3, 0.4e-3, -0.9e-3;
  const Eigen::Vector2d c(3e-3, -2e-3);
  Eigen::VectorXd exact(2 * mesh.nodes.size());
  for (std::size_t n = 0; n < mesh.nodes.size(); ++n) exact.segment<2>(2 * n) = c + a * mesh.nodes[n];
  const Eigen::VectorXd u = model.Solve(Eigen::VectorXd::Zero(exact.size()), exact);
  double worst = 0.0;
  *interior = 0;
  for (std::size_t n = 0; n < mesh.nodes.size(); ++n) {
    if (boundary[n]) continue;
    ++*interior;
    worst = std::max(worst, (u.segment<2>(2 * n) - exact.segment<2>(2 * n)).norm());
  }
  return worst / exact.cwiseAbs().maxCoeff();
}

int NearestNode(const fe::T6Mesh& mesh, const Eigen::Vector2d& p) {
  int best = 0;
  for (std::size_t n = 1; n < mesh.nodes.size(); ++n) {
    if ((mesh.nodes[n] - p).norm() < (mesh.nodes[best] - p).norm()) best = static_cast<int>(n);
  }
  return best;
}

// Torsion of an annulus (inner radius a clamped, torque T as a uniform tangential traction on the
// outer radius r, thickness B): the FE rotation of the outer rim, work-conjugate to the traction
// (f^T u / T), and the closed form psi = T (1/a^2 - 1/r^2) / (4 pi G B) (pure shear: tau =
// T / (2 pi rho^2 B), d psi / d rho = tau / (G rho) from psi(a) = 0; Timoshenko and Goodier,
// Theory of Elasticity, 3rd ed., 1970, ch. 4, polar coordinates; the same in plane strain and
// plane stress).
struct TorsionRun {
  double fe, exact;
  int nodes;
};
TorsionRun AnnulusTorsion(double size) {
  const double a = 10.0, r = 40.0, torque = 1.0e5;  // mm, N*mm
  const DiscBodyDesign d = Annulus(a, r, size);
  const fe::T6Mesh mesh = fe::MeshDisc(d);
  const fe::Elasticity el{PlaneModel::kStrain, d.young_modulus_mpa, d.poisson_ratio, d.thickness_mm};
  const fe::ElasticModel model(mesh, el, DofsOf(BoundaryNodes(mesh, true)));
  const double tau = torque / (2.0 * kPi * r * r * d.thickness_mm);  // MPa
  const Eigen::VectorXd f = fe::EdgeLoad(
      mesh, d.thickness_mm, [](const fe::BoundaryEdge& e) { return e.boundary == fe::Boundary::kOutline; },
      [&](const Eigen::Vector2d& x) -> Eigen::Vector2d { return tau * Eigen::Vector2d(-x.y(), x.x()) / x.norm(); });
  const Eigen::VectorXd u = model.Solve(f);
  const double g = d.young_modulus_mpa / (2.0 * (1.0 + d.poisson_ratio));
  return {f.dot(u) / torque, torque * (1.0 / (a * a) - 1.0 / (r * r)) / (4.0 * kPi * g * d.thickness_mm),
          static_cast<int>(mesh.nodes.size())};
}

TEST_CASE("contact: the T6 disc mesh reproduces a constant-strain field exactly at its interior nodes (patch test)") {
  // The patch test (Irons; Zienkiewicz, Taylor and Zhu 2005, ch. 9): u = c + A x imposed on
  // every boundary node of an irregular gmsh mesh must be reproduced at every interior node
  // (vertices and mid-sides) to round-off: 1e-10 of the largest displacement. Two meshes: a disc
  // with a bore, two holes and a refined spot (curved isoparametric edges), and an irregular
  // 9-gon (its outline meshed as straight lines) with a bore.
  DiscBodyDesign round = Annulus(8.0, 40.0, 6.0);
  round.holes = {DiscHole{{22.0, 3.0}, 4.0}, DiscHole{{-14.0, 17.0}, 5.5}};
  round.refined_size_mm = 0.8;
  round.refine_near_mm = {{40.0, 0.0}};
  round.plane = PlaneModel::kStress;
  DiscBodyDesign polygon = Annulus(6.0, 1.0, 5.0);
  polygon.outline_mm = {{38.0, 0.0}, {30.0, 22.0}, {9.0, 41.0}, {-18.0, 30.0}, {-36.0, 14.0},
                        {-33.0, -15.0}, {-12.0, -37.0}, {14.0, -35.0}, {33.0, -19.0}};
  for (const DiscBodyDesign& d : {round, polygon}) {
    const fe::T6Mesh mesh = fe::MeshDisc(d);
    int interior = 0;
    const double error = PatchTestError(mesh, d.plane, d.thickness_mm, &interior);
    MESSAGE("patch test: " << mesh.nodes.size() << " nodes, " << interior << " interior, worst error " << error
                           << " of the largest displacement");
    CHECK(interior > 100);
    CHECK(error <= 1e-10);
  }
}

TEST_CASE("contact: a disc design that cannot be meshed is refused naming the field") {
  const auto message = [](const DiscBodyDesign& d) {
    try {
      d.Validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  DiscBodyDesign d = Annulus(10.0, 40.0, 4.0);
  CHECK(message(d).empty());
  d.holes = {DiscHole{{14.0, 0.0}, 5.0}};
  CHECK(message(d).find("a hole meets the bore") != std::string::npos);
  d = Annulus(10.0, 40.0, 4.0);
  d.poisson_ratio = 0.5;
  CHECK(message(d).find("poisson_ratio") != std::string::npos);
  d = Annulus(10.0, 40.0, 4.0);
  d.refined_size_mm = 5.0;
  CHECK(message(d).find("refined_size_mm") != std::string::npos);
  d = Annulus(0.0, 40.0, 4.0);
  CHECK(message(d).find("bore_radius_mm") != std::string::npos);
  d = Annulus(10.0, 40.0, 4.0);
  d.outline_mm = {{40.0, 0.0}, {0.0, 40.0}};
  CHECK(message(d).find("at least 3 points") != std::string::npos);
  // A load point's patch must have a positive half-width.
  CHECK_THROWS_AS(ltca::contact::CondenseDiscCompliance(Annulus(10.0, 40.0, 8.0), {DiscLoadPoint{{40.0, 0.0}, {1.0, 0.0}, 0.0}}),
                  std::invalid_argument);
}

TEST_CASE("contact: the T6 disc gives the torsion of an annulus within 0.5 % and converges with refinement") {
  // psi = T (1/a^2 - 1/r^2) / (4 pi G B), a = 10 mm held, r = 40 mm, B = 10 mm, T = 100 N*m.
  const TorsionRun moderate = AnnulusTorsion(4.0);
  MESSAGE("annulus torsion, element 4 mm: " << moderate.fe << " rad against " << moderate.exact << " ("
                                            << moderate.nodes << " nodes)");
  CHECK(std::abs(moderate.fe / moderate.exact - 1.0) < 0.005);
  double previous = 1.0;
  for (const double size : {12.0, 6.0, 3.0}) {
    const TorsionRun run = AnnulusTorsion(size);
    const double error = std::abs(run.fe / run.exact - 1.0);
    MESSAGE("element " << size << " mm: " << run.nodes << " nodes, relative error " << error);
    CHECK(error < previous);
    previous = error;
  }
}

TEST_CASE("contact: the T6 disc gives Lame's thick cylinder under internal pressure within 0.5 %") {
  // Lame (Timoshenko and Goodier 1970, ch. 4, the thick-walled cylinder): a = 10, b = 40 mm, p = 100 MPa on the bore, the
  // outside free; u(rho) = p a^2 / (E (b^2 - a^2)) [(1 - nu) rho + (1 + nu) b^2 / rho] in plane
  // stress, (1 + nu) p a^2 / (E (b^2 - a^2)) [(1 - 2 nu) rho + b^2 / rho] in plane strain. Rigid
  // modes held at three outer nodes on the axes (v at (+-b, 0), u at (0, b)): zero reactions for the
  // exact field. Every boundary vertex and mid-side node's radial displacement within 0.5 % with
  // 2 mm elements (the worst, at the bore, measured 0.068 % in plane strain; 0.44 % with 4 mm
  // elements, 0.008 % with 1 mm: the bore's 1/rho^2 gradient on about 32 edges).
  const double a = 10.0, b = 40.0, p = 100.0;
  for (const PlaneModel plane : {PlaneModel::kStress, PlaneModel::kStrain}) {
    const DiscBodyDesign d = Annulus(a, b, 2.0);
    const fe::T6Mesh mesh = fe::MeshDisc(d);
    const std::vector<int> held{2 * NearestNode(mesh, {b, 0.0}) + 1, 2 * NearestNode(mesh, {-b, 0.0}) + 1,
                                2 * NearestNode(mesh, {0.0, b})};
    const fe::Elasticity el{plane, d.young_modulus_mpa, d.poisson_ratio, d.thickness_mm};
    const fe::ElasticModel model(mesh, el, held);
    const Eigen::VectorXd f = fe::EdgeLoad(
        mesh, d.thickness_mm, [](const fe::BoundaryEdge& e) { return e.boundary == fe::Boundary::kBore; },
        [&](const Eigen::Vector2d& x) -> Eigen::Vector2d { return p * x.normalized(); });
    const Eigen::VectorXd u = model.Solve(f);
    const double e = d.young_modulus_mpa, nu = d.poisson_ratio;
    const auto exact = [&](double rho) {
      return plane == PlaneModel::kStress
                 ? p * a * a / (e * (b * b - a * a)) * ((1.0 - nu) * rho + (1.0 + nu) * b * b / rho)
                 : (1.0 + nu) * p * a * a / (e * (b * b - a * a)) * ((1.0 - 2.0 * nu) * rho + b * b / rho);
    };
    double worst = 0.0;
    const std::vector<char> boundary = BoundaryNodes(mesh, false);
    for (std::size_t n = 0; n < mesh.nodes.size(); ++n) {
      if (!boundary[n]) continue;
      const double rho = mesh.nodes[n].norm();
      const double ur = u.segment<2>(2 * n).dot(mesh.nodes[n] / rho);
      worst = std::max(worst, std::abs(ur / exact(rho) - 1.0));
    }
    MESSAGE((plane == PlaneModel::kStress ? "plane stress" : "plane strain")
            << ": u(a) exact " << exact(a) << " mm, worst boundary node relative error " << worst);
    CHECK(worst < 0.005);
  }
}

DiscBodyDesign HoledDisc() {
  DiscBodyDesign d = Annulus(12.0, 45.0, 4.0);
  for (int k = 0; k < 6; ++k) {
    const double angle = 2.0 * kPi * k / 6.0 + 0.3;
    d.holes.push_back(DiscHole{{28.0 * std::cos(angle), 28.0 * std::sin(angle)}, 5.0});
  }
  return d;
}

TEST_CASE("contact: the disc's condensed compliance is symmetric (Maxwell-Betti) to 1e-9 and positive definite") {
  // C(i, j) = f_i^T K^-1 f_j: Betti's reciprocal theorem makes it symmetric; a body held at its
  // bore stores positive energy under any load, so C is positive definite. Six patches on the rim,
  // radial, tangential and oblique, and one on a hole.
  DiscBodyDesign d = HoledDisc();
  std::vector<DiscLoadPoint> points;
  for (int k = 0; k < 6; ++k) {
    const double angle = 2.0 * kPi * k / 6.0;
    const Eigen::Vector2d at(45.0 * std::cos(angle), 45.0 * std::sin(angle));
    const Eigen::Vector2d dir = k % 3 == 0 ? Eigen::Vector2d(-at.normalized())
                                : k % 3 == 1 ? Eigen::Vector2d(-at.y(), at.x()).normalized()
                                             : Eigen::Vector2d(-at.normalized() + 0.5 * Eigen::Vector2d(-at.y(), at.x()).normalized());
    points.push_back(DiscLoadPoint{at, dir, 0.5});
    d.refine_near_mm.push_back(at);
  }
  d.refined_size_mm = 0.5;
  points.push_back(DiscLoadPoint{d.holes[0].centre_mm + Eigen::Vector2d(5.0, 0.0), Eigen::Vector2d(1.0, 1.0), 0.5});
  const ltca::contact::DiscCompliance c = ltca::contact::CondenseDiscCompliance(d, points);
  const Eigen::MatrixXd& m = c.compliance_mm_per_n;
  REQUIRE(m.rows() == 7);
  REQUIRE(m.cols() == 7);
  const double asymmetry = (m - m.transpose()).cwiseAbs().maxCoeff() / m.cwiseAbs().maxCoeff();
  MESSAGE("compliance: " << c.nodes << " nodes, asymmetry " << asymmetry << ", diagonal " << m.diagonal().transpose());
  CHECK(asymmetry < 1e-9);
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (m + m.transpose()));
  CHECK(llt.info() == Eigen::Success);
  CHECK(m.diagonal().minCoeff() > 0.0);
}

TEST_CASE("contact: the T6 model's sparse condensation (forward solves over the elimination tree, Y^T Y) equals a dense direct solve and the full solves to round-off") {
  // ElasticModel::Condense (the stage body's set-up: Y = L^-1 P F over each column's reach, C =
  // Y^T Y) against two references on a small body (HoledDisc: 6 holes, 4 mm elements, the bore
  // clamped): (1) a dense direct solve, K assembled here from T6Stiffness element by element (no
  // CHOLMOD), its free block solved by a dense Cholesky (Eigen::LLT): C = F_f^T K_ff^-1 F_f; (2) the
  // full solves the set-up made before, F^T Solve(F). Loads: 40 rim patches (radial, tangential,
  // oblique), 12 on two holes' walls, a column with a force on a clamped bore node only (ignored, a
  // reaction: a zero row and column), an empty column, and a column that is the sum of two others
  // (its row is their rows' sum). Round-off: within 1e-12 of C's largest entry, exactly symmetric.
  const DiscBodyDesign d = HoledDisc();
  const fe::T6Mesh mesh = fe::MeshDisc(d);
  const std::vector<char> bore = BoundaryNodes(mesh, true);
  const std::vector<int> clamped = DofsOf(bore);
  const fe::Elasticity el{PlaneModel::kStrain, d.young_modulus_mpa, d.poisson_ratio, d.thickness_mm};
  const fe::ElasticModel model(mesh, el, clamped);
  const auto dofs = static_cast<Eigen::Index>(2 * mesh.nodes.size());
  const auto loadable = [](const fe::BoundaryEdge& e) { return e.boundary != fe::Boundary::kBore; };
  std::vector<Eigen::VectorXd> columns;
  for (int k = 0; k < 40; ++k) {
    const double angle = 2.0 * kPi * k / 40.0 + 0.01;
    const Eigen::Vector2d at(45.0 * std::cos(angle), 45.0 * std::sin(angle));
    const Eigen::Vector2d t(-at.y(), at.x());
    const Eigen::Vector2d dir = k % 3 == 0 ? Eigen::Vector2d(-at.normalized())
                                : k % 3 == 1 ? Eigen::Vector2d(t.normalized())
                                             : Eigen::Vector2d((-at.normalized() + 0.5 * t.normalized()).normalized());
    columns.push_back(fe::PatchLoad(mesh, loadable, at, dir, 0.8));
  }
  for (int h = 0; h < 2; ++h) {
    for (int k = 0; k < 6; ++k) {
      const Eigen::Vector2d dir(std::cos(2.0 * kPi * k / 6.0), std::sin(2.0 * kPi * k / 6.0));
      columns.push_back(fe::PatchLoad(mesh, loadable, d.holes[static_cast<std::size_t>(3 * h)].centre_mm + 5.0 * dir, dir, 0.6));
    }
  }
  const int bore_column = static_cast<int>(columns.size());
  Eigen::VectorXd on_bore = Eigen::VectorXd::Zero(dofs);
  on_bore[clamped[0]] = 1.0;
  on_bore[clamped[3]] = -2.0;
  columns.push_back(on_bore);
  const int empty_column = static_cast<int>(columns.size());
  columns.push_back(Eigen::VectorXd::Zero(dofs));
  const int sum_column = static_cast<int>(columns.size());
  columns.push_back(columns[3] + columns[45]);
  const auto n = static_cast<Eigen::Index>(columns.size());
  Eigen::MatrixXd f(dofs, n);
  for (Eigen::Index j = 0; j < n; ++j) f.col(j) = columns[static_cast<std::size_t>(j)];
  const Eigen::SparseMatrix<double> sparse = f.sparseView();
  const Eigen::MatrixXd c = model.Condense(sparse);
  REQUIRE(c.rows() == n);
  REQUIRE(c.cols() == n);
  // (1) the dense direct solve.
  std::vector<int> free_of(static_cast<std::size_t>(dofs), -1);
  Eigen::Index free = 0;
  for (Eigen::Index i = 0; i < dofs; ++i) {
    if (!bore[static_cast<std::size_t>(i / 2)]) free_of[static_cast<std::size_t>(i)] = static_cast<int>(free++);
  }
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(free, free);
  const Eigen::Matrix3d dm = el.D();
  for (const auto& t : mesh.triangles) {
    fe::T6Coordinates x;
    for (int a = 0; a < 6; ++a) x[static_cast<std::size_t>(a)] = mesh.nodes[static_cast<std::size_t>(t[static_cast<std::size_t>(a)])];
    const fe::T6Matrix ke = fe::T6Stiffness(x, dm, el.thickness_mm);
    for (int a = 0; a < 12; ++a) {
      const int r = free_of[static_cast<std::size_t>(2 * t[static_cast<std::size_t>(a / 2)] + a % 2)];
      for (int b = 0; b < 12 && r >= 0; ++b) {
        const int q = free_of[static_cast<std::size_t>(2 * t[static_cast<std::size_t>(b / 2)] + b % 2)];
        if (q >= 0) k(r, q) += ke(a, b);
      }
    }
  }
  Eigen::MatrixXd ff = Eigen::MatrixXd::Zero(free, n);
  for (Eigen::Index i = 0; i < dofs; ++i) {
    if (free_of[static_cast<std::size_t>(i)] >= 0) ff.row(free_of[static_cast<std::size_t>(i)]) = f.row(i);
  }
  const Eigen::LLT<Eigen::MatrixXd> dense(k);
  REQUIRE(dense.info() == Eigen::Success);
  const Eigen::MatrixXd direct = ff.transpose() * dense.solve(ff);
  // (2) the full solves.
  const Eigen::MatrixXd full = f.transpose() * model.Solve(f);
  const double scale = direct.cwiseAbs().maxCoeff();
  const double to_direct = (c - direct).cwiseAbs().maxCoeff() / scale;
  const double to_full = (c - full).cwiseAbs().maxCoeff() / scale;
  MESSAGE("sparse condensation: " << mesh.nodes.size() << " nodes, " << free << " free dofs, " << n
                                  << " columns; against the dense direct solve " << to_direct << ", against the full solves "
                                  << to_full << " of the largest entry");
  CHECK(to_direct < 1e-12);
  CHECK(to_full < 1e-12);
  CHECK((c - c.transpose()).cwiseAbs().maxCoeff() == 0.0);
  CHECK(c.row(bore_column).cwiseAbs().maxCoeff() == 0.0);
  CHECK(c.row(empty_column).cwiseAbs().maxCoeff() == 0.0);
  CHECK((c.row(sum_column) - c.row(3) - c.row(45)).cwiseAbs().maxCoeff() < 1e-12 * scale);
  CHECK(c.diagonal().head(52).minCoeff() > 0.0);
}

// A tooth-like disc: 12 lobes, rho(t) = 40 + 2 cos(12 t) mm (1,440 outline points, meshed as
// splines), bore 11 mm, B = 10 mm, plane strain; the point on a flank (12 t = pi/2), loaded along
// the inward normal over a 0.25 mm half-width; the mesh 2 mm away from it, refined there.
double ToothFlankCompliance(double refined, int* nodes) {
  constexpr int kLobes = 12, kPoints = 1440;
  const auto at = [](double t) {
    const double rho = 40.0 + 2.0 * std::cos(kLobes * t);
    return Eigen::Vector2d(rho * std::cos(t), rho * std::sin(t));
  };
  DiscBodyDesign d;
  d.bore_radius_mm = 11.0;
  d.thickness_mm = 10.0;
  for (int i = 0; i < kPoints; ++i) d.outline_mm.push_back(at(2.0 * kPi * i / kPoints));
  const double t0 = kPi / (2.0 * kLobes);
  const Eigen::Vector2d tangent = (at(t0 + 1e-6) - at(t0 - 1e-6)).normalized();
  const Eigen::Vector2d inward(-tangent.y(), tangent.x());  // left of a counterclockwise outline
  d.element_size_mm = 2.0;
  d.refined_size_mm = refined;
  d.refine_radius_mm = 6.0;
  d.refine_near_mm = {at(t0)};
  const ltca::contact::DiscCompliance c = ltca::contact::CondenseDiscCompliance(d, {DiscLoadPoint{at(t0), inward, 0.25}});
  *nodes = c.nodes;
  return c.compliance_mm_per_n(0, 0);
}

TEST_CASE("contact: the disc's influence coefficient at a tooth flank converges under mesh refinement") {
  // No closed form: the influence coefficient of a 0.25 mm patch on a flank must settle as the
  // mesh is refined at it (the patch's load is distributed, so its mean displacement is finite; a
  // nodal force's would grow like ln(1/h)). Measured (release, gmsh 4.8.4): refined size 1, 0.5,
  // 0.25, 0.125 mm -> 1.7973, 1.8562, 1.8809, 1.8887 nm/N (6,198 to 6,373 nodes); changes 3.3 %,
  // 1.3 %, 0.41 %. The check: each change smaller than the one before, the last below 1 %.
  double previous = 0.0, previous_change = 1.0;
  for (const double refined : {1.0, 0.5, 0.25, 0.125}) {
    int nodes = 0;
    const double c = ToothFlankCompliance(refined, &nodes);
    MESSAGE("refined " << refined << " mm: " << nodes << " nodes, C = " << c * 1e6 << " nm/N");
    CHECK(c > 0.0);
    if (previous > 0.0) {
      const double change = std::abs(c / previous - 1.0);
      CHECK(change < previous_change);
      previous_change = change;
    }
    previous = c;
  }
  CHECK(previous_change < 0.01);
}

// The real disc of cases/liu2021_sec52_base.toml ([pair] 40 pins, 39 teeth, r_rp 3, R_p 64, e 1.3,
// B 12 mm; [modification] dR_rp -4 um, dR_p -17 um; E 206,000 MPa, nu 0.3): its modified profile
// (48 points per tooth space), a 22 mm bore clamped, plane strain, optionally a ring of 8 holes of
// 7 mm radius at 40 mm; condensed at the ring-pin contact points of crank 0 on the loaded side
// (arm > 0: pins 2 to 20), each loaded along its inward normal over a 0.2 mm half-width; 3 mm
// elements, `refined` at the contacts growing to 3 mm over 6 mm.
// Liu 2021 section 5.2's base pair (cases/liu2021_sec52_base.toml): Table 1's pair (tests/pairs.hpp)
// with dR_rp = -4 um and dR_p = -17 um.
ltca::contact::MeshModel Sec52Model() {
  ltca::geometry::Modification modification;
  modification.pin_radius = -0.004;
  modification.pin_circle_radius = -0.017;
  return ltca::contact::MeshModel(ltca::geometry::RealPair(ltca::test::LiuPair(), modification));
}

struct RealDisc {
  ltca::contact::DiscCompliance c;
  std::vector<int> pins;  // 1-based
  double seconds = 0.0;   // outline, mesh, factorisation and solves
};
RealDisc Sec52Disc(double refined, bool holes) {
  const auto start = std::chrono::steady_clock::now();
  const ltca::geometry::PairParameters pair = ltca::test::LiuPair();
  const ltca::contact::MeshModel model = Sec52Model();
  const ltca::geometry::CycloidProfile& profile = model.real_pair().profile();
  DiscBodyDesign d;
  d.outline_mm = ltca::contact::DiscOutline(profile, 48);
  d.bore_radius_mm = 22.0;
  d.thickness_mm = pair.face_width;
  d.element_size_mm = 3.0;
  d.refined_size_mm = refined;
  d.refine_radius_mm = 6.0;
  if (holes) {
    for (int k = 0; k < 8; ++k) d.holes.push_back(DiscHole{{40.0 * std::cos(k * kPi / 4.0), 40.0 * std::sin(k * kPi / 4.0)}, 7.0});
  }
  RealDisc disc;
  std::vector<DiscLoadPoint> points;
  for (const ltca::contact::PinContact& pin : model.Evaluate(0.0).pins) {
    if (!(pin.arm > 1e-6)) continue;
    const ltca::geometry::ProfilePoint at = profile.Evaluate(pin.u, pin.tooth_space);  // body frame
    points.push_back(DiscLoadPoint{at.position, -at.normal, 0.2});
    d.refine_near_mm.push_back(at.position);
    disc.pins.push_back(pin.pin + 1);
  }
  disc.c = ltca::contact::CondenseDiscCompliance(d, points);
  disc.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return disc;
}

TEST_CASE("contact: the real disc of Liu's section 5.2 pair is meshed and condensed at its contacts within the set-up budget") {
  // The set-up budget of a disc design: 10 s on 2 cores (measured in release: about 1.5 s, 8,600
  // nodes). The compliance is symmetric positive definite, largest near the middle of the loaded
  // sector and coupling neighbours strongly (C(i, i+1) / C(i, i) about 0.2-0.45), and the holes make
  // the body softer. Its diagonal at pin 5 under refinement (0.2 mm patch; refined size 0.4, 0.2,
  // 0.1, 0.05 mm): 1.9571, 1.9742, 1.9797, 1.9819 nm/N (docs/fe_disc.md).
  const RealDisc solid = Sec52Disc(0.2, false);
  const RealDisc holed = Sec52Disc(0.2, true);
  const Eigen::MatrixXd& c = solid.c.compliance_mm_per_n;
  REQUIRE(solid.pins.size() == 19);
  REQUIRE(solid.pins.front() == 2);
  MESSAGE("solid: " << solid.c.nodes << " nodes, " << solid.c.elements << " T6, mesh " << solid.c.mesh_seconds
                    << " s, solve " << solid.c.solve_seconds << " s, total " << solid.seconds << " s");
  MESSAGE("holed: " << holed.c.nodes << " nodes, mesh " << holed.c.mesh_seconds << " s, solve "
                    << holed.c.solve_seconds << " s, total " << holed.seconds << " s");
  for (std::size_t i = 0; i < solid.pins.size(); ++i) {
    MESSAGE("pin " << solid.pins[i] << ": C_ii " << c(i, i) * 1e6 << " nm/N solid, "
                   << holed.c.compliance_mm_per_n(i, i) * 1e6 << " holed; C_i,i+1 / C_ii "
                   << (i + 1 < solid.pins.size() ? c(i, i + 1) / c(i, i) : 0.0));
  }
  CHECK(solid.seconds < 10.0);
  CHECK(holed.seconds < 10.0);
  CHECK((c - c.transpose()).cwiseAbs().maxCoeff() < 1e-9 * c.cwiseAbs().maxCoeff());
  CHECK(Eigen::LLT<Eigen::MatrixXd>(c).info() == Eigen::Success);
  CHECK(c(3, 3) == doctest::Approx(1.9742e-6).epsilon(0.02));  // pin 5, refined 0.2 mm
  for (std::size_t i = 0; i < solid.pins.size(); ++i) {
    CHECK(holed.c.compliance_mm_per_n(i, i) > c(i, i));
    if (i + 1 < solid.pins.size()) CHECK(c(i, i + 1) > 0.15 * c(i, i));
  }
}

TEST_CASE("contact: without gmsh's library the disc says what to install") {
  // The mesher loads libgmsh.so.4.8 at run time; a library the loader cannot find is a
  // std::runtime_error naming the package (checked with a soname that does not exist).
  std::string message;
  try {
    fe::OpenGmsh("libgmsh.so.0.does-not-exist");
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  CHECK(message.find("apt-get install libgmsh-dev") != std::string::npos);
  CHECK(message.find("libgmsh.so.0.does-not-exist") != std::string::npos);
}

TEST_CASE("contact: the real disc's influence coefficients converge under refinement at its contacts") {
  // Liu's section 5.2 disc (above), the 0.2 mm patches fixed, the mesh at the contacts refined
  // 0.4, 0.2, 0.1, 0.05 mm. Measured (release): pin 5 1.9571, 1.9742, 1.9797, 1.9819 nm/N, pin 11
  // 1.7224, 1.7430, 1.7499, 1.7513, pin 19 1.3735, 1.4011, 1.4067, 1.4089 (docs/fe_disc.md). The
  // check: at every pin each change smaller than the one before, the last below 0.5 %. Labelled
  // slow (2.1 s in release, more under the sanitizers).
  std::vector<Eigen::VectorXd> diagonals;
  for (const double refined : {0.4, 0.2, 0.1, 0.05}) {
    const RealDisc disc = Sec52Disc(refined, false);
    diagonals.push_back(disc.c.compliance_mm_per_n.diagonal());
    MESSAGE("refined " << refined << " mm: " << disc.c.nodes << " nodes, " << disc.seconds << " s; pins 5, 11, 19: "
                       << diagonals.back()[3] * 1e6 << ", " << diagonals.back()[9] * 1e6 << ", "
                       << diagonals.back()[17] * 1e6 << " nm/N");
  }
  for (Eigen::Index i = 0; i < diagonals[0].size(); ++i) {
    double previous_change = 1.0;
    for (std::size_t k = 1; k < diagonals.size(); ++k) {
      const double change = std::abs(diagonals[k][i] / diagonals[k - 1][i] - 1.0);
      CHECK(change < previous_change);
      previous_change = change;
    }
    CHECK(previous_change < 0.005);
  }
}

TEST_CASE("contact: the real disc's body rotation under the rigid model's forces grows with a smaller bore and like ln 1/w with the patch") {
  // Indicative only, before the local/global split: the body's work-conjugate rotation F^T C F / T
  // of Liu's section 5.2 disc under the forces of today's rigid model at crank 0 and 206 N*m (ltca
  // solve cases/liu2021_sec52_base.toml --set sweep.positions=1: pins 3-8 carry 271.45, 924.48,
  // 998.25, 972.98, 684.63, 301.67 N), for bores of 22 and 12 mm and patch half-widths w. Measured
  // (release): 22 mm bore 16.80, 17.34, 17.90 arcsec at w = 0.2, 0.1, 0.05 mm; 12 mm bore 35.78,
  // 36.33, 36.89. Each halving of w adds the same 0.56 arcsec: the 2D half-plane's ln(1/w) local
  // part, which the coupling must take out where the Hertz approach already counts it. The checks:
  // the 12 mm bore at least 1.8x the 22 mm one; the increments per halving equal within 10 %.
  // Labelled slow (6 condensations).
  const ltca::geometry::PairParameters pair = ltca::test::LiuPair();
  const ltca::contact::MeshModel model = Sec52Model();
  const ltca::geometry::CycloidProfile& profile = model.real_pair().profile();
  const std::vector<double> force{0.0, 0.0, 271.45400, 924.47914, 998.25342, 972.98050, 684.63246, 301.66719};
  constexpr double kTorque = 206000.0, kArcsec = 180.0 * 3600.0 / kPi;  // N*mm
  std::vector<std::vector<double>> psi;
  for (const double bore : {22.0, 12.0}) {
    psi.emplace_back();
    for (const double w : {0.2, 0.1, 0.05}) {
      DiscBodyDesign d;
      d.outline_mm = ltca::contact::DiscOutline(profile, 48);
      d.bore_radius_mm = bore;
      d.thickness_mm = pair.face_width;
      d.element_size_mm = 3.0;
      d.refined_size_mm = std::min(0.05, w / 2.0);
      d.refine_radius_mm = 6.0;
      std::vector<DiscLoadPoint> points;
      std::vector<double> f;
      double torque = 0.0;
      for (const ltca::contact::PinContact& pin : model.Evaluate(0.0).pins) {
        if (pin.pin >= static_cast<int>(force.size()) || force[pin.pin] <= 0.0) continue;
        const ltca::geometry::ProfilePoint at = profile.Evaluate(pin.u, pin.tooth_space);
        points.push_back(DiscLoadPoint{at.position, -at.normal, w});
        d.refine_near_mm.push_back(at.position);
        f.push_back(force[pin.pin]);
        torque += force[pin.pin] * pin.arm;
      }
      REQUIRE(torque == doctest::Approx(kTorque).epsilon(1e-6));
      const Eigen::Map<const Eigen::VectorXd> forces(f.data(), static_cast<Eigen::Index>(f.size()));
      const ltca::contact::DiscCompliance c = ltca::contact::CondenseDiscCompliance(d, points);
      psi.back().push_back(forces.dot(c.compliance_mm_per_n * forces) / kTorque * kArcsec);
      MESSAGE("bore " << bore << " mm, w " << w << " mm: " << c.nodes << " nodes, body rotation " << psi.back().back() << " arcsec");
    }
  }
  for (std::size_t k = 0; k < psi[0].size(); ++k) CHECK(psi[1][k] > 1.8 * psi[0][k]);
  for (const std::vector<double>& row : psi) {
    CHECK(row[1] > row[0]);
    CHECK(row[2] - row[1] == doctest::Approx(row[1] - row[0]).epsilon(0.1));
  }
}

TEST_CASE("contact: a disc body factorised once condenses any points: each call gives the blocks of one condensation") {
  // DiscBody keeps the mesh and the factorisation: condensing points a few at a time (and on a copy)
  // must give exactly the entries of condensing them all at once (the same K^-1, the same patches).
  DiscBodyDesign d = HoledDisc();
  std::vector<DiscLoadPoint> points;
  for (int k = 0; k < 4; ++k) {
    const double angle = 2.0 * kPi * k / 4.0 + 0.2;
    const Eigen::Vector2d at(45.0 * std::cos(angle), 45.0 * std::sin(angle));
    points.push_back(DiscLoadPoint{at, -at.normalized(), 0.4});
  }
  const ltca::contact::DiscBody body(d);
  const Eigen::MatrixXd all = body.Condense(points).compliance_mm_per_n;
  const ltca::contact::DiscBody copy = body;
  const Eigen::MatrixXd first = body.Condense({points[0], points[1]}).compliance_mm_per_n;
  const Eigen::MatrixXd last = copy.Condense({points[3]}).compliance_mm_per_n;
  CHECK((first - all.topLeftCorner(2, 2)).cwiseAbs().maxCoeff() <= 1e-12 * all.cwiseAbs().maxCoeff());
  CHECK(std::abs(last(0, 0) - all(3, 3)) <= 1e-12 * all.cwiseAbs().maxCoeff());
  CHECK(ltca::contact::CondenseDiscCompliance(d, points).compliance_mm_per_n.isApprox(all, 1e-12));
}


TEST_CASE("contact: the flank compliance interpolates the grid, reproduces a direct condensation between grid points and is positive semidefinite") {
  // DiscFlankCompliance on Liu's section 5.2 disc (22 mm bore, plane strain, the defaults: 32
  // points a tooth space evenly in arc length, w0 = 0.2 mm, the outline meshed at 0.2 mm): at a grid
  // point the coupling is K's entry; at crank 0's contacts (between grid points) it is within 2 % of
  // a direct condensation of the same disc at those points, meshed at 0.1 mm (diagonal and the
  // pins' neighbours, relative to sqrt(C_ii C_jj)); every pose's coupling is positive semidefinite;
  // slices scale it by B / length and do not couple. Its set-up time is printed, not checked (a
  // timed test fails under load; benchmarks/elastic_disc_timing.py measures it). Measured
  // (release): 1.6 %, the largest at pins 2-3 near the root where the flank turns fastest (24
  // points evenly in u: 5.9 %, in arc length: 3.3 %; 0.5 % of it is the meshes' 0.2 against 0.1 mm);
  // 1,248 grid points; the full mesh 31,558 nodes, 7.7 s; the cyclic one (one sector turned 39
  // times, 32 columns solved) 34,788 nodes, 1.7 %, 0.65 s of CPU for a whole `ltca solve`.
  const ltca::geometry::PairParameters pair = ltca::test::LiuPair();
  const ltca::contact::MeshModel model = Sec52Model();
  const ltca::geometry::CycloidProfile& profile = model.real_pair().profile();
  DiscBodyDesign body;
  body.bore_radius_mm = 22.0;
  body.thickness_mm = pair.face_width;
  body.element_size_mm = 3.0;
  body.refine_radius_mm = 6.0;
  const ltca::contact::DiscFlankCompliance flank(profile, body);
  MESSAGE("flank grid: " << flank.grid_points() << " points, " << flank.nodes() << " nodes, set-up "
                         << flank.setup_seconds() << " s");
  CHECK(flank.cycloid_log_radius_mm() == doctest::Approx(0.2 / std::sqrt(std::numbers::e)));

  // A direct condensation at crank 0's loaded contacts, same body, same patches.
  const std::vector<ltca::contact::PinContact> pins = model.Evaluate(0.0).pins;
  std::vector<DiscLoadPoint> points;
  std::vector<ltca::contact::PinContact> loaded;
  DiscBodyDesign direct = body;
  direct.outline_mm = ltca::contact::DiscOutline(profile, 48);
  direct.refine_near_mm = direct.outline_mm;
  direct.refined_size_mm = 0.1;
  for (const ltca::contact::PinContact& pin : pins) {
    if (!(pin.arm > 1e-6)) continue;
    const ltca::geometry::ProfilePoint at = profile.Evaluate(pin.u, pin.tooth_space);
    points.push_back(DiscLoadPoint{at.position, -at.normal, 0.2});
    loaded.push_back(pin);
  }
  const Eigen::MatrixXd reference = ltca::contact::CondenseDiscCompliance(direct, points).compliance_mm_per_n;
  const Eigen::MatrixXd c = flank.Coupling(loaded);
  double worst = 0.0;
  for (Eigen::Index i = 0; i < c.rows(); ++i) {
    for (Eigen::Index j = std::max<Eigen::Index>(0, i - 1); j <= std::min<Eigen::Index>(c.rows() - 1, i + 1); ++j) {
      worst = std::max(worst, std::abs(c(i, j) - reference(i, j)) / std::sqrt(reference(i, i) * reference(j, j)));
    }
  }
  MESSAGE("largest relative difference, diagonal and neighbours: " << worst);
  CHECK(worst < 0.02);
  CHECK((c - c.transpose()).cwiseAbs().maxCoeff() == 0.0);

  // At the grid points themselves (u on the grid): K's entries exactly.
  std::vector<ltca::contact::PinContact> on_grid(2);
  on_grid[0].u = flank.grid_u(5), on_grid[0].tooth_space = 3, on_grid[0].length = pair.face_width;
  on_grid[1].u = flank.grid_u(17), on_grid[1].tooth_space = 7, on_grid[1].length = pair.face_width;
  const Eigen::MatrixXd g = flank.Coupling(on_grid);
  const Eigen::MatrixXd& k = flank.grid_compliance();
  const int m = flank.grid().points_per_space;
  CHECK(g(0, 0) == doctest::Approx(k(3 * m + 5, 3 * m + 5)).epsilon(1e-12));
  CHECK(g(0, 1) == doctest::Approx(k(3 * m + 5, 7 * m + 17)).epsilon(1e-12));

  // Every pose's coupling over a mesh period is positive semidefinite; slices scale and decouple.
  for (int step = 0; step <= 8; ++step) {
    const Eigen::MatrixXd cp = flank.Coupling(model.Evaluate(step * 2.0 * kPi / 180.0).pins);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cp);
    CHECK(eig.eigenvalues().minCoeff() >= -1e-12 * eig.eigenvalues().maxCoeff());
  }
  std::vector<ltca::contact::PinContact> sliced{loaded[3], loaded[3], loaded[4]};
  sliced[0].length = sliced[1].length = sliced[2].length = pair.face_width / 4.0;
  sliced[1].slice = 1;
  const Eigen::MatrixXd cs = flank.Coupling(sliced);
  CHECK(cs(0, 0) == doctest::Approx(4.0 * c(3, 3)).epsilon(1e-12));
  CHECK(cs(0, 2) == doctest::Approx(4.0 * c(3, 4)).epsilon(1e-12));
  CHECK(cs(0, 1) == 0.0);
}

TEST_CASE("contact: the cyclic disc mesh (one sector turned z_c times) is whole: the same after a turn, and it passes the patch test") {
  // fe::MeshDiscSector on Liu's section 5.2 outline (39 spaces, 22 mm bore, coarse sizes): every
  // node turned through 2 pi / 39 is a node (to 1e-9 mm), every boundary edge is the outline's or
  // the bore's (the cuts inside, their nodes shared), and a constant-strain field imposed on the
  // boundary is reproduced at the interior nodes to 1e-10 (a cut whose nodes were not shared would
  // be a crack, whose free faces cannot carry the field's traction).
  const ltca::contact::MeshModel model = Sec52Model();
  const ltca::geometry::CycloidProfile& profile = model.real_pair().profile();
  fe::DiscSector sector;
  const double phi = profile.phi_max();
  for (int j = 0; j <= 24; ++j) sector.outline_mm.push_back(profile.Position(-phi + phi * j / 12.0, 0));
  sector.copies = 39;
  const Eigen::Vector2d a = sector.outline_mm.front(), b = sector.outline_mm.back();
  sector.angle_rad = std::remainder(std::atan2(b.y(), b.x()) - std::atan2(a.y(), a.x()), 2.0 * kPi);
  sector.bore_radius_mm = 22.0;
  sector.element_size_mm = 4.0;
  sector.refined_size_mm = 1.0;
  sector.refine_radius_mm = 4.0;
  const fe::T6Mesh mesh = fe::MeshDiscSector(sector);
  const double turn = 2.0 * kPi / 39.0;
  const Eigen::Matrix2d r{{std::cos(turn), -std::sin(turn)}, {std::sin(turn), std::cos(turn)}};
  int unmatched = 0;
  for (const Eigen::Vector2d& p : mesh.nodes) {
    const Eigen::Vector2d q = r * p;
    if ((mesh.nodes[static_cast<std::size_t>(NearestNode(mesh, q))] - q).norm() > 1e-9) ++unmatched;
  }
  CHECK(unmatched == 0);
  const auto other = std::count_if(mesh.edges.begin(), mesh.edges.end(), [](const fe::BoundaryEdge& e) {
    return e.boundary != fe::Boundary::kOutline && e.boundary != fe::Boundary::kBore;
  });
  CHECK(other == 0);
  int interior = 0;
  const double error = PatchTestError(mesh, PlaneModel::kStrain, 12.0, &interior);
  MESSAGE("cyclic mesh: " << mesh.nodes.size() << " nodes, " << interior << " interior, patch error " << error);
  CHECK(interior > 1000);
  CHECK(error <= 1e-10);
}

}  // namespace disc_body_test
