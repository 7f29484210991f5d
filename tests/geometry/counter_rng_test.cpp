// Counter-based random numbers: Philox4x32-10 against the known-answer vectors of its authors
// (Random123, tests/kat_vectors), and the draws against the moments of their distributions.
// The statistical checks run on fixed seeds, so they are deterministic; each bound is 4 standard
// errors of the estimate, from the distribution's own moments.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include <doctest/doctest.h>

#include "helpers.hpp"
#include "ltca/geometry/counter_rng.hpp"

namespace rng = ltca::geometry::rng;

namespace {

using ltca::test::Moments;
using ltca::test::MomentsOf;

double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const Moments ma = MomentsOf(a), mb = MomentsOf(b);
  double c = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) c += (a[i] - ma.mean) * (b[i] - mb.mean);
  return c / static_cast<double>(a.size()) / std::sqrt(ma.variance * mb.variance);
}

constexpr int kDraws = 100'000;

}  // namespace

TEST_CASE("geometry: Philox4x32-10 reproduces the Random123 known-answer vectors") {
  // Random123 tests/kat_vectors, the three "philox4x32 10" lines: counter, key, expected.
  CHECK(rng::Philox4x32_10({0, 0, 0, 0}, {0, 0}) ==
        rng::PhiloxCounter{0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8});
  CHECK(rng::Philox4x32_10({0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff}, {0xffffffff, 0xffffffff}) ==
        rng::PhiloxCounter{0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd});
  CHECK(rng::Philox4x32_10({0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344}, {0xa4093822, 0x299f31d0}) ==
        rng::PhiloxCounter{0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1});
  // The seed is the key, the counter (index low, index high, stream low, stream high).
  const auto bits = rng::Bits128(0x299f31d0a4093822ull, 0x0370734413198a2eull, 0x85a308d3243f6a88ull);
  CHECK(bits[0] == 0x94fdcceb'd16cfe09ull);
  CHECK(bits[1] == 0x24126ea1'5001e420ull);
}

TEST_CASE("geometry: Uniform01 lies in the half-open unit interval on a 2^-53 grid with the mean and variance of U(0, 1)") {
  std::vector<double> x(kDraws);
  for (int i = 0; i < kDraws; ++i) x[static_cast<std::size_t>(i)] = rng::Uniform01(20240611, 7, static_cast<std::uint64_t>(i));
  for (const double v : x) {
    REQUIRE(v >= 0.0);
    REQUIRE(v < 1.0);
    const double k = v * 0x1.0p53;
    REQUIRE(k == std::floor(k));
  }
  const Moments m = MomentsOf(x);
  const double n = kDraws;
  // U(0, 1): mean 1/2, variance 1/12, fourth central moment 1/80.
  CHECK(std::abs(m.mean - 0.5) < 4.0 * std::sqrt(1.0 / 12.0 / n));
  CHECK(std::abs(m.variance - 1.0 / 12.0) < 4.0 * std::sqrt((1.0 / 80.0 - 1.0 / 144.0) / n));
  // Ten equal bins: chi-square with 9 degrees of freedom; 33.7 is its 0.9999 quantile.
  std::vector<double> bins(10, 0.0);
  for (const double v : x) bins[static_cast<std::size_t>(v * 10.0)] += 1.0;
  double chi2 = 0.0;
  for (const double b : bins) chi2 += (b - n / 10.0) * (b - n / 10.0) / (n / 10.0);
  CHECK(chi2 < 33.7);
  // The low bits are random too: the 2^-53 grid is used, not a coarser one.
  int odd = 0;
  for (const double v : x) odd += static_cast<int>(static_cast<std::uint64_t>(v * 0x1.0p53) & 1u);
  CHECK(std::abs(odd - n / 2.0) < 4.0 * std::sqrt(n / 4.0));
}

TEST_CASE("geometry: StandardNormal has the mean, variance and tail mass of N(0, 1)") {
  std::vector<double> z(kDraws);
  for (int i = 0; i < kDraws; ++i) z[static_cast<std::size_t>(i)] = rng::StandardNormal(99, 3, static_cast<std::uint64_t>(i));
  const Moments m = MomentsOf(z);
  const double n = kDraws;
  // N(0, 1): variance of the sample mean 1/n, of the sample variance (mu4 - sigma^4)/n = 2/n.
  CHECK(std::abs(m.mean) < 4.0 / std::sqrt(n));
  CHECK(std::abs(m.variance - 1.0) < 4.0 * std::sqrt(2.0 / n));
  // P(|z| > 2) = erfc(2 / sqrt 2): a binomial count.
  const double p = std::erfc(2.0 / std::sqrt(2.0));
  const double beyond = static_cast<double>(std::count_if(z.begin(), z.end(), [](double v) { return std::abs(v) > 2.0; }));
  CHECK(std::abs(beyond - n * p) < 4.0 * std::sqrt(n * p * (1.0 - p)));
  // Symmetric: the third moment of N(0, 1) is 0, its sample value has variance 15/n.
  double m3 = 0.0;
  for (const double v : z) m3 += v * v * v;
  CHECK(std::abs(m3 / n) < 4.0 * std::sqrt(15.0 / n));
}

TEST_CASE("geometry: neighbouring streams, seeds and indices of the counter generator are uncorrelated") {
  // For independent samples the sample correlation has standard error 1/sqrt(n).
  const double bound = 4.0 / std::sqrt(static_cast<double>(kDraws));
  std::vector<double> s0(kDraws), s1(kDraws), seed1(kDraws), lag(kDraws);
  for (int i = 0; i < kDraws; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const auto idx = static_cast<std::uint64_t>(i);
    s0[k] = rng::Uniform01(5, 0, idx);
    s1[k] = rng::Uniform01(5, 1, idx);
    seed1[k] = rng::Uniform01(6, 0, idx);
    lag[k] = rng::Uniform01(5, 0, idx + 1);
  }
  CHECK(std::abs(Correlation(s0, s1)) < bound);
  CHECK(std::abs(Correlation(s0, seed1)) < bound);
  CHECK(std::abs(Correlation(s0, lag)) < bound);
  // The stream in the high counter words: stream 2^32 is not stream 0 either.
  std::vector<double> high(kDraws);
  for (int i = 0; i < kDraws; ++i) high[static_cast<std::size_t>(i)] = rng::Uniform01(5, std::uint64_t{1} << 32, static_cast<std::uint64_t>(i));
  CHECK(std::abs(Correlation(s0, high)) < bound);
  // Normal draws of two streams likewise.
  std::vector<double> z0(kDraws), z1(kDraws);
  for (int i = 0; i < kDraws; ++i) {
    z0[static_cast<std::size_t>(i)] = rng::StandardNormal(5, 10, static_cast<std::uint64_t>(i));
    z1[static_cast<std::size_t>(i)] = rng::StandardNormal(5, 11, static_cast<std::uint64_t>(i));
  }
  CHECK(std::abs(Correlation(z0, z1)) < bound);
}

TEST_CASE("geometry: a counter draw depends on (seed, stream, index) only, not on the order of the calls") {
  constexpr int n = 1000;
  std::vector<double> forward(n), forward_z(n);
  for (int i = 0; i < n; ++i) {
    forward[static_cast<std::size_t>(i)] = rng::Uniform01(42, 17, static_cast<std::uint64_t>(i));
    forward_z[static_cast<std::size_t>(i)] = rng::StandardNormal(42, 18, static_cast<std::uint64_t>(i));
  }
  // A scrambled order (a full-period stride permutation), with unrelated draws in between.
  std::vector<double> scrambled(n), scrambled_z(n);
  double noise = 0.0;
  for (int j = 0; j < n; ++j) {
    const int i = (j * 617 + 311) % n;  // 617 is prime to 1000: every i once
    noise += rng::Uniform01(7, 0, static_cast<std::uint64_t>(j)) + rng::StandardNormal(42, 17, static_cast<std::uint64_t>(j));
    scrambled_z[static_cast<std::size_t>(i)] = rng::StandardNormal(42, 18, static_cast<std::uint64_t>(i));
    scrambled[static_cast<std::size_t>(i)] = rng::Uniform01(42, 17, static_cast<std::uint64_t>(i));
  }
  CHECK(std::isfinite(noise));
  for (int i = 0; i < n; ++i) {
    REQUIRE(scrambled[static_cast<std::size_t>(i)] == forward[static_cast<std::size_t>(i)]);
    REQUIRE(scrambled_z[static_cast<std::size_t>(i)] == forward_z[static_cast<std::size_t>(i)]);
  }
  // And the three coordinates each matter.
  CHECK(rng::Uniform01(42, 17, 5) != rng::Uniform01(43, 17, 5));
  CHECK(rng::Uniform01(42, 17, 5) != rng::Uniform01(42, 16, 5));
  CHECK(rng::Uniform01(42, 17, 5) != rng::Uniform01(42, 17, 6));
  // Usable at compile time (a pure function).
  static_assert(rng::Uniform01(1, 2, 3) == rng::Uniform01(1, 2, 3));
}
