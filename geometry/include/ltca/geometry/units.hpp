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
constexpr double ArcminToRad(double arcmin) { return arcmin * kPi / (180.0 * 60.0); }
constexpr double NmToNmm(double torque_nm) { return torque_nm * 1000.0; }
constexpr double NmmToNm(double torque_nmm) { return torque_nmm / 1000.0; }
/// Torsional rigidity: N*mm/rad to N*m/arcmin (the catalogue unit of a reducer's rigidity).
constexpr double NmmPerRadToNmPerArcmin(double nmm_per_rad) { return NmmToNm(nmm_per_rad) / RadToArcmin(1.0); }
constexpr double MmToUm(double mm) { return mm * 1000.0; }
constexpr double UmToMm(double um) { return um / 1000.0; }
/// Speeds: internal rad/s (the crank's), decks and outputs rpm.
constexpr double RpmToRadPerS(double rpm) { return rpm * 2.0 * kPi / 60.0; }
constexpr double RadPerSToRpm(double rad_per_s) { return rad_per_s * 60.0 / (2.0 * kPi); }
/// Viscosity: internal MPa*s, decks Pa*s; pressure-viscosity coefficient: internal 1/MPa, decks 1/GPa.
constexpr double PaSToMPaS(double pa_s) { return pa_s * 1e-6; }
constexpr double MPaSToPaS(double mpa_s) { return mpa_s * 1e6; }
constexpr double PerGPaToPerMPa(double per_gpa) { return per_gpa * 1e-3; }
constexpr double PerMPaToPerGPa(double per_mpa) { return per_mpa * 1e3; }
/// Power: N*mm/s (torque times rad/s) to W.
constexpr double NmmPerSToW(double nmm_per_s) { return nmm_per_s * 1e-3; }

}  // namespace ltca::units
