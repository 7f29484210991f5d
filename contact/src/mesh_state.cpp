#include "ltca/contact/mesh_state.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

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
double ClosestParameter(const CycloidProfile& profile, int k, const Eigen::Vector2d& p, double u0,
                        double lo, double hi) {
  const auto g = [&](double u, double* dg) {
    const auto x = profile.Evaluate(u, k);
    const Eigen::Vector2d r = x.position - p;
    if (dg != nullptr) *dg = x.d1.squaredNorm() + r.dot(x.d2);
    return r.dot(x.d1);
  };
  u0 = std::clamp(u0, lo, hi);
  // Fast path: plain Newton from the seed (the meshing equation puts it next to the foot point),
  // accepted only while it behaves: positive curvature of the distance, small steps inside the arc.
  // Converged when the step is below 1e-15 of the arc: the rounding noise of g is ~1e-17 rad, and
  // the arm and the gap cannot feel less than ~1e-12 rad.
  const double tol = 1e-15 * (hi - lo) + 4.0 * std::numeric_limits<double>::epsilon() * std::abs(u0);
  {
    double u = u0;
    const double max_step = 0.05 * (hi - lo);
    for (int it = 0; it < 8; ++it) {
      double dg = 0.0;
      const double gu = g(u, &dg);
      if (!(dg > 0.0)) break;
      const double step = -gu / dg;
      if (std::abs(step) > max_step || u + step < lo || u + step > hi) break;
      u += step;
      if (std::abs(step) <= tol) return u;
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
  if (ga > 0.0) return a;  // distance increasing from the lower end: the end is closest
  if (gb < 0.0) return b;  // distance decreasing up to the upper end
  double u = (ga == 0.0) ? a : (gb == 0.0 ? b : 0.5 * (a + b));
  if (u0 > a && u0 < b) u = u0;
  for (int it = 0; it < 100; ++it) {
    double dg = 0.0;
    const double gu = g(u, &dg);
    if (gu == 0.0) return u;
    if (gu < 0.0) a = u; else b = u;
    double next = (dg > 0.0) ? u - gu / dg : 0.5 * (a + b);
    if (!(next > a && next < b)) next = 0.5 * (a + b);
    if (std::abs(next - u) <= tol || b - a <= tol) return next;
    u = next;
  }
  return u;
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
        worst = std::max(worst, std::abs(EvaluatePointElements(j, 0, crank, 0.0).clearance - analytic));
      }
    }
    interference_tolerance_ = std::max(interference_tolerance_, 2.0 * worst);
  }
}

PinContact MeshModel::EvaluatePointElements(int pin, int slice, double crank, double loaded_rotation) const {
  // Liu 2021 section 3: the element facing the pin (nearest control point) and the gap of its
  // equivalent cylinder (eq. 19, signed for a concave element):
  //   gap = sigma (|p - C| - |rho|) - r,  C = x - rho n (centre of curvature), sigma = sign(rho).
  // Liu searches every width slice; here the search runs per slice of the model that runs, which
  // is one slice (the plane model) unless something varies along the width (MeshModel).
  const geometry::Pose pose = CyclePose(crank, loaded_rotation, SliceZ(slice));
  const Eigen::Vector2d centre_fixed = PinCentre(pin);
  const Eigen::Vector2d p = pose.ToBody(centre_fixed);
  const double r_pin = real_.PinRadius(pin);
  const int zc = pair().tooth_count;
  const double pitch = real_.profile().tooth_pitch();
  const int k_polar = static_cast<int>(std::lround((std::atan2(p.y(), p.x()) - real_.profile().ToothSpaceRotation(0)) / pitch));
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
  c.angle = real_.kinematics().AngleFromLineOfCentres(pin, crank);
  c.u = best.u;
  c.tooth_space = 0;
  c.pin_radius = r_pin;
  c.cycloid_curvature = best.curvature;
  c.clearance = best_gap;
  c.cycloid_point = pose.ToFixed(best_point);
  c.normal = pose.DirectionToFixed(best_normal);
  c.pin_point = centre_fixed - r_pin * c.normal;
  c.arm = load_direction_ * Cross(c.cycloid_point - pose.centre, c.normal);  // Liu eq. 27
  FinishPoint(slice, &c);
  return c;
}

void MeshModel::FinishPoint(int slice, PinContact* c) const {
  c->slice = slice;
  c->length = pair().face_width / slices_;
  c->z = SliceZ(slice);
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
  if (discrete_) return EvaluatePointElements(pin, slice, crank, loaded_rotation);
  // Seed from the meshing equation (exact for the nominal pair at psi = 0; the loaded rotation,
  // the modifications and the errors move the foot point by little).
  const geometry::MeshSeed seed = real_.kinematics().Seed(pin, crank);
  return EvaluatePointFrom(pin, slice, crank, loaded_rotation, seed.tooth_space, seed.u);
}

PinContact MeshModel::EvaluatePoint(const PinContact& near, double crank, double loaded_rotation) const {
  if (discrete_) return EvaluatePointElements(near.pin, near.slice, crank, loaded_rotation);
  return EvaluatePointFrom(near.pin, near.slice, crank, loaded_rotation, near.tooth_space, near.u);
}

PinContact MeshModel::EvaluatePointFrom(int pin, int slice, double crank, double loaded_rotation, int seed_space,
                                        double seed_u) const {
  return EvaluatePointAt(pin, slice, crank, CyclePose(crank, loaded_rotation, SliceZ(slice)), seed_space, seed_u);
}

PinContact MeshModel::EvaluatePointAt(int pin, int slice, double crank, const geometry::Pose& pose, int seed_space,
                                      double seed_u) const {
  const Eigen::Vector2d centre_fixed = PinCentre(pin);
  const Eigen::Vector2d p = pose.ToBody(centre_fixed);
  const double r_pin = real_.PinRadius(pin);
  const double phi_max = real_.profile().phi_max();
  const int zc = pair().tooth_count;
  const int d = real_.profile().tooth_difference();

  int k = seed_space;
  double u = seed_u;
  bool edge = false;
  if (std::abs(d) == 1) {
    // The profile is smooth across the tips: search the generating curve of one pitch around
    // the seed, then fold the result back into [-phi_max, phi_max] of its own tooth space.
    const double pitch = real_.profile().tooth_pitch();
    u = ClosestParameter(real_.profile(), k, p, u, u - pitch, u + pitch);
    const double lobe = 2.0 * kPi * d / zc;
    const double m = std::round(u / lobe);
    u -= m * lobe;
    k = static_cast<int>(((k + static_cast<long>(m) * d) % zc + zc) % zc);
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
      const double uu = ClosestParameter(real_.profile(), kk, p, start, -phi_max, phi_max);
      const double dist = (real_.profile().Position(uu, kk) - p).norm();
      if (dist < best) best = dist, k = kk, u = uu;
    }
    edge = std::abs(u) >= phi_max;
  }

  const geometry::ProfilePoint x = real_.profile().Evaluate(u, k);
  PinContact c;
  c.pin = pin;
  c.angle = real_.kinematics().AngleFromLineOfCentres(pin, crank);
  c.tooth_space = k;
  c.u = u;
  c.edge = edge;
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
  c.cycloid_point = pose.ToFixed(x.position);
  c.normal = pose.DirectionToFixed(normal_body);
  c.pin_point = centre_fixed - r_pin * c.normal;
  // Liu eq. 27: the lever arm of the normal about the cycloid centre, signed by the load direction.
  c.arm = load_direction_ * Cross(c.cycloid_point - pose.centre, c.normal);
  FinishPoint(slice, &c);
  return c;
}

MeshState MeshModel::Evaluate(double crank, double loaded_rotation) const {
  MeshState state;
  state.crank = crank;
  state.loaded_rotation = loaded_rotation;
  state.pins.reserve(static_cast<std::size_t>(point_count()));
  if (slices_ == 1 || discrete_) {
    for (int j = 0; j < pin_count(); ++j) {
      for (int k = 0; k < slices_; ++k) state.pins.push_back(EvaluatePoint(j, k, crank, loaded_rotation));
    }
    return state;
  }
  // The slice model: one pose per slice, and each slice of a pin searched from its neighbour's
  // foot point (the slices differ by micrometres), not from the meshing equation again.
  std::vector<geometry::Pose> poses;
  poses.reserve(static_cast<std::size_t>(slices_));
  for (int k = 0; k < slices_; ++k) poses.push_back(CyclePose(crank, loaded_rotation, SliceZ(k)));
  for (int j = 0; j < pin_count(); ++j) {
    const geometry::MeshSeed seed = real_.kinematics().Seed(j, crank);
    state.pins.push_back(EvaluatePointAt(j, 0, crank, poses[0], seed.tooth_space, seed.u));
    for (int k = 1; k < slices_; ++k) {
      const PinContact& near = state.pins.back();
      state.pins.push_back(EvaluatePointAt(j, k, crank, poses[static_cast<std::size_t>(k)], near.tooth_space, near.u));
    }
  }
  return state;
}

}  // namespace ltca::contact
