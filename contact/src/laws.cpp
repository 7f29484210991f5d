#include "ltca/contact/laws.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::contact {
namespace {

using units::kPi;
constexpr double kInf = std::numeric_limits<double>::infinity();

// rho - sqrt(rho^2 - s) without cancellation; 0 for an infinite radius.
double Sagitta(double rho, double s) {
  if (std::isinf(rho)) return 0.0;
  return s / (rho + std::sqrt(rho * rho - s));
}
// d/ds of Sagitta.
double SagittaSlope(double rho, double s) {
  if (std::isinf(rho)) return 0.0;
  return 0.5 / std::sqrt(rho * rho - s);
}
// int_0^s Sagitta(rho, t) dt = s^2 (rho + 2q) / (3 (rho + q)^2), q = sqrt(rho^2 - s).
double SagittaIntegral(double rho, double s) {
  if (std::isinf(rho)) return 0.0;
  const double q = std::sqrt(rho * rho - s);
  return s * s * (rho + 2.0 * q) / (3.0 * (rho + q) * (rho + q));
}

}  // namespace

void ContactSettings::Validate() const {
  if (law == LawKind::kLinear &&
      !(stiffness_per_length >= kMinStiffness && stiffness_per_length <= kMaxStiffness)) {
    throw std::invalid_argument(fmt::format(
        "[contact] stiffness_n_per_mm2 = {}: the linear law needs a stiffness per mm of contact "
        "length from {:g} to {:g} N/mm^2 (steel line contacts: about 1e4 to 1e5)",
        stiffness_per_length, kMinStiffness, kMaxStiffness));
  }
  if (law != LawKind::kLinear && stiffness_per_length != 0.0) {
    throw std::invalid_argument(fmt::format(
        "[contact] stiffness_n_per_mm2 = {}: applies to law = \"linear\" only (law is \"{}\")",
        stiffness_per_length, ToString(law)));
  }
  if (!(log_radius_cap >= 0.0) || !std::isfinite(log_radius_cap)) {
    throw std::invalid_argument(fmt::format(
        "[contact] log_radius_cap_mm = {}: expected a finite length >= 0 (0: the pin-circle radius)",
        log_radius_cap));
  }
}

LawKind ParseLawKind(const std::string& text) {
  if (text == "hertz-line") return LawKind::kHertzLine;
  if (text == "sagitta") return LawKind::kSagitta;
  if (text == "linear") return LawKind::kLinear;
  throw std::invalid_argument(fmt::format(
      "[contact] law = \"{}\": expected one of \"hertz-line\", \"sagitta\", \"linear\"", text));
}

RhoConvention ParseRhoConvention(const std::string& text) {
  if (text == "signed") return RhoConvention::kSigned;
  if (text == "absolute") return RhoConvention::kAbsolute;
  throw std::invalid_argument(fmt::format(
      "[contact] rho_convention = \"{}\": expected \"signed\" or \"absolute\"", text));
}

const char* ToString(LawKind kind) {
  switch (kind) {
    case LawKind::kHertzLine: return "hertz-line";
    case LawKind::kSagitta: return "sagitta";
    case LawKind::kLinear: return "linear";
  }
  return "?";
}

const char* ToString(RhoConvention convention) {
  return convention == RhoConvention::kSigned ? "signed" : "absolute";
}

ContactLaw::ContactLaw(const ContactSettings& settings, const Material& material,
                       double cycloid_curvature, double pin_radius, double length,
                       double log_radius_cap)
    : kind_(settings.law), length_(length), rho_p_(pin_radius) {
  if (!std::isfinite(cycloid_curvature)) {
    throw std::invalid_argument(
        "edge contact (a pin on a tip corner): the line-contact laws do not apply");
  }
  cc_ = (1.0 - material.poisson_ratio * material.poisson_ratio) / material.young_modulus;
  cp_ = (1.0 - material.pin_poisson_ratio * material.pin_poisson_ratio) / material.pin_young_modulus;
  e_star_ = 1.0 / (cc_ + cp_);  // Liu eq. 24
  // Equivalent radius, Liu eq. 25 / Li eq. 4.
  const double kappa = settings.rho_convention == RhoConvention::kSigned ? cycloid_curvature
                                                                         : std::abs(cycloid_curvature);
  // A concave radius below the pin radius cannot occur on a valid pair (it would interfere);
  // keep rho* finite and positive regardless.
  rho_eq_ = 1.0 / std::max(kappa + 1.0 / pin_radius, 1e-12 / pin_radius);
  const double rho_c = cycloid_curvature == 0.0 ? kInf : 1.0 / std::abs(cycloid_curvature);
  valid_half_width_ = 0.1 * std::min(rho_c, pin_radius);

  switch (kind_) {
    case LawKind::kLinear:
      k_lin_ = settings.stiffness_per_length * length;
      max_force_ = kInf;
      max_approach_ = kInf;
      break;
    case LawKind::kHertzLine: {
      // delta = (2F / (pi B)) [A - (C/2) ln F] with b = b1 sqrt(F).
      rho_c_abs_ = std::min(rho_c, log_radius_cap);
      const double b1 = std::sqrt(4.0 * rho_eq_ / (kPi * length * e_star_));
      hertz_a_ = cc_ * (std::log(4.0 * rho_c_abs_ / b1) - 0.5) + cp_ * (std::log(4.0 * rho_p_ / b1) - 0.5);
      const double c = cc_ + cp_;
      const double x_max = 2.0 * hertz_a_ / c - 1.0;
      max_force_ = std::exp(x_max);
      max_approach_ = max_force_ * c / (kPi * length);
      break;
    }
    case LawKind::kSagitta: {
      rho_c_abs_ = rho_c;
      sagitta_factor_ = 4.0 * rho_eq_ * (cc_ + cp_) / (kPi * length);  // Li eq. 3: a^2 = factor F
      const double s_max = std::pow(std::min(rho_c, pin_radius), 2);
      max_force_ = s_max / sagitta_factor_;
      max_approach_ = SagittaApproach(s_max);
      break;
    }
  }
}

double ContactLaw::HertzApproach(double force) const {
  return 2.0 * force / (kPi * length_) * (hertz_a_ - 0.5 * (cc_ + cp_) * std::log(force));
}

double ContactLaw::SagittaApproach(double s) const {
  return Sagitta(rho_c_abs_, s) + Sagitta(rho_p_, s);
}

double ContactLaw::Approach(double force) const {
  if (!(force > 0.0)) return 0.0;
  switch (kind_) {
    case LawKind::kLinear: return force / k_lin_;
    case LawKind::kHertzLine: return HertzApproach(std::min(force, max_force_));
    case LawKind::kSagitta: return SagittaApproach(sagitta_factor_ * std::min(force, max_force_));
  }
  return 0.0;
}

double ContactLaw::Force(double approach) const {
  double no_hint = 0.0;
  return Force(approach, &no_hint);
}

double ContactLaw::Force(double approach, double* hint) const {
  if (!(approach > 0.0)) return 0.0;
  if (approach >= max_approach_) return max_force_;
  switch (kind_) {
    case LawKind::kLinear:
      return *hint = k_lin_ * approach;
    case LawKind::kHertzLine: {
      // Solve h(x) = x + ln(A - (C/2) x) + ln(2 / (pi B)) - ln(delta) = 0 for x = ln F. h is
      // increasing and concave below x_max, so Newton from the left converges monotonically.
      const double c = cc_ + cp_;
      const double x_max = 2.0 * hertz_a_ / c - 1.0;
      const double shift = std::log(2.0 / (kPi * length_)) - std::log(approach);
      const auto h = [&](double x) { return x + std::log(hertz_a_ - 0.5 * c * x) + shift; };
      // From either side the first Newton iterate of a concave increasing function lands left of
      // the root, so a warm start from a nearby earlier force is as safe as the cold one.
      double x = (*hint > 0.0 && *hint < max_force_) ? std::log(*hint)
                                                     : std::log(approach * kPi * length_ / (2.0 * hertz_a_));
      x = std::min(x, x_max - 1.0);
      for (int it = 0; it < 100; ++it) {
        const double step = -h(x) / (1.0 - 0.5 * c / (hertz_a_ - 0.5 * c * x));
        x = std::min(x + step, 0.5 * (x + x_max));  // stay left of x_max
        if (std::abs(step) <= 1e-15 * std::max(1.0, std::abs(x))) break;
      }
      *hint = std::exp(x);
      return *hint;
    }
    case LawKind::kSagitta: {
      // delta(s) is increasing and convex in s = a^2: Newton from the right converges
      // monotonically. Start at the linearisation (to the right of the root), capped at s_max.
      const double s_max = max_force_ * sagitta_factor_;
      double s = std::min(approach / (SagittaSlope(rho_c_abs_, 0.0) + SagittaSlope(rho_p_, 0.0)), s_max);
      for (int it = 0; it < 100; ++it) {
        const double slope = SagittaSlope(rho_c_abs_, s) + SagittaSlope(rho_p_, s);
        if (!std::isfinite(slope)) {  // at s_max exactly: step back a little
          s *= 1.0 - 1e-12;
          continue;
        }
        const double step = (SagittaApproach(s) - approach) / slope;
        s -= step;
        if (std::abs(step) <= 1e-16 * s) break;
      }
      *hint = s / sagitta_factor_;
      return *hint;
    }
  }
  return 0.0;
}

double ContactLaw::Stiffness(double approach) const {
  if (!(approach > 0.0) || approach >= max_approach_) return 0.0;
  switch (kind_) {
    case LawKind::kLinear: return k_lin_;
    case LawKind::kHertzLine: {
      const double f = Force(approach);
      const double c = cc_ + cp_;
      return 1.0 / (2.0 / (kPi * length_) * (hertz_a_ - 0.5 * c * std::log(f) - 0.5 * c));
    }
    case LawKind::kSagitta: {
      const double s = sagitta_factor_ * Force(approach);
      return 1.0 / (sagitta_factor_ * (SagittaSlope(rho_c_abs_, s) + SagittaSlope(rho_p_, s)));
    }
  }
  return 0.0;
}

double ContactLaw::Compliance(double force) const {
  if (force >= max_force_) return 0.0;
  switch (kind_) {
    case LawKind::kLinear: return 1.0 / k_lin_;
    case LawKind::kHertzLine: {
      if (!(force > 0.0)) return kInf;
      const double c = cc_ + cp_;
      return 2.0 / (kPi * length_) * (hertz_a_ - 0.5 * c * std::log(force) - 0.5 * c);
    }
    case LawKind::kSagitta: {
      const double s = sagitta_factor_ * std::max(force, 0.0);
      return sagitta_factor_ * (SagittaSlope(rho_c_abs_, s) + SagittaSlope(rho_p_, s));
    }
  }
  return 0.0;
}

double ContactLaw::Approach(double force, double* compliance) const {
  if (kind_ != LawKind::kHertzLine || !(force > 0.0) || force >= max_force_) {
    *compliance = Compliance(force);
    return Approach(force);
  }
  const double c = cc_ + cp_;
  const double log_f = std::log(force);
  *compliance = 2.0 / (kPi * length_) * (hertz_a_ - 0.5 * c * log_f - 0.5 * c);
  return 2.0 * force / (kPi * length_) * (hertz_a_ - 0.5 * c * log_f);
}

double ContactLaw::ComplementaryEnergy(double force) const {
  if (!(force > 0.0)) return 0.0;
  switch (kind_) {
    case LawKind::kLinear: return 0.5 * force * force / k_lin_;
    case LawKind::kHertzLine: {
      const double c = cc_ + cp_;
      return force * force / (kPi * length_) * (hertz_a_ - 0.5 * c * std::log(force) + 0.25 * c);
    }
    case LawKind::kSagitta: {
      const double s = sagitta_factor_ * force;
      return (SagittaIntegral(rho_c_abs_, s) + SagittaIntegral(rho_p_, s)) / sagitta_factor_;
    }
  }
  return 0.0;
}

double ContactLaw::HalfWidth(double force) const {
  if (!(force > 0.0)) return 0.0;
  return std::sqrt(4.0 * force * rho_eq_ / (kPi * length_ * e_star_));  // Liu eq. 23
}

double ContactLaw::MaxPressure(double force) const {
  if (!(force > 0.0)) return 0.0;
  return 2.0 * force / (kPi * HalfWidth(force) * length_);
}

}  // namespace ltca::contact
