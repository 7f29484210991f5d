#include "ltca/contact/material.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace ltca::contact {
namespace {

void CheckModulus(double value, const char* key) {
  if (!std::isfinite(value) || value < Material::kMinModulus || value > Material::kMaxModulus) {
    throw std::invalid_argument(fmt::format(
        "[material] {} = {}: expected a finite positive modulus from {:g} to {:g} MPa (steel: "
        "about 206000 MPa)",
        key, value, Material::kMinModulus, Material::kMaxModulus));
  }
}

void CheckPoisson(double value, const char* key) {
  if (!std::isfinite(value) || value < 0.0 || value >= 0.5) {
    throw std::invalid_argument(
        fmt::format("[material] {} = {}: expected a Poisson ratio in [0, 0.5)", key, value));
  }
}

}  // namespace

double Material::EquivalentModulus() const {
  return young_modulus * pin_young_modulus /
         (pin_young_modulus * (1.0 - poisson_ratio * poisson_ratio) +
          young_modulus * (1.0 - pin_poisson_ratio * pin_poisson_ratio));
}

void Material::Validate() const {
  CheckModulus(young_modulus, "young_modulus_mpa");
  CheckPoisson(poisson_ratio, "poisson_ratio");
  CheckModulus(pin_young_modulus, "pin_young_modulus_mpa");
  CheckPoisson(pin_poisson_ratio, "pin_poisson_ratio");
  if (!std::isfinite(contact_stress_limit) || contact_stress_limit <= 0.0) {
    throw std::invalid_argument(fmt::format(
        "[material] contact_stress_limit_mpa = {}: expected a finite positive stress in MPa "
        "(default 4000 MPa, ISO 76 for hardened bearing steel)",
        contact_stress_limit));
  }
  if (!std::isfinite(contact_fatigue_limit) || contact_fatigue_limit <= 0.0 || contact_fatigue_limit > 1e5) {
    throw std::invalid_argument(fmt::format(
        "[material] contact_fatigue_limit_mpa = {}: expected a finite positive endurance limit sigma_Hlim in MPa, at most "
        "100000 (default 1500 MPa, ISO 6336-5 case-hardened steel MQ)",
        contact_fatigue_limit));
  }
}

}  // namespace ltca::contact
