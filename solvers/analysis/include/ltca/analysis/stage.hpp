#pragma once
// The stage: everything that is loaded together, built once and shared by every
// analysis. StageDesign is its data as a deck gives it (internal units); Stage is the immutable
// object built from it: the discs' real pairs and mesh models (one disc, or the two discs of an RV
// stage on one pin ring), pin bending's coupling of the pin ring, and the crank angles it has
// checked for interference. It hands out the load problem at a crank and a torque.
//
// The output mechanism and the bearings join the stage as elements that are not pins:
// StageDesign::reducer, handed to every problem (LoadProblem::WithReducer).
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ltca/contact/disc_body.hpp"
#include "ltca/contact/laws.hpp"
#include "ltca/contact/material.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/contact/pin_bending.hpp"
#include "ltca/geometry/errors.hpp"
#include "ltca/geometry/pair.hpp"
#include "ltca/solvers/load_problem.hpp"
#include "ltca/solvers/load_solver.hpp"

namespace ltca::analysis {

// The solver layer's vocabulary, used throughout the analyses.
using solvers::LoadResult;
using solvers::LoadSolver;
using solvers::SolverOptions;
using solvers::SolverStatus;

/// The second cycloid disc of an RV stage (docs/stiffness.md "Two discs"), half a crank
/// turn from the first on one pin ring, turning the output with it: its own modification and the
/// disc's errors (profile, lead, centre, eccentricity and misalignment). The pin ring's errors (pin
/// circle, pitch, pin radii and positions) are common: the first disc's.
struct SecondDisc {
  geometry::Modification modification;
  geometry::ManufacturingErrors errors;  ///< the pin ring's members as the first disc's
  geometry::AssemblyErrors assembly;
  /// Indexing deviation of this disc, mm along the pin circle: its teeth stand this far ahead of
  /// the first disc's in the sense of +T (a rigid turn of the disc by the value / R_p, added to its
  /// rotation modification).
  double indexing_deviation = 0.0;
};

/// The reducer stage's clearances that `ltca optimise` and `[tolerances]` may vary:
/// where the deck key ("bearing.radial_clearance_mm", "output.hole_radius_mm",
/// "output.pin_radius_mm") goes in the stage's settings (internal units, mm), or nullptr for any
/// other key. The output pins' hole and pin radii set the holes' clearance r_h - r_w - e.
double* ReducerClearance(solvers::ReducerSettings& stage, std::string_view key);
/// Why a deck with this stage (none: no [output]) cannot vary that clearance, "" when it can: no
/// stage, output pins' radii with crankshafts, a rigid bearing's play (it has none).
std::string StageClearanceRefusal(const std::optional<solvers::ReducerSettings>& stage, std::string_view key);

/// The model that runs for a stage, named in every output.
struct ModelInfo {
  std::string name;     ///< "plane" | "slices" | "slices+pin-bending", "+two-discs" with two discs
  int slices = 1;
  std::string surface;  ///< "analytic" or "elements"
  int discs = 1;
  /// The reducer stage's elements: "" for the mesh alone (disc centres fixed, T on the
  /// discs), else "<output>+<bearing> bearing", e.g. "pins+rollers bearing", "cranks+linear bearing".
  std::string reducer;
  /// The pins' seat in series with every pin-ring contact ([pins] seat): "" for rigid,
  /// else "linear" or "groove".
  std::string pin_seat;
  /// The disc body ([disc] body): "" for rigid, else "elastic (...)" with its FE model's settings.
  std::string disc_body;
  /// A reducer stage's scope in one line, what is elastic and what is rigid (docs/stage.md's
  /// table of elements); "" for the mesh alone.
  std::string scope;
};

/// [case]: the provenance of a design.
struct CaseInfo {
  std::string title;
  std::string source;  ///< paper, table / section; free text.
};

/// What is loaded together, as data (a deck's [pair], [modification], [errors], [geometry],
/// [contact], [material], [pins], [second_disc] and [solver] kinematics).
struct StageDesign {
  std::string name;  ///< where the design comes from (a deck's file path), for messages
  geometry::PairParameters pair;
  geometry::Modification modification;
  geometry::ManufacturingErrors errors;
  geometry::AssemblyErrors assembly;
  geometry::GeometrySettings geometry;
  contact::ContactSettings contact;
  /// How the contact geometry follows the loaded rotation (the load problem's, and the unloaded
  /// analysis's): linearised (frozen) or exact (re-evaluated).
  contact::ContactKinematics kinematics = contact::ContactKinematics::kLinearised;
  std::optional<contact::PinSupport> pins;     ///< pin bending; none: rigid pins
  std::optional<SecondDisc> second_disc;       ///< the two discs of an RV stage
  std::optional<contact::Material> material;  ///< required for load problems
  /// The reducer stage ([output] and [bearing]): output pins or crankshafts and the
  /// eccentric or needle bearings; none: the mesh alone, every disc about a fixed centre.
  std::optional<solvers::ReducerSettings> reducer;
  /// The disc body ([disc]): rigid (the default), or elastic, its FE compliance coupling the
  /// contacts (contact::DiscFlankCompliance).
  contact::DiscBodySettings disc;

  /// The pair as made: modification and errors applied once (geometry::RealPair).
  geometry::RealPair MakeRealPair() const { return {pair, modification, errors, assembly}; }
  /// The pair as the contact layer sees it (the real pair, geometry mode, the slices it needs).
  contact::MeshModel MakeModel() const { return contact::MeshModel(MakeRealPair(), geometry, SlicesForced()); }
  /// The second disc as made; throws std::invalid_argument without one.
  geometry::RealPair MakeSecondRealPair() const;
  int disc_count() const { return second_disc ? 2 : 1; }
  /// The slice model is forced on every disc: pin bending couples the slices; with two discs one
  /// that varies along the width makes both run it (one point layout per position).
  bool SlicesForced() const;
  /// Whether the second disc is the same part as the first: no indexing deviation, the same
  /// modification, errors and assembly, and no profile deviation (random or measured) on either.
  /// Its state at crank theta is then the first disc's at theta + pi.
  bool SecondDiscIsFirst() const;
  /// The model that runs (the rule of contact::MeshModel: slices when something varies along the
  /// face width, or pin bending couples the slices).
  ModelInfo Model() const;
  /// What the stage's models can run as one design: pin bending with two discs is not supported
  /// yet (the pin beams would couple both discs' contacts), nor an elastic disc body with two discs,
  /// a reducer stage, a law other than hertz-line, a tip relief or d < 0. Throws
  /// std::invalid_argument naming the deck's sections and keys.
  void Validate() const;
};

/// Immutable once built; copies share the models and the coupling, and a Stage may be shared
/// across threads.
class Stage {
 public:
  using ModelPtr = std::shared_ptr<const contact::MeshModel>;
  /// Positions a mesh period below which SamplingNote speaks (a curve needs about 8 points a cycle).
  static constexpr double kMinPositionsPerMeshPeriod = 8.0;
  /// Builds the discs' models and pin bending's coupling (with the material; without one no
  /// problem can be built, and Problem throws), evaluates
  /// the stage at every crank of `cranks` (rad) and throws std::invalid_argument naming the pins
  /// when a pin overlaps a disc at any of them, before anything is solved. The states evaluated
  /// for the check are kept for the problems when they fit in kKeptStatesBytes.
  Stage(StageDesign design, std::vector<double> cranks);

  /// 32 MB: a sweep keeps its states up to about 4,500 positions of 40 pins (plane model), and the
  /// whole process of `ltca solve`, about 15 MB beside them, stays under 64 MB at any length (it
  /// was 64 MB, and a 9,000-position sweep peaked at 70 MB; tests/app/check_solve_memory.py).
  static constexpr std::size_t kKeptStatesBytes = std::size_t{32} << 20;

  const StageDesign& design() const { return *design_; }
  ModelInfo Model() const { return design_->Model(); }
  int disc_count() const { return second_ ? 2 : 1; }
  /// The model of disc 0 (the first) or 1.
  const contact::MeshModel& model(int disc = 0) const { return disc == 0 ? *first_ : *second_; }
  const ModelPtr& shared_model(int disc = 0) const { return disc == 0 ? first_ : second_; }
  contact::ContactKinematics kinematics() const { return design_->kinematics; }
  /// The same stage (models, coupling, checked cranks shared) under other kinematics.
  Stage WithKinematics(contact::ContactKinematics kinematics) const;

  /// The checked crank angles, rad, in the order given.
  const std::vector<double>& cranks() const { return checked_->cranks; }
  /// The last checked crank repeats the state of the first (contact::SameMesh: a whole crank
  /// turn, or a mesh period of a pair that keeps that symmetry), so means weigh it once.
  /// Never for a reducer stage: its output elements do not repeat with the mesh.
  bool closed_period() const { return checked_->closed; }
  /// The overlap a check tolerates, mm: the largest of the discs' models'.
  double interference_tolerance() const;
  /// A note for the user when the cranks sample the mesh period (360 / pin_count deg of crank)
  /// with fewer than kMinPositionsPerMeshPeriod positions: TE, backlash and efficiency curves
  /// alias into a saw-tooth (issue 54). Empty otherwise (and for one position).
  std::string SamplingNote() const;

  /// Every contact point of the stage at a crank (rad), unloaded (loaded rotation 0): one disc,
  /// or both (contact::EvaluateTwoDiscs). The kept state of a checked crank, else evaluated; a
  /// crank that was not checked is checked now (std::invalid_argument on interference).
  contact::MeshState State(double crank) const;
  /// The load problem at a crank (rad) and a signed torque (N*mm), with the stage's coupling.
  solvers::LoadProblem Problem(double crank, double torque) const;
  /// The same on a state of this stage (State(crank), or a copy of one).
  solvers::LoadProblem Problem(contact::MeshState state, double torque) const;
  /// The material; throws std::invalid_argument when the design has none.
  const contact::Material& material() const { return RequireMaterial(); }
  /// Pin bending's coupling, checked once (matrix nullptr without [pins]).
  const solvers::LoadProblem::CheckedCoupling& coupling() const { return *coupling_; }
  /// The elastic disc body's flank compliance of disc 0 (the first) or 1 (shared by every stage of
  /// the same body design in the process), or nullptr for a rigid disc (or no second disc). The
  /// second disc's may be the first's, turned (second_body_turn()).
  const std::shared_ptr<const contact::DiscFlankCompliance>& disc_body(int disc = 0) const {
    return disc == 0 ? disc_body_ : second_body_;
  }
  /// The second disc's body as the first's turned: its frame is the first body's turned by `angle`
  /// (rad, counterclockwise), which carries the first body's tooth space k onto the second's k +
  /// `spaces` and its hole j onto the second's (j + `holes`) mod n; a point of the second body is
  /// the first's at the point and direction turned back. (DiscBodyTurn, docs/fe_disc.md "Two discs".)
  struct BodyTurn {
    double angle = 0.0;
    int spaces = 0;
    int holes = 0;
  };
  /// The turn when the second disc's body is the first's turned (one set-up for both), else nullopt.
  const std::optional<BodyTurn>& second_body_turn() const { return second_turn_; }

 private:
  struct Checked {
    std::vector<double> cranks;
    std::vector<contact::MeshState> states;  // kept states, in crank order, or empty
    std::vector<std::size_t> order;          // indices of cranks sorted by angle (lookup)
    bool closed = false;
  };
  /// Index of a checked crank, or -1.
  std::ptrdiff_t CheckedIndex(double crank) const;
  const contact::Material& RequireMaterial() const;
  /// A stage problem of output pins with the elastic body: its coupling over the pin ring's points
  /// and every disc's output pins' hole contacts, each disc on its own body
  /// (LoadProblem::WithStageBodyCoupling).
  solvers::LoadProblem WithStageBody(solvers::LoadProblem problem) const;
  /// The same for a stage of crankshafts: the pin ring's points and every needle roller on its
  /// crank hole's wall, each disc on its own body.
  solvers::LoadProblem WithCrankBody(solvers::LoadProblem problem) const;
  /// Each disc's elastic body, disc 0 first (one per disc of the stage).
  std::vector<const contact::DiscFlankCompliance*> Bodies() const;

  std::shared_ptr<const StageDesign> design_;
  ModelPtr first_, second_;
  std::shared_ptr<const solvers::LoadProblem::CheckedCoupling> coupling_;
  std::shared_ptr<const Checked> checked_;
  std::shared_ptr<const solvers::ReducerSettings> reducer_;  // nullptr: the mesh alone
  std::shared_ptr<const contact::DiscFlankCompliance> disc_body_;  // nullptr: a rigid disc
  std::shared_ptr<const contact::DiscFlankCompliance> second_body_;  // the second disc's (its holes half a tooth pitch on in its frame)
  std::optional<BodyTurn> second_turn_;  // set: second_body_ is disc_body_, turned
};

/// The elastic disc body of a design: the unmodified profile's body (the pair, [disc] and the
/// disc's elastic constants; modifications and errors, micrometres to tens of micrometres, change
/// its coefficients by less than its mesh does: docs/fe_disc.md), condensed once per body design in
/// the process and kept for the last few designs, so that a sweep, a tolerance study or an optimiser
/// over modifications pays the set-up once. Thread-safe (one build at a time).
/// `disc` 1: the second disc's body (an RV stage: its crank holes sit -pi / I further on in its
/// own frame than the first's).
std::shared_ptr<const contact::DiscFlankCompliance> ElasticDiscBody(const StageDesign& design, int disc = 0);

}  // namespace ltca::analysis
