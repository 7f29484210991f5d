#include "ltca/contact/sliding.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::contact {
namespace {

using units::kPi;

using geometry::Perp;

/// Simpson's rule on [a, b] with n (even) intervals.
template <class F>
double Simpson(F f, double a, double b, int n) {
  const double h = (b - a) / n;
  double s = f(a) + f(b);
  for (int i = 1; i < n; ++i) s += (i % 2 == 1 ? 4.0 : 2.0) * f(a + h * i);
  return s * h / 3.0;
}

}  // namespace

PoseRate PoseRatePerCrank(const MeshModel& model, double crank, double loaded_rotation, double z, double step) {
  const geometry::Pose plus = model.CyclePose(crank + step, loaded_rotation, z);
  const geometry::Pose minus = model.CyclePose(crank - step, loaded_rotation, z);
  PoseRate r;
  r.centre_velocity = (plus.centre - minus.centre) / (2.0 * step);
  r.angular_velocity = (plus.rotation - minus.rotation) / (2.0 * step);
  return r;
}

ContactVelocities Velocities(const PinContact& c, const geometry::Pose& pose, const PoseRate& rate) {
  ContactVelocities v;
  const Eigen::Vector2d n = c.normal, t = Perp(c.normal);
  // Velocity of the cycloid's material point at the contact: v_O + omega x (P - O).
  const Eigen::Vector2d material = rate.centre_velocity + rate.angular_velocity * Perp(c.cycloid_point - pose.centre);
  v.sliding = t.dot(material);
  v.normal = n.dot(material);
  // The common normal turns at one rate Omega on both bodies. The pin point is C - r_p n, the
  // cycloid point C - (r_p + g) n (g the clearance along n): on the pin w_p = -r_p Omega, on the
  // cycloid Omega = omega_c + kappa_c w_c with w_c = -(r_p + g) Omega - v_s, so
  // Omega = (omega_c - kappa_c v_s) / (1 + kappa_c (r_p + g)) (docs/efficiency.md).
  const double r = c.pin_radius, g = c.clearance;
  const double omega = (rate.angular_velocity - c.cycloid_curvature * v.sliding) / (1.0 + c.cycloid_curvature * (r + g));
  v.point_over_pin = -r * omega;
  v.point_over_cycloid = -(r + g) * omega - v.sliding;
  v.entrainment = -0.5 * (v.point_over_pin + v.point_over_cycloid);
  v.point_velocity = v.point_over_pin * t;
  return v;
}

double PitchPointDistance(const geometry::PairParameters& pair, const geometry::Kinematics& kinematics, int pin,
                          double crank) {
  const double d = pair.eccentricity * pair.pin_count / pair.ToothDifference();  // signed
  const Eigen::Vector2d pitch = d * Eigen::Vector2d(std::cos(crank), std::sin(crank));
  // d > 0: the contact lies between the pin centre and the pitch point; d < 0 (the cycloid the
  // outer member): on the pin's far side.
  return (kinematics.PinCentre(pin) - pitch).norm() + (pair.ToothDifference() > 0 ? -1.0 : 1.0) * pair.pin_radius;
}

ContactShape LineShape(double force, double length, double equivalent_radius, double e_star) {
  ContactShape s;
  if (!(force > 0.0)) return s;
  s.half_width = std::sqrt(4.0 * force * equivalent_radius / (kPi * length * e_star));  // Liu eq. 23
  s.semi_major = 0.5 * length;
  s.max_pressure = 2.0 * force / (kPi * s.half_width * length);
  s.area = 2.0 * s.half_width * length;
  return s;
}

ContactShape EllipseShape(const RelativeCurvature& curvature, double force, double e_star) {
  ContactShape s;
  s.point = true;
  if (!(force > 0.0)) return s;
  const EllipticalContact e = HertzPointContact(curvature, force, e_star);
  s.half_width = e.semi_minor;
  s.semi_major = e.semi_major;
  s.max_pressure = e.max_pressure;
  s.area = kPi * e.semi_major * e.semi_minor;
  return s;
}

double Lubrication::CompositeRoughness() const {
  return std::sqrt(roughness_cycloid * roughness_cycloid + roughness_pin * roughness_pin);
}

double FilmThickness(const Lubrication& lub, double force, double length, double equivalent_radius, double e_star,
                     double entrainment, MixedFriction* detail) {
  // Pan and Hamrock (1989): H = h / R = 1.714 W^-0.128 U^0.694 G^0.568, with E' = 2 E*.
  const double e_prime = 2.0 * e_star;
  const double g = lub.pressure_viscosity * e_prime;
  const double u = lub.viscosity * std::abs(entrainment) / (e_prime * equivalent_radius);
  const double w = force / (e_prime * equivalent_radius * length);
  if (detail != nullptr) {
    detail->material_parameter = g;
    detail->speed_parameter = u;
    detail->load_parameter = w;
  }
  if (!(force > 0.0) || u == 0.0) return 0.0;
  return equivalent_radius * 1.714 * std::pow(w, -0.128) * std::pow(u, 0.694) * std::pow(g, 0.568);
}

double FilmShare(double lambda) {
  if (!(lambda > 0.0)) return 0.0;
  const auto fit = [](double l) { return 1.21 * std::pow(l, 0.64) / (1.0 + 0.37 * std::pow(l, 1.26)); };
  // The fit reaches 1 near lambda = 2.02 and falls beyond (outside its range): from there on the
  // film carries everything, f_lambda = 1 (monotone).
  static const double full = [&fit] {
    double lo = 1.0, hi = 2.5;  // fit(1) = 0.883 < 1 < fit(2.5) = 1.004, rising between
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (fit(mid) < 1.0 ? lo : hi) = mid;
    }
    return hi;
  }();
  return lambda >= full ? 1.0 : std::min(1.0, fit(lambda));
}

double EffectivePressure(const Lubrication& lub, double max_pressure, bool point) {
  if (!(max_pressure > 0.0)) return 0.0;
  const double delta = 1.0 / (lub.power_law_exponent * lub.pressure_viscosity);
  const double c = max_pressure / delta;
  // ln(mean of exp(c g)) = c + ln(mean of exp(c (g - 1))), g = p / p_h in [0, 1]: no overflow.
  double mean = 0.0;
  if (point) {  // ellipsoid: the area fraction with p / p_h >= s is 1 - s^2, density 2 s
    mean = Simpson([c](double s) { return 2.0 * s * std::exp(c * (s - 1.0)); }, 0.0, 1.0, 512);
  } else {  // semi-ellipse over the width, x = sin(t): mean = int_0^{pi/2} exp(c cos t) cos t dt
    mean = Simpson([c](double t) { return std::cos(t) * std::exp(c * (std::cos(t) - 1.0)); }, 0.0, kPi / 2.0, 512);
  }
  return delta * (c + std::log(mean));
}

double EffectivePressureClosedForm(const Lubrication& lub, double max_pressure) {
  const double delta = 1.0 / (lub.power_law_exponent * lub.pressure_viscosity), p = max_pressure;
  return delta * std::log(2.0 * delta / p * std::exp(p / delta) * (1.0 - delta / p) + 2.0 * delta * delta / (p * p));
}

double CappedFullFilm(const Lubrication& lub, double shear_factor, const ContactShape& shape, double force) {
  if (!(force > 0.0) || !(shear_factor > 0.0) || !(shape.max_pressure > 0.0)) return 0.0;
  const double ph = shape.max_pressure, gamma = lub.limiting_shear_coefficient, tau0 = lub.limiting_shear_stress;
  const double c = lub.power_law_exponent * lub.pressure_viscosity * ph;  // exponent at g = p / p_h = 1
  const double log_k = std::log(shear_factor);
  // The shear stress at g = p / p_h: the power law with the Barus viscosity, capped by tau_L.
  const auto tau = [&](double g) { return std::min(tau0 + gamma * ph * g, std::exp(log_k + c * g)); };
  // d(g) = K exp(c g) - tau_L(g) is convex in g: the power law lies below the cap on one interval
  // [g1, g2] at most, about d's minimum g_m (K c exp(c g_m) = gamma p_h).
  const auto d = [&](double g) { return log_k + c * g - std::log(tau0 + gamma * ph * g); };  // sign of d
  double g_m = 1.0;
  if (c > 0.0) g_m = gamma > 0.0 ? std::clamp((std::log(gamma * ph / c) - log_k) / c, 0.0, 1.0) : 0.0;
  double g1 = 0.0, g2 = 0.0;  // empty: capped everywhere
  if (d(g_m) < 0.0) {
    const auto root = [&](double lo, double hi) {  // d(lo), d(hi) of opposite signs
      const bool rising = d(hi) > d(lo);
      for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
        const double mid = 0.5 * (lo + hi);
        ((d(mid) < 0.0) == rising ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    };
    g1 = d(0.0) > 0.0 ? root(0.0, g_m) : 0.0;
    g2 = d(1.0) > 0.0 ? root(g_m, 1.0) : 1.0;
  }
  constexpr int kIntervals = 256;  // per piece; each piece is smooth
  double mean = 0.0;
  const double cuts[] = {0.0, g1, g2, 1.0};
  for (int k = 0; k < 3; ++k) {
    const double lo = cuts[k], hi = cuts[k + 1];
    if (!(hi > lo)) continue;
    if (shape.point) {  // ellipsoid: the area fraction with p / p_h >= g is 1 - g^2, density 2 g
      mean += Simpson([&](double g) { return 2.0 * g * tau(g); }, lo, hi, kIntervals);
    } else {  // semi-ellipse over the width, g = cos t: mean = int_0^{pi/2} tau(cos t) cos t dt
      mean += Simpson([&](double t) { return std::cos(t) * tau(std::cos(t)); }, std::acos(hi), std::acos(lo), kIntervals);
    }
  }
  return shape.area / force * mean;
}

MixedFriction MixedCoefficient(const Lubrication& lub, double force, const ContactShape& shape, double length,
                               double equivalent_radius, double e_star, double entrainment, double sliding) {
  MixedFriction m;
  m.film_thickness = FilmThickness(lub, force, length, equivalent_radius, e_star, entrainment, &m);
  m.lambda = m.film_thickness / lub.CompositeRoughness();
  m.film_share = FilmShare(m.lambda);
  if (m.lambda > MixedLimits::kMaxLambda) {
    m.film_share = 1.0;
    m.warnings.push_back(fmt::format(
        "jiang.lambda_above_fit: lambda = {:.3g} > {:g}: the load sharing of eq. 21 is fitted for the mixed regime; "
        "full film (f_lambda = 1) used",
        m.lambda, MixedLimits::kMaxLambda));
  }
  if (force > 0.0 && (m.load_parameter < MixedLimits::kMinLoadParameter ||
                      m.load_parameter > MixedLimits::kMaxLoadParameter)) {
    m.warnings.push_back(fmt::format(
        "jiang.load_parameter_outside_fit: W* = {:.3g} outside [{:g}, {:g}] (a decade either side of the 1e-5 Jiang "
        "fitted the film thickness for, section 4.4)",
        m.load_parameter, MixedLimits::kMinLoadParameter, MixedLimits::kMaxLoadParameter));
  }
  m.effective_pressure = EffectivePressure(lub, shape.max_pressure, shape.point);
  // Eq. 23: f_e = (A / W) G^(1-n) exp(n alpha p_ef) (eta_0 |du| / h)^n, the area integral of the
  // power-law shear stress with the Barus viscosity, over the load.
  if (force > 0.0 && m.film_thickness > 0.0) {
    const double n = lub.power_law_exponent;
    const double shear_factor = std::pow(lub.limiting_shear_modulus, 1.0 - n) *
                                std::pow(lub.viscosity * std::abs(sliding) / m.film_thickness, n);
    m.full_film = shape.area / force * shear_factor * std::exp(n * lub.pressure_viscosity * m.effective_pressure);
    m.full_film_uncapped = m.full_film;
    if (lub.capped()) m.full_film = CappedFullFilm(lub, shear_factor, shape, force);
  }
  // Eq. 20 as printed: f_lambda^1.2 f_e + (1 - f_lambda) f_b.
  m.coefficient = std::pow(m.film_share, 1.2) * m.full_film + (1.0 - m.film_share) * lub.boundary_coefficient;
  if (m.full_film > lub.boundary_coefficient) {
    m.warnings.push_back(fmt::format(
        "jiang.full_film_above_boundary: f_e = {:.3g} > f_b = {:g}: the full-film coefficient exceeds the boundary one "
        "(beyond the power-law fluid's range)",
        m.full_film, lub.boundary_coefficient));
  }
  return m;
}

}  // namespace ltca::contact
