#include "ltca/geometry/discrete_profile.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

namespace ltca::geometry {
namespace {

// Arc length of the real profile of one tooth space from -phi_max to u: 8-point Gauss-Legendre
// on 64 panels (the speed |x'(u)| is smooth on the arc).
class ArcLength {
 public:
  explicit ArcLength(const CycloidProfile& p) : p_(p) {}
  double operator()(double a, double b) const {
    static const double x[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
    static const double w[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
    const int panels = 64;
    double sum = 0.0;
    const double h = (b - a) / panels;
    for (int k = 0; k < panels; ++k) {
      const double mid = a + (k + 0.5) * h, half = 0.5 * h;
      for (int i = 0; i < 4; ++i) {
        sum += w[i] * half * (p_.Evaluate(mid - half * x[i]).d1.norm() + p_.Evaluate(mid + half * x[i]).d1.norm());
      }
    }
    return sum;
  }

 private:
  const CycloidProfile& p_;
};

}  // namespace

void GeometrySettings::Validate() const {
  if (mode == Mode::kElements && profile_elements < 2) {
    throw std::invalid_argument(fmt::format("[geometry] profile_elements = {}: expected >= 2", profile_elements));
  }
  if (mode == Mode::kElements && width_slices < 1) {
    throw std::invalid_argument(fmt::format("[geometry] width_slices = {}: expected >= 1", width_slices));
  }
  if (profile_elements > kMaxProfileElements) {
    throw std::invalid_argument(fmt::format(
        "[geometry] profile_elements = {}: expected at most {} (docs/decks.md, Limits)",
        profile_elements, kMaxProfileElements));
  }
  if (width_slices > kMaxWidthSlices) {
    throw std::invalid_argument(fmt::format(
        "[geometry] width_slices = {}: expected at most {} (docs/decks.md, Limits)", width_slices,
        kMaxWidthSlices));
  }
  const long long product = static_cast<long long>(profile_elements) * width_slices;
  if (mode == Mode::kElements && product > kMaxElementsTimesSlices) {
    throw std::invalid_argument(fmt::format(
        "[geometry] profile_elements = {} x width_slices = {} = {} elements: expected at most {} "
        "(Liu's 800 x 100 = 80000; docs/decks.md, Limits)",
        profile_elements, width_slices, product, kMaxElementsTimesSlices));
  }
}

DiscreteProfile::DiscreteProfile(const CycloidProfile& profile, int elements, int slices, int polynomial_order)
    : profile_(profile), slices_(slices) {
  if (elements < 2) throw std::invalid_argument(fmt::format("[geometry] profile_elements = {}: expected >= 2", elements));
  if (slices < 1) throw std::invalid_argument(fmt::format("[geometry] width_slices = {}: expected >= 1", slices));
  if (polynomial_order < 1 || polynomial_order > 15) {
    throw std::invalid_argument(fmt::format("polynomial order {}: expected 1..15", polynomial_order));
  }
  const double phi = profile.phi_max();
  const ArcLength length(profile);
  // Liu eq. 3: u as a polynomial of the arc length s, fitted by least squares to (s_i, u_i) at
  // 8 N sample points (in a scaled variable t = 2 s / S - 1 for conditioning).
  const int samples = 8 * polynomial_order + 1;
  std::vector<double> s(static_cast<std::size_t>(samples)), u(static_cast<std::size_t>(samples));
  double acc = 0.0;
  for (int i = 0; i < samples; ++i) {
    u[static_cast<std::size_t>(i)] = -phi + 2.0 * phi * i / (samples - 1);
    if (i > 0) acc += length(u[static_cast<std::size_t>(i - 1)], u[static_cast<std::size_t>(i)]);
    s[static_cast<std::size_t>(i)] = acc;
  }
  arc_length_ = acc;
  Eigen::MatrixXd a(samples, polynomial_order + 1);
  Eigen::VectorXd b(samples);
  for (int i = 0; i < samples; ++i) {
    const double t = 2.0 * s[static_cast<std::size_t>(i)] / arc_length_ - 1.0;
    double power = 1.0;
    for (int k = 0; k <= polynomial_order; ++k, power *= t) a(i, k) = power;
    b(i) = u[static_cast<std::size_t>(i)];
  }
  const Eigen::VectorXd coef = a.colPivHouseholderQr().solve(b);
  const auto u_of_s = [&](double arc) {
    const double t = 2.0 * arc / arc_length_ - 1.0;
    double value = 0.0, power = 1.0;
    for (int k = 0; k <= polynomial_order; ++k, power *= t) value += coef(k) * power;
    return value;
  };
  for (int i = 0; i < samples; ++i) {
    fit_error_ = std::max(fit_error_, std::abs(u_of_s(s[static_cast<std::size_t>(i)]) - u[static_cast<std::size_t>(i)]));
  }
  // Departure from eq. 3: the polynomial misses u(s) by up to fit_error (3e-3 rad on the Liu
  // profile at order 9: the arc length grows very unevenly with u near the root), which would
  // break the equal arc length the elements are for. It only seeds a Newton iteration on a
  // tabulated s(u) (2048 panels, 4-point Gauss-Legendre each) that places every control point at
  // exactly s = S (j - 1/2) / n.
  const int panels = 2048;
  std::vector<double> node(panels + 1), cumulative(panels + 1, 0.0);
  const auto panel_length = [&](double a, double b) {
    static const double x[2] = {0.3399810435848563, 0.8611363115940526};
    static const double w[2] = {0.6521451548625461, 0.3478548451374538};
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    double sum = 0.0;
    for (int i = 0; i < 2; ++i) {
      sum += w[i] * half * (profile.Evaluate(mid - half * x[i]).d1.norm() + profile.Evaluate(mid + half * x[i]).d1.norm());
    }
    return sum;
  };
  for (int i = 0; i <= panels; ++i) node[static_cast<std::size_t>(i)] = -phi + 2.0 * phi * i / panels;
  for (int i = 1; i <= panels; ++i) {
    cumulative[static_cast<std::size_t>(i)] =
        cumulative[static_cast<std::size_t>(i - 1)] + panel_length(node[static_cast<std::size_t>(i - 1)], node[static_cast<std::size_t>(i)]);
  }
  arc_length_ = cumulative.back();
  const auto u_at = [&](double target, double seed) {
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
    const auto i = static_cast<std::size_t>(std::clamp<long>(it - cumulative.begin() - 1, 0, panels - 1));
    double u = std::clamp(seed, node[i], node[i + 1]);
    for (int iter = 0; iter < 20; ++iter) {
      const double step = (cumulative[i] + panel_length(node[i], u) - target) / profile.Evaluate(u).d1.norm();
      u = std::clamp(u - step, node[i], node[i + 1]);
      if (std::abs(step) < 1e-15) break;
    }
    return u;
  };
  elements_.reserve(static_cast<std::size_t>(elements));
  for (int j = 0; j < elements; ++j) {
    // Liu eq. 3: the control point at s = S (j - 1/2) / n (1-based j).
    const double target = arc_length_ * (j + 0.5) / elements;
    const double uj = u_at(target, std::clamp(u_of_s(target), -phi, phi));
    const ProfilePoint p = profile.Evaluate(uj);
    elements_.push_back({uj, p.position, p.normal, p.curvature, 0.0});
  }
}

ProfileElement DiscreteProfile::Element(int j, int tooth_space) const {
  ProfileElement e = elements_[static_cast<std::size_t>(j)];
  const double angle = profile_.tooth_pitch() * tooth_space;  // the elements carry the rotation modification
  const double c = std::cos(angle), s = std::sin(angle);
  e.position = Eigen::Vector2d(c * e.position.x() - s * e.position.y(), s * e.position.x() + c * e.position.y());
  e.normal = Eigen::Vector2d(c * e.normal.x() - s * e.normal.y(), s * e.normal.x() + c * e.normal.y());
  return e;
}

}  // namespace ltca::geometry
