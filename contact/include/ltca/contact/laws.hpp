#pragma once
// Contact laws: normal force <-> normal approach of one pin-cycloid contact of length B.
// All laws: F = 0 for approach <= 0; monotone increasing up to the largest force the law can
// represent (max_force(); beyond it the formula stops being monotone or real, and solvers report
// the load as one the law cannot carry). Units: N, mm, MPa.
//
//  hertz-line  Liu 2021 eq. 22-25. delta = (2F / (pi B)) [C_c (ln(4 rho_c / b) - 1/2)
//              + C_p (ln(4 rho_p / b) - 1/2)], b = sqrt(4 F rho* / (pi B E*)), C = (1 - nu^2) / E.
//              Departures: |rho_c| enters the logarithm (a concave radius cannot), capped at
//              log_radius_cap (the inflection point has rho_c -> infinity, where the formula's
//              approach diverges; the cap is a reference depth, docs/contact.md). rho* per
//              rho_convention. Since b ~ sqrt(F), delta(F) = (2F / (pi B)) [A - (C/2) ln F]: it
//              rises up to F_max = exp(2A / C - 1).
//  sagitta     Li eq. 3-10: Hertz half-width a (eq. 3, 4) and the approach as the sum of the two
//              sagittas, delta = |rho_c| - sqrt(rho_c^2 - a^2) + r - sqrt(r^2 - a^2) (eq. 6-7, the
//              series stiffness of eq. 8-10). Eq. 12 as printed (delta = F / (K_n L^2)) is not
//              dimensionally a length; the normal deflection F / K_n is used (docs/validation.md).
//              Valid while a < min(|rho_c|, r).
//  linear      F = k B delta, k in N/mm^2 (per mm of contact length): closed-form checks.
//
// A pin seat (PinSeat; docs/stage.md "Pin seats") adds the compliance of the pin's seat
// in its housing groove in series: the approach at a force is the contact's plus the seat's,
// delta(F) = delta_contact(F) + delta_seat(F), one law per contact point (each slice of the face
// width seated on its own length of groove, as each slice carries its own contact). A linear seat
// gives delta_seat = F / (k_s B); a groove the hertz-line formula of a pin of radius r_p inside a
// concave groove of radius r_g > r_p (1/rho* = 1/r_p - 1/r_g; the pin and the housing as the two
// bodies: C_p (ln(4 r_p / b) - 1/2) + C_h (ln(4 min(r_g, cap) / b) - 1/2)). Both keep the form
// delta = (2F / (pi B)) [A - (C/2) ln F] of hertz-line, with A and C the sums of the parts'
// (a linear part adds pi B / (2 k) to A and nothing to C). The stresses and the half-width stay the
// pin-cycloid contact's.
#include <limits>
#include <string>

#include "ltca/contact/material.hpp"

namespace ltca::contact {

/// How a concave cycloid radius enters the equivalent radius rho* (Liu eq. 25, Li eq. 4).
enum class RhoConvention {
  kSigned,    ///< 1/rho* = kappa_c + 1/rho_p with the signed curvature: conformal contact in a
              ///< concave flank (physically correct; the default)
  kAbsolute,  ///< 1/rho* = |kappa_c| + 1/rho_p: every contact treated as convex-convex (matches
              ///< Liu's published numbers)
};

enum class LawKind { kHertzLine, kSagitta, kLinear };

/// The seat of every ring pin in its housing groove ([pins] seat keys): rigid (today's model), a
/// linear foundation, or the groove's conformal Hertz line contact. In series with each contact.
struct PinSeat {
  enum class Kind { kRigid, kLinear, kGroove };
  Kind kind = Kind::kRigid;
  double stiffness_per_length = 0.0;   ///< kLinear: N/mm^2 per mm of seat length (deck: seat_stiffness_n_per_mm2)
  double groove_radius = 0.0;          ///< kGroove: r_g, mm (deck: groove_radius_mm), > the pin radius
  double housing_young_modulus = 0.0;  ///< kGroove: MPa (deck: housing_young_modulus_mpa)
  double housing_poisson_ratio = 0.0;  ///< kGroove (deck: housing_poisson_ratio)
  bool seated() const { return kind != Kind::kRigid; }
  /// Throws std::invalid_argument naming the `[pins]` key: a linear stiffness from 1 to 1e9
  /// N/mm^2, a groove radius finite and larger than pin_radius (mm), the housing's E > 0 and
  /// 0 <= nu < 0.5.
  void Validate(double pin_radius) const;
};
PinSeat::Kind ParsePinSeatKind(const std::string& text);  ///< "rigid" | "linear" | "groove"; names `[pins] seat`
const char* ToString(PinSeat::Kind kind);

/// The [contact] section.
struct ContactSettings {
  LawKind law = LawKind::kHertzLine;
  RhoConvention rho_convention = RhoConvention::kSigned;
  double stiffness_per_length = 0.0;  ///< linear law only, N/mm^2 (deck: stiffness_n_per_mm2)
  /// Accepted range of stiffness_per_length, N/mm^2: steel line contacts are about 1e4-1e5.
  static constexpr double kMinStiffness = 1.0;
  static constexpr double kMaxStiffness = 1e9;
  /// Largest |rho_c| entering the logarithm of the hertz-line law, mm; 0 = the pin-circle radius
  /// of the pair (deck: log_radius_cap_mm).
  double log_radius_cap = 0.0;
  /// > 0: the cycloid's term of the hertz-line logarithm takes exactly this radius, mm, in place of
  /// min(|rho_c|, cap): with an elastic disc body (contact/disc_body.hpp) the term is the Hertz
  /// contact's local field beyond the FE's uniform patch, rho = w0 / sqrt(e). Not a deck key: the
  /// stage sets it from the body. 0: the rigid disc's law.
  double cycloid_log_radius = 0.0;
  /// The pins' seat, in series with every pin-ring contact (deck: [pins] seat keys). The output
  /// pins of a stage are not seated (their laws are built without it).
  PinSeat seat;
  /// Also refuses a seat with the sagitta law (not built: its approach is not of the log form).
  void Validate() const;
};

LawKind ParseLawKind(const std::string& text);
RhoConvention ParseRhoConvention(const std::string& text);
const char* ToString(LawKind kind);
const char* ToString(RhoConvention convention);

/// The law of one contact: value type, cheap to copy, built per pin and pose.
class ContactLaw {
 public:
  /// cycloid_curvature: signed, 1/mm (+ convex); pin_radius and length in mm;
  /// log_radius_cap resolved (> 0).
  ContactLaw(const ContactSettings& settings, const Material& material, double cycloid_curvature,
             double pin_radius, double length, double log_radius_cap);

  /// A needle roller between both raceways (contact/bearing.hpp: Palmgren's line contact, Harris
  /// and Kotzalas, Rolling Bearing Analysis, 2007; delta = 2 x 3.84e-5 Q^0.9 / l^0.8 mm, the
  /// bearing's own law, RollerLoad's inverse) plus a linear term s Q (mm/N, s may be negative: an
  /// elastic disc body's correction of the raceway's local field, docs/fe_disc.md "The RV disc"):
  ///   delta(Q) = a Q^0.9 + s Q,   a = 7.68e-5 / l^0.8.
  /// With s < 0 the approach rises while its slope 0.9 a Q^-0.1 + s is positive: max_force() is
  /// (0.9 a / -s)^10 (beyond 1e8 N for a steel disc). Throws std::invalid_argument unless l > 0
  /// and s are finite. HalfWidth and MaxPressure are 0 (the bearing reports its own stress).
  static ContactLaw Roller(double roller_length, double linear_compliance);

  double Force(double approach) const;      ///< N; 0 for approach <= 0; max_force() beyond.
  /// The same, warm-started: *hint holds the force of a nearby earlier call (or <= 0: none) and
  /// receives this one. Solvers that sweep the approach of a pin keep one hint per pin.
  double Force(double approach, double* hint) const;
  double Approach(double force) const;      ///< mm; 0 for force <= 0.
  double Stiffness(double approach) const;  ///< dF/d(approach), N/mm; >= 0.
  /// dw/dF at a force, mm/N, closed form (no law inversion): the tangent compliance the coupled
  /// solvers' Newton steps use. Positive below max_force(), 0 at and beyond it (the approach is
  /// capped there); at F <= 0 the right-hand limit (infinite for hertz-line: w ~ F ln(1/F)).
  double Compliance(double force) const;
  /// Approach(force), with Compliance(force) in *compliance: the same numbers, one logarithm for both.
  double Approach(double force, double* compliance) const;
  /// Complementary energy int_0^F delta(f) df, N*mm (the energy solvers' objective).
  double ComplementaryEnergy(double force) const;
  /// Strain energy U(delta) = F delta - E^c(F), N*mm, given the force F = Force(delta) of this
  /// approach; without a log for the log and linear forms (the law eliminates it).
  double StrainEnergy(double approach, double force) const;
  /// Issue 27: the law whose force at every approach is w times this one's, w > 0 (throws
  /// std::invalid_argument otherwise): F_w(delta) = w F(delta), so delta_w(F) = delta(F / w),
  /// E^c_w(F) = w E^c(F / w). Exact by re-parameterisation, no wrapper in the hot path: the
  /// contact length B becomes w B, which keeps the Hertz half-width and pressure at w F those of
  /// this law at F (they depend on F / B alone); the log form's A becomes A + (C/2) ln w (its
  /// seat's likewise), the linear stiffness w k, the sagitta factor a^2 / F a w-th of this one's.
  /// A torque balance with per-pin moment arms other than the kinematic ones (Coulomb friction)
  /// is a frictionless balance of laws so scaled (ltca/analysis/friction.hpp).
  ContactLaw Scaled(double w) const;
  double max_force() const { return max_force_; }      ///< N (infinite for the linear law)
  double max_approach() const { return max_approach_; }  ///< mm
  /// The seat's part of Approach(force) and of ComplementaryEnergy(force) (0 when not seated), mm
  /// and N*mm: the compliance budget's share of the pin seats.
  double SeatApproach(double force) const;
  double SeatComplementaryEnergy(double force) const;
  /// The groove's Hertz half-width at a force, sqrt(4 F rho*_s / (pi B E*_s)), mm (0 unless a
  /// groove seat), and the largest for which its Hertz idealisation is reasonable (a tenth of the
  /// pin radius; infinite unless a groove seat).
  double SeatHalfWidth(double force) const;
  double seat_valid_half_width() const { return seat_valid_half_width_; }

  double equivalent_radius() const { return rho_eq_; }  ///< rho*, mm (may be large: conformal)
  /// Hertz line-contact half-width b = sqrt(4 F rho* / (pi B E*)), Liu eq. 23, mm.
  double HalfWidth(double force) const;
  /// Hertz line-contact maximum pressure p0 = 2 F / (pi b B), MPa.
  double MaxPressure(double force) const;
  /// The largest half-width for which the Hertz (half-space) idealisation behind these laws is
  /// reasonable: a tenth of the smaller radius of the two bodies (the pin and |rho_c|), mm.
  /// Beyond it a result carries a warning, not a different law.
  double valid_half_width() const { return valid_half_width_; }

 private:
  double HertzApproach(double force) const;
  double SagittaApproach(double s) const;  // s = a^2

  // How the approach is computed: linear (F / k_lin_), the log form
  // (2F / (pi B)) [log_a_ - (log_c_ / 2) ln F] (hertz-line, or any law with a seat but sagitta), or
  // sagitta.
  ContactLaw() = default;  // Roller's
  enum class Form { kLinear, kLog, kSagitta, kRoller };
  LawKind kind_;
  Form form_ = Form::kLinear;
  double log_a_ = 0.0, log_c_ = 0.0;
  double seat_a_ = 0.0, seat_c_ = 0.0;  // the seat's part of log_a_, log_c_ (0: no seat)
  double seat_b1_ = 0.0;                 // groove: b_s = seat_b1_ sqrt(F), mm/N^0.5
  double seat_valid_half_width_ = std::numeric_limits<double>::infinity();
  double length_;
  double e_star_;      // MPa
  double rho_eq_;      // mm
  double rho_c_abs_;   // mm (|rho_c|, capped for the log)
  double rho_p_;       // mm
  double cc_, cp_;     // (1 - nu^2) / E, 1/MPa
  double k_lin_ = 0.0; // N/mm
  double hertz_a_ = 0.0;      // A of delta = (2F / (pi B)) [A - (C/2) ln F]
  double sagitta_factor_ = 0; // a^2 = sagitta_factor F
  double roller_a_ = 0.0, roller_s_ = 0.0;  // kRoller: delta = a Q^0.9 + s Q
  double max_force_ = 0.0;
  double max_approach_ = 0.0;
  double valid_half_width_ = 0.0;  // mm
};

}  // namespace ltca::contact
