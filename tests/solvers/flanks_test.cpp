// Issue 9, both flanks: the sign of the torque picks the flank and the direction of the loaded
// rotation. Independent references: the mirror symmetry of the perfect pair, and the unloaded
// analysis (contact::AnalyseUnloaded), which turns the cycloid both ways to first contact by its
// own code path.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "problems.hpp"

#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "ltca/solvers/registry.hpp"

using ltca::contact::ContactKinematics;
using ltca::solvers::Flank;
using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::SolverOptions;
using ltca::solvers::SolverStatus;
using ltca::test::SolveWith;

TEST_CASE("solvers: perfect pair: TE(-T) at crank -theta = -TE(T) at crank theta, on the mirrored (coast) flank") {
  // The perfect pair is symmetric about the line of centres at crank 0: mirrored, the pose at
  // crank theta becomes the pose at -theta with the rotation reversed. Tolerance: the solves
  // balance the torque to 1e-10, which leaves ~1e-10 relative in the TE.
  // Liu 2021 Table 1 (as cases/hard/zero_clearance.toml): the perfect pair, zero clearance.
  const ltca::test::PaperCase perfect = ltca::test::LiuTable1();
  const auto model = perfect.Model();
  const double torque = perfect.torque;
  int checked = 0;
  for (const auto kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    for (const std::string solver : {"bisection", "energy-qp", "energy-groups", "compatibility"}) {
      for (const double deg : {0.0, 1.3, 2.9, 4.5, 7.7}) {
        const double crank = ltca::units::DegToRad(deg);
        CAPTURE(solver);
        CAPTURE(deg);
        const LoadResult drive = SolveWith(solver, LoadProblem(model, crank, perfect.contact, perfect.material, torque, kinematics));
        const LoadResult coast = SolveWith(solver, LoadProblem(model, -crank, perfect.contact, perfect.material, -torque, kinematics));
        REQUIRE(drive.status == SolverStatus::kSuccess);
        REQUIRE(coast.status == SolverStatus::kSuccess);
        CHECK(drive.flank == Flank::kDrive);
        CHECK(coast.flank == Flank::kCoast);
        CHECK(drive.te < 0.0);
        CHECK(coast.te == doctest::Approx(-drive.te).epsilon(1e-8));
        // The mirror image of pin j (angle phi) is the pin at -phi: it carries the same force.
        const int n = static_cast<int>(drive.force.size());
        double f_max = 0.0;
        for (const double f : drive.force) f_max = std::max(f_max, f);
        for (int j = 0; j < n; ++j) {
          const int mirror = (n - j) % n;
          CHECK(std::abs(coast.force[static_cast<std::size_t>(mirror)] - drive.force[static_cast<std::size_t>(j)]) <= 1e-7 * f_max);
        }
        ++checked;
      }
    }
  }
  CHECK(checked == 40);
}

TEST_CASE("solvers: modified pair: rotation from the loaded position at -T to the one at +T = backlash + both wind-ups") {
  // Liu 2021 section 5.2's base modification (cases/liu2021_sec52_base.toml: backlash 48.1 arcsec;
  // until issue 24 this test ran on the unmodified Table 1 pair, whose backlash is 0). The backlash and the first
  // contact both ways come from the unloaded analysis; each wind-up is the loaded rotation beyond
  // that flank's first contact. The -T problem must find its own first contact at -theta_c2,
  // load only pins that a rotation against the load direction closes (arm < 0 on the drive
  // flank), and turn the cycloid the other way.
  const ltca::test::PaperCase modified = ltca::test::LiuSec52Base();
  const auto model = modified.Model();
  const double torque = modified.torque;
  int checked = 0;
  for (const auto kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    for (const std::string solver : {"bisection", "compatibility"}) {
      const auto cranks = modified.Cranks();
      for (std::size_t k = 0; k < cranks.size(); k += 9) {
        CAPTURE(solver);
        CAPTURE(k);
        const double crank = cranks[k];
        const auto unloaded = ltca::contact::AnalyseUnloaded(*model, crank, kinematics);
        REQUIRE(unloaded.backlash > 0.0);  // the case this test is about: a pair with backlash
        const LoadProblem plus(model, crank, modified.contact, modified.material, torque, kinematics);
        const LoadProblem minus(model, crank, modified.contact, modified.material, -torque, kinematics);
        CHECK(plus.LoadedRotationRange().first_contact == doctest::Approx(unloaded.theta_c1).epsilon(1e-12));
        CHECK(minus.LoadedRotationRange().first_contact == doctest::Approx(-unloaded.theta_c2).epsilon(1e-12));
        const LoadResult a = SolveWith(solver, plus), b = SolveWith(solver, minus);
        REQUIRE(a.status == SolverStatus::kSuccess);
        REQUIRE(b.status == SolverStatus::kSuccess);
        const double phi_plus = plus.direction() * a.rotation, phi_minus = minus.direction() * b.rotation;
        CHECK(phi_plus > 0.0);
        CHECK(phi_minus < 0.0);
        const double windup_plus = a.rotation - unloaded.theta_c1;
        const double windup_minus = b.rotation + unloaded.theta_c2;
        CHECK(windup_plus > 0.0);
        CHECK(windup_minus > 0.0);
        CHECK(phi_plus - phi_minus == doctest::Approx(unloaded.backlash + windup_plus + windup_minus).epsilon(1e-12));
        CHECK(a.te == doctest::Approx(-phi_plus).epsilon(1e-15));
        CHECK(b.te == doctest::Approx(-phi_minus).epsilon(1e-15));
        const auto drive_state = model->Evaluate(crank, 0.0);
        // Pins in contact: above 1e-6 of the largest force.
        double f_max = 0.0;
        for (std::size_t j = 0; j < a.force.size(); ++j) f_max = std::max({f_max, a.force[j], b.force[j]});
        // Pins on the line of centres (arm zero to rounding at psi = 0) are touched on both
        // flanks under exact kinematics: left out.
        const double min_arm = 1e-9 * model->pair().pin_circle_radius;
        for (std::size_t j = 0; j < b.force.size(); ++j) {
          if (std::abs(drive_state.pins[j].arm) <= min_arm) continue;
          if (b.force[j] > 1e-6 * f_max) CHECK(drive_state.pins[j].arm < 0.0);
          if (a.force[j] > 1e-6 * f_max) CHECK(drive_state.pins[j].arm > 0.0);
        }
        ++checked;
      }
    }
  }
  CHECK(checked == 4 * 11);
}
