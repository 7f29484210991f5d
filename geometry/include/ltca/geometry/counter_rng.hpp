#pragma once
// Counter-based random numbers: Philox4x32-10 (Salmon, Moraes, Dror, Shaw, "Parallel random
// numbers: as easy as 1, 2, 3", SC'11; the reference implementation is Random123). Draw `index`
// of stream `stream` under seed `seed` is a pure function of (seed, stream, index): no state is
// carried from one draw to the next, so the draws do not depend on the order of the calls, and a
// Monte Carlo split over threads or MPI ranks gets bit-identical samples. (std::mt19937 cannot do
// this: its state is sequential.)
//
// Layout: the 64-bit seed is the Philox key (low word first); the counter is (index low, index
// high, stream low, stream high). One counter gives 128 bits; Uniform01 uses the low 64 of them,
// StandardNormal all 128 (Box-Muller on two uniforms). A stream is meant for one kind of draw:
// Uniform01 and StandardNormal at the same (seed, stream, index) share bits.
//
// Uniform01 is integer arithmetic and the same on every platform. StandardNormal goes through
// std::log, std::sqrt and std::cos: identical wherever the same C library runs (one build on
// several threads or ranks); another libm may differ in the last bit.
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace ltca::geometry::rng {

using PhiloxCounter = std::array<std::uint32_t, 4>;
using PhiloxKey = std::array<std::uint32_t, 2>;

/// The Philox4x32 bijection with 10 rounds (Random123's philox4x32_R(10, ctr, key)).
constexpr PhiloxCounter Philox4x32_10(PhiloxCounter ctr, PhiloxKey key) {
  constexpr std::uint32_t kM0 = 0xD2511F53u;  // multipliers
  constexpr std::uint32_t kM1 = 0xCD9E8D57u;
  constexpr std::uint32_t kW0 = 0x9E3779B9u;  // Weyl key increments (golden ratio, sqrt(3) - 1)
  constexpr std::uint32_t kW1 = 0xBB67AE85u;
  for (int round = 0; round < 10; ++round) {
    if (round > 0) {
      key[0] += kW0;
      key[1] += kW1;
    }
    const std::uint64_t p0 = std::uint64_t{kM0} * ctr[0];
    const std::uint64_t p1 = std::uint64_t{kM1} * ctr[2];
    ctr = {static_cast<std::uint32_t>(p1 >> 32) ^ ctr[1] ^ key[0], static_cast<std::uint32_t>(p1),
           static_cast<std::uint32_t>(p0 >> 32) ^ ctr[3] ^ key[1], static_cast<std::uint32_t>(p0)};
  }
  return ctr;
}

/// The 128 random bits of (seed, stream, index), as two 64-bit words.
constexpr std::array<std::uint64_t, 2> Bits128(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  const auto lo = [](std::uint64_t v) { return static_cast<std::uint32_t>(v); };
  const auto hi = [](std::uint64_t v) { return static_cast<std::uint32_t>(v >> 32); };
  const PhiloxCounter out = Philox4x32_10({lo(index), hi(index), lo(stream), hi(stream)}, {lo(seed), hi(seed)});
  return {(std::uint64_t{out[1]} << 32) | out[0], (std::uint64_t{out[3]} << 32) | out[2]};
}

/// 53 random bits as a double in [0, 1): k / 2^53, k uniform in 0 .. 2^53 - 1.
constexpr double ToUnitInterval(std::uint64_t bits) {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

/// Uniform on [0, 1), 53 bits, a pure function of (seed, stream, index).
constexpr double Uniform01(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  return ToUnitInterval(Bits128(seed, stream, index)[0]);
}

/// Standard normal N(0, 1), a pure function of (seed, stream, index): Box-Muller on the two
/// 53-bit uniforms u1, u2 of one counter, z = sqrt(-2 ln(1 - u1)) cos(2 pi u2) (1 - u1 > 0, so
/// the logarithm is finite; |z| < 8.6).
inline double StandardNormal(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  const auto bits = Bits128(seed, stream, index);
  const double u1 = ToUnitInterval(bits[0]);
  const double u2 = ToUnitInterval(bits[1]);
  return std::sqrt(-2.0 * std::log1p(-u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

}  // namespace ltca::geometry::rng
