#include "ltca/geometry/arc_length.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace ltca::geometry {
namespace {

constexpr int kPanels = 64;  // even: u = 0 is the middle panel edge

// 8-point Gauss-Legendre on [a, b].
template <class F>
double Gauss8(const F& f, double a, double b) {
  static constexpr double x[4] = {0.18343464249564980494, 0.52553240991632898582, 0.79666647741362673959,
                                  0.96028985649753623168};
  static constexpr double w[4] = {0.36268378337836198297, 0.31370664587788728734, 0.22238103445337447054,
                                  0.10122853629037625915};
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) sum += w[i] * (f(mid - half * x[i]) + f(mid + half * x[i]));
  return half * sum;
}

// Adaptive: halves [a, b] until the two halves agree with the whole to `tol` (absolute).
template <class F>
double Adaptive(const F& f, double a, double b, double whole, double tol, int depth) {
  const double mid = 0.5 * (a + b);
  const double left = Gauss8(f, a, mid), right = Gauss8(f, mid, b);
  if (depth <= 0 || std::abs(left + right - whole) <= tol) return left + right;
  return Adaptive(f, a, mid, left, 0.5 * tol, depth - 1) + Adaptive(f, mid, b, right, 0.5 * tol, depth - 1);
}

constexpr double kRelativeTolerance = 1e-14;
constexpr int kMaxDepth = 30;

}  // namespace

ProfileArcLength::ProfileArcLength(const CycloidProfile& profile) : profile_(profile) {
  const double phi = profile_.phi_max();
  h_ = 2.0 * phi / kPanels;
  const auto speed = [this](double v) { return Speed(v); };
  std::vector<double> panel(kPanels);
  for (int i = 0; i < kPanels; ++i) {
    const double a = -phi + i * h_, b = -phi + (i + 1) * h_;
    const double whole = Gauss8(speed, a, b);
    panel[static_cast<std::size_t>(i)] = Adaptive(speed, a, b, whole, kRelativeTolerance * whole, kMaxDepth);
  }
  // Cumulated outward from u = 0 (node kPanels / 2), so that s(0) = 0 exactly.
  node_s_.assign(kPanels + 1, 0.0);
  for (int i = kPanels / 2; i < kPanels; ++i) {
    node_s_[static_cast<std::size_t>(i + 1)] = node_s_[static_cast<std::size_t>(i)] + panel[static_cast<std::size_t>(i)];
  }
  for (int i = kPanels / 2; i > 0; --i) {
    node_s_[static_cast<std::size_t>(i - 1)] = node_s_[static_cast<std::size_t>(i)] - panel[static_cast<std::size_t>(i - 1)];
  }
}

double ProfileArcLength::Speed(double u) const { return profile_.Evaluate(u).d1.norm(); }

double ProfileArcLength::FromNode(int panel, double u) const {
  const double a = -profile_.phi_max() + panel * h_;
  if (u == a) return node_s_[static_cast<std::size_t>(panel)];
  const auto speed = [this](double v) { return Speed(v); };
  const double whole = Gauss8(speed, a, u);
  return node_s_[static_cast<std::size_t>(panel)] +
         Adaptive(speed, a, u, whole, kRelativeTolerance * std::abs(whole), kMaxDepth);
}

double ProfileArcLength::At(double u) const {
  const double phi = profile_.phi_max();
  if (!(std::abs(u) <= phi)) {
    throw std::out_of_range(fmt::format("ProfileArcLength::At: u = {} rad outside [-{}, {}]", u, phi, phi));
  }
  const int panel = std::clamp(static_cast<int>(std::floor((u + phi) / h_)), 0, kPanels - 1);
  return FromNode(panel, u);
}

double ProfileArcLength::ParameterAt(double s) const {
  if (!(s >= begin() && s <= end())) {
    throw std::out_of_range(fmt::format("ProfileArcLength::ParameterAt: s = {} mm outside [{}, {}]", s, begin(), end()));
  }
  const int panel = std::clamp(
      static_cast<int>(std::upper_bound(node_s_.begin(), node_s_.end(), s) - node_s_.begin()) - 1, 0, kPanels - 1);
  const double phi = profile_.phi_max();
  double lo = -phi + panel * h_, hi = panel + 1 == kPanels ? phi : -phi + (panel + 1) * h_;
  const double s_lo = node_s_[static_cast<std::size_t>(panel)], s_hi = node_s_[static_cast<std::size_t>(panel + 1)];
  if (s == s_lo) return lo;
  if (s == s_hi) return hi;
  // Newton on f(u) = s(u) - s, kept inside the bracket [lo, hi] (f(lo) < 0 < f(hi)); a step that
  // leaves it, or does not halve the bracket's worth, is replaced by bisection.
  double u = lo + (hi - lo) * (s - s_lo) / (s_hi - s_lo);
  for (int it = 0; it < 200; ++it) {
    const double f = FromNode(panel, u) - s;
    if (f == 0.0) return u;
    if (f < 0.0) lo = u; else hi = u;
    double next = u - f / Speed(u);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - u) <= 2.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(u), h_)) return next;
    if (hi - lo <= 2.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(u), h_)) return 0.5 * (lo + hi);
    u = next;
  }
  return u;
}

}  // namespace ltca::geometry
