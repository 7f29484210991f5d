#pragma once
// Rolling bearings of the reducer stage: the eccentric bearing of a cycloidal drive,
// or the needle bearing of an RV crankshaft in the disc's crank hole, as a force element between
// an inner member (the eccentric) and an outer one (the disc's bore).
//
// Rollers (Harris, T. A., Kotzalas, M. N., Rolling Bearing Analysis, 5th ed., CRC 2007: "Contact
// stress and deformation", Palmgren's line contact; "Distribution of internal loading in
// statically loaded bearings"):
// - one roller-raceway contact of effective length l (mm) under Q (N) approaches by
//   delta = 3.84e-5 Q^0.9 / l^0.8 mm (steel on steel, independent of the roller diameter);
// - a roller between both raceways is two such contacts in series: delta = 7.68e-5 Q^0.9 / l^0.8,
//   Q = K_n delta^(10/9), K_n = (7.68e-5)^(-10/9) l^(8/9);
// - roller j sits at psi_j = phase + 2 pi j / Z (rad, in the outer member's frame); for a
//   displacement u of the inner member relative to the outer one its approach is
//   delta_j = u . (cos psi_j, sin psi_j) - c, c the radial clearance (half Harris's diametral
//   P_d), and it carries Q_j = K_n delta_j^(10/9) where delta_j > 0.
// A linear bearing is a radial spring with the same radial clearance: F = k (|u| - c) beyond it.
//
// Rating life (ISO 281:2007, basic rating life; the mean load of a varying load as in the
// bearing makers' handbooks, e.g. the NSK technical catalogue, "mean equivalent load"):
// L10 = (C / P)^p million revolutions, p = 10/3 for roller bearings, 3 for ball bearings;
// L10h = 1e6 L10 / (60 n) hours at n rpm; for loads P_i over equal steps of a revolution,
// P_m = (sum P_i^p / N)^(1/p).
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ltca::contact {

enum class BearingKind {
  kRigid,    ///< "rigid": no compliance, no clearance
  kLinear,   ///< "linear": radial stiffness and radial clearance
  kRollers,  ///< "rollers": every roller a contact point (Palmgren line contact), radial clearance
};
/// "rigid" | "linear" | "rollers"; throws std::invalid_argument naming `[bearing] kind`.
BearingKind ParseBearingKind(const std::string& text);
const char* ToString(BearingKind kind);

/// A bearing's data (the deck's [bearing], in internal units).
struct BearingSettings {
  static constexpr int kMaxRollers = 200;  ///< a full-complement needle bearing has a few dozen
  BearingKind kind = BearingKind::kRigid;
  double radial_stiffness = 0.0;     ///< N/mm, linear (deck: radial_stiffness_n_per_mm)
  /// mm, the radial play (deck: radial_clearance_mm); negative: a preload, every element pressed by
  /// -c at no load (rollers: K_n (u . e - c)^(10/9) as with play; linear: PreloadedLinearBearing)
  double radial_clearance = 0.0;
  int roller_count = 0;              ///< rollers (deck: roller_count)
  double roller_diameter = 0.0;      ///< mm (deck: roller_diameter_mm)
  double roller_length = 0.0;        ///< mm, effective length l (deck: roller_length_mm)
  double dynamic_load_rating = 0.0;  ///< N, C_r of ISO 281; 0: no life (deck: dynamic_load_rating_n)
  /// mm, rollers: the pitch diameter d_m of the roller set; 0: not given, no load-zone life and no
  /// roller contact stress (deck: pitch_diameter_mm)
  double pitch_diameter = 0.0;
  double static_load_rating = 0.0;   ///< N, C_0r of ISO 76; 0: no static safety (deck: static_load_rating_n)
  /// ISO 281:2007's contamination factor e_C (Table 13), in [0, 1] (deck: contamination_factor); used
  /// only for the modified rating life (a_ISO), i.e. when the oil's kinematic viscosity is given.
  double contamination_factor = kDefaultContaminationFactor;
  /// N, ISO 281:2007's fatigue load limit C_u (deck: fatigue_load_limit_n); 0: ISO 281 Annex B's
  /// estimate from C_0r (FatigueLoadLimitEstimate). Used only for the modified rating life.
  double fatigue_load_limit = 0.0;
  /// e_C's default: ISO 281:2007 Table 13, "normal cleanliness" (oil filtered through a fine filter),
  /// D_pw < 100 mm: 0.6 to 0.5; the lower bound.
  static constexpr double kDefaultContaminationFactor = 0.5;
  /// Throws std::invalid_argument naming the `[bearing]` key, its value and what is expected:
  /// clearance finite (negative: a preload); linear: stiffness finite and > 0; rollers: 3 to kMaxRollers rollers,
  /// diameter and length finite and > 0; the ratings finite and >= 0; a pitch diameter 0 or one
  /// on which the rollers fit (d_m sin(pi / Z) >= D_w, so D_w < d_m).
  void Validate() const;
};

/// Palmgren: the approach of one roller-raceway contact (mm) under `load` (N) over `length` (mm).
double PalmgrenApproach(double load, double length);
/// Its inverse: the load (N) of one contact at `approach` (mm); 0 for approach <= 0.
double PalmgrenLoad(double approach, double length);
/// A roller between both raceways (two contacts in series): Q = K_n delta^(10/9), N; 0 for delta <= 0.
double RollerLoad(double approach, double length);

/// What the bearing does at one displacement u (mm) of the inner member relative to the outer:
/// the force it exerts on the inner member (N, opposing u), its tangent stiffness -dF/du (N/mm,
/// symmetric, positive semidefinite), the elastic energy stored (N*mm) and, for rollers, each
/// roller's load (N, roller j at phase + 2 pi j / Z).
struct BearingResponse {
  Eigen::Vector2d force = Eigen::Vector2d::Zero();
  Eigen::Matrix2d stiffness = Eigen::Matrix2d::Zero();
  double energy = 0.0;
  std::vector<double> roller_load;
};
/// The linear kind preloaded by p > 0 (radial_clearance = -p): the limit of a ring of many equal
/// linear elements pressed by p at no load whose radial stiffness without play is k; 2 k u while
/// |u| <= p (every element works), then softening to k per unit of further travel (derivation in
/// bearing.cpp and docs/stage.md "Preload").
BearingResponse PreloadedLinearBearing(double k, double p, const Eigen::Vector2d& u);
/// Not for kRigid (throws std::invalid_argument: a rigid bearing is a constraint, not a force).
BearingResponse BearingAt(const BearingSettings& bearing, const Eigen::Vector2d& displacement, double phase = 0.0);
/// The same; without roller_loads, BearingResponse::roller_load stays empty (no allocation: the
/// solvers' inner loop).
BearingResponse BearingAt(const BearingSettings& bearing, const Eigen::Vector2d& displacement, double phase,
                          bool roller_loads);

/// The displacement u of the inner member at which the bearing carries `load` (N, the force the
/// inner member puts on the bearing: BearingAt(u).force = -load), by Newton's method on the convex
/// energy E(u) - load . u with backtracking, to 1e-12 of |load| (+ 1e-9 N). Throws
/// std::invalid_argument for kRigid; std::runtime_error if it does not converge in 200 steps.
Eigen::Vector2d BearingDisplacement(const BearingSettings& bearing, const Eigen::Vector2d& load, double phase = 0.0);

/// ISO 281 life exponents.
inline constexpr double kRollerLifeExponent = 10.0 / 3.0;
inline constexpr double kBallLifeExponent = 3.0;
/// The mean equivalent load of loads over equal steps (N): (sum P_i^p / N)^(1/p); NaN when empty
/// or when a load is not finite.
double MeanEquivalentLoad(const std::vector<double>& loads, double exponent = kRollerLifeExponent);
/// ISO 281 basic rating life L10 in millions of revolutions; infinite for P = 0, NaN without a rating.
double RatingLife(double dynamic_load_rating, double equivalent_load, double exponent = kRollerLifeExponent);
/// L10 (millions of revolutions) in hours at `rpm` revolutions per minute of the bearing.
double RatingLifeHours(double life_million_revolutions, double rpm);

/// ISO 281:2007's modified rating life L_10m = a_ISO L_10 (9.3; a_1 = 1 at 90 % reliability) of a
/// radial roller bearing, the systems approach's life modification factor a_ISO from the viscosity
/// ratio kappa = nu / nu_1, the contamination factor e_C and the fatigue load limit C_u.
///
/// The reference kinematic viscosity nu_1 (mm^2/s) of ISO 281:2007 (9.3.3, the viscosity ratio)
/// at `rpm` revolutions per minute of the bearing's rings relative to each other and the pitch
/// diameter D_pw (mm): nu_1 = 45000 n^-0.83 D_pw^-0.5 for n < 1000 r/min, nu_1 = 4500 n^-0.5
/// D_pw^-0.5 for n >= 1000 r/min. NaN unless rpm > 0 and D_pw > 0 (both finite).
double ReferenceViscosity(double rpm, double pitch_diameter_mm);
/// ISO 281:2007 (9.3.3): the formulas hold for 0.1 <= kappa <= 4; kappa > 4 is taken as 4, and
/// kappa < 0.1 lies outside them (taken as 0.1 here, where a_ISO is 0.1, the method's floor).
inline constexpr double kViscosityRatioMin = 0.1;
inline constexpr double kViscosityRatioMax = 4.0;
/// ISO 281:2007 (9.3.3): a_ISO is limited to 50.
inline constexpr double kLifeModificationMax = 50.0;
/// ISO 281:2007's a_ISO of a radial roller bearing (9.3.3, the radial roller bearing formulas):
///   a_ISO = 0.1 [1 - (1.5859 - c / kappa^e) (e_C C_u / P)^0.4]^-9.185,
///   0.1 <= kappa < 0.4: c = 1.3993, e = 0.054381; 0.4 <= kappa < 1: c = 1.2348, e = 0.19087;
///   1 <= kappa <= 4: c = 1.2348, e = 0.071739;
/// kappa clamped to [kViscosityRatioMin, kViscosityRatioMax], the result capped at
/// kLifeModificationMax (also where the bracket reaches 0). `load_ratio` is e_C C_u / P (>= 0;
/// +inf for P = 0 gives the cap). NaN when kappa or load_ratio is NaN or load_ratio < 0.
double LifeModificationFactor(double kappa, double load_ratio);
/// ISO 281:2007 Annex B's simplified estimate of a roller bearing's fatigue load limit (B.20):
/// C_u = C_0r / 8.2 for D_pw <= 100 mm (N). NaN for D_pw > 100 mm, where the standard scales it
/// with D_pw (B.21) and ltca asks for C_u itself, and without C_0r.
double FatigueLoadLimitEstimate(double static_load_rating, double pitch_diameter_mm);
/// The pitch diameter (mm) up to which FatigueLoadLimitEstimate applies.
inline constexpr double kFatigueLoadLimitEstimateMaxPitchDiameter = 100.0;

// Load-zone life: the reference rating life of ISO/TS 16281 in its Lundberg-Palmgren form for
// line contact (Harris, T. A., Kotzalas, M. N., Rolling Bearing Analysis, 5th ed., CRC 2007,
// "Fatigue life: basic theory and rating standards"):
// - per raceway the equivalent roller load over one pass of the rollers, with the Z roller loads
//   Q_j of a load state: Q_e = ((1/Z) sum Q_j^4)^(1/4) for the raceway that turns against the
//   load (each of its points meets every roller), Q_e = ((1/Z) sum Q_j^4.5)^(1/4.5) for the one
//   that stands against it (each point sees the roller loads of its own angle);
// - the raceways' basic dynamic capacities for line contact, Q_c ~ (1 -+ g)^(29/27) / (1 +- g)^(1/4)
//   (inner: upper signs), so Q_c,in / Q_c,out = ((1 - g) / (1 + g))^(29/27 + 1/4), g = D_w / d_m;
// - L = (Q_c / Q_e)^4 per raceway, the bearing's L = (L_in^(-9/8) + L_out^(-9/8))^(-8/9);
// - over the load states of a revolution (equal shares) Palmgren-Miner: 1/L = mean of 1/L_k
//   (ISO 281:2007, variable operating conditions).
// The absolute capacity is not computed from the geometry: the bearing is calibrated on its own
// rating. The load-zone equivalent load P_lz is the stationary radial load under which the same
// bearing without play, inner ring turning against the load, its cage carrying the rollers through
// the load zone, would take the same damage; the load-zone life is ISO 281's (C / P_lz)^(10/3). So
// it equals ISO 281's basic life wherever ISO 281 applies, at any load (zero play makes every roller
// load proportional to the applied load, and the damage goes as its fourth power).

enum class Raceway { kInner, kOuter };
/// "inner" | "outer".
const char* ToString(Raceway raceway);

/// Q_c,inner / Q_c,outer = ((1 - g) / (1 + g))^(29/27 + 1/4), g = D_w / d_m (0 < g < 1).
double RacewayCapacityRatio(double roller_diameter, double pitch_diameter);

/// One load state's roller loads as the raceways see them: (1/Z) sum Q_j^4 (N^4) and
/// (1/Z) sum Q_j^4.5 (N^4.5); Z = the number of loads given.
struct RollerLoadMoments {
  double fourth = 0.0;
  double four_and_half = 0.0;
};
RollerLoadMoments LoadMoments(const std::vector<double>& roller_load);

/// The damage of one revolution in that load state, 1/L in units of Q_c,out = 1 N (N^4): the
/// raceway `turning` takes the exponent-4 equivalent load, the other the exponent-4.5 one;
/// capacity_ratio = RacewayCapacityRatio.
double LundbergPalmgrenDamage(const RollerLoadMoments& moments, double capacity_ratio, Raceway turning);

/// The number of roller phases over one roller pitch the reference state averages (the cage
/// carrying the rollers through a stationary load): phases 2 pi m / (M Z), m = 0 .. M - 1.
inline constexpr int kReferencePhases = 16;

/// The reference: the mean damage per revolution (units of LundbergPalmgrenDamage) of `bearing`
/// without play under a stationary radial load of 1 N, the inner ring turning against it, over
/// kReferencePhases roller phases (each state solved by BearingDisplacement). Requires rollers and
/// a pitch diameter (std::invalid_argument naming the key otherwise).
double LoadZoneReferenceDamage(const BearingSettings& bearing);

/// The load-zone equivalent load (N) of a mean damage per revolution: (damage / reference)^(1/4);
/// NaN when either is not finite or the reference is not > 0.
double LoadZoneEquivalentLoad(double mean_damage, double reference_damage);

/// Hertz's largest pressure (MPa) of the roller's line contact with the inner raceway, the more
/// curved of the two (Johnson, Contact Mechanics, 1985, eq. 4.45: p0 = sqrt(Q E* / (pi l R)),
/// 1/R = 2/D_w + 2/(d_m - D_w), 1/E* = 2 (1 - nu^2) / E), for roller and rings of bearing steel,
/// E = kBearingSteelModulus, nu = kBearingSteelPoisson. Requires rollers and a pitch diameter.
inline constexpr double kBearingSteelModulus = 207000.0;  ///< MPa
inline constexpr double kBearingSteelPoisson = 0.3;
double RollerContactStress(const BearingSettings& bearing, double roller_load);

/// ISO 76:2006's stress basis of C_0 for roller bearings: 4,000 MPa at the centre of the most
/// heavily loaded roller-raceway contact.
inline constexpr double kStaticStressLimitRoller = 4000.0;  ///< MPa

}  // namespace ltca::contact
