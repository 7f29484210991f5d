#pragma once
// The disc as a 2D linear-elastic body (docs/fe_disc.md): its outline, bore and holes, meshed
// with 6-node quadratic triangles (gmsh, loaded at run time), and its compliance condensed to
// given boundary points along given directions, relative to the supports: every node of the
// bore clamped (the torque taken out rigidly at the bore, the centre held, as the rigid disc
// holds it). Plain data only: no mesher, sparse-matrix or factorisation type appears here.
// Units: mm, N, MPa; compliance mm/N.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "ltca/geometry/profile.hpp"

namespace ltca::contact {

/// Which 2D idealisation of the disc of thickness B: plane strain (sigma_zz = nu (sigma_xx +
/// sigma_yy), a thick disc held between faces) or plane stress (sigma_zz = 0, a thin free disc).
enum class PlaneModel { kStrain, kStress };

/// A circular hole through the disc (output-pin hole, crank hole), mm in the body frame.
struct DiscHole {
  Eigen::Vector2d centre_mm = Eigen::Vector2d::Zero();
  double radius_mm = 0.0;
};

/// The disc as an elastic body, in its body frame about the disc centre.
struct DiscBodyDesign {
  /// The outline: a closed polygon (first point not repeated), counterclockwise, mm: the modified
  /// profile's points. Empty: a circle of `outer_radius_mm` (an annulus, for the closed forms).
  std::vector<Eigen::Vector2d> outline_mm;
  double outer_radius_mm = 0.0;  ///< Used when `outline_mm` is empty, mm.
  /// The central bore, mm (> 0): its nodes are the support, clamped (u = 0).
  double bore_radius_mm = 0.0;
  std::vector<DiscHole> holes;   ///< Traction-free holes, inside the outline, outside the bore.
  PlaneModel plane = PlaneModel::kStrain;
  double young_modulus_mpa = 206000.0;  ///< E, MPa.
  double poisson_ratio = 0.3;           ///< nu, in [0, 0.5).
  double thickness_mm = 1.0;            ///< B, the face width carried by the 2D section, mm.
  /// Target element edge length away from the refinement points, mm.
  double element_size_mm = 2.0;
  /// Element edge length at the refinement points, mm (<= element_size_mm); it grows linearly
  /// with the distance from the nearest refinement point to element_size_mm at refine_radius_mm.
  double refined_size_mm = 0.25;
  double refine_radius_mm = 5.0;
  std::vector<Eigen::Vector2d> refine_near_mm;  ///< Refinement points (the contacts), mm.

  /// Throws std::invalid_argument naming the field: sizes, radii and constants not finite and
  /// positive, nu outside [0, 0.5), fewer than 3 outline points, a hole crossing the bore.
  void Validate() const;
};

/// A condensation point: the load is a uniform traction of total 1 N along `direction` (made a
/// unit vector) on the boundary arc within `half_width_mm` of the boundary point nearest to
/// `point_mm` (the clamped bore excluded); its displacement is the same traction's work-conjugate
/// mean of the boundary displacement along `direction`. A finite patch, not a nodal force: a point
/// force's displacement on an elastic half-plane diverges like ln(1/h) as the mesh is refined
/// (Flamant; Johnson, Contact Mechanics, 1985, sec. 2.2), so only a distributed load converges.
struct DiscLoadPoint {
  Eigen::Vector2d point_mm = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();
  double half_width_mm = 0.25;
};

/// The condensed compliance and what it took.
struct DiscCompliance {
  /// C(i, j): the displacement of point i along its direction under 1 N at point j along its
  /// direction, mm/N. Symmetric positive definite (Maxwell-Betti).
  Eigen::MatrixXd compliance_mm_per_n;
  int nodes = 0;      ///< Nodes of the T6 mesh.
  int elements = 0;   ///< T6 elements.
  double mesh_seconds = 0.0;       ///< gmsh: geometry, mesh, second order.
  double solve_seconds = 0.0;      ///< Assembly, one CHOLMOD factorisation, the solves.
};

/// The cycloid's real profile (modifications and profile layer applied: geometry::RealPair's
/// profile()) as the disc's outline: a closed counterclockwise polygon in the body frame, mm, every
/// tooth space sampled at `points_per_space` points evenly in u over [-phi_max, phi_max). Throws
/// std::invalid_argument for a tip relief (its caps are not sampled yet), a cycloid that is the
/// outer member (d < 0) or fewer than 8 points per space.
std::vector<Eigen::Vector2d> DiscOutline(const geometry::CycloidProfile& profile, int points_per_space);

/// The disc meshed, assembled and factorised once: condense it at any points, as often as needed
/// (the condensation points along the flanks, a design's cache). Copies share the factorisation;
/// concurrent Condense calls on one body or its copies are safe: their solves take turns on the
/// one CHOLMOD workspace (a thread that needs its own solves in parallel builds its own body).
class DiscBody {
 public:
  /// Meshes the disc (gmsh 4.8, loaded with dlopen: std::runtime_error naming the package to
  /// install when libgmsh.so.4.8 is absent), clamps the bore, assembles and factorises (CHOLMOD).
  /// Throws std::invalid_argument for an invalid design.
  explicit DiscBody(const DiscBodyDesign& design);
  ~DiscBody();
  DiscBody(const DiscBody&);
  DiscBody& operator=(const DiscBody&);

  /// The compliance at `points` (one solve per point, no new factorisation); its nodes, elements
  /// and mesh seconds are the body's, its solve seconds the set-up's factorisation plus these
  /// solves. Throws std::invalid_argument for a point that is not finite or a patch of zero width.
  DiscCompliance Condense(const std::vector<DiscLoadPoint>& points) const;

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
};

/// DiscBody(design).Condense(points).
DiscCompliance CondenseDiscCompliance(const DiscBodyDesign& design,
                                      const std::vector<DiscLoadPoint>& points);

}  // namespace ltca::contact
