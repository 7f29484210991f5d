#pragma once
// The tests' own balance of a preloaded mesh: a rigid disc turning by phi about its held centre
// against linear springs on both flanks, F_i = k_i (L_i phi - c_i) where positive, arm L_i of
// either sign. M(phi) = sum_i F_i L_i is piecewise linear and non-decreasing (slope
// sum_active k_i L_i^2), its breakpoints the closings c_i / L_i: the balance M(phi) = T lies on
// the one piece whose ends bracket T, solved there in closed form. Independent of the solvers it
// checks (a breakpoint walk, not their root search; tests/solvers/preload_test.cpp).
#include <algorithm>
#include <cstddef>
#include <vector>

namespace ltca::test {

struct FlankSpring {
  double arm = 0.0;        ///< L_i, mm, physical frame (signed)
  double clearance = 0.0;  ///< c_i, mm (negative: an overlap)
  double k = 0.0;          ///< N/mm
};

struct TwoFlankBalance {
  double phi = 0.0;            ///< rad, physical frame
  std::vector<double> force;   ///< N
  int contacts = 0;
};

inline double TwoFlankMoment(const std::vector<FlankSpring>& springs, double phi) {
  double m = 0.0;
  for (const FlankSpring& s : springs) m += s.k * std::max(0.0, s.arm * phi - s.clearance) * s.arm;
  return m;
}

/// The balance at torque T (N*mm, physical frame). Springs with a zero arm keep their force and
/// carry no moment. Assumes M reaches T (some spring of each arm sign, or the right one).
inline TwoFlankBalance SolveTwoFlankNetwork(const std::vector<FlankSpring>& springs, double torque) {
  std::vector<double> breaks;
  for (const FlankSpring& s : springs) {
    if (s.arm != 0.0) breaks.push_back(s.clearance / s.arm);
  }
  std::sort(breaks.begin(), breaks.end());
  // The piece [a, b] holding the root; beyond the outer breakpoints M is linear too.
  const auto slope_at = [&](double phi) {  // sum k L^2 of the springs pressed just past phi
    double k = 0.0;
    for (const FlankSpring& s : springs) {
      if (s.arm * phi - s.clearance > 0.0) k += s.k * s.arm * s.arm;
    }
    return k;
  };
  double a = breaks.front() - 1.0;  // 1 rad outside: a point on the outer piece
  for (std::size_t j = 0; j < breaks.size(); ++j) {
    if (TwoFlankMoment(springs, breaks[j]) <= torque) a = breaks[j];
  }
  double b = breaks.back() + 1.0;
  for (std::size_t j = breaks.size(); j-- > 0;) {
    if (TwoFlankMoment(springs, breaks[j]) >= torque) b = breaks[j];
  }
  const double mid = 0.5 * (a + b);
  const double slope = slope_at(mid);
  // On the piece, M(phi) = M(mid) + slope (phi - mid).
  TwoFlankBalance out;
  out.phi = mid + (torque - TwoFlankMoment(springs, mid)) / slope;
  for (const FlankSpring& s : springs) {
    const double f = s.k * std::max(0.0, s.arm * out.phi - s.clearance);
    out.force.push_back(f);
    out.contacts += f > 0.0 ? 1 : 0;
  }
  return out;
}

}  // namespace ltca::test
