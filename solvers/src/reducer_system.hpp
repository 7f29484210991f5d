#pragma once
// The reducer stage of a load problem (ltca/solvers/reducer.hpp) assembled at its crank
// under linearised kinematics: every element's gap affine in the unknowns, its convex energy, and
// the total potential energy Pi(q) = sum_e E_e(q) - T psi with its gradient and Hessian. Shared by
// the backends that solve the stage and by the judge.
//
// Coordinates (what the solution reports): per disc x, y (mm, fixed frame) and phi (rad, problem
// frame), then psi (rad, problem frame: the output member's elements, its pins or cranks; the
// result's rotation adds the carrier's twist in series, CarrierTwist), then the shaft deflections (mm) of each disc's cranks when
// both the needle bearing and the shaft are compliant. Degrees of freedom (what the minimisation
// moves): the coordinates a rigid element does not hold at zero (a rigid eccentric bearing holds
// the disc's centre), rotations scaled by the pin-circle radius so that every dof is a length in mm
// and every component of the gradient a force in N.
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "ltca/contact/bearing.hpp"
#include "ltca/contact/laws.hpp"
#include "ltca/solvers/load_problem.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "ltca/solvers/reducer.hpp"

namespace ltca::solvers {

class CoupledContact;

class ReducerSystem {
 public:
  /// The law of every output pin in its hole (a stage of kind pins): the deck's [contact] law,
  /// conformal and unseated (contact::OutputPinLaw), over the face width, with the problem's cap.
  static contact::ContactLaw OutputPinLaw(const LoadProblem& problem);
  /// The law of every needle roller of a crank bearing on an elastic disc body (the coupled set's
  /// rollers): contact::ContactLaw::Roller of the bearing's roller length, with the body the raceway's
  /// local field beyond the body's patches (docs/fe_disc.md "The RV disc"); without it Palmgren's alone.
  static contact::ContactLaw CrankRollerLaw(const LoadProblem& problem);

  /// The stage at its nominal poses (linearised kinematics). Throws std::invalid_argument when the
  /// problem has no reducer.
  ///
  /// With pin bending (the problem's coupling) the pin-ring points of one pin share its
  /// beam: `coupled` solves their contact problem at each evaluation (CoupledContactFor, kept in
  /// the workspace); a system without it can judge (Judge) but not evaluate.
  explicit ReducerSystem(const LoadProblem& problem, CoupledContact* coupled = nullptr);
  /// The stage linearised about the poses `origin` (coordinates, as a result reports them): every
  /// element re-evaluated there, its gap the exact one at those poses and its gradients the exact
  /// ones (exact kinematics: each iterate of LoadSolver's outer loop). The coordinates the system
  /// works in are then relative to the origin; Fill and Judge report and read absolute ones.
  ReducerSystem(const LoadProblem& problem, const Eigen::VectorXd& origin, CoupledContact* coupled = nullptr);
  ReducerSystem(const ReducerSystem&) = delete;
  ReducerSystem& operator=(const ReducerSystem&) = delete;

  int coordinate_count() const { return static_cast<int>(coordinate_dof_.size()); }
  int dof_count() const { return dofs_; }
  /// The dof of the output rotation psi (always free).
  int output_dof() const { return coordinate_dof_[static_cast<std::size_t>(psi_coordinate_)]; }
  /// psi = scale * q[output_dof()], rad.
  double rotation_scale() const { return 1.0 / radius_; }
  int disc_count() const { return discs_; }
  /// The coupled contact solver of pin bending (nullptr: none given).
  CoupledContact* coupled() const { return coupled_; }

  struct Evaluation {
    double energy = 0.0;        ///< Pi, N*mm
    Eigen::VectorXd gradient;   ///< dPi/dq, N
    Eigen::MatrixXd hessian;    ///< N/mm (only when asked)
    bool saturated = false;     ///< a loaded element beyond its law's largest force
    bool edge = false;          ///< a pin-ring point on a tip corner closes (approach > 0)
    /// How finely the gradient is resolved in double precision, N: 16 eps times the largest sum
    /// of the magnitudes that add up to one of its components. No balance can be closer.
    double rounding = 0.0;
    /// How finely the energy is resolved, N*mm: each loaded element's force times the rounding of
    /// its approach (eps times the magnitudes it is the difference of: a clearance taken up almost
    /// exactly leaves few digits of the approach, and of its energy).
    double energy_rounding = 0.0;
    /// Pin bending: why the pins' coupled contact problem did not converge (empty: it did, or
    /// there is none). The energy is then NaN.
    std::string failure;
  };
  /// hints: one per scalar element (law inversions' warm starts), resized as needed.
  void Evaluate(const Eigen::VectorXd& q, bool with_hessian, std::vector<double>* hints, Evaluation* out) const;

  enum class Outcome { kConverged, kMaxIterations, kNumerical };
  /// Minimises Pi over the dofs (all, or all but psi when hold_output) from *q, by Newton's method
  /// with a Levenberg-Marquardt damping that a ratio of actual to predicted decrease adapts (a
  /// trust region: it walks through the flat region before first contact, and takes pure Newton
  /// steps near the minimum). Converged when every component of the gradient (the free ones) is
  /// within tolerance * T / R_p (N), every balance within `tolerance` relative to T, or within
  /// the gradient's rounding (Evaluation::rounding), or when neither the energy nor the gradient
  /// (its 2-norm, where the energy is below its rounding) can tell a step from staying: a trust
  /// region below the resolution of a position (a few eps of R_p about an origin, of the largest
  /// dof or gap in the nominal system). The arithmetic's limit; the shared judge then decides.
  Outcome Minimise(Eigen::VectorXd* q, bool hold_output, double tolerance, int max_iterations,
                   std::vector<double>* hints, int* iterations, Evaluation* last) const;

  /// The generalised force on psi of every element, N*mm: the torque the stage returns to the
  /// output member at q (T at a balanced solution).
  double OutputTorque(const Evaluation& at) const { return at.gradient(output_dof()) * radius_ + torque_; }
  double torque() const { return torque_; }
  /// The carrier's twist under T in series with the stage, rad (problem frame): T / k, zero for a
  /// rigid carrier. The output member's moment balance holds the carrier's torque at T exactly, so
  /// the output's rotation is the elements' psi plus this (the result reports the output's).
  double CarrierTwist() const { return torque_ / settings_.carrier_stiffness; }

  /// The solution at q: rotation (psi, rad), pin-ring forces and the stage's elements
  /// (LoadResult::reducer), without status or residuals.
  void Fill(const Eigen::VectorXd& q, LoadResult* result) const;

  /// The shared judge of a stage solution: the balance of every coordinate with the forces the
  /// result reports (each disc's forces and moment, the output member's torque, each shaft), the
  /// complementarity of each scalar element's force with its approach, and each planar element's
  /// force against its law at its displacement. Sets result->residuals and the stage's balances.
  void Judge(LoadResult* result) const;

  /// Whether an element besides the pin ring is pressed at the nominal poses: an output pin whose
  /// hole is smaller than pin + 2 e (its gap below -tolerance, mm), or a bearing (the stage's or the
  /// second disc's) with a negative radial clearance. A preloaded stage (docs/stage.md "Preload").
  bool ElementsPreloaded(double tolerance) const;

  /// Start of a solve: zero, or the dofs of an earlier solution of the same layout.
  Eigen::VectorXd Zero() const { return Eigen::VectorXd::Zero(dofs_); }

  /// The coordinates a result reports (its disc poses, output rotation and shaft deflections),
  /// absolute; zero where the result has none.
  Eigen::VectorXd CoordinatesOf(const LoadResult& result) const;
  /// The origin in dofs (zero for the nominal system): absolute dofs = OriginDofs() + q.
  Eigen::VectorXd OriginDofs() const;
  /// The largest of |a - b| over the coordinates, rotations times R_p: mm.
  double Distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const;

 private:
  /// A row over coordinates (at most 6 non-zeros).
  struct Row {
    int n = 0;
    std::array<int, 6> index{};
    std::array<double, 6> value{};
    void Add(int i, double v);
    double Dot(const Eigen::VectorXd& x) const;
  };
  /// A contact point: approach = row . coordinates - gap; its force follows a ContactLaw.
  struct Scalar {
    Row row;        // over dofs
    Row coordinates;  // over coordinates
    double gap = 0.0;
    int law = -1;   // into laws_, -1: an edge point (no law: must stay open)
    // Output pins: n_j, the force's on the disc; pin ring: the contact normal n (from the
    // cycloid toward the pin; the pin pushes the disc along -n).
    Eigen::Vector2d direction = Eigen::Vector2d::Zero();
    StageGroup group = StageGroup::kMesh;
    int disc = 0, index = 0;  // index: the problem's point, or the output pin
  };
  /// A planar element: displacement u = rows . coordinates + offset, energy of a bearing
  /// (contact::BearingAt: linear spring with clearance, or rollers).
  struct Planar {
    std::array<Row, 2> row;          // over dofs
    std::array<Row, 2> coordinates;  // over coordinates
    Eigen::Vector2d offset = Eigen::Vector2d::Zero();
    bool shaft = false;  // the shaft's spring (shaft_), else the stage's bearing
    double phase = 0.0;
    StageGroup group = StageGroup::kBearings;
    int disc = 0, index = 0;  // index: the crank (0 for the eccentric bearing)
  };

  Row ToDofs(const Row& coordinates) const;
  /// The planar element's law: the shaft's spring, or its disc's bearing (the second disc's own play).
  const contact::BearingSettings& Bearing(const Planar& p) const {
    return p.shaft ? shaft_ : Bearing(p.disc);
  }
  /// Disc d's bearing (the second disc's own play).
  const contact::BearingSettings& Bearing(int disc) const { return disc == 1 ? second_bearing_ : settings_.bearing; }
  Eigen::VectorXd Coordinates(const Eigen::VectorXd& q) const;
  /// u of a planar element at dofs q, or at coordinates c.
  static Eigen::Vector2d Displacement(const Planar& p, const Eigen::VectorXd& q);
  static Eigen::Vector2d DisplacementAt(const Planar& p, const Eigen::VectorXd& c);

  void Build(const LoadProblem& problem, const Eigen::VectorXd* origin);
  /// Pin bending (and an elastic disc body): the forces of the coupled set at the approaches
  /// `approach` (one per coupled point), by the coupled contact solver; `force` is the warm start
  /// and the answer.
  struct CoupledForces {
    bool converged = false, saturated = false, edge = false;
    std::string failure;
  };
  CoupledForces SolveCoupled(const std::vector<double>& approach, std::vector<double>* force) const;
  /// Pin bending's part of an evaluation at dofs q (the pin-ring points; the others as without).
  void EvaluateCoupled(const Eigen::VectorXd& q, bool with_hessian, std::vector<double>* hints, Evaluation* out,
                       Eigen::VectorXd* magnitude) const;

  const LoadProblem* problem_;
  Eigen::VectorXd origin_;  // coordinates about which the system is linearised (zero: nominal)
  bool exact_ = false;      // built about an origin: its geometry re-evaluated there
  ReducerSettings settings_;
  contact::BearingSettings shaft_;  // kCranks with a compliant shaft: a linear spring without play
  contact::BearingSettings second_bearing_;  // the second disc's bearing (ReducerSettings::BearingOf(1))
  int discs_ = 1;
  int crank_count_ = 0;  // cranks per disc (0 for output pins)
  bool shaft_coordinates_ = false;
  // Crankshafts as beams: per crank and direction the two discs' shaft deflections v share the
  // energy v^T K v / 2, K = C^-1 the beam's 2 x 2 compliance inverted; C_beam_ its beam part.
  bool shaft_beam_ = false;
  Eigen::Matrix2d beam_stiffness_ = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d beam_compliance_ = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d beam_part_ = Eigen::Matrix2d::Zero();
  /// The coordinate of disc d's shaft deflection at crank j (x; y is the next).
  int ShaftCoordinate(int d, int j) const { return psi_coordinate_ + 1 + 2 * (d * crank_count_ + j); }
  double radius_ = 1.0;  // R_p, mm: the rotations' scale
  double torque_ = 0.0;  // |T|, N*mm
  Eigen::VectorXd applied_;  // the loads besides T over the coordinates (StageLoads), N and N*mm
  int psi_coordinate_ = 0;
  int dofs_ = 0;
  std::vector<int> coordinate_dof_;       // -1: held at zero
  std::vector<double> coordinate_scale_;  // coordinate = scale * dof
  std::vector<contact::ContactLaw> laws_;
  std::vector<Scalar> scalars_;
  std::vector<Planar> planars_;
  // Pin bending: the coupling C over the problem's points (scalars_[0..points) are they, in
  // order), its blocks (the points one beam couples, with C's dense block) and the solver.
  const Eigen::SparseMatrix<double>* coupling_ = nullptr;
  struct Block {
    std::vector<int> points;
    Eigen::MatrixXd c;
  };
  std::vector<Block> blocks_;
  int mesh_points_ = 0;
  // The coupled set: scalars_[0..coupled_points_), the problem's points and, with an elastic disc
  // body (LoadProblem::stage_body_coupling), every disc's output pins after them (disc, pin), or
  // every disc's needle rollers (disc, crank, roller) in place of the crank bearings' planar elements.
  int coupled_points_ = 0;
  const Eigen::SparseMatrix<double>* body_coupling_ = nullptr;  // the body's part of coupling_ (the budget)
  double force_scale_ = 1.0;  // N, CoupledForceScale
  CoupledContact* coupled_ = nullptr;
};

/// Sets the status and message of a stage solve from the minimisation's outcome and its last
/// evaluation (a saturated law, a closed edge point), and fills the solution at q.
void FinishReducer(const ReducerSystem& system, const Eigen::VectorXd& q, ReducerSystem::Outcome outcome,
                 const ReducerSystem::Evaluation& last, LoadResult* result);

/// A warm start kept in the workspace under `key`: the (absolute) dofs of the last stage solve
/// with as many dofs, relative to the system's origin; else zero.
Eigen::VectorXd ReducerStart(const ReducerSystem& system, Workspace& workspace, const std::string& key);
void KeepReducerStart(const ReducerSystem& system, const Eigen::VectorXd& q, Workspace& workspace, const std::string& key);


}  // namespace ltca::solvers
