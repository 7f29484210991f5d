#pragma once
// Internal unit system of ltca (stated once, also in docs/units.md):
//   length mm, force N, stress and modulus MPa (= N/mm^2), torque N*mm, angle rad.
// Decks and outputs carry their unit in the key name; these are the only conversions.
#include <numbers>

namespace ltca::units {

inline constexpr double kPi = std::numbers::pi;

constexpr double DegToRad(double deg) { return deg * kPi / 180.0; }
constexpr double RadToDeg(double rad) { return rad * 180.0 / kPi; }
constexpr double RadToArcsec(double rad) { return rad * 180.0 * 3600.0 / kPi; }
constexpr double ArcsecToRad(double arcsec) { return arcsec * kPi / (180.0 * 3600.0); }
constexpr double RadToArcmin(double rad) { return rad * 180.0 * 60.0 / kPi; }
constexpr double NmToNmm(double torque_nm) { return torque_nm * 1000.0; }
constexpr double NmmToNm(double torque_nmm) { return torque_nmm / 1000.0; }
constexpr double MmToUm(double mm) { return mm * 1000.0; }
constexpr double UmToMm(double um) { return um / 1000.0; }

}  // namespace ltca::units
