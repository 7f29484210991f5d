#pragma once
// Pin bending: every pin is a Timoshenko beam of solid circular section (radius r_p,
// the pin radius) between its two supports in the pin housing, loaded by its contact slices over
// the cycloid's face width. Its compliance couples the slices of one pin: the deflection of slice
// i is sum_j C_ij F_j (mm), C the slice compliance of the pin (mm/N), which enters the contact
// problem as the coupling of LoadProblem::WithCoupling.
//
// Beam: E and nu of the pins (Material::pin_young_modulus, pin_poisson_ratio), G = E / (2 (1 + nu)),
// I = pi r^4 / 4, A = pi r^2, shear coefficient of a solid circle kappa = 6 (1 + nu) / (7 + 6 nu)
// (G. R. Cowper, "The shear coefficient in Timoshenko's beam theory", J. Appl. Mech. 33 (1966)
// 335-340, Table 1). Deflection = bending + shear, the shear strain V / (kappa G A) uniform over
// the section. Supports: simply supported (deflection zero at both ends) or clamped (deflection and
// section rotation zero at both ends; the redundant end moments then depend on the shear
// stiffness, see Deflection()).
//
// Axial positions x are measured from the first support; the cycloid's face B starts at
// face_offset, and slice k of n (the slice model, pin-major point order
// pin * n + slice) occupies [face_offset + k B / n, face_offset + (k + 1) B / n].
//
// Direction: the slice forces of one pin are taken to act along one direction. The normals of
// one pin's slices differ only by the tiny misalignment angle (their cosine is 1 to about 1e-8),
// so the deflection along a slice's normal is the beam deflection.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "ltca/contact/material.hpp"
#include "ltca/contact/mesh_state.hpp"

namespace ltca::contact {

enum class PinSupportKind {
  kSimplySupported,  ///< "simply-supported": deflection zero at both supports, free rotation
  kClamped,          ///< "clamped": deflection and section rotation zero at both supports
};

/// "simply-supported" | "clamped"; throws std::invalid_argument naming `[pins] support`.
PinSupportKind ParsePinSupport(const std::string& text);
const char* ToString(PinSupportKind kind);

/// The [pins] settings of the beam: how a pin is held.
struct PinSupport {
  double span = 0.0;  ///< distance between the two supports, mm (deck: span_mm); > 0
  PinSupportKind support = PinSupportKind::kSimplySupported;  ///< deck: support
  double face_offset = 0.0;  ///< from the first support to face B of the cycloid, mm (deck: face_offset_mm); >= 0
  /// The longest span a deck may give, mm (10 m: far beyond any reducer's pin, and short enough
  /// that the beam's compliance, ~ span^3, stays a finite number).
  static constexpr double kMaxSpan = 1e4;
  /// Throws std::invalid_argument naming the key (`[pins] span_mm`, `face_offset_mm`, `support`),
  /// its value and what is expected unless 0 < span <= kMaxSpan, face_offset >= 0 (both finite), the
  /// support is a known kind, and, for face_width > 0, face_offset + face_width <= span.
  void Validate(double face_width = 0.0) const;
};

/// One pin as a Timoshenko beam. Value type; all lengths mm, forces N, compliances mm/N.
class PinBeam {
 public:
  /// Throws std::invalid_argument for bad settings (PinSupport::Validate), a pin radius that is
  /// not finite and positive, or a pin modulus / Poisson ratio outside E > 0, 0 <= nu < 0.5.
  PinBeam(const PinSupport& support, const Material& material, double pin_radius);

  /// Green's function: deflection at x per unit load at a (both from the first support, in
  /// [0, span]), mm/N; symmetric in x and a (Maxwell). Closed form, b = L - a, phi = EI / (kappa G A):
  ///   simply supported, x <= a:  b x (L^2 - b^2 - x^2) / (6 EI L) + x b / (L kappa G A)
  ///   (x >= a by the mirror image x -> L - x, a -> L - a);
  ///   clamped: the same plus the end moments (sagging positive) of the redundant supports,
  ///   x (L - x) [M_A (2L - x) + M_B (L + x)] / (6 EI L), with
  ///   M_A, M_B = -(a b / 2) [1 / L +- (b - a) / (L^2 + 12 phi)]
  ///   from zero section rotation at both ends (the end moments' uniform shear adds no deflection
  ///   between two supports). phi = 0 gives the Euler-Bernoulli M_A = -a b^2 / L^2.
  double Deflection(double x, double a) const;

  /// C_ij = mean deflection over slice i under 1 N spread uniformly over slice j, n x n, mm/N;
  /// slice j occupies [face_offset + j B / n, face_offset + (j + 1) B / n]. The Green's function
  /// is piecewise cubic in each variable, integrated exactly by Gauss-Legendre (split at the
  /// kink x = a on the diagonal blocks), so sum_j C_ij q B / n is the slice mean of the
  /// uniform-load deflection exactly. Symmetric (stored so) and positive definite. Throws
  /// std::invalid_argument for face_width <= 0, n_slices < 1, or face_offset + face_width > span.
  Eigen::MatrixXd SliceCompliance(double face_width, int n_slices) const;

  /// The same compliance in factored form (the linear-cost coupled solves):
  /// SliceCompliance = loads K^-1 loads^T + diag(local), exactly. K (`stiffness`) is the banded
  /// finite-element stiffness of the pin with Przemieniecki's two-node Timoshenko element (exact at
  /// the nodes), nodes at the supports, face B, every slice boundary and the far face (coinciding
  /// nodes merged), dofs (w, theta) per node with the support's conditions applied (w = 0 at the
  /// supports; clamped also theta = 0). Row j of `loads` (n x dofs) is the consistent load vector
  /// of 1 N spread uniformly over slice j (the slice means of the element's homogeneous shape
  /// functions: 1/2, l/12, 1/2, -l/12), so B K^-1 B^T is the slice mean of the nodal-interpolated
  /// deflection; `local` adds each slice's own fixed-fixed particular solution, l^3 / (720 EI) +
  /// l / (12 kappa G A) for slice length l. Throws as SliceCompliance.
  struct SliceBeam {
    Eigen::SparseMatrix<double> stiffness;  ///< K, dofs x dofs, N/mm (and N*mm/rad), symmetric, both triangles
    Eigen::SparseMatrix<double> loads;      ///< B, n x dofs
    Eigen::VectorXd local;                  ///< E, n, mm/N
  };
  SliceBeam SliceBeamModel(double face_width, int n_slices) const;

  const PinSupport& support() const { return support_; }
  double bending_stiffness() const { return ei_; }  ///< EI, N*mm^2
  double shear_stiffness() const { return kga_; }   ///< kappa G A, N
  /// Cowper's shear coefficient of a solid circular section, 6 (1 + nu) / (7 + 6 nu).
  static double ShearCoefficient(double poisson_ratio);

 private:
  /// The checks SliceCompliance and SliceBeamModel share (std::invalid_argument).
  void ValidateSlices(double face_width, int n_slices) const;
  PinSupport support_;
  double ei_ = 0.0;
  double kga_ = 0.0;
};

/// The block-diagonal coupling of pin bending over contact points grouped by `pin` (any order):
/// the points of one pin, indexed by `slice` 0 .. n - 1 (each once, each of length B / n), get the
/// n x n block beam.SliceCompliance(face_width, n) at their rows and columns; points of different
/// pins are not coupled. Ready for LoadProblem::WithCoupling (mm/N, symmetric, positive
/// definite). Throws std::invalid_argument when a pin's slices are not 0 .. n - 1 or a point's
/// length is not B / n (to 1e-9 relative).
Eigen::SparseMatrix<double> PinBendingCoupling(const std::vector<PinContact>& points, const PinBeam& beam,
                                               double face_width);

/// PinBendingCoupling in factored form: C = loads K^-1 loads^T + diag(local) with K block-diagonal
/// over the pins (one PinBeam::SliceBeamModel per pin, pins in ascending order), loads (points x
/// dofs) placing each point's slice row at its pin's dofs. Same checks as PinBendingCoupling.
struct FactoredPinBending {
  Eigen::SparseMatrix<double> stiffness;
  Eigen::SparseMatrix<double> loads;
  Eigen::VectorXd local;
};
FactoredPinBending PinBendingFactors(const std::vector<PinContact>& points, const PinBeam& beam, double face_width);

}  // namespace ltca::contact
