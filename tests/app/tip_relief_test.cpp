// Issue 12: tip relief under load. As the rounding radius shrinks, the loaded results approach
// those of the sharp tips wherever the sharp tip carries no load; the sharp tips themselves (both
// keys 0) keep their honest edge-contact status; and a pin on the rounding arc has the arm and gap
// of the line from the arc's centre (closed form, tests/geometry/tip_relief_closed_form.hpp).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "geometry/tip_relief_closed_form.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/solvers/registry.hpp"

using ltca::solvers::SolverStatus;

namespace {

struct Run {
  std::vector<ltca::solvers::LoadResult> results;
};

Run Solve(const std::string& deck_file, double rho) {
  const auto deck = ltca::app::LoadDeck(std::string(LTCA_CASES_DIR) + "/" + deck_file,
                                        {"modification.tip_truncation_mm=0",
                                         "modification.tip_rounding_radius_mm=" + std::to_string(rho)});
  const ltca::analysis::Stage stage = deck.MakeStage();
  Run run;
  ltca::solvers::SolverOptions options;
  options.name = "compatibility";
  for (const double crank : deck.sweep.CrankAngles()) {
    run.results.push_back(ltca::solvers::MakeSolver(options.name)
                              ->Solve(stage.Problem(crank, deck.load->torque), options));
  }
  return run;
}

}  // namespace

TEST_CASE("app: as the rounding radius shrinks the results reach the sharp tips wherever those are not loaded") {
  for (const std::string file : {"hard/d2_loaded.toml", "hard/d3_loaded.toml"}) {
    CAPTURE(file);
    const Run sharp = Solve(file, 0.0);
    int edge = 0;
    for (const auto& r : sharp.results) edge += r.status == SolverStatus::kEdgeContact ? 1 : 0;
    CHECK(edge > 0);  // the sharp tips stay honest: loaded corners are edge contact
    double largest_change = 0.0;
    for (const double rho : {0.8, 0.4, 0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625}) {
      CAPTURE(rho);
      const Run relieved = Solve(file, rho);
      double change = 0.0;  // over the positions the sharp tips solve
      for (std::size_t i = 0; i < sharp.results.size(); ++i) {
        REQUIRE(relieved.results[i].status == SolverStatus::kSuccess);  // relieved: every position solves
        if (sharp.results[i].status != SolverStatus::kSuccess) continue;
        double f_max = 0.0;
        for (const double f : sharp.results[i].force) f_max = std::max(f_max, f);
        change = std::max(change, std::abs(relieved.results[i].te - sharp.results[i].te));
        for (std::size_t k = 0; k < sharp.results[i].force.size(); ++k) {
          if (rho <= 0.0125) CHECK(std::abs(relieved.results[i].force[k] - sharp.results[i].force[k]) <= 1e-9 * f_max);
        }
      }
      largest_change = std::max(largest_change, change);
      // Below 0.0125 mm the relief reaches no loaded flank point of either deck (measured: the
      // last change is at 0.025 mm on d3); rounding only then.
      if (rho <= 0.0125) CHECK(change <= 1e-14);
    }
    CHECK(largest_change > 1e-6);  // a large relief does change them: the check has power
  }
}

TEST_CASE("app: a pin on the rounding arc has the gap and arm of the line from the arc centre") {
  const double rho = 0.5;
  const auto deck = ltca::app::LoadDeck(std::string(LTCA_CASES_DIR) + "/hard/d2_loaded.toml",
                                        {"modification.tip_truncation_mm=0", "modification.tip_rounding_radius_mm=0.5"});
  const ltca::contact::MeshModel model = deck.MakeModel();
  const auto& profile = model.profile();
  int on_arc = 0;
  for (int step = 0; step < 60; ++step) {
    const double crank = 0.25 * step * model.kinematics().MeshPeriod() / 15.0;
    const auto state = model.Evaluate(crank, 0.0);
    for (const auto& c : state.pins) {
      if (c.part != ltca::geometry::SurfacePart::kTipRounding) continue;
      ++on_arc;
      const int tip = c.u > 0 ? c.tooth_space : c.tooth_space - 1;
      const Eigen::Vector2d centre_body = ltca::test::RoundingCentre(profile, tip, rho);
      const auto pose = model.CyclePose(crank, 0.0, c.z);
      const Eigen::Vector2d centre = pose.ToFixed(centre_body);
      const Eigen::Vector2d pin = model.PinCentre(c.pin);
      const Eigen::Vector2d n = (pin - centre).normalized();
      const Eigen::Vector2d lever = centre - pose.centre;
      CHECK(c.clearance == doctest::Approx((pin - centre).norm() - rho - c.pin_radius).epsilon(1e-9).scale(1.0));
      CHECK(c.arm == doctest::Approx(model.load_direction() * (lever.x() * n.y() - lever.y() * n.x())).epsilon(1e-8));
      CHECK(c.cycloid_curvature == doctest::Approx(1.0 / rho));
      CHECK(c.normal.dot(n) == doctest::Approx(1.0).epsilon(1e-9));
    }
  }
  CHECK(on_arc > 0);
}
