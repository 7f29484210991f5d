// The deviation chart's fit (geometry/deviation_fit.hpp): a trace made here from a known
// modification, by a method of the test's own (the design's normal line at u cut with the
// modified profile by bisection, not the library's Newton), is fitted back to that modification
// to 1e-6 mm (the rotation as its arc on the pin circle, R_p x rotation); and the isometric
// modification alone deviates the profile by -dR_rp exactly (the equidistant of the pin-centre
// locus), 1e-12 mm.
#include <cmath>
#include <stdexcept>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/geometry/deviation_fit.hpp"
#include "pairs.hpp"

namespace deviation_fit_test {

using ltca::geometry::CycloidProfile;
using ltca::geometry::Modification;

/// t where the profile made with `design`'s modification plus `delta` cuts the design's normal
/// line at u: bisection of the cross product of (x_m(v) - x(u)) with n(u) over v in u +- 0.02 rad.
double OwnDeviation(const CycloidProfile& design, const Modification& delta, double u) {
  Modification m = design.modification();
  m.pin_circle_radius += delta.pin_circle_radius;
  m.pin_radius += delta.pin_radius;
  m.rotation += delta.rotation;
  const CycloidProfile other(design.pair(), m);
  const auto at = design.Evaluate(u, 0);
  const auto side = [&](double v) {
    const Eigen::Vector2d r = other.Position(v, 0) - at.position;
    return r.x() * at.normal.y() - r.y() * at.normal.x();
  };
  double a = u - 0.02, b = u + 0.02;
  REQUIRE(side(a) * side(b) < 0.0);
  for (int it = 0; it < 200 && b - a > 1e-16; ++it) {
    const double c = 0.5 * (a + b);
    (side(a) * side(c) <= 0.0 ? b : a) = c;
  }
  return (other.Position(0.5 * (a + b), 0) - at.position).dot(at.normal);
}

void CheckFit(const CycloidProfile& design, const Modification& known) {
  std::vector<double> u, delta;
  const double span = 0.98 * design.phi_max();
  for (int i = 0; i <= 80; ++i) {
    u.push_back(-span + 2.0 * span * i / 80.0);
    delta.push_back(OwnDeviation(design, known, u.back()));
  }
  const ltca::geometry::DeviationFit fit = ltca::geometry::FitModification(design, u, delta);
  const double lever = design.pair().pin_circle_radius;
  MESSAGE("fitted dR_p " << fit.offset << " mm, dR_rp " << fit.isometric << " mm, rotation " << fit.rotation
                         << " rad in " << fit.iterations << " steps, rms residual " << fit.rms_residual << " mm");
  CHECK(std::abs(fit.offset - known.pin_circle_radius) <= 1e-6);
  CHECK(std::abs(fit.isometric - known.pin_radius) <= 1e-6);
  CHECK(lever * std::abs(fit.rotation - known.rotation) <= 1e-6);
  CHECK(fit.max_residual <= 1e-6);
}

}  // namespace deviation_fit_test

TEST_CASE("geometry: an isometric modification alone deviates the profile by -dR_rp, the equidistant (1e-12 mm)") {
  const CycloidProfile design(ltca::test::LiuPair(), ltca::test::Mod(-4.0, -17.0));
  Modification iso;
  iso.pin_radius = 0.006;
  for (const double f : {-0.9, -0.4, 0.0, 0.3, 0.95}) {
    CHECK(std::abs(ltca::geometry::ModificationDeviation(design, iso, f * design.phi_max()) + 0.006) <= 1e-12);
  }
}

TEST_CASE("geometry: the fit of a trace made from a known offset, isometric and rotation modification returns it "
          "to 1e-6 mm (d = 1 Liu, d = 2 and d = -1 Chen)") {
  Modification known;
  known.pin_circle_radius = 0.012;
  known.pin_radius = -0.007;
  known.rotation = 0.01 * 3.14159265358979323846 / 180.0;
  SUBCASE("Liu Table 1 as modified in section 5.2") {
    deviation_fit_test::CheckFit(CycloidProfile(ltca::test::LiuPair(), ltca::test::Mod(-4.0, -17.0)), known);
  }
  SUBCASE("Chen d = 2") { deviation_fit_test::CheckFit(CycloidProfile(ltca::test::ChenPairs()[1].pair), known); }
  SUBCASE("Chen d = -1 (a ring)") { deviation_fit_test::CheckFit(CycloidProfile(ltca::test::ChenPairs()[3].pair), known); }
}

TEST_CASE("geometry: the deviation fit refuses a trace of one flank") {
  const CycloidProfile design(ltca::test::LiuPair());
  CHECK_THROWS_AS(ltca::geometry::FitModification(design, {0.01, 0.02, 0.03}, {0.0, 0.0, 0.0}), std::invalid_argument);
}
