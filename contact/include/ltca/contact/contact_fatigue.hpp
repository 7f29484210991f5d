#pragma once
// Pitting (contact) fatigue of the pin-cycloid contact: the allowable contact stress over the
// number of load cycles, by ISO 6336-2:2006's life factor Z_NT (method B, clause 10, the curves of
// its life-factor table) on a material's endurance limit sigma_Hlim (ISO 6336-5:2016, e.g. 1500
// MPa for case-hardened wrought steel of quality MQ). The other factors of the permissible stress
// (lubricant Z_L, speed Z_v, roughness Z_R, work hardening Z_W, size Z_X) are taken as 1: the
// rating compares ltca's computed Hertz pressure with sigma_Hlim Z_NT, as ISO 6336-2's
// sigma_HP = sigma_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X / S_Hmin does with those factors at 1
// (docs/stage.md, "Contact fatigue").

namespace ltca::contact {

/// The curves of ISO 6336-2:2006's life factor Z_NT (log-log straight lines between the points):
///   kSteel:         St, V, GGG (perl., bai.), GTS (perl.), Eh, IF: 1.6 up to 1e5 cycles, 1.0 at
///                   5e7, 0.85 at 1e10 and beyond;
///   kSteelLimitedPitting: the same materials when some pitting is permitted: 1.6 up to 6e5,
///                   1.3 at 1e7, 1.0 at 1e9, 0.85 at 1e10 and beyond;
///   kNitrided:      GG, GGG (ferr.), NT (nitr.), NV (nitr.): 1.3 up to 1e5, 1.0 at 2e6, 0.85 at 1e10;
///   kNitrocarburized: NV (nitrocar.): 1.1 up to 1e5, 1.0 at 2e6, 0.85 at 1e10.
/// Beyond 1e10 cycles the factor stays 0.85 (the standard's value without optimum conditions).
enum class LifeCurve { kSteel, kSteelLimitedPitting, kNitrided, kNitrocarburized };

/// "steel", "steel-limited-pitting", "nitrided", "nitrocarburized".
const char* ToString(LifeCurve curve);

/// Z_NT at `cycles` load cycles (> 0): the static value at and below the curve's first point.
double LifeFactor(LifeCurve curve, double cycles);

/// The load cycles to pitting at a contact stress (MPa) on a material of endurance limit
/// sigma_hlim (MPa): the N with sigma_hlim Z_NT(N) = stress on the falling part of the curve;
/// +inf at or below sigma_hlim Z_NT(1e10) (the curve is flat there: no damage). Above the static
/// value sigma_hlim Z_NT(0) the first sloped segment is extended to fewer cycles than the static
/// point, as ISO 6336-6:2019's worked load spectrum does (Annex C, Table C.2: Z_NT 1.61 at 90,500
/// cycles); the static strength itself is judged by the safety factor, whose Z_NT stays flat there
/// (LifeFactor). Stress <= 0: +inf.
double CyclesToPitting(LifeCurve curve, double sigma_hlim, double stress);

}  // namespace ltca::contact
