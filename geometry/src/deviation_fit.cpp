#include "ltca/geometry/deviation_fit.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

namespace ltca::geometry {

Modification DeviationFit::AsModification() const {
  Modification m;
  m.pin_circle_radius = offset;
  m.pin_radius = isometric;
  m.rotation = rotation;
  return m;
}

namespace {

Modification Plus(const Modification& base, const Modification& delta) {
  Modification m = base;
  m.pin_circle_radius += delta.pin_circle_radius;
  m.pin_radius += delta.pin_radius;
  m.rotation += delta.rotation;
  return m;
}

/// t where `other`'s space 0 meets the design's normal line at u (Newton in (u', t)).
double NormalDeviation(const ProfilePoint& at, const CycloidProfile& other, double u) {
  double v = u, t = 0.0;
  for (int it = 0; it < 50; ++it) {
    const ProfilePoint q = other.Evaluate(v, 0);
    const Eigen::Vector2d r = q.position - at.position - t * at.normal;
    if (r.norm() < 1e-14) break;
    Eigen::Matrix2d j;
    j.col(0) = q.d1;
    j.col(1) = -at.normal;
    const Eigen::Vector2d step = j.lu().solve(-r);
    v += step(0), t += step(1);
    if (std::abs(step(0)) < 1e-15 && std::abs(step(1)) < 1e-15) break;
  }
  return t;
}

}  // namespace

double ModificationDeviation(const CycloidProfile& design, const Modification& delta, double u) {
  const CycloidProfile other(design.pair(), Plus(design.modification(), delta));
  return NormalDeviation(design.Evaluate(u, 0), other, u);
}

DeviationFit FitModification(const CycloidProfile& design, const std::vector<double>& u, const std::vector<double>& delta) {
  if (u.size() != delta.size() || u.size() < 3) {
    throw std::invalid_argument(fmt::format("deviation fit: {} abscissae and {} deviations: expected the same number, at least 3",
                                            u.size(), delta.size()));
  }
  // Both flanks: for d > 0 the root is at u = 0, for a ring the tip (the flanks are u < 0 and u > 0 either way).
  const bool left = std::any_of(u.begin(), u.end(), [](double x) { return x < 0.0; });
  const bool right = std::any_of(u.begin(), u.end(), [](double x) { return x > 0.0; });
  if (!left || !right) {
    throw std::invalid_argument("deviation fit: the trace covers one flank only; offset, isometric and rotation need both");
  }
  const Eigen::Index n = static_cast<Eigen::Index>(u.size());
  std::vector<ProfilePoint> at;
  at.reserve(u.size());
  for (const double x : u) at.push_back(design.Evaluate(x, 0));
  const auto residuals = [&](const Eigen::Vector3d& p) {
    Modification d;
    d.pin_circle_radius = p(0), d.pin_radius = p(1), d.rotation = p(2);
    const CycloidProfile other(design.pair(), Plus(design.modification(), d));
    Eigen::VectorXd r(n);
    for (Eigen::Index i = 0; i < n; ++i) r(i) = NormalDeviation(at[static_cast<std::size_t>(i)], other, u[static_cast<std::size_t>(i)]);
    return r;
  };
  Eigen::VectorXd target(n);
  for (Eigen::Index i = 0; i < n; ++i) target(i) = delta[static_cast<std::size_t>(i)];
  const Eigen::Vector3d h(1e-5, 1e-5, 1e-7);
  const double lever = design.pair().pin_circle_radius;  // a rotation's step as a length
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  DeviationFit fit;
  for (int it = 0; it < 30; ++it) {
    Eigen::MatrixXd j(n, 3);
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e(c) = h(c);
      j.col(c) = (residuals(p + e) - residuals(p - e)) / (2.0 * h(c));
    }
    const Eigen::Vector3d step = j.colPivHouseholderQr().solve(target - residuals(p));
    p += step;
    fit.iterations = it + 1;
    if (std::max({std::abs(step(0)), std::abs(step(1)), lever * std::abs(step(2))}) < 1e-12) break;
  }
  fit.offset = p(0), fit.isometric = p(1), fit.rotation = p(2);
  const Eigen::VectorXd r = target - residuals(p);
  fit.rms_residual = std::sqrt(r.squaredNorm() / static_cast<double>(n));
  fit.max_residual = r.cwiseAbs().maxCoeff();
  return fit;
}

}  // namespace ltca::geometry
