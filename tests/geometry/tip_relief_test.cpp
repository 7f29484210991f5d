// Issue 12: the relieved tooth tip (geometry::TipCap) against closed forms computed here.
#include <cmath>
#include <stdexcept>

#include <doctest/doctest.h>

#include "geometry/tip_relief_closed_form.hpp"
#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/tip_relief.hpp"
#include "pairs.hpp"

using ltca::geometry::CapFoot;
using ltca::geometry::CycloidProfile;
using ltca::geometry::Modification;
using ltca::geometry::SurfacePart;

namespace {

Modification Relief(double truncation, double rho) {
  Modification m;
  m.tip_relief = {truncation, rho};
  return m;
}

// Radius of the circle through three points.
double Circumradius(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d u = b - a, v = c - a;
  const double area2 = std::abs(u.x() * v.y() - u.y() * v.x());
  return (b - c).norm() * v.norm() * u.norm() / (2.0 * area2);
}

}  // namespace

TEST_CASE("geometry: a tip relief leaves Chen's flank figures unchanged (phi_max, contact ratio, curvature)") {
  for (const auto& named : ltca::test::ChenPairs()) {
    CAPTURE(named.name);
    const CycloidProfile sharp(named.pair);
    for (const auto& [t, rho] : {std::pair{0.0, 0.5}, std::pair{0.3, 0.5}, std::pair{0.3, 0.0}}) {
      const CycloidProfile relieved(named.pair, Relief(t, rho));
      CHECK(relieved.phi_max() == sharp.phi_max());
      CHECK(relieved.contact_ratio() == sharp.contact_ratio());
      CHECK(relieved.min_curvature_radius() == sharp.min_curvature_radius());
      CHECK(relieved.undercut_margin() == sharp.undercut_margin());
      CHECK(relieved.Position(0.3 * sharp.phi_max(), 2) == sharp.Position(0.3 * sharp.phi_max(), 2));
      // A truncation always cuts; a rounding alone changes a sharp tip only (|d| >= 2).
      CHECK(relieved.tip_cap().active() == (t > 0.0 || std::abs(named.pair.ToothDifference()) >= 2));
    }
  }
}

TEST_CASE("geometry: the rounding arc has curvature 1 / rho and the closed-form centre, tangent to the flank") {
  const auto pair = ltca::test::ChenPairs()[1].pair;  // Chen 3.2, d = 2
  const double rho = 0.5;
  const CycloidProfile profile(pair, Relief(0.0, rho));
  const auto& cap = profile.tip_cap();
  REQUIRE(cap.active());
  REQUIRE_FALSE(cap.truncated());
  for (const int tip : {0, 5}) {
    CAPTURE(tip);
    // Three points of the arc lie on a circle of radius rho, around the closed-form centre.
    const Eigen::Vector2d centre = ltca::test::RoundingCentre(profile, tip, rho);
    const CapFoot a = cap.Point(-0.7, tip), b = cap.Point(0.1, tip), c = cap.Point(0.9, tip);
    CHECK(Circumradius(a.point, b.point, c.point) == doctest::Approx(rho).epsilon(1e-9));
    for (const CapFoot& f : {a, b, c}) {
      CHECK(f.part == SurfacePart::kTipRounding);
      CHECK(f.curvature == doctest::Approx(1.0 / rho).epsilon(1e-15));
      CHECK((f.point - centre).norm() == doctest::Approx(rho).epsilon(1e-9));
      CHECK((f.point - centre).normalized().dot(f.normal) == doctest::Approx(1.0).epsilon(1e-9));
    }
    // Tangency: at the junction the arc starts where the flank ends, with the flank's normal, on
    // both sides of the tip (space tip at +u_j, space tip + 1 at -u_j).
    const double u_j = cap.junction();
    const auto flank_hi = profile.Evaluate(u_j, tip);
    const auto flank_lo = profile.Evaluate(-u_j, tip + 1);
    CHECK((cap.Point(1.0, tip).point - flank_hi.position).norm() < 1e-12);
    CHECK((cap.Point(-1.0, tip).point - flank_lo.position).norm() < 1e-12);
    CHECK(cap.Point(1.0, tip).normal.dot(flank_hi.normal) == doctest::Approx(1.0).epsilon(1e-12));
    CHECK(cap.Point(-1.0, tip).normal.dot(flank_lo.normal) == doctest::Approx(1.0).epsilon(1e-12));
    // The arc's own tangent just inside the junction is the flank's tangent there (to O(step)).
    const Eigen::Vector2d chord = (cap.Point(1.0, tip).point - cap.Point(1.0 - 1e-6, tip).point).normalized();
    CHECK(std::abs(chord.dot(flank_hi.normal)) < 1e-5);
    // The nearest point of a pin centre 7 mm out along a radius of the arc is on that radius.
    for (const double w : {-0.5, 0.0, 0.6}) {
      const CapFoot on = cap.Point(w, tip);
      const Eigen::Vector2d p = centre + (rho + 7.0) * (on.point - centre).normalized();
      const CapFoot f = cap.Nearest(p, tip);
      CHECK(f.part == SurfacePart::kTipRounding);
      CHECK(f.distance == doctest::Approx(7.0).epsilon(1e-9));
      CHECK((f.point - on.point).norm() < 1e-9);
    }
  }
}

TEST_CASE("geometry: a truncation cuts the tip back along its axis, and the arc is tangent to the line") {
  const auto pair = ltca::test::ChenPairs()[2].pair;  // Chen 3.3, d = 3
  const double t = 0.3, rho = 0.4;
  const CycloidProfile profile(pair, Relief(t, rho));
  const CycloidProfile sharp(pair);
  const auto& cap = profile.tip_cap();
  REQUIRE(cap.truncated());
  const int tip = 3;
  const Eigen::Vector2d corner = sharp.Position(sharp.phi_max(), tip);
  // The apex (w = 0) lies on the axis, t inside the corner; the land is perpendicular to the axis.
  const Eigen::Vector2d apex = cap.Point(0.0, tip).point;
  CHECK(apex.norm() == doctest::Approx(corner.norm() - t).epsilon(1e-13));
  CHECK(std::abs(apex.normalized().dot(corner.normalized()) - 1.0) < 1e-14);
  const double w_land = cap.land_half_width() / (0.5 * cap.length());
  const CapFoot land_end = cap.Point(w_land, tip);
  CHECK(land_end.part == SurfacePart::kTipTruncation);
  CHECK((land_end.point - apex).dot(corner.normalized()) == doctest::Approx(0.0).scale(1.0).epsilon(1e-12));
  CHECK((land_end.point - apex).norm() == doctest::Approx(cap.land_half_width()).epsilon(1e-12));
  // Across the line-arc tangency the normal turns continuously.
  const CapFoot before = cap.Point(w_land - 1e-7, tip), after = cap.Point(w_land + 1e-7, tip);
  CHECK(before.part == SurfacePart::kTipTruncation);
  CHECK(after.part == SurfacePart::kTipRounding);
  CHECK(before.normal.dot(after.normal) == doctest::Approx(1.0).epsilon(1e-9));
  CHECK((before.point - after.point).norm() < 1e-6);
  // A point straight out from the land sees the land.
  const CapFoot f = cap.Nearest(apex + 5.0 * corner.normalized(), tip);
  CHECK(f.part == SurfacePart::kTipTruncation);
  CHECK(f.distance == doctest::Approx(5.0).epsilon(1e-12));
  CHECK(f.curvature == 0.0);
}

TEST_CASE("geometry: a relief that does not fit the tooth is an error naming the key") {
  const auto pair = ltca::test::ChenPairs()[1].pair;
  CHECK_THROWS_WITH_AS(CycloidProfile(pair, Relief(40.0, 0.0)), doctest::Contains("tip_truncation_mm = 40"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(CycloidProfile(pair, Relief(0.0, -1.0)), doctest::Contains("tip_rounding_radius_mm = -1"),
                       std::invalid_argument);
}
