#pragma once
// Elastic constants of the two bodies (the [material] section of a deck). Units: MPa.

#include "ltca/contact/contact_fatigue.hpp"

namespace ltca::contact {

struct Material {
  double young_modulus = 206000.0;      ///< E_c of the cycloid, MPa.
  double poisson_ratio = 0.3;           ///< nu_c of the cycloid.
  double pin_young_modulus = 206000.0;  ///< E_p of the pins, MPa (deck default: = E_c).
  double pin_poisson_ratio = 0.3;       ///< nu_p of the pins (deck default: = nu_c).
  /// Contact stress above which a result carries a warning, MPa (deck: contact_stress_limit_mpa;
  /// default 4000 MPa, the ISO 76 static limit for roller bearings of hardened bearing steel).
  double contact_stress_limit = 4000.0;
  /// Endurance limit of the flanks in pitting, sigma_Hlim, MPa (deck: contact_fatigue_limit_mpa;
  /// default 1500 MPa, ISO 6336-5:2016 for case-hardened wrought steel of quality MQ).
  double contact_fatigue_limit = 1500.0;
  /// The life factor's curve over the load cycles (deck: contact_life_curve; contact_fatigue.hpp).
  LifeCurve life_curve = LifeCurve::kSteel;

  /// Equivalent modulus E* = E_c E_p / (E_p (1 - nu_c^2) + E_c (1 - nu_p^2)), Liu eq. 24, MPa.
  double EquivalentModulus() const;

  /// Smallest and largest accepted modulus, MPa: soft polymers (a few MPa) to diamond (1.2e6 MPa).
  static constexpr double kMinModulus = 1.0;
  static constexpr double kMaxModulus = 1e7;

  /// Throws std::invalid_argument naming the key for a modulus outside [kMinModulus,
  /// kMaxModulus], a Poisson ratio outside [0, 0.5), or a contact-stress limit or fatigue limit
  /// that is not finite and positive.
  void Validate() const;
};

}  // namespace ltca::contact
