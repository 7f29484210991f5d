// Issue 11, the 3D -> 2D limit: with nothing that varies along the face width, n identical slices
// of width B / n carry the plane model's load. Every contact law here depends on the force per
// unit length only (Liu eq. 22-25: delta(F, B) is a function of F / B; the linear law F = k B
// delta), so each slice carries F / n at the plane model's approach, the torque balance is the
// same equation, and the loaded rotation and the pin totals must equal the plane model's. The
// slices are forced here (MeshModel's coupled_along_width), since the program itself would run
// the plane model for such a pair.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "problems.hpp"

#include "ltca/solvers/load_solver.hpp"
#include "ltca/solvers/registry.hpp"

using ltca::contact::ContactKinematics;
using ltca::contact::MeshModel;
using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::SolverOptions;
using ltca::solvers::SolverStatus;

namespace {

using ltca::test::SolveTight;

std::vector<double> PinTotals(const LoadProblem& problem, const std::vector<double>& force) {
  std::vector<double> total(static_cast<std::size_t>(problem.model().pin_count()), 0.0);
  for (std::size_t i = 0; i < force.size(); ++i) total[static_cast<std::size_t>(problem.base_state().pins[i].pin)] += force[i];
  return total;
}

}  // namespace

TEST_CASE("solvers: n identical slices reproduce the plane model (3D -> 2D limit, n = 1, 3, 20)") {
  // Tolerance: 1e-12 relative in the rotation and 1e-12 of the largest pin force; the solves
  // balance the torque to 1e-13 (or the resolution of the rotation in double precision).
  // The forces are held to what each method resolves: a torque balanced to 1e-13 leaves the
  // rotation free by ~1e-13 relative, and a force moves by k L dpsi, which relative to the largest
  // force is dpsi / (psi - psi_closing): the clearance makes psi ten to fifty times the
  // deformation part, so 1e-10 of the largest force for bisection, compatibility and
  // energy-groups; energy-qp's forces are Ipopt's interior-point iterates (1e-8). The rotation
  // is held to 1e-12 for all.
  const ltca::test::PaperCase liu = ltca::test::LiuTable1();
  const auto plane = liu.Model();
  REQUIRE(plane->slice_count() == 1);
  for (const int n : {1, 3, 20}) {
    auto geometry = liu.geometry;
    geometry.width_slices = n;
    const auto sliced = std::make_shared<const MeshModel>(ltca::geometry::RealPair(liu.pair, liu.modification, liu.errors, {}),
                                                          geometry, /*coupled_along_width=*/true);
    REQUIRE(sliced->slice_count() == n);
    for (const auto kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
      for (const std::string solver : {"bisection", "energy-qp", "energy-groups", "compatibility"}) {
        for (const double crank : {0.0, 0.05, 0.11}) {
          CAPTURE(n);
          CAPTURE(solver);
          CAPTURE(crank);
          CAPTURE(static_cast<int>(kinematics));
          const LoadProblem p_plane = liu.Problem(plane, crank, kinematics);
          const LoadProblem p_sliced = liu.Problem(sliced, crank, kinematics);
          const LoadResult a = SolveTight(solver, p_plane), b = SolveTight(solver, p_sliced);
          REQUIRE(a.status == SolverStatus::kSuccess);
          REQUIRE(b.status == SolverStatus::kSuccess);
          CHECK(b.rotation == doctest::Approx(a.rotation).epsilon(1e-12));
          const auto fa = PinTotals(p_plane, a.force), fb = PinTotals(p_sliced, b.force);
          double f_max = 0.0, diff = 0.0;
          for (std::size_t j = 0; j < fa.size(); ++j) {
            f_max = std::max(f_max, fa[j]);
            diff = std::max(diff, std::abs(fa[j] - fb[j]));
          }
          const double tolerance = solver == "energy-qp" ? 1e-8 : 1e-10;
          CHECK(diff <= tolerance * f_max);
          // Identical slices share their pin's load equally.
          double unequal = 0.0;
          for (std::size_t i = 0; i < b.force.size(); ++i) {
            const auto j = static_cast<std::size_t>(p_sliced.base_state().pins[i].pin);
            unequal = std::max(unequal, std::abs(b.force[i] - fb[j] / n));
          }
          CHECK(unequal <= tolerance * f_max);
        }
      }
    }
  }
}

TEST_CASE("solvers: pin bending moves load toward the supports: the pin ends carry more than the uncoupled slices give them") {
  // A beam loaded along the face deflects most away from its supports, so the slices near the
  // supports become the stiffer ones. cases/pin_bending.toml: clamped, span 20 mm, face 4-16 mm
  // (symmetric): the outer halves of a pin's slices carry more than half its load; the uncoupled
  // identical slices carry exactly half. Moving the face toward the first support (offset 1 mm)
  // moves each loaded pin's load centroid toward face B (z < B / 2).
  ltca::test::PaperCase bending = ltca::test::PinBendingCase();
  const auto bent = bending.Model();
  REQUIRE(bent->slice_count() == 20);
  const auto outer_share = [](const LoadProblem& problem, const LoadResult& r) {
    // Of the most loaded pin: the load on slices 0-4 and 15-19 over the pin's total.
    const auto total = PinTotals(problem, r.force);
    const auto heaviest = static_cast<int>(std::max_element(total.begin(), total.end()) - total.begin());
    double outer = 0.0;
    for (std::size_t i = 0; i < r.force.size(); ++i) {
      const auto& p = problem.base_state().pins[i];
      if (p.pin == heaviest && (p.slice < 5 || p.slice >= 15)) outer += r.force[i];
    }
    return outer / total[static_cast<std::size_t>(heaviest)];
  };
  for (const double crank : {0.0, 0.1}) {
    const LoadProblem coupled = bending.Problem(bent, crank, ContactKinematics::kLinearised);
    REQUIRE(coupled.has_coupling());
    const LoadProblem uncoupled(bent, crank, bending.contact, bending.material, bending.torque, ContactKinematics::kLinearised);
    const LoadResult a = SolveTight("compatibility", coupled), b = SolveTight("compatibility", uncoupled);
    REQUIRE(a.status == SolverStatus::kSuccess);
    REQUIRE(b.status == SolverStatus::kSuccess);
    CHECK(outer_share(uncoupled, b) == doctest::Approx(0.5).epsilon(1e-9));
    CHECK(outer_share(coupled, a) > 0.5 + 1e-3);
  }
  bending.pins->face_offset = 1.0;
  const LoadProblem shifted = bending.Problem(bent, 0.0, ContactKinematics::kLinearised);
  const LoadResult r = SolveTight("compatibility", shifted);
  REQUIRE(r.status == SolverStatus::kSuccess);
  const auto total = PinTotals(shifted, r.force);
  std::vector<double> moment(total.size(), 0.0);
  for (std::size_t i = 0; i < r.force.size(); ++i) {
    const auto& p = shifted.base_state().pins[i];
    moment[static_cast<std::size_t>(p.pin)] += r.force[i] * p.z;
  }
  const double f_max = *std::max_element(total.begin(), total.end());
  int loaded = 0;
  for (std::size_t j = 0; j < total.size(); ++j) {
    if (total[j] < 0.05 * f_max) continue;
    ++loaded;
    CHECK(moment[j] / total[j] < 0.5 * bending.pair.face_width - 0.1);
  }
  CHECK(loaded >= 3);
}
