#pragma once
// Sliding, rolling and friction at one pin-cycloid contact (docs/efficiency.md):
//  - the kinematics of sliding (Jiang 2022 eq. 13-14): the relative velocity of the cycloid and
//    the pin at the contact point, the speed of the contact point over each surface and the
//    entrainment (mean rolling) speed, from the pose's rate of change and the curvatures;
//  - the shape of the contact (Liu's line contact; Jiang eq. 15-19's ellipse, point_contact.hpp);
//  - the film thickness (Pan-Hamrock, Jiang eq. 24-26), the film ratio lambda, the load sharing
//    (Zhu-Hu, Jiang eq. 21), the full-film coefficient from the effective pressure (Jiang eq.
//    22-23) and the mixed coefficient (Jiang eq. 20), with their validity ranges checked.
// Units as everywhere inside: mm, N, MPa, s (speeds mm/s, viscosity MPa*s, alpha 1/MPa).
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ltca/contact/mesh_state.hpp"
#include "ltca/contact/point_contact.hpp"
#include "ltca/geometry/kinematics.hpp"

namespace ltca::contact {

/// Rate of change of the cycloid pose per unit of time (or per radian of crank: the caller
/// chooses; every velocity below is then in the same unit).
struct PoseRate {
  Eigen::Vector2d centre_velocity = Eigen::Vector2d::Zero();  ///< dO_c/dt, mm per unit
  double angular_velocity = 0.0;                              ///< d(rotation)/dt, rad per unit
};

/// The pose's rate at crank theta_f, per radian of crank: a central difference of the model's pose
/// (Liu eq. 14-15 with the assembly errors) over +-step rad; the nominal pose gives
/// e (-sin, cos) theta_f and -d / z_c exactly to the difference's O(step^2).
PoseRate PoseRatePerCrank(const MeshModel& model, double crank, double loaded_rotation, double z, double step = 1e-6);

/// Velocities at one contact point, pins fixed. t = Rot(+90 deg) n is the tangent (n the common
/// normal from the cycloid toward the pin); every tangential figure is signed along t.
struct ContactVelocities {
  double sliding = 0.0;          ///< v_s = t . (v_cycloid - v_pin) at the point (pin at rest), Jiang eq. 13
  double normal = 0.0;           ///< n . (v_cycloid - v_pin): the approach rate, 0 on a conjugate pair
  double point_over_pin = 0.0;   ///< w_p: speed of the contact point over the pin surface (along t)
  double point_over_cycloid = 0.0;  ///< w_c: speed of the cycloid's point over its surface (along t); w_p - v_s in contact
  /// U = -(w_p + w_c) / 2: the mean of the two surfaces' velocities relative to the contact
  /// point (the entrainment or mean rolling speed; its magnitude enters the film thickness).
  double entrainment = 0.0;
  Eigen::Vector2d point_velocity = Eigen::Vector2d::Zero();  ///< dP/dt of the pin's contact point, fixed frame
};

/// The velocities at contact c (its cycloid point, normal, curvatures) of a cycloid at pose `pose`
/// moving at `rate`. The contact point's motion follows from the rotation rate of the common
/// normal, equal on both bodies (Omega = -w_p / r_p on the pin, omega_c + kappa_c w_c on the
/// cycloid): in contact w_p = (kappa_c v_s - omega_c) / (kappa_c + 1 / r_p); with a clearance g
/// the closest points' form. Checked against a finite difference of the contact points (a test).
ContactVelocities Velocities(const PinContact& c, const geometry::Pose& pose, const PoseRate& rate);

/// Jiang eq. 13: |I_cp k| = sqrt(R_b^2 + d^2 - 2 R_b d cos theta_i) - r_p, the distance from the
/// instant centre of the cycloid relative to the pins (the pitch point, at d = e z_p / (z_p - z_c)
/// from O_f on the line of centres) to the contact point of pin `pin`; |v_s| = |omega_c| |I_cp k|
/// on the unmodified pair. For d < 0 (the cycloid outside the pins, beyond Jiang) + r_p.
double PitchPointDistance(const geometry::PairParameters& pair, const geometry::Kinematics& kinematics, int pin,
                          double crank);

/// The shape of the contact: Hertz line (Liu eq. 23, half-width b over the length l) or Hertz
/// ellipse (Jiang eq. 15-19).
struct ContactShape {
  bool point = false;          ///< false: line contact; true: ellipse
  double half_width = 0.0;     ///< line: b, mm; ellipse: the semi-minor axis
  double semi_major = 0.0;     ///< ellipse: a, mm; line: half the contact length
  double max_pressure = 0.0;   ///< p_h, MPa
  double area = 0.0;           ///< 2 b l (line) or pi a b (ellipse), mm^2
};
/// Line contact of force F (N) over length l (mm), equivalent radius rho* (mm) and E* (MPa).
ContactShape LineShape(double force, double length, double equivalent_radius, double e_star);
/// Ellipse from point_contact.hpp (Jiang eq. 15-19).
ContactShape EllipseShape(const RelativeCurvature& curvature, double force, double e_star);

/// The mixed-lubrication inputs (deck [operation] and [friction], docs/efficiency.md).
struct Lubrication {
  double viscosity = 30e-9;           ///< eta_0, MPa*s (Jiang: 30 mPa*s = 30e-9 MPa*s)
  double pressure_viscosity = 0.01;   ///< alpha, 1/MPa (Jiang: 10 GPa^-1)
  double roughness_cycloid = 0.3e-3;  ///< Ra, mm
  double roughness_pin = 0.3e-3;      ///< Ra, mm
  double boundary_coefficient = 0.1;  ///< f_b (Jiang: 0.1)
  double limiting_shear_modulus = 1.0;  ///< G of eq. 23, MPa (Jiang: 1 MPa)
  double power_law_exponent = 0.5;    ///< n of eq. 22-23 (Jiang: 0.5)
  /// The limiting shear stress tau_L = tau_L0 + gamma p of the lubricant (Bair and Winer, J. Lubr.
  /// Technol. 101 (1979) 251-257; Evans and Johnson, Proc. IMechE C 200 (1986) 313-324): the
  /// power-law shear stress of eq. 23 is capped by it point by point. gamma dimensionless, NaN: no
  /// cap (Jiang's model as printed); tau_L0 in MPa (0: tau_L = gamma p, Bair and Winer's form).
  double limiting_shear_coefficient = std::numeric_limits<double>::quiet_NaN();
  double limiting_shear_stress = 0.0;
  bool capped() const { return !std::isnan(limiting_shear_coefficient); }
  /// Composite roughness sigma = sqrt(Ra_c^2 + Ra_p^2), mm (the chosen reading, docs/efficiency.md).
  double CompositeRoughness() const;
};

/// Validity range of the fits (docs/efficiency.md): beyond it a result carries a named warning.
struct MixedLimits {
  static constexpr double kMaxLambda = 3.0;     ///< eq. 21 reaches 1 near lambda = 2.02; fitted for the mixed regime
  static constexpr double kMinLoadParameter = 1e-6;  ///< W*: a decade either side of Jiang's 1e-5 (section 4.4)
  static constexpr double kMaxLoadParameter = 1e-4;
};

/// Everything the mixed model computes at one contact.
struct MixedFriction {
  double material_parameter = 0.0;  ///< G* = alpha E_e (eq. 25)
  double speed_parameter = 0.0;     ///< U* = eta_0 |U| / (E_e R_e)
  double load_parameter = 0.0;      ///< W* = W / (E_e R_e l_e)
  double film_thickness = 0.0;      ///< h_min, mm (eq. 24)
  double lambda = 0.0;              ///< h_min / sigma
  double film_share = 0.0;          ///< f_lambda (eq. 21), in [0, 1]
  double effective_pressure = 0.0;  ///< p_ef, MPa (eq. 22)
  double full_film = 0.0;           ///< f_e (eq. 23), capped by the limiting shear stress when given
  /// f_e of eq. 23 without the cap (equal to full_film when there is none)
  double full_film_uncapped = 0.0;
  double coefficient = 0.0;         ///< f_mix (eq. 20)
  std::vector<std::string> warnings;  ///< named: "jiang.lambda_above_fit", "jiang.load_parameter_outside_fit", ...
};

/// Pan-Hamrock minimum film thickness of a line contact (Jiang eq. 24-26), mm, with the source's
/// constant 1.714 (Jiang prints 1.174) and E' = 2 E* (Jiang's E_e = E / 2(1 - nu^2) read as E*
/// would halve it; docs/efficiency.md). force N, length mm, radius mm, e_star MPa, speed mm/s.
double FilmThickness(const Lubrication& lub, double force, double length, double equivalent_radius, double e_star,
                     double entrainment, MixedFriction* detail = nullptr);
/// Zhu-Hu load sharing, Jiang eq. 21: 1.21 lambda^0.64 / (1 + 0.37 lambda^1.26), capped at 1.
double FilmShare(double lambda);
/// Effective pressure of eq. 22: delta ln(mean of exp(p / delta) over the contact area),
/// delta = 1 / (n alpha); the Hertz ellipsoidal pressure (point) or the semi-elliptic one (line),
/// by quadrature. For the ellipse it equals Jiang's closed form with 2 delta^2 / p_h^2 as the
/// last term (printed 2 delta / p_h^2: a typo; a test).
double EffectivePressure(const Lubrication& lub, double max_pressure, bool point);
/// Jiang eq. 22 in closed form (the ellipse), with the corrected last term.
double EffectivePressureClosedForm(const Lubrication& lub, double max_pressure);
/// The full-film coefficient with the limiting shear stress: f_e = (A / W) mean over the contact
/// area of min(K exp(n alpha p), tau_L0 + gamma p), K = G^(1-n) (eta_0 |v_s| / h)^n, the Hertz
/// pressure p over the ellipse (point) or the line's width; by Simpson's rule split at the
/// crossings of the two curves (found by bisection), so the kink costs no accuracy.
double CappedFullFilm(const Lubrication& lub, double shear_factor, const ContactShape& shape, double force);
/// The mixed coefficient (eq. 20-25) at one contact: force N, shape, equivalent radius and
/// length of the line contact for the film, E* MPa, entrainment and sliding speeds mm/s.
MixedFriction MixedCoefficient(const Lubrication& lub, double force, const ContactShape& shape, double length,
                               double equivalent_radius, double e_star, double entrainment, double sliding);

}  // namespace ltca::contact
