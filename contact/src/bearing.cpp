#include "ltca/contact/bearing.hpp"

#include <algorithm>
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
  // Negative: a preloaded bearing (its elements pressed by -c at no load; docs/stage.md "Preload").
  require(std::isfinite(radial_clearance), "radial_clearance_mm", radial_clearance,
          "a finite radial clearance in mm (negative: a preload)");
  require(std::isfinite(dynamic_load_rating) && dynamic_load_rating >= 0.0, "dynamic_load_rating_n", dynamic_load_rating,
          "a finite rating >= 0 N (0: no life)");
  require(std::isfinite(static_load_rating) && static_load_rating >= 0.0, "static_load_rating_n", static_load_rating,
          "a finite rating >= 0 N (0: no static safety)");
  require(std::isfinite(contamination_factor) && contamination_factor >= 0.0 && contamination_factor <= 1.0,
          "contamination_factor", contamination_factor, "a contamination factor e_C in [0, 1] (ISO 281:2007 Table 13)");
  require(std::isfinite(fatigue_load_limit) && fatigue_load_limit >= 0.0, "fatigue_load_limit_n", fatigue_load_limit,
          "a finite fatigue load limit C_u >= 0 N (0: ISO 281 Annex B's estimate C_0r / 8.2)");
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
    // The rollers fit on their pitch circle: neighbours' centres a chord d_m sin(pi / Z) >= D_w
    // apart (so g = D_w / d_m < 1).
    const double fits = roller_diameter / std::sin(units::kPi / roller_count);
    require(std::isfinite(pitch_diameter) && (pitch_diameter == 0.0 || pitch_diameter >= fits), "pitch_diameter_mm",
            pitch_diameter,
            fmt::format("0 (not given) or a pitch diameter on which the rollers fit, >= D_w / sin(pi / Z) = {:.6g} mm", fits).c_str());
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

BearingResponse PreloadedLinearBearing(double k, double p, const Eigen::Vector2d& u) {
  // A ring of many equal linear elements, each of stiffness k_e along its direction e(theta) and
  // pressed by p at u = 0 (Z elements, Z -> infinity, k = k_e Z / 4 the ring's radial stiffness
  // without play: sum_j k_e (u . e_j)_+ e_j -> k_e Z / (2 pi) int_{-pi/2}^{pi/2} cos^2 = k_e Z / 4).
  // Element j presses with k_e (u . e_j + p)_+; with r = |u|, a = p / r and theta_0 = acos(-a)
  // (the elements within theta_0 of u carry load, all of them while r <= p):
  //   |F| = (2 k / pi) int_0^theta_0 (r cos + p) cos = (2 k / pi) [r theta_0 + p sqrt(1 - a^2)],
  //         = 2 k r while r <= p (theta_0 = pi: the preload doubles the stiffness),
  //   d|F|/dr = (2 k / pi) (theta_0 - a sqrt(1 - a^2)) (radial), |F| / r (tangential),
  //   E = (k / pi) [r^2 (theta_0 - a s) + 4 r p s + 2 p^2 theta_0] - 2 k p^2, s = sqrt(1 - a^2)
  //     (1/2 sum k_e (u . e + p)_+^2 less its value at u = 0), = k r^2 while r <= p.
  // Continuous in r at r = p and, as p -> 0, the law without play, k r (the linear kind at c = 0).
  BearingResponse out;
  const double r = u.norm();
  if (!(r > 0.0)) {
    out.stiffness = 2.0 * k * Eigen::Matrix2d::Identity();
    return out;
  }
  const Eigen::Vector2d n = u / r;
  const Eigen::Matrix2d nn = n * n.transpose();
  if (r <= p) {
    out.force = -2.0 * k * u;
    out.stiffness = 2.0 * k * Eigen::Matrix2d::Identity();
    out.energy = k * r * r;
    return out;
  }
  const double a = p / r, s = std::sqrt(std::max(0.0, 1.0 - a * a)), theta0 = std::acos(-a);
  const double magnitude = (2.0 * k / units::kPi) * (r * theta0 + p * s);
  const double radial = (2.0 * k / units::kPi) * (theta0 - a * s);
  out.force = -magnitude * n;
  out.stiffness = radial * nn + (magnitude / r) * (Eigen::Matrix2d::Identity() - nn);
  out.energy = (k / units::kPi) * (r * r * (theta0 - a * s) + 4.0 * r * p * s + 2.0 * p * p * theta0) - 2.0 * k * p * p;
  return out;
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
      if (c < 0.0) return PreloadedLinearBearing(bearing.radial_stiffness, -c, u);
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

double ReferenceViscosity(double rpm, double pitch_diameter_mm) {
  if (!(std::isfinite(rpm) && rpm > 0.0 && std::isfinite(pitch_diameter_mm) && pitch_diameter_mm > 0.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  // ISO 281:2007 9.3.3: the two forms by speed (they meet within 2.3 % at 1000 r/min).
  return rpm < 1000.0 ? 45000.0 * std::pow(rpm, -0.83) / std::sqrt(pitch_diameter_mm)
                      : 4500.0 / std::sqrt(rpm * pitch_diameter_mm);
}

double LifeModificationFactor(double kappa, double load_ratio) {
  if (std::isnan(kappa) || std::isnan(load_ratio) || load_ratio < 0.0) return std::numeric_limits<double>::quiet_NaN();
  const double k = std::clamp(kappa, kViscosityRatioMin, kViscosityRatioMax);
  // ISO 281:2007 9.3.3, radial roller bearings: the three ranges of kappa.
  const double c = k < 0.4 ? 1.3993 : 1.2348;
  const double e = k < 0.4 ? 0.054381 : (k < 1.0 ? 0.19087 : 0.071739);
  const double bracket = 1.0 - (1.5859 - c / std::pow(k, e)) * std::pow(load_ratio, 0.4);
  if (!(bracket > 0.0)) return kLifeModificationMax;
  return std::min(0.1 * std::pow(bracket, -9.185), kLifeModificationMax);
}

double FatigueLoadLimitEstimate(double static_load_rating, double pitch_diameter_mm) {
  if (!(static_load_rating > 0.0) || !std::isfinite(static_load_rating) || !(pitch_diameter_mm > 0.0) ||
      pitch_diameter_mm > kFatigueLoadLimitEstimateMaxPitchDiameter) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return static_load_rating / 8.2;  // ISO 281:2007 Annex B (B.20), roller bearings
}

const char* ToString(Raceway raceway) { return raceway == Raceway::kInner ? "inner" : "outer"; }

double RacewayCapacityRatio(double roller_diameter, double pitch_diameter) {
  const double g = roller_diameter / pitch_diameter;
  return std::pow((1.0 - g) / (1.0 + g), 29.0 / 27.0 + 0.25);  // Harris & Kotzalas, Q_c of line contact
}

RollerLoadMoments LoadMoments(const std::vector<double>& roller_load) {
  RollerLoadMoments m;
  if (roller_load.empty()) return m;
  for (const double q : roller_load) {
    const double q2 = q * q;
    m.fourth += q2 * q2;
    m.four_and_half += q2 * q2 * std::sqrt(std::max(q, 0.0));
  }
  const double z = static_cast<double>(roller_load.size());
  m.fourth /= z;
  m.four_and_half /= z;
  return m;
}

double LundbergPalmgrenDamage(const RollerLoadMoments& m, double capacity_ratio, Raceway turning) {
  // Q_e of each raceway: exponent 4 for the one turning against the load, 4.5 for the other.
  const double turning_load = std::pow(m.fourth, 0.25), standing_load = std::pow(m.four_and_half, 1.0 / 4.5);
  const double inner = turning == Raceway::kInner ? turning_load : standing_load;
  const double outer = turning == Raceway::kInner ? standing_load : turning_load;
  // L_in = (Q_c,in / Q_e,in)^4, L_out = (Q_c,out / Q_e,out)^4 with Q_c,out = 1 N; the bearing's
  // 1/L = (L_in^(-9/8) + L_out^(-9/8))^(8/9), L^(-9/8) = (Q_e / Q_c)^4.5.
  return std::pow(std::pow(inner / capacity_ratio, 4.5) + std::pow(outer, 4.5), 8.0 / 9.0);
}

namespace {

void RequireLoadZoneGeometry(const BearingSettings& bearing, const char* what) {
  if (bearing.kind != BearingKind::kRollers) {
    throw std::invalid_argument(fmt::format("[bearing] kind = \"{}\": {} needs kind = \"rollers\"", ToString(bearing.kind), what));
  }
  if (!(bearing.pitch_diameter > bearing.roller_diameter)) {
    throw std::invalid_argument(fmt::format("[bearing] pitch_diameter_mm = {:g}: {} needs the roller set's pitch diameter, > the "
                                            "roller diameter {:g} mm",
                                            bearing.pitch_diameter, what, bearing.roller_diameter));
  }
}

}  // namespace

double LoadZoneReferenceDamage(const BearingSettings& bearing) {
  RequireLoadZoneGeometry(bearing, "the load-zone life");
  BearingSettings tight = bearing;
  tight.radial_clearance = 0.0;
  const double ratio = RacewayCapacityRatio(bearing.roller_diameter, bearing.pitch_diameter);
  // Without play every roller load is proportional to the applied load: solve at a load of the
  // order of the rating's and scale the damage (fourth power) to 1 N.
  const double load = bearing.dynamic_load_rating > 0.0 ? bearing.dynamic_load_rating : 1000.0;
  const double pitch = 2.0 * units::kPi / bearing.roller_count;
  double sum = 0.0;
  for (int m = 0; m < kReferencePhases; ++m) {
    const double phase = pitch * m / kReferencePhases;
    const Eigen::Vector2d u = BearingDisplacement(tight, Eigen::Vector2d(load, 0.0), phase);
    const BearingResponse r = BearingAt(tight, u, phase);
    sum += LundbergPalmgrenDamage(LoadMoments(r.roller_load), ratio, Raceway::kInner);
  }
  return sum / kReferencePhases / std::pow(load, 4.0);
}

double LoadZoneEquivalentLoad(double mean_damage, double reference_damage) {
  if (!std::isfinite(mean_damage) || !std::isfinite(reference_damage) || !(reference_damage > 0.0) || mean_damage < 0.0) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return std::pow(mean_damage / reference_damage, 0.25);
}

double RollerContactStress(const BearingSettings& bearing, double roller_load) {
  RequireLoadZoneGeometry(bearing, "the roller contact stress");
  if (!(roller_load > 0.0)) return 0.0;
  const double d = bearing.roller_diameter;
  const double curvature = 2.0 / d + 2.0 / (bearing.pitch_diameter - d);  // 1/R, roller and inner raceway
  const double modulus = kBearingSteelModulus / (2.0 * (1.0 - kBearingSteelPoisson * kBearingSteelPoisson));  // E*
  return std::sqrt(roller_load * modulus * curvature / (units::kPi * bearing.roller_length));
}

}  // namespace ltca::contact
