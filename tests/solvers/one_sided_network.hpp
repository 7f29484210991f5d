#pragma once
// The tests' own solution of a stage assembled by hand as a one-sided linear network: a fixed
// stiffness (bearings, shafts) and springs that act only when closed (force k (a . q - gap)),
// solved with Eigen's LDLT over the active set until the set repeats, which is the network's exact
// solution. Independent of the solvers it checks (tests/solvers/stage_test.cpp, rv_stage_test.cpp).
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Dense>

namespace ltca::test {

/// The displacements q with `torque` on dof `torque_dof` (the output's rotation), and `load` (a
/// fixed element's preload, e.g. -k g^T o of a spring stretched by o at q = 0; empty: none), or none
/// when the active set does not settle in 50 rounds. Spring: any type with members a
/// (Eigen::VectorXd), gap and k.
template <class Spring>
std::optional<Eigen::VectorXd> SolveOneSided(const Eigen::MatrixXd& fixed, const std::vector<Spring>& springs,
                                             Eigen::Index torque_dof, double torque, const Eigen::VectorXd& load = {}) {
  const auto n = fixed.rows();
  std::vector<bool> active(springs.size(), true);
  for (int round = 0; round < 50; ++round) {
    Eigen::MatrixXd k = fixed;
    Eigen::VectorXd f = load.size() == n ? load : Eigen::VectorXd::Zero(n);
    f(torque_dof) += torque;
    for (std::size_t e = 0; e < springs.size(); ++e) {
      if (!active[e]) continue;
      k += springs[e].k * springs[e].a * springs[e].a.transpose();
      f += springs[e].k * springs[e].gap * springs[e].a;
    }
    const Eigen::VectorXd q = k.ldlt().solve(f);
    bool same = true;
    for (std::size_t e = 0; e < springs.size(); ++e) {
      const bool closed = springs[e].a.dot(q) - springs[e].gap > 0.0;
      same = same && closed == active[e];
      active[e] = closed;
    }
    if (same) return q;
  }
  return std::nullopt;
}

}  // namespace ltca::test
