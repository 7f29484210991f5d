#include "ltca/geometry/outline.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/geometry/tip_relief.hpp"

namespace ltca::geometry {

std::vector<std::vector<Eigen::Vector2d>> OutlineSegments(const CycloidProfile& profile, double sagitta) {
  if (!(sagitta > 0.0) || !std::isfinite(sagitta)) {
    throw std::invalid_argument(fmt::format("outline sagitta = {}: expected a positive length in mm", sagitta));
  }
  std::vector<std::vector<Eigen::Vector2d>> segments;
  std::vector<bool> is_cap;  // a cap's piece holds its interior points only: the flanks give its ends
  const auto push = [&](const Eigen::Vector2d& p) {
    std::vector<Eigen::Vector2d>& out = segments.back();
    if (out.empty() || (p - out.back()).norm() > 1e-9) out.push_back(p);  // a joint emitted once
  };
  const double target = 0.5 * sagitta;  // half the bound: the curvature changes over a step
  const auto step_length = [&](double curvature) {
    const double k = std::abs(curvature);
    return k == 0.0 ? 1.0 : std::min(1.0, std::sqrt(8.0 * target / k));  // at most 1 mm
  };
  // The flank of space k from u = lo to hi, both ends included.
  const auto flank = [&](int k, double lo, double hi) {
    segments.emplace_back();
    is_cap.push_back(false);
    double u = lo;
    push(profile.Evaluate(u, k).position);
    while (u < hi) {
      const ProfilePoint p = profile.Evaluate(u, k);
      double du = step_length(p.curvature) / p.d1.norm();
      for (int it = 0; it < 3; ++it) {  // the step's far end and middle may be more curved
        const double next = std::min(u + du, hi);
        const ProfilePoint q = profile.Evaluate(next, k);
        const ProfilePoint m = profile.Evaluate(0.5 * (u + next), k);
        const double curvature = std::max({std::abs(p.curvature), std::abs(q.curvature), std::abs(m.curvature)});
        const double speed = std::max({p.d1.norm(), q.d1.norm(), m.d1.norm()});
        const double shorter = step_length(curvature) / speed;
        if (shorter >= du * 0.999) break;
        du = shorter;
      }
      u = std::min(u + du, hi);
      if (hi - u < 1e-12) u = hi;
      push(profile.Evaluate(u, k).position);
    }
  };
  const TipCap& cap = profile.tip_cap();
  // Tip `tip`'s cap from w = from to -from, its junctions excluded (the flanks give them).
  const auto tip_cap = [&](int tip, double from) {
    const double rho = cap.relief().rounding_radius;
    const double h = rho > 0.0 ? std::sqrt(8.0 * target * rho) : cap.length();
    const int n = std::max(1, static_cast<int>(std::ceil(cap.length() / h)));
    segments.emplace_back();
    is_cap.push_back(true);
    for (int i = 1; i < n; ++i) push(cap.Point(from * (1.0 - 2.0 * i / n), tip).point);
  };
  const int z = profile.pair().tooth_count;
  for (int k = 0; k < z; ++k) {
    if (!cap.active()) {
      flank(k, -profile.phi_max(), profile.phi_max());
    } else if (profile.tooth_difference() > 0) {
      flank(k, -cap.junction(), cap.junction());
      tip_cap(k, 1.0);
    } else {
      flank(k, -profile.phi_max(), -cap.junction());
      tip_cap(k, -1.0);
      flank(k, cap.junction(), profile.phi_max());
    }
  }
  // A flank's piece runs from end to end; a cap's gets the junctions, the ends of the flanks
  // before and after it. Consecutive flanks (no relief) share their tip point.
  const std::size_t n = segments.size();
  std::vector<std::vector<Eigen::Vector2d>> closed(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<Eigen::Vector2d>& c = closed[i];
    if (is_cap[i]) c.push_back(segments[(i + n - 1) % n].back());
    c.insert(c.end(), segments[i].begin(), segments[i].end());
    if (is_cap[i]) c.push_back(segments[(i + 1) % n].front());
  }
  return closed;
}

std::vector<Eigen::Vector2d> OutlinePolyline(const CycloidProfile& profile, double sagitta) {
  std::vector<Eigen::Vector2d> out;
  for (const std::vector<Eigen::Vector2d>& segment : OutlineSegments(profile, sagitta)) {
    for (const Eigen::Vector2d& p : segment) {
      if (out.empty() || (p - out.back()).norm() > 1e-9) out.push_back(p);  // a joint emitted once
    }
  }
  if (out.size() > 1 && (out.front() - out.back()).norm() <= 1e-9) out.pop_back();  // closed: the first once
  return out;
}

}  // namespace ltca::geometry
