#include "ltca/contact/laws.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/contact/bearing.hpp"
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
  if (seat.seated() && law == LawKind::kSagitta) {
    throw std::invalid_argument(fmt::format(
        "[pins] seat = \"{}\": a seat in series is built for [contact] law = \"hertz-line\" or \"linear\", not "
        "\"sagitta\" (its approach is not of the hertz-line form the series law keeps)",
        ToString(seat.kind)));
  }
}

void PinSeat::Validate(double pin_radius) const {
  switch (kind) {
    case Kind::kRigid: return;
    case Kind::kLinear:
      if (!(stiffness_per_length >= ContactSettings::kMinStiffness && stiffness_per_length <= ContactSettings::kMaxStiffness)) {
        throw std::invalid_argument(fmt::format(
            "[pins] seat_stiffness_n_per_mm2 = {}: expected the seat's stiffness per mm of pin length from {:g} to {:g} "
            "N/mm^2",
            stiffness_per_length, ContactSettings::kMinStiffness, ContactSettings::kMaxStiffness));
      }
      return;
    case Kind::kGroove:
      if (!(groove_radius > pin_radius) || !std::isfinite(groove_radius)) {
        throw std::invalid_argument(fmt::format(
            "[pins] groove_radius_mm = {}: expected a finite groove radius larger than the pin radius {} mm (the "
            "conformal contact's 1/rho* = 1/r_p - 1/r_g must be > 0)",
            groove_radius, pin_radius));
      }
      if (!(housing_young_modulus > 0.0) || !std::isfinite(housing_young_modulus)) {
        throw std::invalid_argument(fmt::format(
            "[pins] housing_young_modulus_mpa = {}: expected a finite modulus > 0 MPa", housing_young_modulus));
      }
      if (!(housing_poisson_ratio >= 0.0 && housing_poisson_ratio < 0.5)) {
        throw std::invalid_argument(fmt::format(
            "[pins] housing_poisson_ratio = {}: expected 0 <= nu < 0.5", housing_poisson_ratio));
      }
      return;
  }
}

PinSeat::Kind ParsePinSeatKind(const std::string& text) {
  if (text == "rigid") return PinSeat::Kind::kRigid;
  if (text == "linear") return PinSeat::Kind::kLinear;
  if (text == "groove") return PinSeat::Kind::kGroove;
  throw std::invalid_argument(fmt::format(
      "[pins] seat = \"{}\": expected one of \"rigid\", \"linear\", \"groove\"", text));
}

const char* ToString(PinSeat::Kind kind) {
  switch (kind) {
    case PinSeat::Kind::kRigid: return "rigid";
    case PinSeat::Kind::kLinear: return "linear";
    case PinSeat::Kind::kGroove: return "groove";
  }
  return "?";
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
      form_ = Form::kLinear;
      k_lin_ = settings.stiffness_per_length * length;
      max_force_ = kInf;
      max_approach_ = kInf;
      break;
    case LawKind::kHertzLine: {
      // delta = (2F / (pi B)) [A - (C/2) ln F] with b = b1 sqrt(F).
      form_ = Form::kLog;
      rho_c_abs_ = settings.cycloid_log_radius > 0.0 ? settings.cycloid_log_radius : std::min(rho_c, log_radius_cap);
      const double b1 = std::sqrt(4.0 * rho_eq_ / (kPi * length * e_star_));
      hertz_a_ = cc_ * (std::log(4.0 * rho_c_abs_ / b1) - 0.5) + cp_ * (std::log(4.0 * rho_p_ / b1) - 0.5);
      log_a_ = hertz_a_;
      log_c_ = cc_ + cp_;
      const double x_max = 2.0 * log_a_ / log_c_ - 1.0;
      max_force_ = std::exp(x_max);
      max_approach_ = max_force_ * log_c_ / (kPi * length);
      break;
    }
    case LawKind::kSagitta: {
      rho_c_abs_ = rho_c;
      sagitta_factor_ = 4.0 * rho_eq_ * (cc_ + cp_) / (kPi * length);  // Li eq. 3: a^2 = factor F
      const double s_max = std::pow(std::min(rho_c, pin_radius), 2);
      max_force_ = s_max / sagitta_factor_;
      max_approach_ = SagittaApproach(s_max);
      form_ = Form::kSagitta;
      break;
    }
  }
  const PinSeat& seat = settings.seat;
  if (!seat.seated()) return;
  if (kind_ == LawKind::kSagitta) settings.Validate();  // throws: not built
  // The seat in series (laws.hpp): its A and C, and its own largest force.
  double seat_max = kInf;
  if (seat.kind == PinSeat::Kind::kLinear) {
    seat_a_ = kPi / (2.0 * seat.stiffness_per_length);  // F / (k_s B) = (2F / (pi B)) pi / (2 k_s)
  } else {
    seat.Validate(pin_radius);
    const double ch = (1.0 - seat.housing_poisson_ratio * seat.housing_poisson_ratio) / seat.housing_young_modulus;
    const double rho_s = 1.0 / (1.0 / pin_radius - 1.0 / seat.groove_radius);
    seat_b1_ = std::sqrt(4.0 * rho_s * (cp_ + ch) / (kPi * length));
    seat_a_ = cp_ * (std::log(4.0 * pin_radius / seat_b1_) - 0.5) +
              ch * (std::log(4.0 * std::min(seat.groove_radius, log_radius_cap) / seat_b1_) - 0.5);
    seat_c_ = cp_ + ch;
    seat_max = std::exp(2.0 * seat_a_ / seat_c_ - 1.0);
    seat_valid_half_width_ = 0.1 * pin_radius;
  }
  if (form_ == Form::kLinear && seat.kind == PinSeat::Kind::kLinear) {
    k_lin_ = 1.0 / (1.0 / k_lin_ + 1.0 / (seat.stiffness_per_length * length));
    return;
  }
  if (form_ == Form::kLinear) {  // a linear contact in the log form: F / k = (2F / (pi B)) pi B / (2 k)
    log_a_ = kPi * length / (2.0 * k_lin_);
    log_c_ = 0.0;
    form_ = Form::kLog;
  }
  log_a_ += seat_a_;
  log_c_ += seat_c_;
  // Each part rises while ln F < 2 A_i / C_i - 1, so the sum does up to the smaller of the parts'
  // largest forces (a linear part has none); beyond it a part's formula stops meaning anything.
  max_force_ = std::min(max_force_, seat_max);
  max_approach_ = std::isfinite(max_force_) ? HertzApproach(max_force_) : kInf;
}

ContactLaw ContactLaw::Roller(double roller_length, double linear_compliance) {
  if (!(std::isfinite(roller_length) && roller_length > 0.0) || !std::isfinite(linear_compliance)) {
    throw std::invalid_argument(fmt::format(
        "ContactLaw::Roller: roller length {} mm, linear compliance {} mm/N: expected a finite length > 0 and a finite "
        "compliance",
        roller_length, linear_compliance));
  }
  ContactLaw law;
  law.kind_ = LawKind::kLinear;  // not a pin-cycloid law: the form says what it is
  law.form_ = Form::kRoller;
  law.length_ = roller_length;
  law.e_star_ = 0.0;
  law.rho_eq_ = 0.0;
  law.rho_c_abs_ = 0.0;
  law.rho_p_ = 0.0;
  law.cc_ = 0.0;
  law.cp_ = 0.0;
  law.valid_half_width_ = kInf;
  // Both raceway contacts in series, Palmgren's 3.84e-5 Q^0.9 / l^0.8 each (PalmgrenApproach at 1 N).
  law.roller_a_ = 2.0 * PalmgrenApproach(1.0, roller_length);
  law.roller_s_ = linear_compliance;
  if (linear_compliance < 0.0) {
    law.max_force_ = std::pow(0.9 * law.roller_a_ / -linear_compliance, 10.0);
    law.max_approach_ = law.roller_a_ * std::pow(law.max_force_, 0.9) + linear_compliance * law.max_force_;
  } else {
    law.max_force_ = kInf;
    law.max_approach_ = kInf;
  }
  return law;
}

ContactLaw ContactLaw::Scaled(double w) const {
  if (!(std::isfinite(w) && w > 0.0)) {
    throw std::invalid_argument(fmt::format("ContactLaw::Scaled: force scale {}: expected a finite number above 0", w));
  }
  ContactLaw law = *this;
  law.length_ = w * length_;
  law.max_force_ = w * max_force_;  // the approach at the largest force is unchanged
  law.k_lin_ = w * k_lin_;
  law.sagitta_factor_ = sagitta_factor_ / w;
  // delta = (2F / (pi B)) [A - (C/2) ln F] at F / w: (2F / (pi w B)) [A + (C/2) ln w - (C/2) ln F].
  const double log_w = std::log(w);
  law.log_a_ = log_a_ + 0.5 * log_c_ * log_w;
  law.seat_a_ = seat_a_ + 0.5 * seat_c_ * log_w;
  law.seat_b1_ = seat_b1_ / std::sqrt(w);  // b_s = b1 sqrt(F / w)
  law.roller_a_ = roller_a_ * std::pow(w, -0.9);  // a (Q / w)^0.9 + s Q / w
  law.roller_s_ = roller_s_ / w;
  return law;
}

double ContactLaw::HertzApproach(double force) const {
  return 2.0 * force / (kPi * length_) * (log_a_ - 0.5 * log_c_ * std::log(force));
}

double ContactLaw::SagittaApproach(double s) const {
  return Sagitta(rho_c_abs_, s) + Sagitta(rho_p_, s);
}

double ContactLaw::Approach(double force) const {
  if (!(force > 0.0)) return 0.0;
  switch (form_) {
    case Form::kLinear: return force / k_lin_;
    case Form::kLog: return HertzApproach(std::min(force, max_force_));
    case Form::kSagitta: return SagittaApproach(sagitta_factor_ * std::min(force, max_force_));
    case Form::kRoller: {
      const double f = std::min(force, max_force_);
      return roller_a_ * std::pow(f, 0.9) + roller_s_ * f;
    }
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
  switch (form_) {
    case Form::kLinear:
      return *hint = k_lin_ * approach;
    case Form::kLog: {
      // Solve g(F) = F (A - (C/2) ln F) - D = 0, D = delta pi B / 2, by Halley's method (one log
      // a step: g' = A - (C/2)(ln F + 1), g'' = -C / (2F)). g is increasing and concave below
      // max_force, so every iterate is kept inside (0, max_force): a step that leaves it is
      // replaced by the geometric midpoint toward the bound it crossed. (C > 0 here: a linear
      // contact on a linear seat stays in the linear form, and a groove adds its C.) Halley's
      // error falls as the cube of the last one, e' = K e^3, with K F^2 of order 0.01 on steel
      // line contacts (F^2 g'''/(6 g') - (F g''/(2 g'))^2): once an unclamped Halley step is below
      // 1e-5 of F the next error is below about 1e-17 of F, so that step is the last. Issue 29:
      // about 2 logs a call from a warm start, where the Newton iteration on ln F took 5-7 and an exp.
      const double a = log_a_, c = log_c_;
      const double d = 0.5 * kPi * length_ * approach;
      const double cap = max_force_;
      double f = (*hint > 0.0 && *hint < cap) ? *hint : std::min(d / a, cap / std::exp(1.0));
      for (int it = 0; it < 100; ++it) {
        const double l = std::log(f);
        const double g = f * (a - 0.5 * c * l) - d;
        const double g1 = a - 0.5 * c * (l + 1.0);
        const double g2 = -0.5 * c / f;
        const double denominator = 2.0 * g1 * g1 - g * g2;
        // Far left of the root (g < 0, F small) Halley's denominator can vanish: a Newton step there.
        const bool halley = denominator >= g1 * g1;
        const double step = halley ? -2.0 * g * g1 / denominator : -g / g1;
        double next = f + step;
        bool clamped = false;
        if (!(next > 0.0)) {
          next = 0.5 * f, clamped = true;
        } else if (!(next < cap)) {
          next = std::sqrt(f * cap), clamped = true;
        }
        const bool done = !clamped && std::abs(step) <= (halley ? 1e-5 : 4e-16) * f;
        f = next;
        if (done) break;
      }
      *hint = f;
      return f;
    }
    case Form::kSagitta: {
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
    case Form::kRoller: {
      // g(Q) = a Q^0.9 + s Q - delta is increasing and concave below max_force: Newton's iterates
      // from any point land left of the root and then rise to it monotonically. Start at the
      // root without the linear term (exact for s = 0).
      const double a = roller_a_, s = roller_s_;
      double f = std::pow(approach / a, 10.0 / 9.0);
      if (s != 0.0) {
        for (int it = 0; it < 100; ++it) {
          const double p = std::pow(f, 0.9);
          const double step = (a * p + s * f - approach) / (0.9 * a * p / f + s);
          double next = f - step;
          if (!(next > 0.0)) next = 0.5 * f;
          if (!(next < max_force_)) next = 0.5 * (f + max_force_);
          const bool done = std::abs(next - f) <= 4e-16 * f;
          f = next;
          if (done) break;
        }
      }
      *hint = f;
      return f;
    }
  }
  return 0.0;
}

double ContactLaw::Stiffness(double approach) const {
  if (!(approach > 0.0) || approach >= max_approach_) return 0.0;
  switch (form_) {
    case Form::kLinear: return k_lin_;
    case Form::kLog: {
      const double f = Force(approach);
      const double c = log_c_;
      return 1.0 / (2.0 / (kPi * length_) * (log_a_ - 0.5 * c * std::log(f) - 0.5 * c));
    }
    case Form::kSagitta: {
      const double s = sagitta_factor_ * Force(approach);
      return 1.0 / (sagitta_factor_ * (SagittaSlope(rho_c_abs_, s) + SagittaSlope(rho_p_, s)));
    }
    case Form::kRoller: return 1.0 / Compliance(Force(approach));
  }
  return 0.0;
}

double ContactLaw::Compliance(double force) const {
  if (force >= max_force_) return 0.0;
  switch (form_) {
    case Form::kLinear: return 1.0 / k_lin_;
    case Form::kLog: {
      if (!(force > 0.0)) return log_c_ > 0.0 ? kInf : 2.0 / (kPi * length_) * log_a_;
      const double c = log_c_;
      return 2.0 / (kPi * length_) * (log_a_ - 0.5 * c * std::log(force) - 0.5 * c);
    }
    case Form::kSagitta: {
      const double s = sagitta_factor_ * std::max(force, 0.0);
      return sagitta_factor_ * (SagittaSlope(rho_c_abs_, s) + SagittaSlope(rho_p_, s));
    }
    case Form::kRoller:
      if (!(force > 0.0)) return kInf;
      return 0.9 * roller_a_ * std::pow(force, -0.1) + roller_s_;
  }
  return 0.0;
}

double ContactLaw::Approach(double force, double* compliance) const {
  if (form_ != Form::kLog || !(force > 0.0) || force >= max_force_) {
    *compliance = Compliance(force);
    return Approach(force);
  }
  const double c = log_c_;
  const double log_f = std::log(force);
  *compliance = 2.0 / (kPi * length_) * (log_a_ - 0.5 * c * log_f - 0.5 * c);
  return 2.0 * force / (kPi * length_) * (log_a_ - 0.5 * c * log_f);
}

double ContactLaw::ComplementaryEnergy(double force) const {
  if (!(force > 0.0)) return 0.0;
  switch (form_) {
    case Form::kLinear: return 0.5 * force * force / k_lin_;
    case Form::kLog: {
      const double c = log_c_;
      return force * force / (kPi * length_) * (log_a_ - 0.5 * c * std::log(force) + 0.25 * c);
    }
    case Form::kSagitta: {
      const double s = sagitta_factor_ * force;
      return (SagittaIntegral(rho_c_abs_, s) + SagittaIntegral(rho_p_, s)) / sagitta_factor_;
    }
    case Form::kRoller: return roller_a_ * std::pow(force, 1.9) / 1.9 + 0.5 * roller_s_ * force * force;
  }
  return 0.0;
}

double ContactLaw::StrainEnergy(double approach, double force) const {
  if (!(approach > 0.0) || !(force > 0.0)) return 0.0;
  if (approach < max_approach_) {
    switch (form_) {
      case Form::kLinear: return 0.5 * force * approach;
      // F delta - E^c(F) with (A - (C/2) ln F) = delta pi B / (2F) from the law itself: no log.
      case Form::kLog: return 0.5 * force * approach - 0.25 * log_c_ * force * force / (kPi * length_);
      case Form::kSagitta:
      case Form::kRoller: break;
    }
  }
  return force * approach - ComplementaryEnergy(force);
}

double ContactLaw::SeatApproach(double force) const {
  if (!(force > 0.0) || (seat_a_ == 0.0 && seat_c_ == 0.0)) return 0.0;
  const double f = std::min(force, max_force_);
  return 2.0 * f / (kPi * length_) * (seat_a_ - 0.5 * seat_c_ * std::log(f));
}

double ContactLaw::SeatComplementaryEnergy(double force) const {
  if (!(force > 0.0) || (seat_a_ == 0.0 && seat_c_ == 0.0)) return 0.0;
  return force * force / (kPi * length_) * (seat_a_ - 0.5 * seat_c_ * std::log(force) + 0.25 * seat_c_);
}

double ContactLaw::SeatHalfWidth(double force) const {
  if (!(force > 0.0) || seat_b1_ == 0.0) return 0.0;
  return seat_b1_ * std::sqrt(force);
}

double ContactLaw::HalfWidth(double force) const {
  if (!(force > 0.0) || form_ == Form::kRoller) return 0.0;
  return std::sqrt(4.0 * force * rho_eq_ / (kPi * length_ * e_star_));  // Liu eq. 23
}

double ContactLaw::MaxPressure(double force) const {
  if (!(force > 0.0) || form_ == Form::kRoller) return 0.0;
  return 2.0 * force / (kPi * HalfWidth(force) * length_);
}

}  // namespace ltca::contact
