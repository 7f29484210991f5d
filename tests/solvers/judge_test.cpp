// The shared judge (issue 10): a success is verified, not believed. The residual alone cannot see
// a rotation whole tooth pitches off (the exact geometry repeats every pitch), an interfering pair,
// or figures beyond the material and the law; these tests show the judge does.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/solvers/registry.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "pairs.hpp"
#include "problems.hpp"

using ltca::contact::ContactKinematics;
using ltca::contact::MeshModel;
using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::MakeSolver;
using ltca::solvers::SolverNames;
using ltca::solvers::SolverOptions;
using ltca::solvers::SolverStatus;

namespace {

// A backend that answers with the true solution turned by a whole number of cycloid tooth pitches:
// the same forces and, on the exact geometry, the same approaches, so the residual is as small as
// the true answer's.
class ShiftedSolver final : public ltca::solvers::LoadSolver {
 public:
  explicit ShiftedSolver(int pitches) : pitches_(pitches) {}
  std::string name() const override { return "shifted"; }

 private:
  void DoSolve(const LoadProblem& problem, const SolverOptions& options, ltca::solvers::Workspace& workspace,
               LoadResult* result) const override {
    SolverOptions inner = options;
    inner.name = "compatibility";
    const LoadResult truth = MakeSolver("compatibility")->Solve(problem, inner, workspace);
    result->status = truth.status;
    result->message = "shifted";
    result->force = truth.force;
    result->rotation = truth.rotation + pitches_ * problem.model().profile().tooth_pitch();
  }
  int pitches_;
};

}  // namespace

TEST_CASE("solvers: exact kinematics at the crank where energy-qp answered 7,956 pitches off: every solver agrees") {
  // Issue 10, cases/liu2021_sec52_base.toml at crank 8.99756997569976 deg: energy-qp reported
  // success with TE +264,383,964.9 arcsec, bisection max-iterations. Independent reference: the
  // linearised model of the same pose (frozen geometry, no periodicity), which differs from the
  // exact one by the second-order change of the contact geometry (about 0.004 arcsec on these
  // pairs, docs/performance.md): every solver must succeed with exact kinematics, lie within
  // 0.05 arcsec of it, and the four must agree to 1e-6 relative.
  const ltca::test::PaperCase sec52 = ltca::test::LiuSec52Base();
  const auto model = sec52.Model();
  const double crank = ltca::units::DegToRad(8.99756997569976);
  const LoadProblem linear = sec52.Problem(model, crank, ContactKinematics::kLinearised);
  SolverOptions lin_options;
  lin_options.name = "compatibility";
  const LoadResult reference = MakeSolver("compatibility")->Solve(linear, lin_options);
  REQUIRE(reference.status == SolverStatus::kSuccess);
  const LoadProblem exact = sec52.Problem(model, crank, ContactKinematics::kExact);
  double first_te = NAN;
  for (const auto& name : SolverNames()) {
    CAPTURE(name);
    SolverOptions options;
    options.name = name;
    const LoadResult r = MakeSolver(name)->Solve(exact, options);
    REQUIRE(r.status == SolverStatus::kSuccess);
    CHECK(std::abs(ltca::units::RadToArcsec(r.te - reference.te)) < 0.05);
    if (std::isnan(first_te)) first_te = r.te;
    CHECK(r.te == doctest::Approx(first_te).epsilon(1e-6));
  }
}

TEST_CASE("solvers: the judge rejects a rotation one tooth pitch off that the residual cannot see") {
  // The exact geometry repeats every cycloid tooth pitch 2 pi / z_c: the true forces at the true
  // rotation plus one pitch pass the residual, and only the range check (first contact <= psi <=
  // single-pin bound, |psi| <= a quarter pitch) can tell. Linearised kinematics has no such
  // periodicity, so the shifted answer fails the residual there as well; both must not be success.
  const MeshModel model(ltca::test::LiuPair(), ltca::test::Mod(-4, -17));
  for (const auto kinematics : {ContactKinematics::kExact, ContactKinematics::kLinearised}) {
    const LoadProblem problem(model, 0.05, {}, {}, 206e3, kinematics);
    SolverOptions options;
    for (const int pitches : {1, -1, 7956}) {
      CAPTURE(pitches);
      const LoadResult r = ShiftedSolver(pitches).Solve(problem, options);
      CHECK(r.status != SolverStatus::kSuccess);
      if (kinematics == ContactKinematics::kExact) {
        // The residual alone would have accepted it: the range check is what caught it.
        CHECK(r.residuals.Normalised() < 1e-6);
        CHECK(r.status == SolverStatus::kRotationOutOfRange);
      }
    }
    const LoadResult truth = ShiftedSolver(0).Solve(problem, options);  // the unshifted answer passes
    CHECK(truth.status == SolverStatus::kSuccess);
  }
}

TEST_CASE("solvers: a pin overlapping the cycloid beyond what the material carries cannot be assembled, never a success") {
  // Issue 10: with dR_rp = -1 mm compatibility reported success with 40 of 40 pins and 1.3 MN.
  // dR_rp < dR_p (d = 1) makes the pins overlap the cycloid on both flanks before any load: a
  // preload. 20 um presses every pin beyond the default 4000 MPa limit at zero torque (Hertz line
  // contact, 12 mm face, E = 206 GPa), 1 mm beyond any law: every solver, both kinematics, must
  // answer cannot-assemble naming the pins, and produce no rotation.
  for (const double overlap_um : {20.0, 1000.0}) {
    const MeshModel model(ltca::test::LiuPair(), ltca::test::Mod(-overlap_um, 0.0));
    for (const auto kinematics : {ContactKinematics::kExact, ContactKinematics::kLinearised}) {
      const LoadProblem problem(model, 0.0, {}, {}, 206e3, kinematics);
      for (const auto& name : SolverNames()) {
        CAPTURE(name);
        SolverOptions options;
        options.name = name;
        const LoadResult r = MakeSolver(name)->Solve(problem, options);
        CHECK(r.status == SolverStatus::kCannotAssemble);
        CHECK(r.message.find("pin ") != std::string::npos);
        CHECK(std::isnan(r.te));
        // Figures only from a preload balance that was found, its stress beyond the limit (none where
        // no balance within the laws was found: no valid solve produced them).
        if (overlap_um == 20.0) REQUIRE(r.preload.has_value());
        if (r.preload) CHECK(r.preload->max_stress_mpa > problem.material().contact_stress_limit);
      }
    }
  }
}

TEST_CASE("solvers: a contact stress beyond the material limit is a warning, one within it is not") {
  // Liu 2021 Table 1 prints a largest contact stress of 1067.50 MPa (our 1064.76 under the
  // absolute convention, docs/validation.md): a 500 MPa limit must be exceeded at some position
  // and name the key, the default 4000 MPa (steel) and 2000 MPa must not. A 20-fold torque with a
  // linear law of small stiffness opens half-widths beyond a tenth of the pin radius: a warning.
  const ltca::test::PaperCase table1 = ltca::test::LiuTable1Absolute();
  const auto model = table1.Model();
  for (const double limit : {500.0, 2000.0, 4000.0}) {
    CAPTURE(limit);
    auto material = table1.material;
    material.contact_stress_limit = limit;
    bool warned = false;
    for (const double crank : {0.0, 0.03, 0.06, 0.09, 0.12, 0.15}) {
      const LoadProblem problem(model, crank, table1.contact, material, table1.torque, ContactKinematics::kLinearised);
      const LoadResult r = MakeSolver("compatibility")->Solve(problem, SolverOptions{});
      REQUIRE(r.status == SolverStatus::kSuccess);  // a warning does not change the status
      for (const auto& w : r.warnings) {
        if (w.find("contact_stress_limit_mpa") != std::string::npos) warned = true;
      }
    }
    CHECK(warned == (limit < 1067.5));
  }
}

