// The analytic profile against finite differences of its own position, Liu's curvature formula,
// and the validity checks.
#include <cmath>
#include <stdexcept>
#include <string>

#include <doctest/doctest.h>

#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/units.hpp"
#include "helpers.hpp"
#include "pairs.hpp"

using ltca::geometry::CycloidProfile;
using ltca::geometry::Modification;
using ltca::geometry::PairParameters;

namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

TEST_CASE("geometry: normals, derivatives and curvature radii agree with finite differences") {
  // Five-point finite differences of Position(u) (test only). Compared at 1e-6 relative, away
  // from the inflection point where the radius of curvature is unbounded (|rho| < 1e3 mm).
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    for (const double d_rrp : {0.0, 0.01}) {
      Modification mod;
      mod.pin_radius = d_rrp;
      mod.pin_circle_radius = -0.02;
      const CycloidProfile profile(pair, mod);
      const double s = pair.ToothDifference() > 0 ? 1.0 : -1.0;
      for (int k : {0, 3}) {
        for (int i = -40; i <= 40; ++i) {
          const double u = profile.phi_max() * (i + 0.37) / 41.0;
          CAPTURE(name);
          CAPTURE(u);
          const auto p = profile.Evaluate(u, k);
          CHECK((p.position - profile.Position(u, k)).norm() < 1e-12);
          // Five-point stencils, step scaled to the fastest term (e Ze^2): truncation ~(Ze h)^4.
          const double h = 2e-3 / std::max(1.0, std::abs(static_cast<double>(pair.pin_count) / pair.ToothDifference()));
          const auto fd = [&](auto f) {
            const Eigen::Vector2d m2 = f(u - 2 * h), m1 = f(u - h), z = f(u), p1 = f(u + h), p2 = f(u + 2 * h);
            return std::pair<Eigen::Vector2d, Eigen::Vector2d>{(m2 - 8 * m1 + 8 * p1 - p2) / (12 * h),
                                                              (-m2 + 16 * m1 - 30 * z + 16 * p1 - p2) / (12 * h * h)};
          };
          const auto [fd1, fd2] = fd([&](double v) { return profile.Position(v, k); });
          CHECK((p.d1 - fd1).norm() < 1e-6 * fd1.norm());
          CHECK((p.d2 - fd2).norm() < 1e-5 * std::max(fd2.norm(), fd1.norm()));
          // Unit normal, perpendicular to the tangent, pointing out of the material: for d > 0
          // the material is on the side of the gear centre at the root.
          CHECK(std::abs(p.normal.norm() - 1.0) < 1e-12);
          CHECK(std::abs(p.normal.dot(fd1)) < 1e-6 * fd1.norm());
          CHECK(s * Cross(fd1, p.normal) < 0.0);
          // Signed curvature toward the material from the finite-difference derivatives.
          const double kappa_m = s * Cross(fd1, fd2) / std::pow(fd1.norm(), 3);
          if (std::abs(p.CurvatureRadius()) < 1e3) {
            CHECK(std::abs(1.0 / kappa_m - p.CurvatureRadius()) < 1e-6 * std::abs(p.CurvatureRadius()));
          }
          // The same for the pin-centre locus (the theoretical profile, r = 0).
          const auto [q1, q2] = fd([&](double v) { return profile.PinCentreLocus(v, k); });
          const double kl = s * Cross(q1, q2) / std::pow(q1.norm(), 3);
          CHECK(std::abs(kl - profile.LocusCurvature(u)) < 1e-6 * std::max(std::abs(kl), 1.0 / pair.pin_circle_radius));
        }
      }
    }
  }
}

TEST_CASE("geometry: curvature radius matches Liu 2021 eq. 8, concave at the root, convex at the tip") {
  // Liu eq. 8 typed in for the Table 1 pair with a compound modification; 1e-9 relative.
  const auto pair = ltca::test::LiuPair();
  Modification mod;
  mod.pin_radius = -0.004;
  mod.pin_circle_radius = -0.017;
  const CycloidProfile profile(pair, mod);
  const double e = 1.3, zp = 40, rp = 64 - 0.017, rrp = 3 - 0.004;
  for (int i = 0; i <= 100; ++i) {
    const double phi_p = ltca::units::kPi * i / 100.0;  // Liu's phi_p = z_c u
    const double num = std::pow(e * e * zp * zp + rp * rp - 2 * e * zp * rp * std::cos(phi_p), 1.5);
    const double den = e * e * zp * zp * zp + rp * rp - e * zp * (1 + zp) * rp * std::cos(phi_p);
    const double rho_liu = num / den - rrp;
    const double rho = profile.Evaluate(phi_p / pair.tooth_count).CurvatureRadius();
    if (std::abs(rho_liu) < 1e4) CHECK(std::abs(rho - rho_liu) < 1e-9 * std::abs(rho_liu));
  }
  // At the root the theoretical profile has a 0.0714 mm concave radius (R (1-K1)^2 / (1 - K1 z_p))
  // and the real one r' + 0.0714 mm; the pair is valid (the offset goes to the convex side).
  const CycloidProfile perfect(pair);
  CHECK(perfect.Evaluate(0.0).CurvatureRadius() == doctest::Approx(-(3.0 + 64 * 0.1875 * 0.1875 / 31.5)).epsilon(1e-12));
  CHECK(perfect.Evaluate(perfect.phi_max()).CurvatureRadius() > 0.0);
}

TEST_CASE("geometry: undercut margin and minimum curvature radius are the extremes over the tooth") {
  // The closed-form extremes (one critical point of the curvature in cos(Z_d u)) against a
  // dense scan of the analytic curvature; 1e-6 relative (scan step 1e-5 of the flank).
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    CAPTURE(name);
    const CycloidProfile profile(pair);
    double min_abs_rho = 1e300, min_convex_locus = 1e300;
    for (int i = 0; i <= 100000; ++i) {
      const double u = profile.phi_max() * i / 100000.0;
      min_abs_rho = std::min(min_abs_rho, std::abs(profile.Evaluate(u).CurvatureRadius()));
      const double kl = profile.LocusCurvature(u);
      if (kl > 0) min_convex_locus = std::min(min_convex_locus, 1.0 / kl);
    }
    CHECK(profile.min_curvature_radius() == doctest::Approx(min_abs_rho).epsilon(1e-6));
    CHECK(profile.undercut_margin() == doctest::Approx(min_convex_locus - pair.pin_radius).epsilon(1e-6));
    CHECK(profile.undercut_margin() > 0.0);
  }
}

TEST_CASE("geometry: invalid pairs are rejected with the key, the value and what is expected") {
  const PairParameters good = ltca::test::LiuPair();
  auto with = [&](auto change) {
    PairParameters p = good;
    change(p);
    return ltca::test::InvalidArgumentMessage([&] { CycloidProfile profile(p); });
  };
  CHECK(with([](PairParameters&) {}) == "");
  CHECK(with([](PairParameters& p) { p.tooth_count = 40; }).find("tooth_count = 40") != std::string::npos);
  CHECK(with([](PairParameters& p) { p.pin_radius = -3; }).find("pin_radius_mm = -3") != std::string::npos);
  CHECK(with([](PairParameters& p) { p.pin_circle_radius = 0; }).find("pin_circle_radius_mm") != std::string::npos);
  CHECK(with([](PairParameters& p) { p.eccentricity = NAN; }).find("eccentricity_mm") != std::string::npos);
  CHECK(with([](PairParameters& p) { p.face_width = 0; }).find("face_width_mm") != std::string::npos);
  CHECK(with([](PairParameters& p) { p.pin_count = 1; }).find("pin_count") != std::string::npos);
  // K1 = e z_p / R_p >= 1 (prolate, not a cycloid drive).
  CHECK(with([](PairParameters& p) { p.eccentricity = 1.6; }).find("curtate coefficient") != std::string::npos);
  // Pins overlap: r_rp >= R_p sin(pi / z_p) = 5.02 mm.
  CHECK(with([](PairParameters& p) { p.pin_radius = 5.1; }).find("pins overlap") != std::string::npos);
  // Undercut: the smallest convex radius of the Liu locus is 4.6117 mm (margin 1.6117 at r = 3).
  CHECK(with([](PairParameters& p) { p.pin_radius = 4.7; }).find("undercut") != std::string::npos);
  CHECK(with([](PairParameters& p) { p.pin_radius = 4.5; }) == "");
  // A modification that makes the generating radius vanish or K1 reach 1.
  Modification m;
  m.pin_radius = -3.0;
  CHECK(ltca::test::InvalidArgumentMessage([&] { CycloidProfile profile(good, m); }).find("[modification] pin_radius_mm") != std::string::npos);
  m = {};
  m.pin_circle_radius = -12.0;  // K1 = 52 / 52 = 1
  CHECK(ltca::test::InvalidArgumentMessage([&] { CycloidProfile profile(good, m); }).find("[modification] pin_circle_radius_mm") != std::string::npos);
}

TEST_CASE("geometry: undercut is judged on the side the profile is offset to, also for d = -1") {
  // d = -1: the real profile is the outer equidistant, so the undercut comes from locus parts
  // convex toward the outside, not from those that undercut a d > 0 profile. The margin is the
  // smallest such radius minus r'; a pin radius just above (still without overlapping pins)
  // must be rejected and one just below accepted.
  PairParameters p = ltca::test::ChenPair(15, 16, 120, 10, 5);
  p.eccentricity = 7.0;  // K1 = 0.875: tighter curvature
  const CycloidProfile base(p);
  const double limit = base.undercut_margin() + p.pin_radius;
  REQUIRE(limit < p.pin_circle_radius * std::sin(ltca::units::kPi / 15));
  PairParameters above = p, below = p;
  above.pin_radius = limit * 1.001;
  below.pin_radius = limit * 0.999;
  CHECK(ltca::test::InvalidArgumentMessage([&] { CycloidProfile profile(above); }).find("undercut") != std::string::npos);
  CHECK(ltca::test::InvalidArgumentMessage([&] { CycloidProfile profile(below); }) == "");
  // Why: the equidistant x = q + s r n stretches by 1 - r kappa_m (kappa_m: locus curvature toward
  // the material, checked against finite differences above). Past the limit that factor turns
  // negative somewhere on the tooth (a cusp); below it, it stays positive everywhere.
  double min_stretch_above = 1e300, min_stretch_below = 1e300;
  for (int i = 0; i <= 20000; ++i) {
    const double u = base.phi_max() * i / 20000.0;
    min_stretch_above = std::min(min_stretch_above, 1.0 - above.pin_radius * base.LocusCurvature(u));
    min_stretch_below = std::min(min_stretch_below, 1.0 - below.pin_radius * base.LocusCurvature(u));
  }
  CHECK(min_stretch_above < 0.0);
  CHECK(min_stretch_below > 0.0);
}

TEST_CASE("geometry: the contact ratio of a 100,000-pin pair has no int overflow") {
  // z_p z_c = 100,000 x 99,999 overflows an int. For d = 1, phi_max = pi / z_c (Chen eq. 16;
  // 180 / 11 deg for z_c = 11 in chen_test), so eq. 27 gives z_p / 2 = 50,000 exactly.
  // R_p = 1.6 z_p keeps the pin spacing and K1 = 0.8125 of the Liu pair.
  const int zp = 100'000;
  const PairParameters pair{zp, zp - 1, 3.0, 1.6 * zp, 1.3, 12.0};
  const ltca::geometry::CycloidProfile profile(pair);
  CHECK(profile.contact_ratio() == doctest::Approx(50'000.0).epsilon(1e-9));
}
