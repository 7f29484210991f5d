#pragma once
// Hertz point contact (elliptical contact area) for a pin whose axis is tilted against the
// cycloid's by misalignment: Jiang 2022 eq. 15-19, with the complete elliptic integrals of the
// C++ standard library. Jiang's eq. 16 is the Hamrock-Brewe form with his E = E' = 2 E*; his
// eq. 19 as extracted is garbled, the standard relation between the ellipse eccentricity e and
// the principal relative curvatures A <= B (gap s = A x^2 + B y^2) is used:
//   (B - A) / (B + A) = [E(e) (2 - e^2) - 2 K(e) (1 - e^2)] / (E(e) e^2),   b / a = sqrt(1 - e^2),
// solved for e by bisection ("dichotomy", as in Jiang).

namespace ltca::contact {

struct EllipticalContact {
  double semi_major = 0.0;    ///< a, mm
  double semi_minor = 0.0;    ///< b, mm
  double eccentricity = 0.0;  ///< e = sqrt(1 - (b / a)^2), Jiang's psi
  double max_pressure = 0.0;  ///< p_h = 3 P / (2 pi a b), Jiang eq. 15, MPa
};

/// Principal relative curvatures (A, B), 1/mm, of two cylinders whose axes cross at angle
/// crossing (rad); curvatures signed (+ convex). Parallel axes give A = 0 (line contact).
struct RelativeCurvature {
  double a = 0.0;
  double b = 0.0;
};
RelativeCurvature CrossedCylinders(double curvature_1, double curvature_2, double crossing);

/// The contact ellipse under normal force P (N) with equivalent modulus e_star (MPa; 1/E* =
/// sum (1 - nu^2) / E). Throws std::invalid_argument for A <= 0 (a line contact: use the
/// line-contact laws) or B <= 0.
EllipticalContact HertzPointContact(const RelativeCurvature& curvature, double force, double e_star);

}  // namespace ltca::contact
