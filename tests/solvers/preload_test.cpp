// A preloaded pair (pins overlapping the cycloid on both flanks, no rotation seating the disc):
// the mesh alone balances over both flanks from the preload state (docs/solvers.md "Two flanks").
// Independent reference: tests/solvers/two_flank_network.hpp, the linear springs' balance by a
// breakpoint walk, on the contact layer's clearances and arms of the unloaded state.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/contact/mesh_state.hpp"
#include "ltca/solvers/registry.hpp"
#include "pairs.hpp"
#include "problems.hpp"
#include "two_flank_network.hpp"

namespace {

using ltca::contact::ContactKinematics;
using ltca::contact::MeshModel;
using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::SolverStatus;

constexpr double kStiffness = 2e4;  // N/mm per mm of contact length (tests/problems.hpp LinearLaw)

/// Liu Table 1 with every pin overlapping by `overlap_um` (dR_rp = -overlap: Liu eq. (5)'s
/// isometric modification the other way), slices as asked.
std::shared_ptr<const MeshModel> Overlapping(double overlap_um) {
  return std::make_shared<const MeshModel>(ltca::test::LiuPair(), ltca::test::Mod(-overlap_um, 0.0));
}

std::vector<ltca::test::FlankSpring> Springs(const MeshModel& model, double crank) {
  std::vector<ltca::test::FlankSpring> springs;
  for (const auto& pin : model.Evaluate(crank, 0.0).pins) {
    springs.push_back({pin.arm, pin.clearance, kStiffness * pin.length});
  }
  return springs;
}

LoadResult Solve(const LoadProblem& problem) { return ltca::test::SolveTight("bisection", problem); }

}  // namespace

TEST_CASE("solvers: a preloaded pair balances both flanks as the independent two-flank network does") {
  // Liu Table 1, every pin 0.5 um into the cycloid, the linear law: at the deck's 206 N*m, at zero
  // torque (the preload) and at -206 N*m, TE, every pin force and the contact count within 1e-6
  // relative of the breakpoint walk (the tolerance: the solve balances to 1e-13; the walk is exact).
  const auto model = Overlapping(0.5);
  for (const double crank_deg : {0.0, 2.7}) {
    const double crank = ltca::units::DegToRad(crank_deg);
    const auto springs = Springs(*model, crank);
    for (const double torque : {206e3, 0.0, -206e3}) {
      CAPTURE(crank_deg);
      CAPTURE(torque);
      const LoadProblem problem(model, crank, ltca::test::LinearLaw(kStiffness), {}, torque,
                                ContactKinematics::kLinearised);
      REQUIRE(problem.preloaded());
      const LoadResult r = Solve(problem);
      REQUIRE(r.status == SolverStatus::kSuccess);
      REQUIRE(r.preload.has_value());
      const ltca::test::TwoFlankBalance want = ltca::test::SolveTwoFlankNetwork(springs, torque);
      CHECK(r.te == doctest::Approx(-want.phi).epsilon(1e-6));
      const double f_max = *std::max_element(want.force.begin(), want.force.end());
      REQUIRE(r.force.size() == want.force.size());
      int contacts = 0;
      for (std::size_t i = 0; i < r.force.size(); ++i) {
        CAPTURE(i);
        CHECK(std::abs(r.force[i] - want.force[i]) <= 1e-6 * f_max);
        contacts += r.force[i] > 1e-9 * f_max ? 1 : 0;
      }
      CHECK(contacts == want.contacts);
      CHECK(static_cast<int>(r.active.size()) == want.contacts);
      // The preload reported is the zero-torque balance's: its largest force and contact count.
      const ltca::test::TwoFlankBalance zero = ltca::test::SolveTwoFlankNetwork(springs, 0.0);
      CHECK(r.preload->max_force_n ==
            doctest::Approx(*std::max_element(zero.force.begin(), zero.force.end())).epsilon(1e-6));
      CHECK(r.preload->contacts == zero.contacts);
      if (torque != 0.0) CHECK(want.contacts < zero.contacts);  // the load unloads part of one flank
      if (torque != 0.0) CHECK(want.contacts > zero.contacts / 2);  // and not all of it
      CHECK(r.residuals.Normalised() <= 1e-6);
    }
  }
}

TEST_CASE("solvers: as the interference goes to zero the preloaded results meet the zero-clearance ones") {
  // Liu Table 1, Hertz line law, both kinematics: the conjugate pair (zero clearance, one flank from
  // first contact) against overlaps of 1, 0.1 and 0.01 um. The TE and the largest pin force
  // approach the conjugate pair's linearly in the overlap (the difference shrinks with it).
  const auto conjugate = Overlapping(0.0);
  for (const auto kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    CAPTURE(static_cast<int>(kinematics));
    const LoadProblem reference(conjugate, 0.0, {}, {}, 206e3, kinematics);
    REQUIRE_FALSE(reference.preloaded());
    const LoadResult base = Solve(reference);
    REQUIRE(base.status == SolverStatus::kSuccess);
    const double f_base = *std::max_element(base.force.begin(), base.force.end());
    double last_te = 0.0, last_f = 0.0;
    for (const double overlap_um : {1.0, 0.1, 0.01}) {
      CAPTURE(overlap_um);
      const LoadProblem problem(Overlapping(overlap_um), 0.0, {}, {}, 206e3, kinematics);
      REQUIRE(problem.preloaded());
      const LoadResult r = Solve(problem);
      REQUIRE(r.status == SolverStatus::kSuccess);
      const double d_te = std::abs(r.te - base.te) / std::abs(base.te);
      const double d_f = std::abs(*std::max_element(r.force.begin(), r.force.end()) - f_base) / f_base;
      MESSAGE("overlap ", overlap_um, " um: TE off by ", d_te, ", largest force by ", d_f);
      if (last_te > 0.0) {
        CHECK(d_te < 0.3 * last_te);
        CHECK(d_f < 0.3 * last_f);
      }
      last_te = d_te, last_f = d_f;
    }
    CHECK(last_te < 2e-2);  // 0.01 um: about 1 % of the TE, falling in proportion to the overlap
  }
}

namespace {

/// A backend without the two-flank balance (a test-only one: every registered backend has it).
class OneFlankOnly final : public ltca::solvers::LoadSolver {
 public:
  std::string name() const override { return "one-flank-only"; }

 private:
  void DoSolve(const LoadProblem&, const ltca::solvers::SolverOptions&, ltca::solvers::Workspace&,
               LoadResult*) const override {}
};

int Contacts(const std::vector<double>& force, double f_max) {
  return static_cast<int>(std::count_if(force.begin(), force.end(), [&](double f) { return f > 1e-9 * f_max; }));
}

}  // namespace

TEST_CASE("solvers: every registered solver solves a preloaded pair under load, both kinematics") {
  // Liu Table 1, every pin 0.5 um into the cycloid, the linear law, cranks 0 and 2.7 deg, at +206,
  // 0 and -206 N*m. Each backend by its own method (bisection: the two-flank root search;
  // energy-qp: the complementary-energy QP over the pins of both arms; energy-groups: Li's groups
  // about the preload state; compatibility: the potential bracketed about the preload state).
  // Linearised: TE, every pin force and the contact count against the independent breakpoint
  // walk (two_flank_network.hpp, exact for linear springs) to 1e-9 (each solve balances the torque to
  // 1e-13; Ipopt's forces hold 1e-12 of its scale). Exact kinematics (no closed reference): every
  // backend against bisection to 1e-9, the same figures.
  const auto model = Overlapping(0.5);
  for (const auto kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    for (const double crank_deg : {0.0, 2.7}) {
      const double crank = ltca::units::DegToRad(crank_deg);
      const auto springs = Springs(*model, crank);
      for (const double torque : {206e3, 0.0, -206e3}) {
        CAPTURE(static_cast<int>(kinematics));
        CAPTURE(crank_deg);
        CAPTURE(torque);
        const LoadProblem problem(model, crank, ltca::test::LinearLaw(kStiffness), {}, torque, kinematics);
        REQUIRE(problem.preloaded());
        const LoadResult reference = Solve(problem);
        REQUIRE(reference.status == SolverStatus::kSuccess);
        const double f_ref = *std::max_element(reference.force.begin(), reference.force.end());
        const ltca::test::TwoFlankBalance want = ltca::test::SolveTwoFlankNetwork(springs, torque);
        const double f_want = *std::max_element(want.force.begin(), want.force.end());
        for (const auto& name : ltca::solvers::SolverNames()) {
          CAPTURE(name);
          REQUIRE(ltca::solvers::MakeSolver(name)->supports_two_flanks());
          const LoadResult r = ltca::test::SolveTight(name, problem);
          REQUIRE(r.status == SolverStatus::kSuccess);
          REQUIRE(r.preload.has_value());
          REQUIRE(r.force.size() == reference.force.size());
          CHECK(r.preload->rotation == reference.preload->rotation);  // the shared assembly
          CHECK(std::abs(r.te - reference.te) <= 1e-9 * std::abs(reference.te));
          double worst = 0.0;
          for (std::size_t i = 0; i < r.force.size(); ++i) worst = std::max(worst, std::abs(r.force[i] - reference.force[i]));
          CHECK(worst <= 1e-9 * f_ref);
          CHECK(Contacts(r.force, f_ref) == Contacts(reference.force, f_ref));
          if (kinematics == ContactKinematics::kLinearised) {
            // (at crank 0 and zero torque the preload rotation is 0 by symmetry: 1e-18 rad of rounding)
            CHECK(std::abs(r.te + want.phi) <= 1e-9 * std::abs(want.phi) + 1e-18);
            double off = 0.0;
            for (std::size_t i = 0; i < r.force.size(); ++i) off = std::max(off, std::abs(r.force[i] - want.force[i]));
            CHECK(off <= 1e-9 * f_want);
            CHECK(Contacts(r.force, f_want) == want.contacts);
          }
          CHECK(r.residuals.Normalised() <= 1e-9);
        }
      }
    }
  }
}

TEST_CASE("solvers: a backend without the two-flank balance refuses a loaded preloaded pair by name") {
  // At zero torque the preload state is the assembly's, shared by every backend (the same numbers);
  // under load a backend without supports_two_flanks() is refused with preload-unsupported, naming
  // it and bisection, no TE claimed, the preload figures kept.
  const auto model = Overlapping(0.5);
  const OneFlankOnly backend;
  ltca::solvers::SolverOptions options;
  options.torque_tolerance = 1e-13;
  for (const auto kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    const LoadProblem zero(model, 0.0, {}, {}, 0.0, kinematics);
    const LoadProblem loaded(model, 0.0, {}, {}, 206e3, kinematics);
    const LoadResult reference = Solve(zero);
    REQUIRE(reference.status == SolverStatus::kSuccess);
    const LoadResult z = backend.Solve(zero, options);
    CHECK(z.status == SolverStatus::kSuccess);
    CHECK(z.rotation == reference.rotation);
    CHECK(z.force == reference.force);
    const LoadResult r = backend.Solve(loaded, options);
    REQUIRE(r.preload.has_value());
    CHECK(r.status == SolverStatus::kPreloadUnsupported);
    CHECK(r.message.find("one-flank-only") != std::string::npos);
    CHECK(r.message.find("bisection") != std::string::npos);
    CHECK(std::isnan(r.te));
  }
}
