// analysis::Backlash, the stage's unloaded backlash over its cranks, against the single-purpose
// computation it is built on: contact::AnalyseUnloaded of each disc's own model (Liu 2021 eq. 17,
// theta_c1 - theta_c2). One disc: the positions are that analysis and the mean its plain mean
// (the repeated state of a closed period once). Two discs turning the output together: on each
// flank the output stops at the nearer first contact of either disc, the second disc half a crank
// turn on. The stage is built from data (analysis::StageDesign), no deck.
#include <algorithm>
#include <cmath>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/analysis/backlash.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"

namespace {

using ltca::analysis::Backlash;
using ltca::analysis::BacklashPosition;
using ltca::analysis::Stage;
using ltca::analysis::StageDesign;
using ltca::contact::ContactKinematics;

/// Liu 2021 Table 1 (40 pins, R_p 64 mm, r_rp 3 mm, e 1.3 mm, B 12 mm) with section 5.2's base
/// modification (dR_rp -4 um, dR_p -17 um): clearance at every pin.
StageDesign Liu52() {
  StageDesign d;
  d.name = "Liu 2021 Table 1, section 5.2 base modification";
  d.pair = {40, 39, 3.0, 64.0, 1.3, 12.0};
  d.modification.pin_radius = -0.004;
  d.modification.pin_circle_radius = -0.017;
  return d;
}

std::vector<double> Cranks(double from_deg, double to_deg, int n) {
  std::vector<double> c;
  for (int i = 0; i < n; ++i) c.push_back(ltca::units::DegToRad(from_deg + (to_deg - from_deg) * i / (n - 1)));
  return c;
}

}  // namespace

TEST_CASE("analysis: one disc's backlash is the unloaded analysis at every crank, its mean the plain mean") {
  for (const ContactKinematics kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    CAPTURE(ltca::contact::ToString(kinematics));
    // One mesh period (360 / 40 deg) in 10 positions: the last state repeats the first.
    const Stage stage(Liu52(), Cranks(0.0, 9.0, 10));
    REQUIRE(stage.closed_period());
    std::vector<BacklashPosition> positions;
    const auto result = Backlash(stage, kinematics, [&](const BacklashPosition& p) { positions.push_back(p); });
    REQUIRE(positions.size() == 10);
    CHECK(result.positions == 10);
    CHECK(result.discs == 1);
    CHECK(result.kinematics == kinematics);
    CHECK(result.summary.failed() == 0);
    const ltca::contact::MeshModel model = Liu52().MakeModel();
    double sum = 0.0, lo = INFINITY, hi = -INFINITY;
    for (std::size_t i = 0; i < positions.size(); ++i) {
      const auto own = ltca::contact::AnalyseUnloaded(model, stage.cranks()[i], kinematics);
      CHECK(positions[i].contact.theta_c1 == own.theta_c1);
      CHECK(positions[i].contact.theta_c2 == own.theta_c2);
      CHECK(positions[i].contact.first_pin_c1 == own.first_pin_c1);
      CHECK(positions[i].disc_c1 == 1);
      if (i + 1 < positions.size()) sum += own.backlash;
      lo = std::min(lo, own.backlash), hi = std::max(hi, own.backlash);
    }
    CHECK(result.summary.mean() == doctest::Approx(sum / 9.0).epsilon(1e-14));
    CHECK(result.summary.pp() == doctest::Approx(hi - lo).epsilon(1e-14));
  }
}

TEST_CASE("analysis: two discs stop the output at the nearer first contact of either disc on each flank") {
  StageDesign design = Liu52();
  ltca::analysis::SecondDisc second;
  second.modification = design.modification;
  second.indexing_deviation = 0.005;  // 5 um ahead along the pin circle
  design.second_disc = second;
  const Stage stage(design, Cranks(0.0, 9.0, 7));
  std::vector<BacklashPosition> positions;
  const auto result = Backlash(stage, ContactKinematics::kLinearised, [&](const BacklashPosition& p) { positions.push_back(p); });
  REQUIRE(positions.size() == 7);
  CHECK(result.discs == 2);
  const ltca::contact::MeshModel first = design.MakeModel();
  const ltca::contact::MeshModel other(design.MakeSecondRealPair(), design.geometry, design.SlicesForced());
  bool second_first = false;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const double crank = stage.cranks()[i];
    const auto a = ltca::contact::AnalyseUnloaded(first, crank, ContactKinematics::kLinearised);
    const auto b = ltca::contact::AnalyseUnloaded(other, crank + ltca::contact::kSecondDiscCrankOffset, ContactKinematics::kLinearised);
    const BacklashPosition& p = positions[i];
    CHECK(p.contact.theta_c1 == std::min(a.theta_c1, b.theta_c1));
    CHECK(p.contact.theta_c2 == std::max(a.theta_c2, b.theta_c2));
    CHECK(p.contact.backlash == doctest::Approx(std::min(a.theta_c1, b.theta_c1) - std::max(a.theta_c2, b.theta_c2)).epsilon(1e-14));
    CHECK(p.disc_c1 == (b.theta_c1 < a.theta_c1 ? 2 : 1));
    CHECK(p.disc_c2 == (b.theta_c2 > a.theta_c2 ? 2 : 1));
    second_first = second_first || p.disc_c1 == 2 || p.disc_c2 == 2;
    // Never more than either disc alone: a second disc only takes up free play.
    CHECK(p.contact.backlash <= std::min(a.backlash, b.backlash) + 1e-15);
  }
  CHECK(second_first);  // the 5 um indexing puts the second disc first on a flank
}
