#pragma once
// The loaded contact problem at one crank position, shared by every solver, and the one residual
// that judges every solver's answer (torque balance plus complementarity of gap and force).
//
// Unknowns: the loaded rotation psi (in the direction of the torque) and the pin forces F_i.
// The torque is signed: its sign picks the flank. T >= 0 turns the cycloid in the
// model's load direction (docs/conventions.md) and loads the drive flank; T < 0 turns it the other
// way and loads the coast flank. The problem works in the frame of its torque: psi >= 0 turns
// toward the loaded flank, every arm L_i is signed so that L_i > 0 closes a gap in that frame,
// and torque() is |T|. The physical rotation is direction() * psi. With the
// approach delta_i(psi) (exact or linearised, contact/mesh_state.hpp) and the law's deflection
// w_i(F) = law_i.Approach(F), the deformed gap is g_i = w_i(F_i) - delta_i(psi), and a solution has
//   F_i >= 0,  g_i >= 0,  F_i g_i = 0,  sum_i F_i L_i(psi) = T.
// With a compliance coupling C (WithCoupling) the deflection of pin i is
// w_i(F_i) + (C F)_i: g_i = w_i(F_i) + (C F)_i - delta_i(psi).
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/SparseCore>

#include "ltca/contact/laws.hpp"
#include "ltca/contact/material.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/solvers/reducer.hpp"
#include "ltca/solvers/workspace.hpp"

namespace ltca::solvers {

/// Immutable once built: it shares its model, holds no cache, and may be shared across threads;
/// what a solve writes lives in a Workspace (ltca/solvers/workspace.hpp).
class LoadProblem {
 public:
  using ModelPtr = std::shared_ptr<const contact::MeshModel>;
  /// torque in N*mm, signed (the sign picks the flank); the contact length is the face width.
  LoadProblem(ModelPtr model, double crank, const contact::ContactSettings& contact,
              const contact::Material& material, double torque, contact::ContactKinematics kinematics);
  /// The same on a copy of the model (for a one-off problem; a sweep shares one model).
  LoadProblem(const contact::MeshModel& model, double crank, const contact::ContactSettings& contact,
              const contact::Material& material, double torque, contact::ContactKinematics kinematics);

  /// A problem on a given unloaded mesh state (linearised kinematics only): for imposed clearance
  /// distributions, e.g. the closed-form checks.
  LoadProblem(ModelPtr model, contact::MeshState state, const contact::ContactSettings& contact,
              const contact::Material& material, double torque);
  LoadProblem(const contact::MeshModel& model, contact::MeshState state, const contact::ContactSettings& contact,
              const contact::Material& material, double torque);
  /// A problem on the model's own unloaded state at a crank, evaluated beforehand
  /// (model->Evaluate(crank, 0), e.g. kept from the interference check of a sweep): the same
  /// problem as the crank constructor, without evaluating the mesh again.
  LoadProblem(ModelPtr model, contact::MeshState evaluated, const contact::ContactSettings& contact,
              const contact::Material& material, double torque, contact::ContactKinematics kinematics);

  /// Two discs of an RV stage on one pin ring: `first` at the crank and `second` at
  /// crank + pi (contact::EvaluateTwoDiscs), turned by one output rotation psi, so that the sum
  /// over both discs' points of F_i L_i balances T = T_1 + T_2. The points are the first disc's,
  /// then the second's (PinContact::disc = 1); the split T_1 : T_2 is a result (DiscTorques). A
  /// coupling only with a reducer (the stage's elastic bodies, each disc's points on its own: the
  /// reducer system solves it); without one WithCoupling throws. Throws std::invalid_argument unless both discs share the
  /// pin ring (contact::RequireSamePinRing).
  LoadProblem(ModelPtr first, ModelPtr second, double crank, const contact::ContactSettings& contact,
              const contact::Material& material, double torque, contact::ContactKinematics kinematics);
  /// The same on both discs' state at a crank evaluated beforehand (EvaluateTwoDiscs at loaded
  /// rotation 0, e.g. kept from the interference check of a sweep). A null `second` is one disc
  /// (the one-disc constructor on `evaluated`).
  LoadProblem(ModelPtr first, ModelPtr second, contact::MeshState evaluated, const contact::ContactSettings& contact,
              const contact::Material& material, double torque, contact::ContactKinematics kinematics);

  /// The first disc's model (the only one of a single-disc problem).
  const contact::MeshModel& model() const { return *model_; }
  /// 1, or 2 for the two discs of an RV stage.
  int disc_count() const { return second_ == nullptr ? 1 : 2; }
  /// The model of disc 0 or 1, and the crank angle it is evaluated at (rad).
  const contact::MeshModel& DiscModel(int disc) const { return disc == 0 ? *model_ : *second_; }
  double DiscCrank(int disc) const { return disc == 0 ? crank_ : crank_ + contact::kSecondDiscCrankOffset; }
  /// A linearised problem with |T| on `state`, a state of this problem's points with the arms
  /// already signed for this frame (compatibility's re-linearisation): the same discs.
  LoadProblem LinearisedOn(contact::MeshState state) const;
  /// This problem under linearised kinematics about its base state: what LinearisedOn(base_state())
  /// gives, with the base laws copied instead of built again. Uncoupled problems only.
  LoadProblem Linearised() const;
  /// Per disc, the torque its points carry at rotation psi, sum F_i L_i(psi), N*mm, signed as T
  /// (T_1 + T_2 = T at a balanced solution).
  std::vector<double> DiscTorques(double psi, const std::vector<double>& forces, Workspace& workspace) const;
  const ModelPtr& shared_model() const { return model_; }
  /// Unique per constructed problem (copies share it): keys the workspace's foot points.
  std::uint64_t id() const { return id_; }
  double crank() const { return crank_; }
  /// |T|, N*mm: what the solvers balance.
  double torque() const { return torque_; }
  /// +1 when T >= 0 (drive flank, the model's load direction), -1 when T < 0 (coast flank).
  double direction() const { return direction_; }
  /// T as given, N*mm.
  double signed_torque() const { return direction_ * torque_; }
  /// One pin at rotation psi of this problem's frame, searched from `near` (a contact of the same
  /// pin, e.g. from base_state()): the geometry at the physical rotation direction() * psi, with
  /// the arm signed for this frame.
  contact::PinContact EvaluatePin(const contact::PinContact& near, double psi) const;
  /// The same with the point's disc rotated by phi (this problem's frame) and its centre moved by
  /// `centre_shift` (fixed frame, mm): a reducer stage's floating disc (exact kinematics).
  contact::PinContact EvaluatePin(const contact::PinContact& near, double phi, const Eigen::Vector2d& centre_shift) const;
  /// The contact law of a point (as the problem's own: its curvature, pin radius and length); the
  /// point must not be an edge point.
  contact::ContactLaw LawOf(const contact::PinContact& pin) const;
  contact::ContactKinematics kinematics() const { return kinematics_; }
  /// A preloaded pair: pins overlap the cycloid at the theoretical position (beyond the model's
  /// interference tolerance) and no rotation of the disc about its held centre frees them all
  /// (contact::JamReport non-empty), so both flanks are pressed at zero torque and the balance
  /// sum_i F_i L_i = T runs over the pins of both signs of L_i (docs/solvers.md "Two flanks").
  bool preloaded() const;
  /// Whether a pin overlaps the cycloid at the theoretical position beyond the model's
  /// interference tolerance (a reducer stage's floating disc may still seat itself by translating).
  bool overlapping() const;
  /// This problem at `fraction` (0 .. 1) of its torque, in this problem's frame (its arms keep their
  /// sign): the preload state of a stage (LoadSolver's stage path). The same points, laws, reducer
  /// and coupling.
  LoadProblem Unloaded(double fraction = 0.0) const;
  int point_count() const { return static_cast<int>(base_.pins.size()); }
  /// The unloaded state (psi = 0, arms signed for this problem's frame) and its laws.
  const contact::MeshState& base_state() const { return base_; }
  const std::vector<contact::ContactLaw>& base_laws() const { return base_laws_; }
  const contact::ContactSettings& contact_settings() const { return contact_; }
  /// The largest cycloid radius in the hertz-line logarithm, mm: [contact] log_radius_cap_mm, or
  /// the pin-circle radius when the deck leaves it 0 (every law of the problem takes this one).
  double log_radius_cap() const { return log_radius_cap_; }
  const contact::Material& material() const { return material_; }

  /// Coupled compliance: the deflection of pin i is its law's w_i(F_i) plus
  /// (C F)_i, C a sparse symmetric positive semidefinite n x n matrix over the pins, mm/N (e.g. pin
  /// bending, where one pin's force moves its neighbours). Returns a copy of this problem with C
  /// (the same model, state, laws and id). A 0 x 0 matrix, or one without a non-zero entry,
  /// means no coupling: every number is then exactly that of the uncoupled problem. Throws
  /// std::invalid_argument naming what is wrong unless C is square, n x n (n = point_count()),
  /// finite, symmetric to 1e-12 relative to its largest entry, and positive semidefinite to a
  /// rounding tol = max(1e-12, 8 n eps) of its scale: up to 200 pins the smallest eigenvalue
  /// (Eigen's SelfAdjointEigenSolver on the dense matrix) is at least -tol times the largest
  /// magnitude; beyond, a sparse LDL^T (Eigen's SimplicialLDLT) of C + tol s I, s the largest
  /// absolute row sum, has only positive pivots. Stored symmetrised, (C + C^T) / 2, explicit
  /// zeros dropped.
  LoadProblem WithCoupling(Eigen::SparseMatrix<double> coupling) const;
  /// A coupling checked once as WithCoupling checks it, to be shared by the problems of one point
  /// layout (a sweep: pin bending's matrix does not change with the crank). The matrix is nullptr
  /// for no coupling.
  /// The coupling in factored form (pin bending): C = loads K^-1 loads^T + diag(local)
  /// exactly, K sparse symmetric positive definite (banded per pin), loads points x dofs. With it
  /// the coupled solves of `bisection` and `compatibility` work in O(points) per Newton step
  /// (Woodbury on the active set, CHOLMOD on K + B_A^T (D + E)_A^-1 B_A); everything else uses
  /// the matrix C, which must be the product (the caller's promise; checked only for sizes).
  struct CouplingFactors {
    Eigen::SparseMatrix<double> stiffness;  ///< K, dofs x dofs, both triangles
    Eigen::SparseMatrix<double> loads;      ///< B, points x dofs
    Eigen::VectorXd local;                  ///< E, per point, >= 0
  };
  struct CheckedCoupling {
    std::shared_ptr<const Eigen::SparseMatrix<double>> matrix;
    int points = 0;
    std::shared_ptr<const CouplingFactors> factors;  ///< nullptr: C given only as a matrix
    /// The same C dense, when it was given dense (a small coupling made per pose, the elastic
    /// disc body's): the dense kernel of the coupled solves takes it as it is. nullptr otherwise.
    std::shared_ptr<const Eigen::MatrixXd> dense;
  };
  static CheckedCoupling CheckCoupling(Eigen::SparseMatrix<double> coupling, int points);
  /// The same with the factored form of the same C; throws std::invalid_argument when the
  /// factors' sizes do not fit (K square, loads points x K's size, local of size points, finite,
  /// >= 0) or K is not positive definite (its LDL^T); C's own positive semidefiniteness then
  /// follows from the form and is not checked again (the O(n^3) check of WithCoupling), the
  /// other checks of C (square, finite, symmetric) are made.
  static CheckedCoupling CheckCoupling(Eigen::SparseMatrix<double> coupling, int points, CouplingFactors factors);
  /// The caller's word that C is positive semidefinite by construction, which it must be able to
  /// show from how C is made: a sum of Gram forms W K W^T with K positive semidefinite (a
  /// condensed finite-element compliance L^T K_fe^-1 L, K_fe factorised positive definite) and of
  /// non-negative diagonals (contact::DiscFlankCompliance::Coupling), plus couplings checked
  /// before. For a coupling made anew at every crank position, where the O(n^3) eigenvalue check
  /// of WithCoupling would cost more than the solve. Every other check of WithCoupling is made
  /// (square, points x points, finite, symmetric to 1e-12 relative), and C is stored the same way.
  struct PositiveSemidefiniteByConstruction {};
  static CheckedCoupling CheckCoupling(Eigen::SparseMatrix<double> coupling, int points,
                                       PositiveSemidefiniteByConstruction);
  /// The same for C given dense (the elastic disc body's W K W^T, made per pose): the same checks
  /// on the dense matrix (square, points x points, finite, symmetric to 1e-12 relative), stored
  /// the same way (the sparse matrix: (C + C^T) / 2 without its zeros, the very numbers the
  /// sparse overload stores), and the dense (C + C^T) / 2 kept beside it (CheckedCoupling::dense)
  /// for the dense kernel: no transpose of a sparse matrix, no conversion back to dense.
  static CheckedCoupling CheckCoupling(Eigen::MatrixXd coupling, int points, PositiveSemidefiniteByConstruction);
  /// The same as WithCoupling, without checking again; throws std::invalid_argument when the
  /// coupling was checked for another number of points.
  LoadProblem WithCoupling(const CheckedCoupling& coupling) const;
  bool has_coupling() const { return coupling_ != nullptr; }

  /// Issue 27: a copy whose point i's law carries scales[i] times its force at every approach
  /// (contact::ContactLaw::Scaled): its balance sum_i s_i F_i(delta_i) L_i = T is the balance of
  /// the unscaled forces F_i with the arms s_i L_i (Coulomb friction's moment, analysis/friction).
  /// A solver's forces on it are s_i F_i; its stresses are the contacts' (the scaled law's length
  /// keeps F / B). Linearised kinematics, uncoupled, the mesh alone: there the laws are the
  /// problem's own (exact kinematics rebuilds them at each rotation). Throws
  /// std::invalid_argument otherwise, or unless scales holds point_count() finite numbers above 0.
  /// The same points, arms, clearances and id.
  LoadProblem WithLawScales(const std::vector<double>& scales) const;
  /// Whether WithLawScales can be asked: linearised, uncoupled, no reducer.
  bool scalable_laws() const {
    return kinematics_ == contact::ContactKinematics::kLinearised && coupling_ == nullptr && reducer_ == nullptr;
  }

  /// The reducer stage (ltca/solvers/reducer.hpp): a copy of this problem whose discs
  /// float on their bearings and drive the output member through the stage's output elements, T
  /// on the output member. Validates the settings against the pair (std::invalid_argument naming
  /// the key); nullptr: no reducer (the mesh alone, the disc centres fixed).
  LoadProblem WithReducer(std::shared_ptr<const ReducerSettings> stage) const;
  /// A copy of this stage problem with loads on its discs and output member besides T
  /// (ReducerSystem; ltca/solvers/reducer.hpp, StageLoads). Throws std::invalid_argument without a
  /// stage, for more discs than the problem has, or a load that is not finite.
  LoadProblem WithStageLoads(StageLoads loads) const;
  /// The loads besides T, or nullptr (none).
  const StageLoads* stage_loads() const { return stage_loads_.get(); }
  /// The elastic disc body of a stage whose output elements sit on the body (docs/fe_disc.md "The
  /// stage", "The RV disc"): the coupled set is the problem's points followed by one contact per
  /// output pin (disc by disc, pin by pin), or for a stage of crankshafts on needle rollers one per
  /// roller (disc by disc, crank by crank, roller by roller). `total` is the coupling over that set (the problem's own coupling,
  /// pin bending and the body's flank part, in its top-left block; the body's rows and columns of
  /// the holes beside it); `body` the body's part alone (the compliance budget's disc_body group).
  struct StageBodyCoupling {
    std::shared_ptr<const Eigen::SparseMatrix<double>> total;
    std::shared_ptr<const Eigen::SparseMatrix<double>> body;
    int output_points = 0;  ///< the coupled output-pin (or roller) contacts after the problem's points
  };
  /// A copy of this stage problem with the body's coupling over its points and output pins (or
  /// rollers). Throws std::invalid_argument without a stage of output pins or a stage of
  /// crankshafts on roller bearings, without the problem's own
  /// coupling (the top-left block, which must equal it), or for matrices of other sizes.
  LoadProblem WithStageBodyCoupling(StageBodyCoupling coupling) const;
  /// The body's stage coupling, or nullptr (the rigid disc, or the mesh alone).
  const StageBodyCoupling* stage_body_coupling() const { return stage_body_.get(); }
  /// The stage, or nullptr for the mesh alone.
  const ReducerSettings* reducer() const { return reducer_.get(); }
  bool has_reducer() const { return reducer_ != nullptr; }
  /// The coupling matrix, or nullptr when uncoupled.
  const Eigen::SparseMatrix<double>* coupling() const { return coupling_.get(); }
  /// The factored form of the coupling, or nullptr when it came only as a matrix.
  const std::shared_ptr<const CouplingFactors>& coupling_factors() const { return coupling_factors_; }
  /// The coupling dense, when it was checked dense (CheckedCoupling::dense); nullptr otherwise.
  const Eigen::MatrixXd* coupling_dense() const { return coupling_dense_.get(); }

  /// Per-pin state at rotation psi: linearised (frozen geometry) or exact (re-evaluated).
  struct PinAt {
    double approach = 0.0;  ///< delta_i(psi), mm
    double arm = 0.0;       ///< L_i(psi), mm
    bool edge = false;
    const contact::ContactLaw* law = nullptr;  ///< nullptr for an edge contact
  };
  /// Evaluates every pin at psi; laws for the exact kinematics are rebuilt into the scratch (the
  /// pointers stay valid until its next use). Exact kinematics searches every foot point from the
  /// workspace's last one for this problem.
  std::vector<PinAt> At(double psi, Workspace& workspace, std::vector<contact::ContactLaw>* scratch) const;
  /// The same into *pins, whose storage is reused (no allocation in a solver's inner loop).
  void At(double psi, Workspace& workspace, std::vector<contact::ContactLaw>* scratch, std::vector<PinAt>* pins) const;
  /// Which pins At evaluates under exact kinematics. kAll: every pin at psi. kLoadedOnly (a
  /// solver's trials, where only the pressed pins matter): a pin whose last evaluated clearance c
  /// at psi' is so large that no rotation by |psi - psi'| can close it is not searched again (its
  /// clearance moves at most rho |psi - psi'|, rho the distance of its centre from the disc's
  /// centre of rotation: the distance to the profile is 1-Lipschitz in the pin's position); it is
  /// given the largest approach it can have, -(c - rho |psi - psi'|) < 0, and carries no force.
  /// Its approach and arm are then bounds, not values: the forces and torque are exact, the
  /// unloaded pins' approaches are not (ask kAll for those). kNear (an iterate a solver will
  /// confirm with kLoadedOnly before it trusts it): besides, a pin whose approach extrapolated from
  /// its last search with that search's arm, a + L (psi - psi'), stays below minus half its change
  /// and a second-order allowance (rho (psi - psi'))^2 (per mm of curvature of the gap) is not
  /// searched either and is given that estimate, which is not a bound. Linearised kinematics: no
  /// difference.
  enum class Freshness { kAll, kLoadedOnly, kNear };
  /// Exact kinematics: every contact point searched at psi (from the workspace's last foot points),
  /// as EvaluatePin gives them, kept in the workspace: a later At(psi) on the same workspace
  /// searches nothing again. The reference is valid until the workspace's next evaluation.
  const std::vector<contact::PinContact>& ExactPins(double psi, Workspace& workspace) const;
  void At(double psi, Workspace& workspace, std::vector<contact::ContactLaw>* scratch, std::vector<PinAt>* pins,
          Freshness freshness) const;

  /// Output torque sum F_i(delta_i(psi)) L_i(psi), N*mm (forces of the law at each approach).
  double OutputTorque(double psi, Workspace& workspace) const;
  /// The same with a fresh workspace (for checks outside a solve).
  double OutputTorque(double psi) const;

  /// How finely an approach is resolved in double precision, mm: 0 for linearised kinematics
  /// (frozen geometry, the rounding of L psi - c is covered by TorqueResolution); for exact
  /// kinematics the closest-point search in coordinates of size R_p resolves a gap to about
  /// 16 eps R_p (2.3e-13 mm at R_p = 64 mm), which matters only for deformations near 1e-10 mm
  /// (torques of 1e-6 N*m, cases/hard/tiny_torque.toml).
  double GapResolution() const;

  /// Smallest torque change the arithmetic can resolve at psi, N*mm: sum k_i L_i^2 times the
  /// spacing of doubles at psi (x4), plus sum k_i |L_i| times GapResolution(). Below it no solver
  /// can balance the torque any closer.
  double TorqueResolution(double psi, Workspace& workspace) const;
  /// The same from the pins already evaluated at psi (At(psi)), without evaluating them again;
  /// with their forces (one a pin, the laws' at those approaches) also without inverting a law.
  double TorqueResolution(double psi, const std::vector<PinAt>& pins, const std::vector<double>* forces = nullptr) const;

  /// The largest torque the contact laws can carry at the unrotated geometry: every pin whose gap
  /// closes at its law's largest force, sum F_max,i L_i, N*mm (infinite for the linear law).
  double TorqueCapacity() const;

  /// The convergence rule every solver shares: the output torque is within tolerance of T, or as
  /// close as one ulp of the rotation can get (TorqueResolution). The resolution costs a full
  /// evaluation, so it is only consulted once the miss is below 1e-6 T (+ 1e-6 N*mm): the floor
  /// is ulp-sized, far below that for any torque the laws are meant for.
  bool Balanced(double psi, double torque_out, double tolerance, Workspace& workspace) const;
  /// The same rule from the pins already evaluated at psi (At(psi)): a solver that keeps its
  /// accepted evaluation need not evaluate the geometry at psi again for the resolution.
  bool Balanced(double psi, double torque_out, double tolerance, const std::vector<PinAt>& pins,
                const std::vector<double>* forces = nullptr) const;

  /// Rotation of first contact in the load direction (the smallest closing rotation), rad. The
  /// pin ring's alone: a stage's free play also takes up its holes' and bearings' clearances
  /// (analysis::StiffnessRunner solves it).
  double FirstContactRotation() const;

  /// Where the loaded rotation must lie (the shared judge's range check):
  /// first contact <= psi <= the rotation at which any single pin alone would carry the whole
  /// torque (more loaded pins only turn the cycloid less): min over pins of the closing rotation
  /// plus w(T / L) / L (rigorous for linearised kinematics, first order in the deformation for
  /// exact kinematics; the judge allows for that), and window is contact::RotationWindow.
  /// Coupled, a loaded neighbour adds to pin m's deflection (C_mj > 0), so more loaded pins may turn
  /// the cycloid more: pin m's term becomes the closing rotation plus
  /// [w_m(T / L_m) + C_mm T / L_m + T max_{j != m} max(C_mj, 0) / L_j] / L_m, j over the pins that
  /// can carry load (a law, arm > 0); rigorous for linearised kinematics when every loaded pin
  /// has a positive arm: loaded or not, L_m psi - c_m <= w_m(F_m) + C_mm F_m + sum_{j != m} C_mj F_j
  /// with F_m <= T / L_m and sum_j L_j F_j = T. First contact stays a lower bound:
  /// sum_i F_i (L_i psi - c_i) = sum_i F_i w_i + F^T C F >= 0.
  struct RotationRange {
    double first_contact = 0.0;  ///< rad
    double single_pin = 0.0;     ///< rad (infinite when no pin has a law and an arm)
    double window = 0.0;         ///< rad, |psi| beyond it is a pin jumping teeth
  };
  RotationRange LoadedRotationRange() const;

 private:
  void BuildBaseLaws();
  /// closing_, first_contact_ and single_pin_ from the base state under this problem's kinematics.
  void ComputeClosings();
  /// Closing rotation of a pin of base_ (this problem's frame), rad.
  double Closing(const contact::PinContact& pin) const;
  double SinglePinBound() const;  // LoadedRotationRange's upper end, with the coupling's terms
  /// The workspace's foot points, bound to this problem (from base_ at no rotation when new).
  Workspace::FootPoints& BoundFootPoints(Workspace& workspace) const;
  /// The pose of one rotation, taken once for the pins of one disc and section that a loop over
  /// the pins evaluates in turn (EvaluatePin takes it anew for every pin).
  struct PoseAt {
    int disc = -1;
    double z = std::numeric_limits<double>::quiet_NaN();
    geometry::PoseFrame frame;
  };
  /// EvaluatePin(near, psi) with the pose taken from `pose` when it is of near's disc and section
  /// (the same contact, bit for bit).
  contact::PinContact EvaluatePin(const contact::PinContact& near, double psi, PoseAt* pose) const;
  /// Entry i of `feet` searched at psi (from its extrapolated foot point), with its slope updated.
  void SearchPin(Workspace::FootPoints& feet, std::size_t i, double psi, PoseAt* pose) const;

  ModelPtr model_;
  ModelPtr second_;  // the second disc of a two-disc stage, nullptr for one disc
  std::uint64_t id_;
  double crank_;
  contact::ContactSettings contact_;
  contact::Material material_;
  double torque_;     // |T|
  double direction_;  // sign of T (+1 for zero)
  contact::ContactKinematics kinematics_;
  double log_radius_cap_;
  contact::MeshState base_;
  std::vector<contact::ContactLaw> base_laws_;  // edge pins get a placeholder (never used)
  double first_contact_ = 0.0;  // rad, see BuildBaseLaws
  double single_pin_ = 0.0;     // rad
  // Exact kinematics on the analytic surface: per point, the distance of its pin's centre from
  // the disc's centre of rotation, mm (the rate bound of At's kLoadedOnly); empty otherwise.
  std::vector<double> reach_;
  std::vector<double> closing_;  // rad, per pin (infinite where the arm cannot close it), see BuildBaseLaws
  std::shared_ptr<const Eigen::SparseMatrix<double>> coupling_;  // nullptr: uncoupled
  std::shared_ptr<const CouplingFactors> coupling_factors_;      // nullptr: none (or uncoupled)
  std::shared_ptr<const Eigen::MatrixXd> coupling_dense_;        // coupling_ dense when checked dense
  std::shared_ptr<const ReducerSettings> reducer_;                   // nullptr: the mesh alone
  std::shared_ptr<const StageLoads> stage_loads_;                     // nullptr: none besides T
  std::shared_ptr<const StageBodyCoupling> stage_body_;               // nullptr: no body on the stage's elements
};

/// The forces of the laws at the approaches of `pins`, their torque, and whether a pressed pin sits
/// on a tip corner (edge) or beyond its law's range (saturated). hints: per-pin warm starts of the
/// law inversions (see ContactLaw::Force), or nullptr.
struct Loading {
  std::vector<double> force;  ///< N
  double torque = 0.0;        ///< N*mm
  bool edge = false;
  bool saturated = false;
};
Loading LoadAt(const std::vector<LoadProblem::PinAt>& pins, std::vector<double>* hints = nullptr);
/// The same into *out, whose force storage is reused.
void LoadAt(const std::vector<LoadProblem::PinAt>& pins, std::vector<double>* hints, Loading* out);

/// Pins that can carry load in the linearisation about psi: those whose remaining gap closes
/// before the rotation at which any single pin alone would carry the whole torque (a rigorous
/// upper bound of the loaded rotation: more loaded pins only turn the cycloid less). Li Fig. 5's
/// "maximum deformation". Returns indices into `pins`. Assumes diagonal compliance (no
/// coupling): with coupling the bound does not hold (see LoadedRotationRange).
std::vector<std::size_t> CandidatePins(const std::vector<LoadProblem::PinAt>& pins, double torque, double min_arm);

/// The shared judge: residuals of a candidate (psi, F) recomputed from the problem data, with the
/// coupled gap when the problem has a coupling.
struct Residuals {
  double torque_relative = 0.0;     ///< |sum F_i L_i - T| / max(T, 1 N*mm), less what the arithmetic resolves
  /// |sum F_i L_i - T| / |T| as the forces carry it at the pose they act in, nothing subtracted and
  /// no floor on T: the share of the torque the forces miss (0 for T = 0). Above the acceptance
  /// while torque_relative is within it, the balance is limited by the resolution of the geometry
  /// in double precision, and the solve says so in a warning.
  double torque_miss_relative = 0.0;
  double force_violation_n = 0.0;   ///< max(0, -F_i), N
  double gap_violation_mm = 0.0;    ///< max(0, -g_i), mm
  double complementarity_nmm = 0.0; ///< max |F_i g_i|, N*mm
  /// A stage: the largest imbalance of a disc's forces (over the largest element force)
  /// or of a moment (each disc's, the output member's, over T); 0 for the mesh alone.
  double balance_relative = 0.0;
  /// One normalised number: the torque residual, and the others scaled by the largest force and
  /// the largest approach of the solution.
  double Normalised() const { return normalised; }
  double normalised = 0.0;
};
Residuals ComputeResiduals(const LoadProblem& problem, double psi, const std::vector<double>& forces,
                           Workspace& workspace);
/// The same with a fresh workspace (for checks outside a solve).
Residuals ComputeResiduals(const LoadProblem& problem, double psi, const std::vector<double>& forces);

}  // namespace ltca::solvers
