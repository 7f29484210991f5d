// The contact layer on a cycloid with a profile deviation along the profile (Liu 2021 eq. 4,
// geometry::ProfileDeviation): the gap is the distance from the pin centre to the flank as made,
// x(u) + delta(k, u) n(u), minimised near the smooth foot point (docs/contact.md, "Profile
// deviation along the profile").
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/profile_deviation.hpp"
#include "ltca/geometry/real_pair.hpp"
#include "pairs.hpp"

using ltca::contact::MeshModel;
using ltca::geometry::GeometrySettings;
using ltca::geometry::ManufacturingErrors;
using ltca::geometry::MeasuredProfile;
using ltca::geometry::RealPair;

namespace {

// A measured trace that is `value` mm everywhere: two points at the ends of the flank.
MeasuredProfile ConstantTrace(const ltca::geometry::PairParameters& pair, const ltca::geometry::Modification& mod,
                              double value) {
  const double phi = ltca::geometry::CycloidProfile(pair, mod).phi_max();
  MeasuredProfile trace;
  trace.source = "constant";
  trace.abscissa = MeasuredProfile::Abscissa::kProfileAngle;
  trace.x = {-phi, 0.0, phi};
  trace.deviation = {value, value, value};
  trace.line = {1, 2, 3};
  return trace;
}

// Liu 2021 section 5.2: Table 1 with dR_rp = -4 um, dR_p = -17 um, F_alpha^c = +-3 um (a zone of
// 6 um full width), each of 800 elements random within it (uniform), seed 1.
ManufacturingErrors LiuZone() {
  ManufacturingErrors e;
  e.profile_random.zone = 6e-3;
  e.profile_random.elements = 800;
  e.profile_random.seed = 1;
  return e;
}

// Brute force (test only): the distance from body-frame point p to the flank as made of tooth
// spaces k - 1, k, k + 1, sampled densely (20 samples per random element over the whole flank),
// then every sampled local minimum within 1 um of the best refined by golden section: the
// distance has kinks at the element centres, so one basin may hide the minimum of another.
double BruteDeviatedDistance(const RealPair& real, const Eigen::Vector2d& p, int k) {
  const auto& profile = real.profile();
  const auto& dev = real.profile_deviation();
  const int zc = profile.pair().tooth_count;
  const int n = 20 * 800;
  const double phi = profile.phi_max();
  const auto distance = [&](int kk, double u) {
    const auto x = profile.Evaluate(u, kk);
    return (p - x.position - dev.At(kk, u) * x.normal).norm();
  };
  double best = std::numeric_limits<double>::infinity();
  for (int dk = -1; dk <= 1; ++dk) {
    const int kk = ((k + dk) % zc + zc) % zc;
    std::vector<double> f(static_cast<std::size_t>(n + 1));
    for (int i = 0; i <= n; ++i) f[static_cast<std::size_t>(i)] = distance(kk, -phi + 2.0 * phi * i / n);
    const double sampled = *std::min_element(f.begin(), f.end());
    best = std::min(best, sampled);
    for (int i = 0; i <= n; ++i) {
      const double fi = f[static_cast<std::size_t>(i)];
      if (fi > sampled + 1e-3) continue;
      if ((i > 0 && f[static_cast<std::size_t>(i - 1)] < fi) || (i < n && f[static_cast<std::size_t>(i + 1)] < fi)) continue;
      double a = -phi + 2.0 * phi * std::max(0, i - 1) / n, b = -phi + 2.0 * phi * std::min(n, i + 1) / n;
      const double g = (std::sqrt(5.0) - 1.0) / 2.0;
      for (int it = 0; it < 80; ++it) {
        const double c = b - g * (b - a), d = a + g * (b - a);
        if (distance(kk, c) < distance(kk, d)) b = d; else a = c;
      }
      best = std::min(best, distance(kk, 0.5 * (a + b)));
    }
  }
  return best;
}

}  // namespace

TEST_CASE("contact: a constant profile deviation c is the uniform profile layer c") {
  // Independent path: the layer pair is generated through the pin radius r' - c (RealPair), whose
  // equidistant is the flank x + c n exactly; the deviation pair searches x + c n near the smooth
  // foot point. Every clearance and arm agree to 1e-9 mm and the curvature to 1e-9 relative
  // (kappa / (1 + kappa c) is the equidistant's), on d = 1, 2, 3, -1 and Liu's pair, modified,
  // at rotated poses. Tip corners of |d| >= 2 are left out: the layer pair's corners are where its
  // own arcs meet, a little off the ends of the shifted arcs.
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    CAPTURE(name);
    const auto mod = ltca::test::Mod(4, -9);
    for (const double c : {0.002, -0.003}) {
      CAPTURE(c);
      ManufacturingErrors layer, measured;
      layer.profile_layer = c;
      measured.profile_measured = ConstantTrace(pair, mod, c);
      const MeshModel a(RealPair(pair, mod, layer)), b(RealPair(pair, mod, measured));
      REQUIRE(!b.real_pair().profile_deviation().IsZero());
      for (const double crank : {0.0, 0.05, 1.0}) {
        for (const double psi : {0.0, 2e-4}) {
          const auto sa = a.Evaluate(crank, psi), sb = b.Evaluate(crank, psi);
          for (std::size_t i = 0; i < sa.pins.size(); ++i) {
            const auto &pa = sa.pins[i], &pb = sb.pins[i];
            if (pa.edge || pb.edge) continue;
            CAPTURE(i);
            CHECK(std::abs(pa.clearance - pb.clearance) < 1e-9);
            CHECK(std::abs(pa.arm - pb.arm) < 1e-9);
            CHECK(pb.cycloid_curvature == doctest::Approx(pa.cycloid_curvature).epsilon(1e-9));
            CHECK((pa.cycloid_point - pb.cycloid_point).norm() < 1e-9);
          }
        }
      }
    }
  }
}

TEST_CASE("contact: with Liu's +-3 um random zone the gap is the brute-force minimum over the flank as made") {
  // Liu section 5.2 pair and zone (800 elements, uniform, seed 1), every pin at three cranks and
  // two rotations: the clearance equals the brute-force distance from the pin centre to
  // x(u) + delta(k, u) n(u) over the whole flank of the tooth space and both neighbours, minus r,
  // to 1e-9 mm. Both evaluate the same x and delta; the brute force is refined by golden section
  // to 1e-13 rad (1e-10 mm of arc), so what is left is the rounding of the two searches. (The
  // tolerance of the issue, 1e-6 mm, is that of a plain sampling without refinement.)
  const MeshModel model(RealPair(ltca::test::LiuPair(), ltca::test::Mod(-4, -17), LiuZone()));
  for (const double crank : {0.0, 0.031, 0.1}) {
    for (const double psi : {0.0, 3e-4}) {
      const auto state = model.Evaluate(crank, psi);
      for (const auto& c : state.pins) {
        CAPTURE(crank);
        CAPTURE(psi);
        CAPTURE(c.pin);
        const Eigen::Vector2d p = model.CyclePose(crank, psi, model.SliceZ(0)).ToBody(model.PinCentre(c.pin));
        const double brute = BruteDeviatedDistance(model.real_pair(), p, c.tooth_space) - c.pin_radius;
        CHECK(std::abs(c.clearance - brute) < 1e-9);
      }
    }
  }
}

TEST_CASE("contact: a random zone shifts the mean clearance toward its upper edge, not its mean") {
  // docs/contact.md: the gap opens away from the foot point by only s^2 / (2 rho_rel), so the
  // pin finds the highest elements within s ~ sqrt(rho_rel zone) of it. The shift of each pin's
  // clearance (deviated minus smooth) is at least -MaxAbs = -3 um (delta <= 3 um), and its mean
  // is below -MaxAbs / 3: the elements within s1 = sqrt(rho_rel MaxAbs / 2) of the foot point,
  // where the gap opens by at most MaxAbs / 4, number n1 >= 6 even on the most curved contact
  // (rho_rel ~ 1.5 mm, elements of 14.5 um), and the largest of n1 uniform draws has mean
  // MaxAbs (1 - 2 / (n1 + 1)), so the mean shift is at most -MaxAbs (1 - 2/7 - 1/4) = -0.46 MaxAbs.
  // The foot-point reading, -delta(k, u*), averages to the zone's mean 0 instead (within 4
  // standard errors of sigma = 6 um / sqrt(12) over the samples).
  const auto pair = ltca::test::LiuPair();
  const auto mod = ltca::test::Mod(-4, -17);
  const MeshModel smooth(RealPair(pair, mod)), rough(RealPair(pair, mod, LiuZone()));
  const double max_abs = rough.real_pair().profile_deviation().MaxAbs();
  CHECK(max_abs == doctest::Approx(3e-3).epsilon(1e-3));
  double shift = 0.0, foot = 0.0;
  int count = 0;
  for (int i = 0; i < 20; ++i) {
    const double crank = 0.013 * i;
    const auto a = smooth.Evaluate(crank), b = rough.Evaluate(crank);
    for (std::size_t j = 0; j < a.pins.size(); ++j) {
      const double s = b.pins[j].clearance - a.pins[j].clearance;
      CHECK(s >= -max_abs - 1e-12);
      shift += s;
      foot -= rough.real_pair().profile_deviation().At(a.pins[j].tooth_space, a.pins[j].u);
      ++count;
    }
  }
  shift /= count;
  foot /= count;
  MESSAGE("mean clearance shift " << shift * 1e3 << " um; foot-point reading " << foot * 1e3 << " um");
  CHECK(shift < -max_abs / 3.0);
  CHECK(std::abs(foot) < 4.0 * 6e-3 / std::sqrt(12.0) / std::sqrt(static_cast<double>(count)));
}

TEST_CASE("contact: with a random zone the gap is continuous in the loaded rotation") {
  // The solvers iterate on psi. The gap is the distance from the pin centre to a fixed curve (the
  // flank as made), so it is Lipschitz in psi with constant |p - O_c| (the pin centre's speed in
  // the body frame, < R_p + e + 1 mm): over 3000 steps of 2e-6 rad, which carry the foot point
  // across dozens of elements, no step may change it by more than that bound times the step. A
  // window that lost a winning element would jump by up to the zone (6 um, 50 times the bound).
  const auto pair = ltca::test::LiuPair();
  const MeshModel model(RealPair(pair, ltca::test::Mod(-4, -17), LiuZone()));
  const double crank = 0.02;
  const double step = 2e-6;
  const double bound = (pair.pin_circle_radius + pair.eccentricity + 1.0) * step;
  for (const int pin : {3, 8, 12, 19, 25}) {
    CAPTURE(pin);
    double previous = model.EvaluatePoint(pin, 0, crank, 0.0).clearance;
    double worst = 0.0;
    for (int i = 1; i <= 3000; ++i) {
      const double c = model.EvaluatePoint(pin, 0, crank, i * step).clearance;
      worst = std::max(worst, std::abs(c - previous));
      previous = c;
    }
    CHECK(worst <= bound);
  }
}

TEST_CASE("contact: elements mode with a constant deviation c is the layer pair c to the element error") {
  // Liu eq. 4 and 8: each element moves by c along its normal and its cylinder keeps its centre of
  // curvature (radius rho + c). The element gap then equals the analytic gap of the pair with the
  // uniform layer c to the discretisation error of 800 elements (below 1e-6 mm, as without errors,
  // tests/contact/elements_test.cpp), and the curvature to 1e-3 relative.
  const auto pair = ltca::test::LiuPair();
  const auto mod = ltca::test::Mod(-4, -17);
  const double c = 0.002;
  ManufacturingErrors layer, measured;
  layer.profile_layer = c;
  measured.profile_measured = ConstantTrace(pair, mod, c);
  GeometrySettings g;
  g.mode = GeometrySettings::Mode::kElements;
  g.width_slices = 1;
  const MeshModel analytic(RealPair(pair, mod, layer)), elements(RealPair(pair, mod, measured), g);
  for (const double crank : {0.0, 0.07}) {
    const auto a = analytic.Evaluate(crank), b = elements.Evaluate(crank);
    for (std::size_t i = 0; i < a.pins.size(); ++i) {
      CAPTURE(i);
      CHECK(std::abs(a.pins[i].clearance - b.pins[i].clearance) < 1e-6);
      if (a.pins[i].arm > 5.0) CHECK(b.pins[i].arm == doctest::Approx(a.pins[i].arm).epsilon(2e-2));
    }
  }
}
