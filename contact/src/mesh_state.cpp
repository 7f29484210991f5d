#include "ltca/contact/mesh_state.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::contact {
namespace {

using geometry::CycloidProfile;
using units::kPi;

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// Closest point of body-frame point p on the arc u in [lo, hi] of tooth space k, by a
/// safeguarded Newton iteration on g(u) = (x(u) - p) . x'(u) from the seed u0: the bracket
/// [a, b] with g(a) < 0 < g(b) is kept, and a Newton step that leaves it is replaced by
/// bisection. Returns the parameter; an end of the arc when the distance decreases up to it.
// The foot parameter u in [lo, hi] of tooth space k nearest to p (the root of r . d1), and in
// *point the profile at that u (the converged Newton step's own evaluation, not one more).
double ClosestParameter(const CycloidProfile& profile, int k, const Eigen::Vector2d& p, double u0,
                        double lo, double hi, geometry::ProfilePoint* point) {
  geometry::ProfilePoint x;
  const auto g = [&](double u, double* dg) {
    x = profile.Evaluate(u, k);
    const Eigen::Vector2d r = x.position - p;
    if (dg != nullptr) *dg = x.d1.squaredNorm() + r.dot(x.d2);
    return r.dot(x.d1);
  };
  const auto at = [&](double u) {
    *point = profile.Evaluate(u, k);
    return u;
  };
  u0 = std::clamp(u0, lo, hi);
  // Fast path: plain Newton from the seed (the meshing equation puts it next to the foot point),
  // accepted only while it behaves: positive curvature of the distance, small steps inside the arc.
  // Converged when the next step is below 1e-15 of the arc: the rounding noise of g is ~1e-17 rad,
  // and the arm and the gap cannot feel less than ~1e-12 rad. The answer is then the point just
  // evaluated (the step it asks for is below what the gap, stationary there, can feel).
  const double tol = 1e-15 * (hi - lo) + 4.0 * std::numeric_limits<double>::epsilon() * std::abs(u0);
  {
    double u = u0;
    const double max_step = 0.05 * (hi - lo);
    for (int it = 0; it < 8; ++it) {
      double dg = 0.0;
      const double gu = g(u, &dg);
      if (!(dg > 0.0)) break;
      const double step = -gu / dg;
      if (std::abs(step) <= tol) {
        *point = x;
        return u;
      }
      if (std::abs(step) > max_step || u + step < lo || u + step > hi) break;
      u += step;
    }
  }
  // Safeguarded: bracket the root around the seed, widening geometrically up to the arc ends.
  double step = 1e-3 * (hi - lo);
  double a = u0, b = u0;
  double ga = g(a, nullptr), gb = ga;
  while (ga > 0.0 && a > lo) {
    b = a, gb = ga;
    a = std::max(lo, a - step);
    ga = g(a, nullptr);
    step *= 4.0;
  }
  step = 1e-3 * (hi - lo);
  while (gb < 0.0 && b < hi) {
    a = b, ga = gb;
    b = std::min(hi, b + step);
    gb = g(b, nullptr);
    step *= 4.0;
  }
  if (ga > 0.0) return at(a);  // distance increasing from the lower end: the end is closest
  if (gb < 0.0) return at(b);  // distance decreasing up to the upper end
  double u = (ga == 0.0) ? a : (gb == 0.0 ? b : 0.5 * (a + b));
  if (u0 > a && u0 < b) u = u0;
  for (int it = 0; it < 100; ++it) {
    double dg = 0.0;
    const double gu = g(u, &dg);
    if (gu == 0.0) {
      *point = x;
      return u;
    }
    if (gu < 0.0) a = u; else b = u;
    double next = (dg > 0.0) ? u - gu / dg : 0.5 * (a + b);
    if (!(next > a && next < b)) next = 0.5 * (a + b);
    if (std::abs(next - u) <= tol || b - a <= tol) return at(next);
    u = next;
  }
  *point = x;
  return u;
}

/// Places a contact found in the body frame: its point and the normal toward the pin centre in the
/// fixed frame, the pin's point, and the lever arm of the normal about the cycloid centre, signed
/// by the load direction (Liu eq. 27). c->pin_radius must be set.
void PlaceContact(const geometry::PoseFrame& pose, const Eigen::Vector2d& centre_fixed, double load_direction,
                  const Eigen::Vector2d& point_body, const Eigen::Vector2d& normal_body, PinContact* c) {
  c->cycloid_point = pose.ToFixed(point_body);
  c->normal = pose.DirectionToFixed(normal_body);
  c->pin_point = centre_fixed - c->pin_radius * c->normal;
  c->arm = load_direction * Cross(c->cycloid_point - pose.centre, c->normal);
}

/// The closest point of a profile with relieved tips (geometry/tip_relief.hpp) to the
/// body-frame pin centre p: the flanks |u| <= u_j of the tooth space the pin's polar angle falls in
/// and of both neighbours (the safeguarded Newton search, the seed kept when it is on one of them),
/// and the caps of the four tips around them (closed form). The smallest distance wins; a cap
/// candidate is taken first, so that at a junction (where both give the same point and, with a
/// rounding, the same normal) the cap is reported. With rho = 0 a flank point at its end is the
/// corner it meets the truncation line in.
struct RelievedFoot {
  int k = 0;
  double u = 0.0;
  Eigen::Vector2d point;
  Eigen::Vector2d normal;  // unit, out of the material toward p
  double gap = 0.0;        // signed distance of p, mm
  double curvature = 0.0;
  geometry::SurfacePart part = geometry::SurfacePart::kFlank;
  double w = 0.0;          // on the cap: CapFoot::w
};

RelievedFoot NearestOnRelievedProfile(const CycloidProfile& profile, const Eigen::Vector2d& p, int seed_space,
                                      double seed_u) {
  const geometry::TipCap& cap = profile.tip_cap();
  const double u_j = cap.junction();
  const double phi_max = profile.phi_max();
  const int zc = profile.pair().tooth_count;
  const double pitch = profile.tooth_pitch();
  const double polar = std::atan2(p.y(), p.x()) - profile.ToothSpaceRotation(0);
  const int k_polar = static_cast<int>(std::lround(polar / pitch));
  const auto wrap = [zc](int k) { return ((k % zc) + zc) % zc; };
  RelievedFoot best;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int tip = k_polar - 2; tip <= k_polar + 1; ++tip) {
    const geometry::CapFoot f = cap.Nearest(p, wrap(tip));
    const double distance = std::abs(f.distance);
    if (distance < best_distance) {
      best_distance = distance;
      best.k = f.tooth_space;
      best.u = f.u;
      best.point = f.point, best.normal = f.normal, best.gap = f.distance;
      best.curvature = f.curvature, best.part = f.part, best.w = f.w;
    }
  }
  const bool corners = cap.relief().rounding_radius == 0.0;
  const std::vector<std::pair<double, double>> arcs = cap.FlankArcs();
  for (int dk = -1; dk <= 1; ++dk) {
    const int kk = wrap(k_polar + dk);
    const double rel = std::remainder(polar - (k_polar + dk) * pitch, 2.0 * kPi);
    for (const auto& [lo, hi] : arcs) {
      const double start = kk == seed_space && seed_u >= lo && seed_u <= hi
                               ? seed_u
                               : std::clamp(rel * phi_max / (0.5 * pitch), lo, hi);
      geometry::ProfilePoint x;
      const double uu = ClosestParameter(profile, kk, p, start, lo, hi, &x);
      const double distance = (x.position - p).norm();
      if (!(distance < best_distance)) continue;
      best_distance = distance;
      best.k = kk, best.u = uu, best.point = x.position, best.w = 0.0;
      if (corners && std::abs(uu) == u_j) {  // clamped at the junction: the corner with the line
        best.normal = (p - x.position) / distance;
        best.gap = distance;
        best.curvature = std::numeric_limits<double>::infinity();
        best.part = geometry::SurfacePart::kTipCorner;
        best.w = uu > 0.0 ? 1.0 : -1.0;  // the cap's end at this junction
      } else {
        best.normal = x.normal;
        best.gap = x.normal.dot(p - x.position);
        best.curvature = x.curvature;
        best.part = geometry::SurfacePart::kFlank;
      }
    }
  }
  return best;
}

/// A contact found at a foot point (tooth space k, parameter u) whose pin centre is `centre_gap`
/// from it (signed), before PlaceContact and FinishPoint.
PinContact FootContact(int pin, double angle, int k, double u, double pin_radius, double curvature, double centre_gap) {
  PinContact c;
  c.pin = pin;
  c.angle = angle;
  c.tooth_space = k;
  c.u = u;
  c.pin_radius = pin_radius;
  c.cycloid_curvature = curvature;
  c.clearance = centre_gap - pin_radius;
  return c;
}

/// The foot point on the flank as made, x(u) + delta(k, u) n(u) (a profile deviation along the
/// profile, geometry::ProfileDeviation), docs/contact.md "Profile deviation along the profile".
struct DeviatedFoot {
  int k = 0;
  double u = 0.0;
  Eigen::Vector2d point;   // x(u) + delta n(u), body frame, mm
  Eigen::Vector2d normal;  // unit, from the point toward the pin centre
  double distance = 0.0;   // |p - point|, mm
  double curvature = 0.0;  // of the equidistant at delta through the point: kappa / (1 + kappa delta)
  bool corner = false;     // a tip corner of a |d| >= 2 profile (an end of its arc)
};

/// Nearest point to the body-frame pin centre p of the deviated flank y(u) = x(u) + delta(k, u)
/// n(u) near the smooth foot point (k, u_star):
///  1. the window. Only a u with smooth separation D(u) - D(u*) < 2 MaxAbs (D = |p - x|) can
///     beat u* itself, because |p - y(u)| >= D(u) - MaxAbs and |p - y(u*)| = D(u*) - delta(u*)
///     >= D(u*) - MaxAbs. The half-width starts from the relative curvature at u*,
///     D(u) - D(u*) ~ s^2 / (2 rho_rel), 1 / rho_rel = kappa + 1 / D(u*), s = sqrt(2 rho_rel 2 MaxAbs),
///     and doubles until D at its end exceeds D(u*) + 2 MaxAbs or the arc ends. For |d| = 1 the
///     generating curve runs on across the tips (at most one pitch each way), and the window is cut
///     into arcs of the tooth spaces it crosses (delta jumps at a tip: each space its own draws);
///     for |d| >= 2 an arc ends in a tip corner, and when the window reaches it the neighbouring
///     space is searched from its corner in the same way.
///  2. the minimum over each arc: between two nodes of delta (ProfileDeviation::NodesIn) delta
///     is linear, so |p - y| is smooth there, and its minimum is at an end or where
///     h(u) = (y - p) . y' changes sign from - to +, y' = x' (1 + kappa delta) + delta' n
///     (n' = kappa x'), found by a safeguarded regula falsi. The candidates are the arc ends, the
///     nodes, u* and those interior roots: the result is the minimum over the window, which
///     contains every u that can win, so it is continuous in the pose.
DeviatedFoot NearestOnDeviatedFlank(const CycloidProfile& profile, const geometry::ProfileDeviation& deviation,
                                    const Eigen::Vector2d& p, int k_star, double u_star) {
  const double phi_max = profile.phi_max();
  const int zc = profile.pair().tooth_count;
  const int d = profile.tooth_difference();
  const double reach = 2.0 * deviation.MaxAbs();
  const geometry::ProfilePoint x_star = profile.Evaluate(u_star, k_star);
  const double d_star = (p - x_star.position).norm();
  const auto wrap = [zc](int k) { return ((k % zc) + zc) % zc; };
  // First guess of the half-width in u: s = sqrt(2 rho_rel 2 MaxAbs) over the flank's speed.
  const double inv_rho_rel = std::max(x_star.curvature + 1.0 / d_star, 1e-6);
  const double guess = std::sqrt(2.0 * reach / inv_rho_rel) / x_star.d1.norm();
  // The end of the window from `from` in direction `dir` on space k, not beyond `limit`.
  const auto extend = [&](int k, double from, double dir, double limit) {
    double w = guess;
    for (int it = 0; it < 64; ++it, w *= 2.0) {
      const double end = from + dir * w;
      if (dir * (end - limit) >= 0.0) break;
      if ((profile.Position(end, k) - p).norm() - d_star >= reach) return end;
    }
    return limit;
  };
  struct Arc {
    int k;
    double lo, hi;
  };
  std::vector<Arc> arcs;
  if (std::abs(d) == 1) {
    const double pitch = profile.tooth_pitch();
    const double lo = extend(k_star, u_star, -1.0, u_star - pitch);
    const double hi = extend(k_star, u_star, 1.0, u_star + pitch);
    // Cut [lo, hi] of the generating curve of space k_star where it crosses a tip and fold each
    // piece into its own tooth space, as EvaluatePointFrom folds u*: fold f covers
    // [(f - 1/2) L, (f + 1/2) L], L = 2 pi / z_c, and is space k_star + f at u - f L (for d = +-1
    // both: round(u / lobe) d = f with lobe = 2 pi d / z_c).
    const double fold = 2.0 * kPi / zc;
    for (long f = std::lround(std::floor(lo / fold + 0.5)); f <= std::lround(std::floor(hi / fold + 0.5)); ++f) {
      const double a = std::max(lo, (static_cast<double>(f) - 0.5) * fold);
      const double b = std::min(hi, (static_cast<double>(f) + 0.5) * fold);
      if (b < a) continue;
      const double shift = static_cast<double>(f) * fold;
      arcs.push_back({wrap(k_star + static_cast<int>(f)), a - shift, b - shift});
    }
  } else {
    const double lo = extend(k_star, u_star, -1.0, -phi_max);
    const double hi = extend(k_star, u_star, 1.0, phi_max);
    arcs.push_back({k_star, lo, hi});
    // The window reaches a tip corner: the neighbouring space from its corner (space k's
    // u = +phi_max meets space k + 1's u = -phi_max).
    if (lo == -phi_max && (profile.Position(-phi_max, k_star) - p).norm() - d_star < reach) {
      arcs.push_back({wrap(k_star - 1), extend(wrap(k_star - 1), phi_max, -1.0, -phi_max), phi_max});
    }
    if (hi == phi_max && (profile.Position(phi_max, k_star) - p).norm() - d_star < reach) {
      arcs.push_back({wrap(k_star + 1), -phi_max, extend(wrap(k_star + 1), -phi_max, 1.0, phi_max)});
    }
  }

  DeviatedFoot best;
  best.distance = std::numeric_limits<double>::infinity();
  std::vector<double> us;
  struct Sample {
    geometry::ProfilePoint x;
    double delta;
  };
  std::vector<Sample> samples;
  for (const Arc& arc : arcs) {
    const int k = arc.k;
    us.clear();
    us.push_back(arc.lo);
    deviation.NodesIn(arc.lo, arc.hi, &us);
    us.push_back(arc.hi);
    if (k == k_star && u_star > arc.lo && u_star < arc.hi) {
      us.insert(std::upper_bound(us.begin(), us.end(), u_star), u_star);
    }
    us.erase(std::unique(us.begin(), us.end()), us.end());
    samples.clear();
    for (const double u : us) samples.push_back({profile.Evaluate(u, k), deviation.At(k, u)});
    const auto consider = [&](double u, const geometry::ProfilePoint& x, double delta) {
      const Eigen::Vector2d y = x.position + delta * x.normal;
      const double distance = (p - y).norm();
      if (distance < best.distance) {
        best.k = k, best.u = u, best.point = y, best.distance = distance;
        best.normal = (p - y) / distance;
        best.curvature = x.curvature / (1.0 + x.curvature * delta);
        best.corner = std::abs(d) >= 2 && std::abs(u) >= phi_max;
      }
    };
    for (std::size_t i = 0; i < us.size(); ++i) consider(us[i], samples[i].x, samples[i].delta);
    // Interior minima of the smooth pieces between consecutive candidates.
    for (std::size_t i = 0; i + 1 < us.size(); ++i) {
      const double a = us[i], b = us[i + 1];
      if (!(b > a)) continue;
      const double slope = (samples[i + 1].delta - samples[i].delta) / (b - a);
      const auto h = [&](const geometry::ProfilePoint& x, double delta) {
        const Eigen::Vector2d y = x.position + delta * x.normal;
        const Eigen::Vector2d dy = (1.0 + x.curvature * delta) * x.d1 + slope * x.normal;
        return (y - p).dot(dy);
      };
      double ua = a, ub = b;
      double ha = h(samples[i].x, samples[i].delta), hb = h(samples[i + 1].x, samples[i + 1].delta);
      if (!(ha < 0.0 && hb > 0.0)) continue;
      // Safeguarded regula falsi (Illinois): h changes sign once on a piece this short.
      const double tol = 1e-15 * (b - a) + 4.0 * std::numeric_limits<double>::epsilon() * std::abs(b);
      int side = 0;
      double u = 0.5 * (ua + ub);
      for (int it = 0; it < 100 && ub - ua > tol; ++it) {
        u = (ua * hb - ub * ha) / (hb - ha);
        if (!(u > ua && u < ub)) u = 0.5 * (ua + ub);
        const double delta = samples[i].delta + slope * (u - a);
        const double hu = h(profile.Evaluate(u, k), delta);
        if (hu == 0.0) break;
        if (hu < 0.0) {
          ua = u, ha = hu;
          if (side == -1) hb *= 0.5;
          side = -1;
        } else {
          ub = u, hb = hu;
          if (side == 1) ha *= 0.5;
          side = 1;
        }
      }
      consider(u, profile.Evaluate(u, k), samples[i].delta + slope * (u - a));
    }
  }
  return best;
}

/// Elements mode with a profile deviation (Liu 2021 eq. 4, 8): element j of tooth space k is
/// moved along its normal by delta_j = delta(k, u_j), its equivalent cylinder keeps its centre of
/// curvature and its radius becomes rho + delta (eq. 8 with the sign of ProfileDeviation). The
/// element surface is a patch of that cylinder, one element long (S_c / n of arc, centred on the
/// control point), and the gap is the distance from the pin centre to the nearest patch minus the
/// pin radius: Liu's minimum clearance over the elements. Candidates: the elements whose control
/// point is within 2 MaxAbs + one element length of the nearest control point's distance (no
/// other patch can come closer: a patch lies within half an element of its control point and
/// moves by at most MaxAbs), in the space the pin's polar angle falls in and, when the candidates
/// reach an end of its arc, its neighbour. Without a deviation the model keeps its nearest-control-
/// point search (MeshModel::EvaluatePointElements).
struct ElementFoot {
  int k = 0;
  geometry::ProfileElement element;
  Eigen::Vector2d point;   // nearest point of the shifted patch, body frame
  Eigen::Vector2d normal;  // unit, from it toward the pin centre
  double distance = std::numeric_limits<double>::infinity();
  double curvature = 0.0;  // 1 / (rho + delta)
};

ElementFoot NearestDeviatedElement(const geometry::DiscreteProfile& discrete, const geometry::ProfileDeviation& deviation,
                                   const Eigen::Vector2d& p, int k_polar) {
  const int zc = discrete.profile().pair().tooth_count;
  const int n = discrete.element_count();
  const double half = 0.5 * discrete.arc_length() / n;  // half an element, mm
  const double reach = 2.0 * deviation.MaxAbs() + 2.0 * half;
  const auto wrap = [zc](int k) { return ((k % zc) + zc) % zc; };
  std::vector<double> distance(static_cast<std::size_t>(n));
  double nearest = std::numeric_limits<double>::infinity();
  const auto distances = [&](int k) {
    double smallest = std::numeric_limits<double>::infinity();
    for (int j = 0; j < n; ++j) {
      const double dj = (discrete.Element(j, k).position - p).norm();
      distance[static_cast<std::size_t>(j)] = dj;
      smallest = std::min(smallest, dj);
    }
    return smallest;
  };
  ElementFoot best;
  const auto scan = [&](int k) {  // the candidates of space k (distances filled for k)
    for (int j = 0; j < n; ++j) {
      if (distance[static_cast<std::size_t>(j)] > nearest + reach) continue;
      const geometry::ProfileElement e = discrete.Element(j, k);
      const double delta = deviation.At(k, e.u);
      const Eigen::Vector2d tangent(-e.normal.y(), e.normal.x());
      Eigen::Vector2d q;
      if (e.curvature == 0.0) {
        q = e.position + delta * e.normal + std::clamp((p - e.position).dot(tangent), -half, half) * tangent;
      } else {
        const double rho = 1.0 / e.curvature;
        const Eigen::Vector2d c = e.position - rho * e.normal;
        const Eigen::Vector2d e0 = rho > 0.0 ? e.normal : Eigen::Vector2d(-e.normal);  // centre -> control point
        const Eigen::Vector2d v = p - c;
        const double beta = half / std::abs(rho);
        const double alpha = std::clamp(std::atan2(Cross(e0, v), e0.dot(v)), -beta, beta);
        const Eigen::Vector2d dir = std::cos(alpha) * e0 + std::sin(alpha) * Eigen::Vector2d(-e0.y(), e0.x());
        q = c + std::abs(rho + delta) * dir;
      }
      const double dq = (p - q).norm();
      if (dq < best.distance) {
        best.k = k, best.element = e, best.point = q, best.distance = dq;
        best.normal = (p - q) / dq;
        best.curvature = e.curvature / (1.0 + e.curvature * delta);
      }
    }
  };
  const int k = wrap(k_polar);
  nearest = distances(k);
  const bool low_end = distance.front() <= nearest + reach, high_end = distance.back() <= nearest + reach;
  scan(k);
  for (const int side : {-1, 1}) {
    if (!(side < 0 ? low_end : high_end)) continue;
    const int kk = wrap(k + side);
    nearest = std::min(nearest, distances(kk));
    scan(kk);
  }
  return best;
}

}  // namespace

MeshModel::MeshModel(const geometry::PairParameters& pair,
                     const geometry::Modification& modification,
                     const geometry::ManufacturingErrors& errors, const geometry::GeometrySettings& geometry)
    : MeshModel(geometry::RealPair(pair, modification, errors), geometry) {}

MeshModel::MeshModel(geometry::RealPair real, const geometry::GeometrySettings& geometry, bool coupled_along_width)
    : real_(std::move(real)),
      lead_layer_(real_.errors().VariesAlongWidth()),
      load_direction_(real_.nominal().ToothDifference() > 0 ? 1.0 : -1.0) {
  geometry.Validate();
  if (geometry.mode == geometry::GeometrySettings::Mode::kElements && real_.profile().tip_cap().active()) {
    // Liu's elements are laid over the unrelieved arc [-phi_max, phi_max] (DiscreteProfile).
    const geometry::TipRelief& relief = real_.profile().tip_cap().relief();
    throw std::invalid_argument(fmt::format(
        "[modification] tip_rounding_radius_mm = {}, tip_truncation_mm = {}: a tip relief on the element surface "
        "([geometry] surface = \"elements\") is not supported yet; expected the analytic surface or no relief",
        relief.rounding_radius, relief.truncation));
  }
  // Model only what the scene needs: slices when something varies along the width or couples it.
  if (real_.VariesAlongWidth() || coupled_along_width) {
    if (geometry.width_slices < 1) {
      throw std::invalid_argument(fmt::format("[geometry] width_slices = {}: expected >= 1", geometry.width_slices));
    }
    slices_ = geometry.width_slices;
  }
  if (geometry.mode == geometry::GeometrySettings::Mode::kElements) {
    discrete_ = std::make_shared<geometry::DiscreteProfile>(real_.profile(), geometry.profile_elements, geometry.width_slices);
    // Sampled at 16 crank angles of one mesh period: where a pin meets the surface between two
    // control points varies with the crank.
    double worst = 0.0;
    for (int k = 0; k < 16; ++k) {
      const double crank = real_.kinematics().MeshPeriod() * k / 16.0;
      for (int j = 0; j < pin_count(); ++j) {
        const geometry::MeshSeed seed = real_.kinematics().Seed(j, crank);
        const double analytic = EvaluatePointFrom(j, 0, crank, 0.0, seed.tooth_space, seed.u).clearance;
        worst = std::max(worst, std::abs(EvaluatePointElements(j, 0, SliceZ(0), real_.kinematics().AngleFromLineOfCentres(j, crank),
                                                                  CyclePose(crank, 0.0, SliceZ(0)).Frame()).clearance - analytic));
      }
    }
    interference_tolerance_ = std::max(interference_tolerance_, 2.0 * worst);
  }
}

PinContact MeshModel::EvaluatePointElements(int pin, int slice, double z, double angle, const geometry::PoseFrame& frame) const {
  // Liu 2021 section 3: the element facing the pin (nearest control point) and the gap of its
  // equivalent cylinder (eq. 19, signed for a concave element):
  //   gap = sigma (|p - C| - |rho|) - r,  C = x - rho n (centre of curvature), sigma = sign(rho).
  // Liu searches every width slice; here the search runs per slice of the model that runs, which
  // is one slice (the plane model) unless something varies along the width (MeshModel).
  const Eigen::Vector2d centre_fixed = PinCentre(pin);
  const Eigen::Vector2d p = frame.ToBody(centre_fixed);
  const double r_pin = real_.PinRadius(pin);
  const int zc = pair().tooth_count;
  const double pitch = real_.profile().tooth_pitch();
  const int k_polar = static_cast<int>(std::lround((std::atan2(p.y(), p.x()) - real_.profile().ToothSpaceRotation(0)) / pitch));
  if (!real_.profile_deviation().IsZero()) {
    const ElementFoot f = NearestDeviatedElement(*discrete_, real_.profile_deviation(), p, k_polar);
    PinContact c = FootContact(pin, angle, f.k, f.element.u, r_pin,
                               f.curvature, f.distance);
    PlaceContact(frame, centre_fixed, load_direction_, f.point, f.normal, &c);
    FinishPoint(slice, z, &c);
    return c;
  }
  const int n = discrete_->element_count();
  const auto search = [&](int k) {
    int j_best = 0;
    double d_best = std::numeric_limits<double>::infinity();
    const int kk = ((k % zc) + zc) % zc;
    for (int j = 0; j < n; ++j) {
      const double d = (discrete_->Element(j, kk).position - p).squaredNorm();
      if (d < d_best) d_best = d, j_best = j;
    }
    return std::pair{kk, j_best};
  };
  auto [k, j] = search(k_polar);
  if (j == 0 || j == n - 1) {  // at an end of the arc: the neighbouring space may face the pin
    const auto [k2, j2] = search(k_polar + (j == 0 ? -1 : 1));
    if ((discrete_->Element(j2, k2).position - p).squaredNorm() < (discrete_->Element(j, k).position - p).squaredNorm()) {
      k = k2, j = j2;
    }
  }
  const geometry::ProfileElement best = discrete_->Element(j, k);
  double best_gap;
  Eigen::Vector2d best_normal, best_point;
  if (best.curvature == 0.0) {
    best_normal = best.normal;
    best_gap = best.normal.dot(p - best.position) - r_pin;
    best_point = p - (best_gap + r_pin) * best.normal;
  } else {
    const double rho = 1.0 / best.curvature;
    const Eigen::Vector2d c = best.position - rho * best.normal;
    const double d = (p - c).norm();
    const double sigma = rho > 0.0 ? 1.0 : -1.0;
    best_gap = sigma * (d - std::abs(rho)) - r_pin;
    best_normal = sigma * (p - c) / d;
    best_point = c + std::abs(rho) * (p - c) / d;
  }
  PinContact c;
  c.pin = pin;
  c.angle = angle;
  c.u = best.u;
  c.tooth_space = 0;
  c.pin_radius = r_pin;
  c.cycloid_curvature = best.curvature;
  c.clearance = best_gap;
  PlaceContact(frame, centre_fixed, load_direction_, best_point, best_normal, &c);
  FinishPoint(slice, z, &c);
  return c;
}

void MeshModel::FinishPoint(int slice, double z, PinContact* c) const {
  c->slice = slice;
  c->length = pair().face_width / slices_;
  c->z = z;
  if (!lead_layer_) return;
  // The lead modifications give the slice's flank a layer t along its normal (an equidistant):
  // the foot point stays, the gap falls by t, the point moves by t toward the pin, the radius of
  // curvature grows by t (kappa / (1 + kappa t), signed), and the arm (the normal's lever about
  // the centre) is unchanged. Exact for a layer constant along the profile.
  const double t = real_.LeadLayer(c->z);
  c->clearance -= t;
  c->cycloid_point += t * c->normal;
  if (!c->edge) c->cycloid_curvature /= 1.0 + c->cycloid_curvature * t;
}

Eigen::Vector2d MeshModel::PinCentre(int pin) const { return real_.PinCentre(pin); }

geometry::Pose MeshModel::CyclePose(double crank, double loaded_rotation, double z) const {
  geometry::Pose pose = real_.CycloidPose(crank).RotatedAboutCentre(load_direction_ * loaded_rotation);
  if (real_.assembly().VariesAlongWidth()) pose.centre += real_.SliceShift(z);
  return pose;
}

PinContact MeshModel::EvaluatePoint(int pin, int slice, double crank, double loaded_rotation) const {
  return EvaluateSection(pin, slice, SliceZ(slice), crank, loaded_rotation);
}

PinContact MeshModel::EvaluateSection(int pin, double z, double crank, double loaded_rotation) const {
  const int slice = std::clamp(static_cast<int>(std::floor(z / pair().face_width * slices_)), 0, slices_ - 1);
  return EvaluateSection(pin, slice, z, crank, loaded_rotation);
}

PinContact MeshModel::EvaluateSection(int pin, int slice, double z, double crank, double loaded_rotation) const {
  const double angle = real_.kinematics().AngleFromLineOfCentres(pin, crank);
  if (discrete_) return EvaluatePointElements(pin, slice, z, angle, CyclePose(crank, loaded_rotation, z).Frame());
  // Seed from the meshing equation (exact for the nominal pair at psi = 0; the loaded rotation,
  // the modifications and the errors move the foot point by little).
  const geometry::MeshSeed seed = real_.kinematics().Seed(pin, crank);
  return EvaluatePointAt(pin, slice, z, angle, CyclePose(crank, loaded_rotation, z).Frame(), seed.tooth_space, seed.u);
}

PinContact MeshModel::EvaluatePoint(const PinContact& near, double crank, double loaded_rotation) const {
  return EvaluatePoint(near, crank, loaded_rotation, Eigen::Vector2d::Zero());
}

PinContact MeshModel::EvaluatePoint(const PinContact& near, double crank, double loaded_rotation,
                                    const Eigen::Vector2d& centre_shift) const {
  geometry::Pose pose = CyclePose(crank, loaded_rotation, near.z);
  pose.centre += centre_shift;
  return EvaluatePointInFrame(near, pose.Frame(), real_.kinematics().AngleFromLineOfCentres(near.pin, crank));
}

PinContact MeshModel::EvaluatePointInFrame(const PinContact& near, const geometry::PoseFrame& frame, double angle) const {
  if (discrete_) return EvaluatePointElements(near.pin, near.slice, near.z, angle, frame);
  return EvaluatePointAt(near.pin, near.slice, near.z, angle, frame, near.tooth_space, near.u);
}

PinContact MeshModel::EvaluatePointFrom(int pin, int slice, double crank, double loaded_rotation, int seed_space,
                                        double seed_u) const {
  const double z = SliceZ(slice);
  return EvaluatePointAt(pin, slice, z, real_.kinematics().AngleFromLineOfCentres(pin, crank),
                         CyclePose(crank, loaded_rotation, z).Frame(), seed_space, seed_u);
}

PinContact MeshModel::EvaluatePointAt(int pin, int slice, double z, double angle, const geometry::PoseFrame& frame,
                                      int seed_space, double seed_u) const {
  const Eigen::Vector2d centre_fixed = PinCentre(pin);
  const Eigen::Vector2d p = frame.ToBody(centre_fixed);
  const double r_pin = real_.PinRadius(pin);
  const double phi_max = real_.profile().phi_max();
  const int zc = pair().tooth_count;
  const int d = real_.profile().tooth_difference();

  if (real_.profile().tip_cap().active()) {
    const RelievedFoot f = NearestOnRelievedProfile(real_.profile(), p, seed_space, seed_u);
    PinContact c = FootContact(pin, angle, f.k, f.u, r_pin,
                               f.curvature, f.gap);
    c.part = f.part;
    c.cap_w = f.w;
    c.edge = f.part == geometry::SurfacePart::kTipCorner;
    PlaceContact(frame, centre_fixed, load_direction_, f.point, f.normal, &c);
    FinishPoint(slice, z, &c);
    return c;
  }
  int k = seed_space;
  double u = seed_u;
  bool edge = false;
  geometry::ProfilePoint x;  // the profile at (u, k)
  if (std::abs(d) == 1) {
    // The profile is smooth across the tips: search the generating curve of one pitch around
    // the seed, then fold the result back into [-phi_max, phi_max] of its own tooth space.
    const double pitch = real_.profile().tooth_pitch();
    u = ClosestParameter(real_.profile(), k, p, u, u - pitch, u + pitch, &x);
    const double lobe = 2.0 * kPi * d / zc;
    const double m = std::round(u / lobe);
    if (m != 0.0) {  // the point in its own tooth space's parameters
      u -= m * lobe;
      k = static_cast<int>(((k + static_cast<long>(m) * d) % zc + zc) % zc);
      x = real_.profile().Evaluate(u, k);
    }
  } else {
    // |d| >= 2: arcs meet in sharp tip corners, and a pin far from mesh can face a space several
    // lobes' worth from its meshing-equation seed. Search the arc of the tooth space the pin's
    // polar angle falls in and both neighbours; the closest point may be a tip corner.
    const double pitch = real_.profile().tooth_pitch();
    const double polar = std::atan2(p.y(), p.x()) - real_.profile().ToothSpaceRotation(0);
    const int k_polar = static_cast<int>(std::lround(polar / pitch));
    double best = std::numeric_limits<double>::infinity();
    for (int dk = -1; dk <= 1; ++dk) {
      const int kk = (((k_polar + dk) % zc) + zc) % zc;
      const double rel = std::remainder(polar - (k_polar + dk) * pitch, 2.0 * kPi);
      const double start = kk == seed_space && std::abs(seed_u) <= phi_max
                               ? seed_u
                               : std::clamp(rel * phi_max / (0.5 * pitch), -phi_max, phi_max);
      geometry::ProfilePoint xx;
      const double uu = ClosestParameter(real_.profile(), kk, p, start, -phi_max, phi_max, &xx);
      const double dist = (xx.position - p).norm();
      if (dist < best) best = dist, k = kk, u = uu, x = xx;
    }
    edge = std::abs(u) >= phi_max;
  }

  PinContact c;
  c.pin = pin;
  c.angle = angle;
  c.tooth_space = k;
  c.u = u;
  c.edge = edge;
  if (edge) c.part = geometry::SurfacePart::kTipCorner;
  c.pin_radius = r_pin;
  Eigen::Vector2d normal_body = x.normal;
  double centre_gap = x.normal.dot(p - x.position);  // signed distance of the pin centre
  if (edge) {  // distance to the corner; the normal is the line from the corner to the pin centre
    normal_body = (p - x.position).normalized();
    centre_gap = (p - x.position).norm();
    c.cycloid_curvature = std::numeric_limits<double>::infinity();
  } else {
    c.cycloid_curvature = x.curvature;
  }
  c.clearance = centre_gap - r_pin;
  Eigen::Vector2d point_body = x.position;
  if (!real_.profile_deviation().IsZero()) {
    // The flank as made, x + delta n: its nearest point near the smooth foot point. The curvature
    // is that of the equidistant at delta, as Liu eq. 8 gives his shifted elements (rho + delta).
    const DeviatedFoot f = NearestOnDeviatedFlank(real_.profile(), real_.profile_deviation(), p, k, u);
    c.tooth_space = f.k;
    c.u = f.u;
    c.edge = f.corner;
    c.part = f.corner ? geometry::SurfacePart::kTipCorner : geometry::SurfacePart::kFlank;
    c.cycloid_curvature = f.corner ? std::numeric_limits<double>::infinity() : f.curvature;
    c.clearance = f.distance - r_pin;
    point_body = f.point;
    normal_body = f.normal;
  }
  PlaceContact(frame, centre_fixed, load_direction_, point_body, normal_body, &c);
  FinishPoint(slice, z, &c);
  return c;
}

void RequireSamePinRing(const MeshModel& first, const MeshModel& second) {
  const geometry::PairParameters& a = first.pair();
  const geometry::PairParameters& b = second.pair();
  if (a.pin_count != b.pin_count || a.tooth_count != b.tooth_count || a.pin_radius != b.pin_radius ||
      a.pin_circle_radius != b.pin_circle_radius || a.eccentricity != b.eccentricity) {
    throw std::invalid_argument(fmt::format(
        "two discs: the second disc's pair (z_p {}, z_c {}, r_rp {} mm, R_p {} mm, e {} mm) differs from the first's "
        "(z_p {}, z_c {}, r_rp {} mm, R_p {} mm, e {} mm); expected one pin ring and one crank for both",
        b.pin_count, b.tooth_count, b.pin_radius, b.pin_circle_radius, b.eccentricity, a.pin_count, a.tooth_count,
        a.pin_radius, a.pin_circle_radius, a.eccentricity));
  }
}

MeshState EvaluateTwoDiscs(const MeshModel& first, const MeshModel& second, double crank, double loaded_rotation) {
  RequireSamePinRing(first, second);
  return CombineTwoDiscs(first.Evaluate(crank, loaded_rotation),
                         second.Evaluate(crank + kSecondDiscCrankOffset, loaded_rotation));
}

MeshState CombineTwoDiscs(MeshState first, MeshState behind) {
  first.pins.reserve(first.pins.size() + behind.pins.size());
  for (PinContact& c : behind.pins) {
    c.disc = 1;
    first.pins.push_back(std::move(c));
  }
  return first;
}

bool SameMesh(const MeshState& a, const MeshState& b) {
  if (a.pins.size() != b.pins.size()) return false;
  constexpr double kTolerance = 1e-9;
  const auto key = [](const PinContact& c) { return std::tuple{c.disc, c.slice, c.angle}; };
  const auto sorted = [&](const MeshState& s) {
    std::vector<const PinContact*> out;
    out.reserve(s.pins.size());
    for (const PinContact& c : s.pins) out.push_back(&c);
    std::sort(out.begin(), out.end(), [&](const PinContact* x, const PinContact* y) { return key(*x) < key(*y); });
    return out;
  };
  const auto near = [](double x, double y, double scale) {
    return x == y || std::abs(x - y) <= kTolerance * std::max(1.0, scale);
  };
  const std::vector<const PinContact*> pa = sorted(a), pb = sorted(b);
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const PinContact &x = *pa[i], &y = *pb[i];
    if (x.disc != y.disc || x.slice != y.slice || x.edge != y.edge || x.part != y.part) return false;
    if (!near(std::remainder(x.angle - y.angle, 2.0 * kPi), 0.0, 1.0) || !near(x.clearance, y.clearance, 1.0) ||
        !near(x.arm, y.arm, 1.0) || !near(x.pin_radius, y.pin_radius, 1.0) || !near(x.length, y.length, 1.0) ||
        !near(x.cycloid_curvature, y.cycloid_curvature, std::abs(x.cycloid_curvature))) {
      return false;
    }
  }
  return true;
}

MeshState MeshModel::Evaluate(double crank, double loaded_rotation) const {
  MeshState state;
  state.crank = crank;
  state.loaded_rotation = loaded_rotation;
  state.pins.reserve(static_cast<std::size_t>(point_count()));
  if (discrete_) {
    for (int j = 0; j < pin_count(); ++j) {
      for (int k = 0; k < slices_; ++k) state.pins.push_back(EvaluatePoint(j, k, crank, loaded_rotation));
    }
    return state;
  }
  // One pose per slice, computed once for every pin, and each slice of a pin searched
  // from its neighbour's foot point (the slices differ by micrometres), not from the meshing
  // equation again.
  std::vector<geometry::PoseFrame> poses;
  poses.reserve(static_cast<std::size_t>(slices_));
  for (int k = 0; k < slices_; ++k) poses.push_back(CyclePose(crank, loaded_rotation, SliceZ(k)).Frame());
  for (int j = 0; j < pin_count(); ++j) {
    const geometry::MeshSeed seed = real_.kinematics().Seed(j, crank);
    const double angle = real_.kinematics().AngleFromLineOfCentres(j, crank);
    state.pins.push_back(EvaluatePointAt(j, 0, SliceZ(0), angle, poses[0], seed.tooth_space, seed.u));
    for (int k = 1; k < slices_; ++k) {
      const PinContact& near = state.pins.back();
      state.pins.push_back(
          EvaluatePointAt(j, k, SliceZ(k), angle, poses[static_cast<std::size_t>(k)], near.tooth_space, near.u));
    }
  }
  return state;
}

}  // namespace ltca::contact
