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

#include "ltca/contact/mesh_state.hpp"
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
  /// Indices into `outline_mm` where the outline's curve has a corner or a jump of curvature (a tip
  /// relief's junctions with the flank and its segment's ends, DiscOutline): the mesher's splines
  /// end there instead of running across. Empty: none.
  std::vector<int> outline_corners;
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
/// tooth space sampled at `points_per_space` points evenly in u over [-phi_max, phi_max). With a
/// tip relief (geometry::TipCap) each space's flank is sampled so over [-u_j, u_j) and each tip's cap
/// follows at TipCap::Point's points (w from 1 to -1, evenly in arc length, at most the flank's mean
/// spacing apart and 0.1 rad on the arc; the apex w = 0 among them); `corners`, when given, receives
/// the indices of the junctions and the segment's ends (sorted; empty without a relief). Throws
/// std::invalid_argument for a cycloid that is the outer member (d < 0) or fewer than 8 points per space.
std::vector<Eigen::Vector2d> DiscOutline(const geometry::CycloidProfile& profile, int points_per_space,
                                         std::vector<int>* corners = nullptr);

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

/// How the flank's compliance is condensed (DiscFlankCompliance).
struct DiscFlankGrid {
  /// Condensation points per tooth space, evenly in arc length from u = -phi_max (the same u in
  /// every space): the grid the contacts' coefficients are interpolated on (>= 8). With a tip
  /// relief's caps the flank keeps its share by length and the cap has at least its share, at most
  /// the patch half-width and pi / 16 of its turn apart (DiscFlankCompliance::space_points()).
  int points_per_space = 32;
  /// w0: the half-width of each grid point's uniform load patch, mm (> 0). The boundary is meshed
  /// at w0 along the whole outline.
  double patch_half_width_mm = 0.2;
  /// Condensation points around each of the body's holes (DiscBodyDesign::holes: output-pin or
  /// crank holes), evenly in angle from the hole's +x, each loaded along the hole's outward normal
  /// (into the material: the direction a pin pushes its hole's wall) by the same patch (>= 8).
  int points_per_hole = 48;
};

/// A contact on the wall of one of the body's holes (an output pin in its hole): the hole's index
/// and the direction of the force on the disc in the body frame (from the hole's centre towards
/// the contact point: the hole's outward normal there, into the material), any length.
struct DiscHoleContact {
  int hole = 0;
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();
};

/// The [disc] section: the disc body rigid (every answer as before) or elastic (its FE compliance
/// condensed on the flank, DiscFlankCompliance, coupling the contacts).
struct DiscBodySettings {
  enum class Body { kRigid, kElastic };
  Body body = Body::kRigid;              ///< deck: body = "rigid" | "elastic"
  /// The central bore, mm (deck: bore_radius_mm; required with an elastic body): in the mesh alone
  /// its edge is clamped, the torque taken out rigidly there, the centre held.
  double bore_radius = 0.0;
  PlaneModel plane = PlaneModel::kStrain;  ///< deck: plane = "strain" | "stress"
  double element_size = 3.0;             ///< the body's element size away from the flank, mm (deck: element_size_mm)
  DiscFlankGrid grid;                    ///< deck: grid_points_per_space, patch_half_width_mm
  bool elastic() const { return body == Body::kElastic; }
  /// Throws std::invalid_argument naming the `[disc]` key, its value and what is expected: a bore
  /// that is finite, positive and inside the profile's root circle less 2 element sizes (the
  /// `root_radius` given, mm), an element size from 0.1 to 20 mm, at least 8 grid points per
  /// tooth space (at most 256), a patch half-width from 0.01 to 2 mm and below the element size.
  void Validate(double root_radius) const;
};
const char* ToString(DiscBodySettings::Body body);
const char* ToString(PlaneModel plane);

/// The disc body's compliance along its whole flank, for contacts that move (docs/fe_disc.md,
/// "Local and far field"). The body (its real outline from the profile, the bore clamped) is
/// meshed and factorised once and condensed at a grid of points over every tooth space, each
/// loaded along the inward normal by a uniform patch of half-width w0: K (mm/N) between all grid
/// points, symmetric positive definite. Without holes the body is meshed cyclically symmetric (one
/// tooth space's sector turned z_c times) and only one space's grid points are solved for. With a
/// tip relief (d > 0) the outline has the caps and each space's grid its flank's points then its
/// tip's cap's (space_points()); a contact on a cap (rounding or segment) is interpolated in the
/// cap's w (PinContact::cap_w) as a flank contact is in u. A contact at (tooth space, u) is interpolated linearly in u
/// between its two neighbouring grid points with weights (1 - t, t):
///   C_ab = w_a^T K w_b  (a != b),   C_aa = (1 - t) K_00 + t K_11
/// (the diagonal is interpolated on its own: the product form would dip between grid points by
/// the patches' local part). C = W K W^T + diag(t (1 - t) (e_0 - e_1)^T K (e_0 - e_1)) is
/// positive semidefinite by construction.
///
/// The split (Andersson and Vedmar, J. Sound Vib. 2003; the same idea as Vijayakar's 1991
/// combined surface-integral and FE method): the FE coefficient of a uniform patch of half-width
/// w0 holds the body's far field and the patch's own half-plane part; a Hertz contact of
/// half-width b differs from it, on an elastic half-plane, by the difference of the two local
/// fields alone: u_Hertz,centre - u_uniform,mean = (2F / (pi B)) C_c (ln(4 w0 / b) - 1), C_c =
/// (1 - nu^2) / E (plane strain; Flamant's kernel with Johnson, Contact Mechanics, 1985, eq. 2.19,
/// integrated over both distributions: docs/fe_disc.md). So the disc's approach at a contact is
/// the FE coefficient plus that difference, which is the hertz-line law's cycloid term
/// C_c (ln(4 rho / b) - 1/2) with rho = w0 / sqrt(e) (cycloid_log_radius_mm()): the law keeps the
/// pin's term and this cycloid term, the coupling adds K. Nothing is counted twice.
class DiscFlankCompliance {
 public:
  /// `body` gives the bore, holes, plane, E, nu, thickness (the face width) and the body's
  /// element size; its outline and refinement points are set here from `profile` (the designed
  /// profile: errors of micrometres do not change a body's compliance). Throws
  /// std::invalid_argument for an invalid design or grid, std::runtime_error without gmsh.
  DiscFlankCompliance(const geometry::CycloidProfile& profile, DiscBodyDesign body, DiscFlankGrid grid = {});

  /// rho of the hertz-line law's cycloid term with this body: w0 / sqrt(e), mm.
  double cycloid_log_radius_mm() const;
  /// The coupling of a pose's contact points (pin-major, any slices and one disc): C_ab between
  /// points of the same slice, each slice a plane section of thickness `length`, so K scaled by
  /// thickness / length; 0 between slices and for an edge contact (a cap point too when the body
  /// has no caps). mm/N.
  Eigen::MatrixXd Coupling(const std::vector<PinContact>& points) const;
  /// The coupling of a pose's flank points and hole contacts, in that order (points.size() +
  /// holes.size() square), mm/N. A hole contact carries the whole face width (a pin across the
  /// disc): between it and any point the coefficient is K's, unscaled (a flank slice of thickness
  /// t = B / n, a section of its own, sees a whole-width load's share t / B through its compliance
  /// scaled B / t); flank points among themselves as Coupling(points). A hole contact at angle a
  /// (of its direction) is interpolated linearly in a between the hole's two neighbouring grid
  /// points, its diagonal on its own, as the flank's: positive semidefinite by construction.
  /// Throws std::invalid_argument for a hole index the body does not have.
  Eigen::MatrixXd Coupling(const std::vector<PinContact>& points, const std::vector<DiscHoleContact>& holes) const;
  /// The body's holes (in the order of DiscBodyDesign::holes).
  int hole_count() const { return hole_count_; }
  /// The first grid point of hole h's ring (the flank's grid comes first).
  int hole_grid_start(int h) const { return flank_points_ + h * grid_.points_per_hole; }

  const DiscFlankGrid& grid() const { return grid_; }
  int grid_points() const { return static_cast<int>(k_.rows()); }
  int nodes() const { return nodes_; }
  int elements() const { return elements_; }
  double setup_seconds() const { return setup_seconds_; }  ///< mesh, factorisation, condensation
  /// Whether the body was meshed as one tooth space's sector turned z_c times (no holes): then only
  /// that space's grid points are solved for.
  bool cyclic() const { return cyclic_; }
  /// K, mm/N (the cyclic body's block-circulant K expanded from its generator: 12.5 MB on Liu's pair).
  Eigen::MatrixXd grid_compliance() const;
  /// K(i, j), mm/N: for the cyclic body read from its generator (i in space a, j in space b: the
  /// generator's row of space (a - b) mod z_c, column j's index in its space), the same number.
  double grid_compliance(int i, int j) const {
    if (!cyclic_) return k_(i, j);
    const int m = per_space_;
    const int a = i / m, b = j / m;
    const int shift = a >= b ? a - b : a - b + spaces_;
    return k_(shift * m + (i - a * m), j - b * m);
  }
  /// Grid point g's position and inward unit normal in the body frame, mm.
  Eigen::Vector2d grid_point(int g) const { return points_.col(g); }
  Eigen::Vector2d grid_normal(int g) const { return normals_.col(g); }
  /// The grid's profile parameter j of a tooth space's flank (0 <= j <= flank_intervals(); the last
  /// is phi_max, or with caps the junction u_j). Grid point k space_points() + j is there.
  double grid_u(int j) const { return grid_u_.at(static_cast<std::size_t>(j)); }
  /// The flank's grid intervals in a tooth space: points_per_space, or with caps m_f (their share).
  int flank_intervals() const { return static_cast<int>(grid_u_.size()) - 1; }
  /// Grid points per tooth space: points_per_space; with a tip relief's caps the flank's m_f + 1
  /// points (both junctions), then the cap's (m_c - 1 interior points with a rounding, whose ends
  /// are the flanks' junction points; m_c + 1 of its own with the segment alone, whose junctions
  /// are corners), m_f + m_c = points_per_space.
  int space_points() const { return per_space_; }
  /// Whether the body has a tip relief's caps (their grid points after each space's flank's).
  bool caps() const { return caps_; }
  /// The cap's grid intervals m_c (0 without caps): its points at w = 1 - 2 i / m_c, i = 0 ... m_c
  /// (TipCap::Point's w), the ends shared with the flanks' junction points when the cap is rounded.
  int cap_intervals() const { return cap_intervals_; }
  /// The grid point of tip k's cap point i (0 <= i <= cap_intervals()).
  int cap_grid_point(int tip, int i) const {
    const int slot = cap_slots_.at(static_cast<std::size_t>(i));
    const int k = ((tip % spaces_) + spaces_) % spaces_;
    return slot < per_space_ ? k * per_space_ + slot : ((k + 1) % spaces_) * per_space_ + (slot - per_space_);
  }

 private:
  /// The two grid points around (tooth space, u) of the flank and the second's weight t.
  void Neighbours(int tooth_space, double u, int* first, int* second, double* t) const;
  /// The same on a cap: the contact's tooth space and u (the junction: its sign gives the tip) and w.
  void CapNeighbours(int tooth_space, double u, double w, int* first, int* second, double* t) const;
  /// A contact's two grid neighbours and weight: a flank contact's, or with caps a cap contact's
  /// (rounding or segment); false for an edge, a point of no length, a cap without caps in the body.
  bool OnGrid(const PinContact& p, int* first, int* second, double* t) const;
  /// The same around hole h at the angle of `direction`.
  void HoleNeighbours(int h, const Eigen::Vector2d& direction, int* first, int* second, double* t) const;

  DiscFlankGrid grid_;
  int spaces_ = 0;
  int step_ = 1;        // space k's u = +phi_max meets space (k + step) mod z_c's u = -phi_max
  double phi_max_ = 0.0;
  std::vector<double> grid_u_;  // the grid's u on a tooth space's flank, flank_intervals() + 1 (both ends)
  int per_space_ = 0;           // grid points per tooth space (space_points())
  bool caps_ = false;           // a tip relief's caps (d > 0): each space's grid is its flank's then tip k's cap's
  int cap_intervals_ = 0;       // m_c
  /// Cap point i's slot in tip k's space (k per_space_ + slot); a slot of per_space_ or more is space
  /// k + 1's point slot - per_space_ (the rounded cap's end w = -1: space k + 1's first flank point).
  std::vector<int> cap_slots_;
  double thickness_ = 0.0;
  /// K between the grid points, mm/N. The cyclic body: only its generator, K's first tooth
  /// space's columns (grid points x points_per_space: 1,248 x 32 on Liu's pair, 320 kB, where the
  /// whole K is 12.5 MB and a pose's coupling read it at random); K is block-circulant, K(a m + i,
  /// b m + j) = K((a - b mod z_c) m + i, j) exactly (grid_compliance(i, j)). With holes: K whole.
  Eigen::MatrixXd k_;
  Eigen::Matrix2Xd points_, normals_;
  int nodes_ = 0, elements_ = 0;
  double setup_seconds_ = 0.0;
  bool cyclic_ = false;  // the body without holes: one space's sector meshed and turned
  int flank_points_ = 0;  // the flank's grid points (spaces x space_points()); the holes' follow
  int hole_count_ = 0;
};

}  // namespace ltca::contact
