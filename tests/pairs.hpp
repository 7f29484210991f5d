#pragma once
// Pairs from the papers, typed in from their text (not read from our decks, so that a deck
// typo cannot hide here).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ltca/geometry/pair.hpp"
#include "ltca/geometry/profile.hpp"

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

// A modification in micrometres: isometric dR_rp, offset dR_p.
inline geometry::Modification Mod(double d_rrp_um, double d_rp_um) {
  geometry::Modification m;
  m.pin_radius = d_rrp_um * 1e-3;
  m.pin_circle_radius = d_rp_um * 1e-3;
  return m;
}

// Brute-force distance from body-frame point p to the whole real profile: dense sampling of
// every tooth space, refined by golden section around the best sample (test only).
inline double DistanceToProfile(const geometry::CycloidProfile& profile, const Eigen::Vector2d& p) {
  const int n = 300;
  double best = 1e300, best_u = 0;
  int best_k = 0;
  for (int k = 0; k < profile.pair().tooth_count; ++k) {
    for (int i = -n; i <= n; ++i) {
      const double u = profile.phi_max() * i / n;
      const double dist = (profile.Position(u, k) - p).norm();
      if (dist < best) best = dist, best_u = u, best_k = k;
    }
  }
  double a = std::max(-profile.phi_max(), best_u - profile.phi_max() / n);
  double b = std::min(profile.phi_max(), best_u + profile.phi_max() / n);
  const double g = (std::sqrt(5.0) - 1) / 2;
  for (int it = 0; it < 100; ++it) {
    const double c = b - g * (b - a), d = a + g * (b - a);
    if ((profile.Position(c, best_k) - p).norm() < (profile.Position(d, best_k) - p).norm()) b = d; else a = c;
  }
  return std::min(best, (profile.Position(0.5 * (a + b), best_k) - p).norm());
}

}  // namespace ltca::test
