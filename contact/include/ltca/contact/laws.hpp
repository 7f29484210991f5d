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
  double max_force() const { return max_force_; }      ///< N (infinite for the linear law)
  double max_approach() const { return max_approach_; }  ///< mm

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

  LawKind kind_;
  double length_;
  double e_star_;      // MPa
  double rho_eq_;      // mm
  double rho_c_abs_;   // mm (|rho_c|, capped for the log)
  double rho_p_;       // mm
  double cc_, cp_;     // (1 - nu^2) / E, 1/MPa
  double k_lin_ = 0.0; // N/mm
  double hertz_a_ = 0.0;      // A of delta = (2F / (pi B)) [A - (C/2) ln F]
  double sagitta_factor_ = 0; // a^2 = sagitta_factor F
  double max_force_ = 0.0;
  double max_approach_ = 0.0;
  double valid_half_width_ = 0.0;  // mm
};

}  // namespace ltca::contact
