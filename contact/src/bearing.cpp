#include "ltca/contact/bearing.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::contact {
namespace {

/// Palmgren's coefficient of one steel line contact, mm N^-0.9 mm^0.8 (Harris & Kotzalas).
constexpr double kPalmgren = 3.84e-5;

/// A roller between both raceways: Q = K_n delta^(10/9), K_n = (2 kPalmgren)^(-10/9) l^(8/9).
double RollerConstant(double length) { return std::pow(2.0 * kPalmgren, -10.0 / 9.0) * std::pow(length, 8.0 / 9.0); }

}  // namespace

BearingKind ParseBearingKind(const std::string& text) {
  if (text == "rigid") return BearingKind::kRigid;
  if (text == "linear") return BearingKind::kLinear;
  if (text == "rollers") return BearingKind::kRollers;
  throw std::invalid_argument(fmt::format("[bearing] kind = \"{}\": expected rigid, linear or rollers", text));
}

const char* ToString(BearingKind kind) {
  switch (kind) {
    case BearingKind::kRigid: return "rigid";
    case BearingKind::kLinear: return "linear";
    case BearingKind::kRollers: return "rollers";
  }
  return "unknown";
}

void BearingSettings::Validate() const {
  const auto require = [](bool ok, const char* key, double value, const char* expected) {
    if (!ok) throw std::invalid_argument(fmt::format("[bearing] {} = {:g}: expected {}", key, value, expected));
  };
  require(std::isfinite(radial_clearance) && radial_clearance >= 0.0, "radial_clearance_mm", radial_clearance,
          "a finite radial clearance >= 0 mm");
  require(std::isfinite(dynamic_load_rating) && dynamic_load_rating >= 0.0, "dynamic_load_rating_n", dynamic_load_rating,
          "a finite rating >= 0 N (0: no life)");
  if (kind == BearingKind::kLinear) {
    require(std::isfinite(radial_stiffness) && radial_stiffness > 0.0, "radial_stiffness_n_per_mm", radial_stiffness,
            "a finite radial stiffness > 0 N/mm for kind = \"linear\"");
  }
  if (kind == BearingKind::kRollers) {
    require(roller_count >= 3 && roller_count <= kMaxRollers, "roller_count", roller_count,
            fmt::format("3 to {} rollers for kind = \"rollers\"", kMaxRollers).c_str());
    require(std::isfinite(roller_diameter) && roller_diameter > 0.0, "roller_diameter_mm", roller_diameter,
            "a finite roller diameter > 0 mm for kind = \"rollers\"");
    require(std::isfinite(roller_length) && roller_length > 0.0, "roller_length_mm", roller_length,
            "a finite effective roller length > 0 mm for kind = \"rollers\"");
  }
}

double PalmgrenApproach(double load, double length) {
  return load > 0.0 ? kPalmgren * std::pow(load, 0.9) / std::pow(length, 0.8) : 0.0;
}

double PalmgrenLoad(double approach, double length) {
  return approach > 0.0 ? std::pow(approach * std::pow(length, 0.8) / kPalmgren, 1.0 / 0.9) : 0.0;
}

double RollerLoad(double approach, double length) {
  return approach > 0.0 ? RollerConstant(length) * std::pow(approach, 10.0 / 9.0) : 0.0;
}

BearingResponse BearingAt(const BearingSettings& bearing, const Eigen::Vector2d& u, double phase) {
  return BearingAt(bearing, u, phase, true);
}

BearingResponse BearingAt(const BearingSettings& bearing, const Eigen::Vector2d& u, double phase, bool roller_loads) {
  BearingResponse r;
  const double c = bearing.radial_clearance;
  switch (bearing.kind) {
    case BearingKind::kRigid:
      throw std::invalid_argument("[bearing] kind = \"rigid\": a rigid bearing is a constraint, it has no force law");
    case BearingKind::kLinear: {
      const double radius = u.norm();
      if (radius <= c) return r;
      const Eigen::Vector2d n = u / radius;
      const double k = bearing.radial_stiffness, play = radius - c;
      r.force = -k * play * n;
      const Eigen::Matrix2d nn = n * n.transpose();
      r.stiffness = k * (nn + (play / radius) * (Eigen::Matrix2d::Identity() - nn));
      r.energy = 0.5 * k * play * play;
      return r;
    }
    case BearingKind::kRollers: {
      const int z = bearing.roller_count;
      const double kn = RollerConstant(bearing.roller_length);
      if (roller_loads) r.roller_load.assign(static_cast<std::size_t>(z), 0.0);
      // Roller j on phase + 2 pi j / z: its direction is the first one turned j times by the
      // pitch (a rotation per roller instead of a sine and a cosine; the same directions to a few
      // eps).
      const Eigen::Vector2d first(std::cos(phase), std::sin(phase));
      const double pitch = 2.0 * units::kPi / z;
      const double cp = std::cos(pitch), sp = std::sin(pitch);
      Eigen::Vector2d e = first;
      for (int j = 0; j < z; ++j, e = Eigen::Vector2d(cp * e.x() - sp * e.y(), sp * e.x() + cp * e.y())) {
        const double delta = u.dot(e) - c;
        if (delta <= 0.0) continue;
        const double ninth = std::cbrt(std::cbrt(delta));  // delta^(1/9)
        const double q = kn * delta * ninth;               // K_n delta^(10/9)
        if (roller_loads) r.roller_load[static_cast<std::size_t>(j)] = q;
        r.force -= q * e;
        r.stiffness += (10.0 / 9.0) * kn * ninth * e * e.transpose();
        r.energy += (9.0 / 19.0) * q * delta;  // integral of K_n x^(10/9) from 0 to delta
      }
      return r;
    }
  }
  return r;
}

Eigen::Vector2d BearingDisplacement(const BearingSettings& bearing, const Eigen::Vector2d& load, double phase) {
  if (bearing.kind == BearingKind::kRigid) {
    throw std::invalid_argument("[bearing] kind = \"rigid\": a rigid bearing does not move under load");
  }
  const double magnitude = load.norm();
  if (magnitude == 0.0) return Eigen::Vector2d::Zero();
  const Eigen::Vector2d direction = load / magnitude;
  // Start where the most loaded element would carry the whole load (the linear spring exactly,
  // a roller along the load with Stribeck's factor 5 F / Z), beyond the clearance.
  double reach = 0.0;
  if (bearing.kind == BearingKind::kLinear) {
    reach = magnitude / bearing.radial_stiffness;
  } else {
    reach = std::pow(5.0 * magnitude / bearing.roller_count / RollerConstant(bearing.roller_length), 0.9);
  }
  Eigen::Vector2d u = (bearing.radial_clearance + reach) * direction;
  const double tolerance = 1e-12 * magnitude + 1e-9;
  // The residual of the balance: -F(u) - load, the gradient of the convex energy E(u) - load . u.
  const auto residual = [&](const Eigen::Vector2d& v) -> Eigen::Vector2d { return -BearingAt(bearing, v, phase).force - load; };
  for (int step = 0; step < 200; ++step) {
    const BearingResponse r = BearingAt(bearing, u, phase);
    const Eigen::Vector2d gradient = -r.force - load;
    const double norm = gradient.norm();
    if (norm <= tolerance) return u;
    Eigen::Vector2d du;
    if (r.stiffness.trace() <= 0.0) {
      du = std::max(bearing.radial_clearance, reach) * direction;  // nothing carries yet: move along the load
    } else {
      // One roller alone is stiff along its line only: a small multiple of the identity keeps the
      // step defined.
      const Eigen::Matrix2d h = r.stiffness + 1e-12 * r.stiffness.trace() * Eigen::Matrix2d::Identity();
      du = -h.ldlt().solve(gradient);
    }
    // Backtracking on the residual's norm (the Newton direction decreases it; the energy itself
    // cannot be compared to round-off near the solution).
    double t = 1.0;
    while (t > 1e-14 && residual(u + t * du).norm() > (1.0 - 1e-4 * t) * norm) t *= 0.5;
    u += t * du;
  }
  throw std::runtime_error(fmt::format("bearing displacement under {:g} N: Newton did not converge in 200 steps", magnitude));
}

double MeanEquivalentLoad(const std::vector<double>& loads, double exponent) {
  if (loads.empty()) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (const double p : loads) {
    if (!std::isfinite(p)) return std::numeric_limits<double>::quiet_NaN();
    sum += std::pow(std::abs(p), exponent);
  }
  return std::pow(sum / static_cast<double>(loads.size()), 1.0 / exponent);
}

double RatingLife(double dynamic_load_rating, double equivalent_load, double exponent) {
  if (!(dynamic_load_rating > 0.0) || !std::isfinite(equivalent_load)) return std::numeric_limits<double>::quiet_NaN();
  if (equivalent_load <= 0.0) return std::numeric_limits<double>::infinity();
  return std::pow(dynamic_load_rating / equivalent_load, exponent);
}

double RatingLifeHours(double life_million_revolutions, double rpm) {
  if (!(rpm > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return 1e6 * life_million_revolutions / (60.0 * rpm);
}

}  // namespace ltca::contact
