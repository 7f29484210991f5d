#pragma once
// Pairs from the papers, typed in from their text (not read from our decks, so that a deck
// typo cannot hide here).
#include <string>
#include <vector>

#include "ltca/geometry/pair.hpp"

namespace ltca::test {

struct NamedPair {
  std::string name;
  geometry::PairParameters pair;
};

// Chen 2008 section 3: (Z_b, Z_g, R_Z, r_Z, e); the face width is not in the paper.
inline geometry::PairParameters ChenPair(int zb, int zg, double rz_big, double rz, double e) {
  return {zb, zg, rz, rz_big, e, 10.0};
}

inline std::vector<NamedPair> ChenPairs() {
  return {{"Chen 3.1 d=1", ChenPair(12, 11, 90, 7, 4)},
          {"Chen 3.2 d=2", ChenPair(24, 22, 90, 7, 4)},
          {"Chen 3.3 d=3", ChenPair(36, 33, 90, 7, 4)},
          {"Chen 3.4 d=-1", ChenPair(15, 16, 120, 10, 5)}};
}

// Liu 2021 Table 1: z_c 39, z_p 40, r_rp 3, R_p 64, B_c 12, e 1.3.
inline geometry::PairParameters LiuPair() { return {40, 39, 3.0, 64.0, 1.3, 12.0}; }

inline std::vector<NamedPair> AllPairs() {
  auto pairs = ChenPairs();
  pairs.push_back({"Liu Table 1", LiuPair()});
  return pairs;
}

}  // namespace ltca::test
