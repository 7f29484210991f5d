// Issue 48: the elastic disc body with a tip relief whose caps carry load (docs/fe_disc.md, "A tip
// relief's caps"): the split of the local Hertz field from the body's far field still counts
// nothing twice on a cap contact, and every solver that takes a coupling agrees on the relieved
// elastic body, under both kinematics.
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
#include "problems.hpp"

namespace elastic_caps_test {

using ltca::geometry::SurfacePart;
using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::SolverStatus;
using ltca::test::MaxAbs;
using ltca::test::MaxDifference;

constexpr double kTorque = 500000.0;  // N*mm, cases/hard/d2_loaded.toml

/// cases/hard/d2_loaded.toml (a d = 2 pair whose sharp tips carry load) with a tip rounding of
/// 0.5 mm: its caps carry load.
ltca::analysis::StageDesign D2Relieved() {
  ltca::analysis::StageDesign d;
  d.name = "d = 2, relieved tips";
  d.pair = {24, 22, 7.0, 90.0, 4.0, 20.0};
  d.modification.pin_radius = 0.002;
  d.modification.pin_circle_radius = -0.005;
  d.modification.tip_relief.rounding_radius = 0.5;
  d.material = ltca::contact::Material{};
  d.material->young_modulus = d.material->pin_young_modulus = 206000.0;
  d.material->poisson_ratio = d.material->pin_poisson_ratio = 0.3;
  return d;
}

/// Whether a solved position loads a contact on a tip's rounding.
bool LoadsACap(const LoadProblem& problem, const LoadResult& r) {
  const std::vector<ltca::contact::PinContact>& pins = problem.base_state().pins;
  for (std::size_t i = 0; i < pins.size() && i < r.force.size(); ++i) {
    if (pins[i].part == SurfacePart::kTipRounding && r.force[i] > 0.0) return true;
  }
  return false;
}

/// Crank angles of a mesh period (48 steps) at which the rigid disc loads a cap, at most `count`.
std::vector<double> CapCranks(const ltca::analysis::StageDesign& design, int count) {
  const ltca::contact::MeshModel model = design.MakeModel();
  std::vector<double> cranks;
  for (int step = 0; step < 48 && static_cast<int>(cranks.size()) < count; ++step) {
    const double crank = step * model.kinematics().MeshPeriod() / 48.0;
    const LoadProblem problem(model, crank, design.contact, *design.material, kTorque,
                              ltca::contact::ContactKinematics::kLinearised);
    const LoadResult r = ltca::test::SolveWith("bisection", problem);
    if (r.status == SolverStatus::kSuccess && LoadsACap(problem, r)) cranks.push_back(crank);
  }
  return cranks;
}

TEST_CASE("analysis: with a tip relief whose caps carry load an elastic body that is a half-plane down to the rigid law's reference depth returns the rigid disc's answer") {
  // As "an elastic body that is a half-plane down to the rigid law's reference depth ..."
  // (elastic_disc_test.cpp; Johnson, Contact Mechanics, 1985, sec. 5.6), on a pair whose relieved
  // tips carry load: a cap contact's rigid law takes rho = min(rounding radius, cap), and the body
  // that is the half-plane down to that law's reference depth has the diagonal (2 / (pi B)) C
  // (ln(rho / w0) + 1/2) there as on the flank. With it and the elastic law (rho = w0 / sqrt(e)),
  // every solver that takes a coupling gives the rigid model's TE and forces to 1e-9 (linearised)
  // at two cranks where the rigid disc loads a cap: nothing counted twice on a cap either.
  const ltca::analysis::StageDesign design = D2Relieved();
  const ltca::contact::MeshModel model = design.MakeModel();
  const double w0 = 0.2;  // mm
  ltca::contact::ContactSettings elastic = design.contact;
  elastic.cycloid_log_radius = w0 / std::sqrt(std::numbers::e);
  const double c = (1.0 - 0.3 * 0.3) / 206000.0;
  const std::vector<double> cranks = CapCranks(design, 2);
  REQUIRE(cranks.size() == 2);
  int compared = 0;
  for (const double crank : cranks) {
    CAPTURE(crank);
    const LoadProblem rigid(model, crank, design.contact, *design.material, kTorque,
                            ltca::contact::ContactKinematics::kLinearised);
    const LoadProblem plain(model, crank, elastic, *design.material, kTorque, ltca::contact::ContactKinematics::kLinearised);
    const std::vector<ltca::contact::PinContact>& pins = plain.base_state().pins;
    Eigen::SparseMatrix<double> body(static_cast<Eigen::Index>(pins.size()), static_cast<Eigen::Index>(pins.size()));
    for (std::size_t i = 0; i < pins.size(); ++i) {
      if (pins[i].edge) continue;
      const double rho = std::min(1.0 / std::abs(pins[i].cycloid_curvature), rigid.log_radius_cap());
      body.insert(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) =
          2.0 / (std::numbers::pi * pins[i].length) * c * (std::log(rho / w0) + 0.5);
    }
    const LoadProblem half_plane = plain.WithCoupling(body);
    for (const std::string& name : ltca::solvers::SolverNames()) {
      CAPTURE(name);
      const LoadResult a = ltca::test::SolveWith(name, rigid);
      const LoadResult b = ltca::test::SolveWith(name, half_plane);
      REQUIRE(a.status == SolverStatus::kSuccess);
      CHECK(LoadsACap(rigid, a));
      if (b.status == SolverStatus::kCouplingUnsupported) continue;
      REQUIRE(b.status == SolverStatus::kSuccess);
      CHECK(std::abs(a.te - b.te) <= 1e-9 * std::abs(a.te));
      CHECK(MaxDifference(a.force, b.force) <= 1e-9 * MaxAbs(a.force));
      ++compared;
    }
  }
  CHECK(compared >= 4);
}

TEST_CASE("analysis: every solver agrees on the relieved elastic body (a tip relief whose caps carry load), both kinematics") {
  // The FE body of the relieved d = 2 disc (its outline with the caps, a 30 mm bore, plane strain, 4 mm
  // elements, 16 grid points a space): at two cranks where a cap carries load, every solver that
  // takes a coupling gives bisection's TE and forces to 1e-9, linearised and exact; the cap contacts
  // are coupled (a positive diagonal) and carry load; the body turns the disc further than the rigid
  // disc. Labelled slow (one FE set-up).
  ltca::analysis::StageDesign design = D2Relieved();
  const std::vector<double> cranks = CapCranks(design, 2);
  REQUIRE(cranks.size() == 2);
  const ltca::analysis::StageDesign rigid_design = design;
  design.disc.body = ltca::contact::DiscBodySettings::Body::kElastic;
  design.disc.bore_radius = 30.0;
  design.disc.element_size = 4.0;
  design.disc.grid.points_per_space = 16;
  const ltca::analysis::Stage linear(design, cranks);
  const ltca::analysis::Stage rigid(rigid_design, cranks);
  REQUIRE(linear.disc_body() != nullptr);
  CHECK(linear.disc_body()->caps());
  int compared = 0, loaded_caps = 0;
  double worst_te = 0.0, worst_force = 0.0;
  for (const auto kinematics : {ltca::contact::ContactKinematics::kLinearised, ltca::contact::ContactKinematics::kExact}) {
    const ltca::analysis::Stage stage = linear.WithKinematics(kinematics);
    for (const double at : cranks) {
      CAPTURE(at);
      const LoadProblem problem = stage.Problem(at, kTorque);
      REQUIRE(problem.has_coupling());
      const LoadResult reference = ltca::test::SolveWith("bisection", problem);
      REQUIRE(reference.status == SolverStatus::kSuccess);
      const std::vector<ltca::contact::PinContact>& pins = problem.base_state().pins;
      const Eigen::MatrixXd body = linear.disc_body()->Coupling(pins);
      for (std::size_t i = 0; i < pins.size(); ++i) {
        if (pins[i].part != SurfacePart::kTipRounding || !(reference.force[i] > 0.0)) continue;
        CHECK(body(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) > 0.0);
        ++loaded_caps;
      }
      const LoadResult stiff = ltca::test::SolveWith("bisection", rigid.WithKinematics(kinematics).Problem(at, kTorque));
      CHECK(std::abs(reference.te) > std::abs(stiff.te));
      for (const std::string& name : ltca::solvers::SolverNames()) {
        CAPTURE(name);
        const LoadResult r = ltca::test::SolveWith(name, problem);
        if (r.status == SolverStatus::kCouplingUnsupported) continue;
        REQUIRE(r.status == SolverStatus::kSuccess);
        CHECK(std::abs(r.te - reference.te) <= 1e-9 * std::abs(reference.te));
        CHECK(MaxDifference(r.force, reference.force) <= 1e-9 * MaxAbs(reference.force));
        worst_te = std::max(worst_te, std::abs(r.te - reference.te) / std::abs(reference.te));
        worst_force = std::max(worst_force, MaxDifference(r.force, reference.force) / MaxAbs(reference.force));
        ++compared;
      }
    }
  }
  MESSAGE("loaded cap contacts over both kinematics and both cranks: " << loaded_caps << "; largest difference from "
          "bisection: TE " << worst_te << " relative, forces " << worst_force << " of the largest");
  CHECK(loaded_caps >= 2);
  CHECK(compared >= 8);
}

}  // namespace elastic_caps_test
