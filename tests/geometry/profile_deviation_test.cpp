// The cycloid profile deviation along the profile (issue 11): the random per-element deviation
// against the theory of its distributions and against draws made here from the documented
// counter layout; the measured trace's CSV reader; arc-length abscissae converted with the
// closed-form arc length (arc_length_closed_form.hpp), not with the program's.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "arc_length_closed_form.hpp"
#include "ltca/geometry/counter_rng.hpp"
#include "ltca/geometry/discrete_profile.hpp"
#include "ltca/geometry/profile_deviation.hpp"
#include "helpers.hpp"
#include "pairs.hpp"

using ltca::geometry::CycloidProfile;
using ltca::geometry::DiscreteProfile;
using ltca::geometry::MeasuredProfile;
using ltca::geometry::ParseMeasuredProfile;
using ltca::geometry::ProfileDeviation;
using ltca::geometry::ProfileElementSpacing;
using ltca::geometry::ProfileRandomDistribution;
using ltca::geometry::RandomProfileDeviation;
namespace rng = ltca::geometry::rng;

namespace {

// Liu 2021 Table 1 with the modification of section 5.2 (dR_rp = -4 um, dR_p = -17 um).
CycloidProfile LiuProfile() { return CycloidProfile(ltca::test::LiuPair(), ltca::test::Mod(-4, -17)); }

RandomProfileDeviation Params(double zone_mm, int elements, std::uint64_t seed, ProfileRandomDistribution distribution,
                              ProfileElementSpacing spacing) {
  RandomProfileDeviation r;
  r.zone = zone_mm;
  r.elements = elements;
  r.seed = seed;
  r.distribution = distribution;
  r.spacing = spacing;
  return r;
}

// The draw of element e of tooth space k, written from the counter layout documented in
// profile_deviation.hpp (stream 2^32 + k, index 64 e + attempt), not from the program's code.
double ExpectedDraw(const RandomProfileDeviation& r, int k, int e) {
  const std::uint64_t stream = (std::uint64_t{1} << 32) + static_cast<std::uint64_t>(k);
  if (r.distribution == ProfileRandomDistribution::kUniform) {
    return r.zone * (rng::Uniform01(r.seed, stream, 64u * static_cast<std::uint64_t>(e)) - 0.5);
  }
  for (std::uint64_t a = 0; a < 64; ++a) {
    const double z = rng::StandardNormal(r.seed, stream, 64u * static_cast<std::uint64_t>(e) + a);
    if (std::abs(z) <= 3.0) return r.zone / 6.0 * z;
  }
  FAIL("64 rejections in a row");
  return 0.0;
}

// Element centres with equal intervals of u.
double ParameterCentre(double phi, int n, int e) { return -phi + 2.0 * phi * (e + 0.5) / n; }

// Values at the element centres of every tooth space (equal-parameter spacing).
std::vector<double> CentreValues(const ProfileDeviation& dev, double phi, int teeth, int n) {
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(teeth) * static_cast<std::size_t>(n));
  for (int k = 0; k < teeth; ++k) {
    for (int e = 0; e < n; ++e) v.push_back(dev.At(k, ParameterCentre(phi, n, e)));
  }
  return v;
}

using ltca::test::Moments;
using ltca::test::MomentsOf;

// A CSV row with every digit of both values.
std::string Row(double x, double y) {
  char buffer[80];
  std::snprintf(buffer, sizeof buffer, "%.17g, %.17g\n", x, y);
  return buffer;
}

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// u with closed-form arc length s, by bisection (independent of ProfileArcLength).
double ClosedFormParameter(const ltca::geometry::PairParameters& pair, const ltca::geometry::Modification& mod,
                           double phi, double s) {
  double lo = -phi, hi = phi;
  for (int it = 0; it < 200 && hi - lo > 1e-17; ++it) {
    const double mid = 0.5 * (lo + hi);
    (ltca::test::ClosedFormArcLength(pair, mod, mid) < s ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

TEST_CASE("geometry: the random profile deviation stays within its tolerance zone everywhere") {
  const CycloidProfile profile = LiuProfile();
  const double phi = profile.phi_max();
  const double zone = 0.006;  // Liu 5.2: F_alpha^c = +-3 um
  for (const auto distribution : {ProfileRandomDistribution::kUniform, ProfileRandomDistribution::kNormal}) {
    for (const auto spacing : {ProfileElementSpacing::kArcLength, ProfileElementSpacing::kParameter}) {
      const ProfileDeviation dev = ProfileDeviation::Random(Params(zone, 800, 1, distribution, spacing), profile);
      CHECK_FALSE(dev.IsZero());
      CHECK(dev.tooth_count() == 39);
      CHECK(dev.MaxAbs() <= zone / 2.0);
      double largest = 0.0;
      for (int k = 0; k < 39; ++k) {
        for (int i = -4100; i <= 4100; ++i) {  // u beyond both ends too
          const double value = dev.At(k, 1.02 * phi * i / 4000.0);
          REQUIRE(std::abs(value) <= zone / 2.0);
          largest = std::max(largest, std::abs(value));
        }
      }
      // The zone is used, not a part of it: the largest of 31,200 draws is near its edge.
      CHECK(largest > 0.45 * zone);
    }
  }
}

TEST_CASE("geometry: uniform element deviations have the mean 0 and the standard deviation zone/sqrt(12) of U(-zone/2, zone/2)") {
  const CycloidProfile profile = LiuProfile();
  const double zone = 0.006;
  const int n = 800;
  const ProfileDeviation dev = ProfileDeviation::Random(
      Params(zone, n, 20240611, ProfileRandomDistribution::kUniform, ProfileElementSpacing::kParameter), profile);
  const std::vector<double> v = CentreValues(dev, profile.phi_max(), 39, n);
  const double count = static_cast<double>(v.size());
  const Moments m = MomentsOf(v);
  const double sigma = zone / std::sqrt(12.0);
  CHECK(std::abs(m.mean) < 4.0 * sigma / std::sqrt(count));
  // Sample variance: standard error sqrt((mu4 - sigma^4) / n), mu4 = zone^4 / 80 for the uniform.
  const double mu4 = std::pow(zone, 4) / 80.0;
  CHECK(std::abs(m.variance - sigma * sigma) < 4.0 * std::sqrt((mu4 - std::pow(sigma, 4)) / count));
  // Both edges reached: P(max < zone/2 (1 - 2e-3)) = (1 - 1e-3)^31200 ~ e^-31.
  CHECK(*std::max_element(v.begin(), v.end()) > 0.5 * zone * (1.0 - 2e-3));
  CHECK(*std::min_element(v.begin(), v.end()) < -0.5 * zone * (1.0 - 2e-3));
}

TEST_CASE("geometry: normal element deviations are N(0, (zone/6)^2) truncated to the zone, not clipped or untruncated") {
  // Standard normal truncated to |z| <= c (c = 3), P = erf(c / sqrt 2), phi(c) the density:
  //   E z^2 = 1 - 2 c phi(c) / P,   E z^4 = 3 - (2 c^3 + 6 c) phi(c) / P.
  const double c = 3.0;
  const double density = std::exp(-0.5 * c * c) / std::sqrt(2.0 * std::numbers::pi);
  const double p = std::erf(c / std::sqrt(2.0));
  const double m2 = 1.0 - 2.0 * c * density / p;
  const double m4 = 3.0 - (2.0 * c * c * c + 6.0 * c) * density / p;
  const CycloidProfile profile = LiuProfile();
  const double zone = 0.006, sigma = zone / 6.0;
  const int n = 20'000;  // 780,000 draws: the truncation (1.3 % of sigma) is ~17 standard errors
  const ProfileDeviation dev = ProfileDeviation::Random(
      Params(zone, n, 77, ProfileRandomDistribution::kNormal, ProfileElementSpacing::kParameter), profile);
  const std::vector<double> v = CentreValues(dev, profile.phi_max(), 39, n);
  const double count = static_cast<double>(v.size());
  const Moments m = MomentsOf(v);
  const double var_t = sigma * sigma * m2;
  const double var_se = std::sqrt((m4 - m2 * m2) / count) * sigma * sigma;
  CHECK(std::abs(m.mean) < 4.0 * std::sqrt(var_t / count));
  CHECK(std::abs(m.variance - var_t) < 4.0 * var_se);
  CHECK(std::abs(m.variance - sigma * sigma) > 4.0 * var_se);  // the untruncated law is rejected
  // Mass beyond 2 sigma: (P - erf(2 / sqrt 2)) / P of the truncated law (clipping would put
  // 0.27 % more there, on the edges).
  const double q = (p - std::erf(2.0 / std::sqrt(2.0))) / p;
  const double beyond = static_cast<double>(std::count_if(v.begin(), v.end(), [&](double x) { return std::abs(x) > 2.0 * sigma; }));
  CHECK(std::abs(beyond - count * q) < 4.0 * std::sqrt(count * q * (1.0 - q)));
  // No point mass on the edges.
  CHECK(std::count_if(v.begin(), v.end(), [&](double x) { return std::abs(x) >= 0.5 * zone; }) == 0);
}

TEST_CASE("geometry: the value at an element centre is that element's draw, linear between centres, constant beyond") {
  const CycloidProfile profile = LiuProfile();
  const double phi = profile.phi_max();
  const double zone = 0.006;
  const int n = 800;
  for (const auto distribution : {ProfileRandomDistribution::kUniform, ProfileRandomDistribution::kNormal}) {
    const auto params = Params(zone, n, 3, distribution, ProfileElementSpacing::kParameter);
    const ProfileDeviation dev = ProfileDeviation::Random(params, profile);
    for (const int k : {0, 1, 17, 38}) {
      for (int e = 0; e < n; ++e) {
        const double draw = ExpectedDraw(params, k, e);
        REQUIRE(std::abs(dev.At(k, ParameterCentre(phi, n, e)) - draw) <= 1e-9 * zone);
        if (e + 1 < n) {
          const double mid = 0.5 * (ParameterCentre(phi, n, e) + ParameterCentre(phi, n, e + 1));
          REQUIRE(std::abs(dev.At(k, mid) - 0.5 * (draw + ExpectedDraw(params, k, e + 1))) <= 1e-9 * zone);
        }
      }
      // Constant beyond the outer centres (the first and last half-elements, and off the flank).
      for (const double u : {-phi, -phi + 0.4 * phi / n, -10.0}) CHECK(dev.At(k, u) == ExpectedDraw(params, k, 0));
      for (const double u : {phi, phi - 0.4 * phi / n, 10.0}) CHECK(dev.At(k, u) == ExpectedDraw(params, k, n - 1));
      // Tooth spaces are taken modulo z_c, as CycloidProfile takes them.
      CHECK(dev.At(k + 39, 0.3 * phi) == dev.At(k, 0.3 * phi));
      CHECK(dev.At(k - 39, -0.2 * phi) == dev.At(k, -0.2 * phi));
    }
  }
  SUBCASE("equal arc length: the centres are the control points of Liu's elements (DiscreteProfile)") {
    const auto params = Params(zone, n, 3, ProfileRandomDistribution::kUniform, ProfileElementSpacing::kArcLength);
    const ProfileDeviation dev = ProfileDeviation::Random(params, profile);
    const DiscreteProfile elements(profile, n, 1);
    for (const int k : {0, 5, 38}) {
      for (int e = 0; e < n; ++e) {
        REQUIRE(std::abs(dev.At(k, elements.elements()[static_cast<std::size_t>(e)].u) - ExpectedDraw(params, k, e)) <=
                1e-6 * zone);
      }
    }
    // And they sit at s = S (e + 1/2) / n by the closed-form arc length.
    const auto pair = ltca::test::LiuPair();
    const auto mod = ltca::test::Mod(-4, -17);
    const double flank = ltca::test::ClosedFormArcLength(pair, mod, phi);
    for (const int e : {0, 1, 123, 399, 400, 799}) {
      const double u = ClosedFormParameter(pair, mod, phi, -flank + 2.0 * flank * (e + 0.5) / n);
      CHECK(std::abs(dev.At(2, u) - ExpectedDraw(params, 2, e)) <= 1e-6 * zone);
    }
  }
}

TEST_CASE("geometry: the random deviation is reproducible for one seed, different for another, independent between tooth spaces") {
  const CycloidProfile profile = LiuProfile();
  const double phi = profile.phi_max();
  const int n = 20'000;
  const auto params = Params(0.006, n, 11, ProfileRandomDistribution::kNormal, ProfileElementSpacing::kArcLength);
  const ProfileDeviation a = ProfileDeviation::Random(params, profile);
  const ProfileDeviation again = ProfileDeviation::Random(params, profile);
  auto other_params = params;
  other_params.seed = 12;
  const ProfileDeviation other = ProfileDeviation::Random(other_params, profile);
  std::vector<double> va, vo, v_next;
  int equal = 0;
  for (int i = 0; i < n; ++i) {
    const double u = phi * (2.0 * (i + 0.5) / n - 1.0);
    for (const int k : {0, 20}) REQUIRE(a.At(k, u) == again.At(k, u));  // bit-identical
    va.push_back(a.At(0, u));
    vo.push_back(other.At(0, u));
    v_next.push_back(a.At(1, u));
    equal += a.At(0, u) == other.At(0, u) ? 1 : 0;
  }
  CHECK(equal == 0);
  // The values at points spread along the flank: the sample correlation of independent
  // sequences has standard error 1 / sqrt(n) (points are ~1 element apart, so neighbours share
  // some interpolation: the bound is 4 standard errors of n/2 samples).
  const auto correlation = [](const std::vector<double>& x, const std::vector<double>& y) {
    const Moments mx = MomentsOf(x), my = MomentsOf(y);
    double c = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) c += (x[i] - mx.mean) * (y[i] - my.mean);
    return c / static_cast<double>(x.size()) / std::sqrt(mx.variance * my.variance);
  };
  const double bound = 4.0 / std::sqrt(n / 2.0);
  CHECK(std::abs(correlation(va, vo)) < bound);
  CHECK(std::abs(correlation(va, v_next)) < bound);
}

TEST_CASE("geometry: a zero zone is no deviation, bad random parameters are rejected naming the key") {
  const CycloidProfile profile = LiuProfile();
  RandomProfileDeviation r;
  CHECK(ProfileDeviation::Random(r, profile).IsZero());
  CHECK(ProfileDeviation::Random(r, profile).At(3, 0.01) == 0.0);
  CHECK(ProfileDeviation().At(0, 0.0) == 0.0);
  CHECK(ProfileDeviation().MaxAbs() == 0.0);
  r.zone = -0.001;
  CHECK(Contains(ltca::test::InvalidArgumentMessage([&] { ProfileDeviation::Random(r, profile); }), "[errors] profile_random_zone_um = -1: expected"));
  r.zone = std::numeric_limits<double>::quiet_NaN();
  CHECK(Contains(ltca::test::InvalidArgumentMessage([&] { ProfileDeviation::Random(r, profile); }), "[errors] profile_random_zone_um = nan"));
  r.zone = 0.006;
  r.elements = 0;
  CHECK(Contains(ltca::test::InvalidArgumentMessage([&] { ProfileDeviation::Random(r, profile); }), "[errors] profile_random_elements = 0: expected 1 .. 100000"));
  r.elements = 100'001;
  CHECK(Contains(ltca::test::InvalidArgumentMessage([&] { ProfileDeviation::Random(r, profile); }), "[errors] profile_random_elements = 100001"));
  r.elements = 1;  // one element: a random layer per tooth space
  const ProfileDeviation one = ProfileDeviation::Random(r, profile);
  CHECK(one.At(4, -0.05) == one.At(4, 0.07));
  CHECK(one.At(4, 0.0) == doctest::Approx(ExpectedDraw(r, 4, 0)).epsilon(1e-15));
  CHECK(Contains(ltca::test::InvalidArgumentMessage([] { ltca::geometry::ParseProfileRandomDistribution("gauss"); }),
                 "[errors] profile_random_distribution = \"gauss\": expected \"uniform\" or \"normal\""));
  CHECK(ltca::geometry::ParseProfileRandomDistribution("normal") == ProfileRandomDistribution::kNormal);
  CHECK(Contains(ltca::test::InvalidArgumentMessage([] { ltca::geometry::ParseProfileElementSpacing("arc"); }),
                 "[errors] profile_random_spacing = \"arc\""));
  CHECK(ltca::geometry::ParseProfileElementSpacing("parameter") == ProfileElementSpacing::kParameter);
}

TEST_CASE("geometry: the measured-profile CSV reader accepts the documented format") {
  const std::string text =
      "\xEF\xBB\xBF# exported by a gear measuring centre\r\n"
      "\r\n"
      "   # tooth 1, right flank\n"
      "profile_angle_deg, deviation_um\n"
      "-4.5, 1.25\n"
      "\n"
      "-1\t-0.5\n"
      "0 , +2e-1\n"
      "# a comment between rows\n"
      "  3.25   4  \n";
  const MeasuredProfile trace = ParseMeasuredProfile(text, "tooth1.csv");
  CHECK(trace.source == "tooth1.csv");
  CHECK(trace.abscissa == MeasuredProfile::Abscissa::kProfileAngle);
  REQUIRE(trace.x.size() == 4);
  const double deg = std::numbers::pi / 180.0;
  CHECK(trace.x[0] == doctest::Approx(-4.5 * deg).epsilon(1e-15));
  CHECK(trace.x[1] == doctest::Approx(-1.0 * deg).epsilon(1e-15));
  CHECK(trace.x[2] == 0.0);
  CHECK(trace.x[3] == doctest::Approx(3.25 * deg).epsilon(1e-15));
  CHECK(trace.deviation[0] == doctest::Approx(1.25e-3).epsilon(1e-15));
  CHECK(trace.deviation[1] == doctest::Approx(-0.5e-3).epsilon(1e-15));
  CHECK(trace.deviation[2] == doctest::Approx(0.2e-3).epsilon(1e-15));
  CHECK(trace.deviation[3] == doctest::Approx(4e-3).epsilon(1e-15));
  CHECK(trace.line == std::vector<int>{5, 7, 8, 10});
  const MeasuredProfile arc = ParseMeasuredProfile("arc_length_mm deviation_um\n-1.5 0\n2 1\n", "a.csv");
  CHECK(arc.abscissa == MeasuredProfile::Abscissa::kArcLength);
  CHECK(arc.x == std::vector<double>{-1.5, 2.0});
  CHECK(arc.deviation == std::vector<double>{0.0, 1e-3});
}

TEST_CASE("geometry: the measured-profile CSV reader rejects bad input naming the source, the line and what is expected") {
  struct Bad {
    std::string text;
    std::string message;  // a part of the expected message
  };
  const std::string h = "profile_angle_deg, deviation_um\n";
  const std::vector<Bad> bad = {
      {"", "m.csv: line 1: end of the text without a header: expected a header line naming the columns"},
      {"# only a comment\n\n", "m.csv: line 2: end of the text without a header"},
      {"1, 2\n2, 3\n", "m.csv: line 1: \"1, 2\": expected a header line naming the columns, \"profile_angle_deg, deviation_um\" or \"arc_length_mm, deviation_um\""},
      {"angle_deg, deviation_um\n1, 2\n", "m.csv: line 1: \"angle_deg, deviation_um\": expected a header"},
      {"profile_angle_deg, deviation_mm\n1, 2\n", "m.csv: line 1:"},
      {"profile_angle_deg\n1\n", "m.csv: line 1:"},
      {h + "1, 2\n2, 3, 4\n", "m.csv: line 3: \"2, 3, 4\" has 3 fields: expected two numbers"},
      {h + "1\n2, 3\n", "m.csv: line 2: \"1\" has 1 fields: expected two numbers"},
      {h + "1, 2\n2,\n", "m.csv: line 3: deviation_um \"\": expected a number"},
      {h + "1, 2um\n2, 3\n", "m.csv: line 2: deviation_um \"2um\": expected a number"},
      {h + "# c\n1;2\n2;3\n", "m.csv: line 3: \"1;2\" has 1 fields"},
      {h + "x, 2\n2, 3\n", "m.csv: line 2: profile_angle_deg \"x\": expected a number"},
      {h + "1, nan\n2, 3\n", "m.csv: line 2: deviation_um = nan: expected a finite number"},
      {h + "1, 2\ninf, 3\n", "m.csv: line 3: profile_angle_deg = inf: expected a finite number"},
      {h + "1, 2\n2, 1e999\n", "m.csv: line 3: deviation_um = inf: expected a finite number"},
      {h + "1, 2\n\n1, 3\n", "m.csv: line 4: profile_angle_deg = 1 after 1 on line 2: expected strictly increasing abscissae"},
      {h + "1, 2\n0.5, 3\n", "m.csv: line 3: profile_angle_deg = 0.5 after 1 on line 2: expected strictly increasing"},
      {h + "1, 2\n", "m.csv: line 2: end of the text after 1 data row(s): expected at least 2"},
      {h, "m.csv: line 1: end of the text after 0 data row(s): expected at least 2"},
  };
  for (const Bad& b : bad) {
    CAPTURE(b.text);
    const std::string message = ltca::test::InvalidArgumentMessage([&] { ParseMeasuredProfile(b.text, "m.csv"); });
    CAPTURE(message);
    CHECK(Contains(message, b.message));
  }
}

TEST_CASE("geometry: a measured trace applies to every tooth space at its own points, arc lengths converted by the closed form") {
  const auto pair = ltca::test::LiuPair();
  const auto mod = ltca::test::Mod(-4, -17);
  const CycloidProfile profile(pair, mod);
  const double phi = profile.phi_max();
  const double flank = ltca::test::ClosedFormArcLength(pair, mod, phi);  // root centre to one end
  SUBCASE("arc length") {
    const std::vector<double> s = {-0.999 * flank, -0.5 * flank, -0.01, 0.0, 0.2 * flank, 0.7 * flank, flank};
    const std::vector<double> um = {1.0, -2.0, 0.5, 3.0, -1.5, 2.5, -0.25};
    std::string text = "arc_length_mm, deviation_um\n";
    for (std::size_t i = 0; i < s.size(); ++i) text += Row(s[i], um[i]);
    const ProfileDeviation dev = ProfileDeviation::Measured(ParseMeasuredProfile(text, "arc.csv"), profile);
    CHECK(dev.tooth_count() == 39);
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double u = ClosedFormParameter(pair, mod, phi, s[i]);
      CAPTURE(i);
      for (const int k : {0, 7, 38}) CHECK(std::abs(dev.At(k, u) - um[i] * 1e-3) <= 1e-12);
    }
    // Constant beyond the first and the last point.
    CHECK(dev.At(3, -phi) == doctest::Approx(1e-3).epsilon(1e-15));
    CHECK(dev.At(3, 1.0) == doctest::Approx(-0.25e-3).epsilon(1e-15));
  }
  SUBCASE("profile angle") {
    const ProfileDeviation dev = ProfileDeviation::Measured(
        ParseMeasuredProfile("profile_angle_deg, deviation_um\n-2, 1\n1, 4\n4, -2\n", "deg.csv"), profile);
    const double deg = std::numbers::pi / 180.0;
    CHECK(dev.At(0, -2 * deg) == doctest::Approx(1e-3).epsilon(1e-14));
    CHECK(dev.At(5, 1 * deg) == doctest::Approx(4e-3).epsilon(1e-14));
    CHECK(dev.At(5, 0) == doctest::Approx(3e-3).epsilon(1e-12));      // linear: 1 + 3 (2/3)
    CHECK(dev.At(9, 2.5 * deg) == doctest::Approx(1e-3).epsilon(1e-12));  // 4 - 6 / 2
    CHECK(dev.At(9, -3 * deg) == doctest::Approx(1e-3).epsilon(1e-15));
    CHECK(dev.At(9, 4.5 * deg) == doctest::Approx(-2e-3).epsilon(1e-15));
  }
  SUBCASE("points off the flank are rejected naming the line; rounding at the ends is not") {
    const double end_deg = phi * 180.0 / std::numbers::pi;
    const std::string off_angle = "profile_angle_deg, deviation_um\n0, 1\n" + Row(end_deg * 1.01, 2.0);
    const std::string message = ltca::test::InvalidArgumentMessage([&] { ProfileDeviation::Measured(ParseMeasuredProfile(off_angle, "o.csv"), profile); });
    CHECK(Contains(message, "o.csv: line 3: profile_angle_deg = "));
    CHECK(Contains(message, "is off the flank: expected within [-4.615"));
    const std::string off_arc = "arc_length_mm, deviation_um\n" + Row(-1.01 * flank, 1.0) + "0, 2\n";
    CHECK(Contains(ltca::test::InvalidArgumentMessage([&] { ProfileDeviation::Measured(ParseMeasuredProfile(off_arc, "o.csv"), profile); }),
                   "o.csv: line 2: arc_length_mm = "));
    // Ends rounded up in the file by 1e-4 of the flank: accepted, the value sits at the end.
    // (At the ends the line between the two points is 3e-5 of the way in: 1e-4 of the flank
    // over the tip speed, ~61 mm/rad, against a span of 2 phi_max.)
    const std::string rounded = "arc_length_mm, deviation_um\n" + Row(-1.0001 * flank, 1.0) + Row(1.0001 * flank, 2.0);
    const ProfileDeviation dev = ProfileDeviation::Measured(ParseMeasuredProfile(rounded, "r.csv"), profile);
    CHECK(dev.At(0, -phi) == doctest::Approx(1e-3).epsilon(1e-4));
    CHECK(dev.At(0, phi) == doctest::Approx(2e-3).epsilon(1e-4));
  }
}

TEST_CASE("geometry: a constant measured trace is that constant everywhere, an all-zero trace is no deviation") {
  const CycloidProfile profile = LiuProfile();
  const double phi = profile.phi_max();
  const ProfileDeviation dev = ProfileDeviation::Measured(
      ParseMeasuredProfile("arc_length_mm, deviation_um\n-0.3, 1.5\n0.1, 1.5\n0.2, 1.5\n2.9, 1.5\n", "c.csv"), profile);
  for (int k = -2; k < 42; ++k) {
    for (int i = -200; i <= 200; ++i) REQUIRE(dev.At(k, 1.5 * phi * i / 200.0) == 1.5e-3);
  }
  CHECK(dev.MaxAbs() == 1.5e-3);
  CHECK(ProfileDeviation::Measured(ParseMeasuredProfile("profile_angle_deg deviation_um\n-1 0\n1 0\n", "z.csv"), profile).IsZero());
}

TEST_CASE("geometry: the sum of a random and a measured deviation is their pointwise sum") {
  const CycloidProfile profile = LiuProfile();
  const double phi = profile.phi_max();
  const ProfileDeviation random = ProfileDeviation::Random(
      Params(0.006, 800, 5, ProfileRandomDistribution::kUniform, ProfileElementSpacing::kArcLength), profile);
  const ProfileDeviation measured = ProfileDeviation::Measured(
      ParseMeasuredProfile("profile_angle_deg, deviation_um\n-3, -1\n3, 2\n", "m.csv"), profile);
  const ProfileDeviation sum = ProfileDeviation::Sum(random, measured);
  for (const int k : {0, 13, 38}) {
    for (int i = -50; i <= 50; ++i) {
      const double u = phi * i / 50.0;
      CHECK(sum.At(k, u) == doctest::Approx(random.At(k, u) + measured.At(k, u)).epsilon(1e-15));
    }
  }
  CHECK(sum.MaxAbs() == doctest::Approx(random.MaxAbs() + 2e-3).epsilon(1e-15));
  CHECK(ProfileDeviation::Sum(ProfileDeviation(), measured).At(2, 0.0) == measured.At(2, 0.0));
  CHECK(ProfileDeviation::Sum(ProfileDeviation(), ProfileDeviation()).IsZero());
  const CycloidProfile other(ltca::test::ChenPairs()[0].pair);  // 11 teeth
  const ProfileDeviation elsewhere = ProfileDeviation::Measured(
      ParseMeasuredProfile("profile_angle_deg, deviation_um\n-3, -1\n3, 2\n", "m.csv"), other);
  CHECK(Contains(ltca::test::InvalidArgumentMessage([&] { ProfileDeviation::Sum(random, elsewhere); }), "39 and 11 tooth spaces"));
}
