#pragma once
// Case decks: TOML files whose keys carry their unit (docs/decks.md). One small struct per
// section, each with its own validation; unknown sections and keys and missing required keys
// are errors that name the key. Values are converted to the internal units (mm, N, MPa, N*mm,
// rad) on reading.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "ltca/contact/laws.hpp"
#include "ltca/contact/material.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/contact/pin_bending.hpp"
#include "ltca/geometry/discrete_profile.hpp"
#include "ltca/geometry/errors.hpp"
#include "ltca/geometry/pair.hpp"
#include "ltca/solvers/load_problem.hpp"
#include "ltca/solvers/load_solver.hpp"

namespace ltca::app {

// The solver layer's vocabulary, used throughout the application layer.
using solvers::LoadResult;
using solvers::LoadSolver;
using solvers::SolverOptions;
using solvers::SolverStatus;

/// What a deck may ask for (docs/decks.md, "Limits"). Each limit is far above every published
/// case and keeps one run within memory and a sensible time; a value beyond it is an error that
/// names the key.
struct DeckLimits {
  static constexpr std::uintmax_t kMaxFileBytes = 4u << 20;  ///< 4 MiB; cases/ decks are < 2 kB
  static constexpr int kMaxNesting = 64;          ///< levels of [ ] and { } in the TOML text
  static constexpr int kMaxPins = 10'000;         ///< [pair] pin_count
  static constexpr int kMaxPositions = 1'000'000; ///< [sweep] positions
  static constexpr double kMaxCrankDeg = 3600.0;  ///< |crank_start_deg|, |crank_end_deg| (10 turns)
  /// Modifications and manufacturing errors (lengths) larger than this fraction of the pin
  /// radius look like absolute values (a radius, not a change of it) and are rejected.
  static constexpr double kMaxDeviationFraction = 0.05;
  /// [errors] profile_measured_csv: the trace file, read with a bounded read (a trace of a
  /// measuring centre has a few hundred to a few thousand rows).
  static constexpr std::uintmax_t kMaxProfileCsvBytes = 4u << 20;
};

/// [case]: provenance.
struct CaseInfo {
  std::string title;
  std::string source;  ///< paper, table / section; free text.
};

/// [load]: the output torque of the stage: the one disc's, or with [second_disc] both discs' together.
struct LoadCase {
  double torque = 0.0;  ///< N*mm (deck: torque_nm), finite, signed: the sign picks the flank.
  void Validate() const;
};

/// [sweep]: crank positions; default one mesh period in 91 positions (Liu's 0.1 deg step at z_p = 40).
struct Sweep {
  double crank_start = 0.0;  ///< rad (deck: crank_start_deg).
  double crank_end = 0.0;    ///< rad (deck: crank_end_deg), inclusive.
  int positions = 91;  ///< 1 .. DeckLimits::kMaxPositions.
  /// Throws std::invalid_argument naming the key: positions out of range, angles not finite or
  /// beyond DeckLimits::kMaxCrankDeg, an empty range with several positions.
  void Validate() const;
  /// The crank angles, rad: positions values from start to end inclusive.
  std::vector<double> CrankAngles() const;
};

/// [stiffness]: the torque-twist loop of `ltca stiffness` (issue 13, docs/stiffness.md). The torque
/// runs from -T to +T and back, T = |[load] torque_nm| (the rated torque).
struct StiffnessSettings {
  static constexpr int kMaxSteps = 10'001;
  /// Torque levels per branch from -T to +T inclusive (deck: steps_per_branch): odd, so that zero
  /// and the levels +-T / 2 of an (n - 1) / 4 grid are on it; 3 .. kMaxSteps.
  int steps = 41;
  enum class Rigidity {
    kSecant,   ///< between 50 % and 100 % of T on each flank (catalogue definition, the default)
    kTangent,  ///< the slope at tangent_torque
  };
  Rigidity rigidity = Rigidity::kSecant;  ///< deck: rigidity = "secant" | "tangent"
  /// N*mm, signed (deck: tangent_torque_nm): where the tangent rigidity is taken; finite, not zero
  /// (the free play has no slope). Required when rigidity is tangent.
  double tangent_torque = std::numeric_limits<double>::quiet_NaN();
  /// Lost motion is read at +-fraction T (deck: lost_motion_fraction, default 3 %), in (0, 1).
  double lost_motion_fraction = 0.03;
  /// One crank angle, rad (deck: crank_deg); empty: every position of [sweep].
  std::optional<double> crank;
  /// Throws std::invalid_argument naming the key, the value and what is expected.
  void Validate() const;
};

/// [second_disc]: the second cycloid disc of an RV stage (issue 13, docs/stiffness.md "Two discs"),
/// half a crank turn from the first on one pin ring, turning the output with it. Its own
/// [modification] keys and the disc's [errors] keys (profile, lead, centre, eccentricity and
/// misalignment); every key not given is the first disc's. The pin ring's errors (pin circle,
/// pitch, pin radii and positions) are common and stay in [errors].
struct SecondDisc {
  geometry::Modification modification;
  geometry::ManufacturingErrors errors;  ///< the pin ring's keys as [errors]
  geometry::AssemblyErrors assembly;
  /// Indexing deviation of this disc, mm along the pin circle (deck: indexing_deviation_mm): its
  /// teeth stand this far ahead of the first disc's in the sense of +T (a rigid turn of the disc
  /// by the value / R_p, added to its rotation modification).
  double indexing_deviation = 0.0;
};

// --- issue 15: [tolerances] (docs/tolerance.md, ltca tolerance) -------------------------------
/// One key of [tolerances]: how the value of an [errors] or [modification] key scatters about the
/// deck's own value (its nominal). Values are in the key's unit (mm, um or deg, as its name says).
struct ToleranceDistribution {
  enum class Kind {
    kNormal,   ///< mean + sigma z, z standard normal (deck: sigma, or tolerance read as 3 sigma)
    kUniform,  ///< uniform on mean +- tolerance (deck: tolerance)
  };
  std::string key;      ///< the [tolerances] key, e.g. "pin_circle_deviation_mm"
  Kind kind = Kind::kNormal;
  double sigma = 0.0;       ///< normal: standard deviation, key unit (>= 0)
  double tolerance = 0.0;   ///< uniform: half-width, key unit (>= 0); normal: 3 sigma when given so
  double mean = 0.0;        ///< offset of the distribution's centre from the deck's value, key unit
  bool per_pin = false;     ///< drawn independently for every pin (a list key of [errors])
  /// The half-width of the range the extreme-value (worst-case) method uses: uniform: tolerance;
  /// normal: 3 sigma.
  double WorstCaseHalfWidth() const { return kind == Kind::kUniform ? tolerance : 3.0 * sigma; }
  /// Standard deviation of a draw, key unit.
  double StandardDeviation() const;
  /// Nothing scatters and nothing is offset: the key leaves every sample at the deck's value.
  bool IsZero() const { return sigma == 0.0 && tolerance == 0.0 && mean == 0.0; }
};

/// A user-given acceptance limit on a figure of `ltca tolerance` (deck: [tolerances] limits).
struct ToleranceLimit {
  std::string figure;  ///< a figure name, e.g. "lost_motion_arcmin"
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
};

/// One link of an assembly dimensional chain: a dimension with its upper and lower deviation
/// (deck: [tolerances] chains, e.g. Jiang 2022 Table 3).
struct DimensionLink {
  std::string name;
  bool increasing = true;  ///< an increasing link widens the closing link; a decreasing one narrows it
  double upper = 0.0;      ///< upper deviation (es / ES), um in a deck
  double lower = 0.0;      ///< lower deviation (ei / EI), um in a deck
};
/// A dimensional chain whose closing link (a clearance) is solved for (deck: [tolerances] chains).
struct DimensionChain {
  std::string name;  ///< e.g. "B0"
  std::vector<DimensionLink> links;
};

/// [tolerances]: the Monte Carlo of `ltca tolerance` (issue 15).
struct ToleranceSettings {
  static constexpr std::int64_t kMaxSamples = 10'000'000;
  std::vector<ToleranceDistribution> distributions;  ///< in the order of ToleranceKeys()
  std::int64_t samples = 1000;   ///< 1 .. kMaxSamples
  std::uint64_t seed = 1;        ///< of the counter-based stream: sample i depends on (seed, i) only
  bool lost_motion = false;      ///< also run lost motion (issue 13) per sample
  /// [errors] profile_random_*: every sample its own random profile deviation (the zone and the
  /// law of the deck, the seed drawn from (seed, i)) instead of the deck's one profile.
  bool profile_random_per_sample = false;
  std::vector<ToleranceLimit> limits;
  /// Assembly dimensional chains (deck: chains = { B0 = [ { link = "...", kind = "increasing",
  /// upper_um = 9, lower_um = 0 }, ... ] }): their closing links by the extreme-value method and
  /// by Monte Carlo (every link uniform within its limits), reported beside the pair's figures.
  std::vector<DimensionChain> chains;
  /// The keys [tolerances] knows: every numeric key of [errors] and, prefixed "modification_", the
  /// modifications. The second member says whether the key is per pin.
  static const std::vector<std::pair<std::string, bool>>& ToleranceKeys();
  /// The figure names a limit may name (the summary keys of solve, backlash and stiffness).
  static const std::vector<std::string>& FigureNames();
  /// Throws std::invalid_argument naming the key, the value and what is expected.
  void Validate() const;
};
// --- end of issue 15's [tolerances] ----------------------------------------------------------------
// --- issue 14: [operation] and [friction] (docs/efficiency.md) ------------------------------------
/// [operation]: how the stage runs, for `ltca efficiency`. Internal units: rad/s, MPa*s, 1/MPa, mm.
struct OperationSettings {
  double input_speed = 0.0;          ///< crank speed, rad/s (deck: input_speed_rpm, required, > 0)
  double viscosity = 30e-9;          ///< eta_0, MPa*s (deck: oil_viscosity_pa_s, default 0.03, Jiang)
  double pressure_viscosity = 0.01;  ///< alpha, 1/MPa (deck: pressure_viscosity_per_gpa, default 10, Jiang)
  double roughness_cycloid = 0.3e-3; ///< Ra, mm (deck: roughness_ra_cycloid_um, default 0.3, Jiang)
  double roughness_pin = 0.3e-3;     ///< Ra, mm (deck: roughness_ra_pin_um, default 0.3)
  static constexpr double kMaxSpeedRpm = 100'000.0;
  /// Throws std::invalid_argument naming the key, the value and what is expected.
  void Validate() const;
};

/// [friction]: the friction coefficient model, the pin sleeve and the torque balance.
struct FrictionSettings {
  enum class Model {
    kCoulomb,     ///< constant mu = coefficient (deck: model = "coulomb", the default)
    kJiangMixed,  ///< Jiang 2022 eq. 20-26 (deck: "jiang-mixed"); needs [operation]
  };
  Model model = Model::kCoulomb;
  /// mu (deck: coefficient): Coulomb's constant; with jiang-mixed the coefficient of the first-order
  /// figure is the mixed one, and this key is not used (it may be absent). In [0, 1].
  double coefficient = std::numeric_limits<double>::quiet_NaN();
  double boundary_coefficient = 0.1;    ///< f_b of eq. 20 (deck: boundary_coefficient), in [0, 1]
  double limiting_shear_modulus = 1.0;  ///< G of eq. 23, MPa (deck: limiting_shear_modulus_mpa)
  double power_law_exponent = 0.5;      ///< n of eq. 22-23 (deck: power_law_exponent), in (0, 1]
  /// Pin sleeve (Jiang eq. 34, deck: sleeve_bore_radius_mm): the radius of the pin inside a sleeve
  /// whose outer radius is [pair] pin_radius_mm. Empty: no sleeve.
  std::optional<double> sleeve_bore_radius;
  /// mu at the sleeve's bore (deck: sleeve_coefficient); NaN (the default): the coefficient of the
  /// contact it replaces (Coulomb's mu, or the mixed one there), Jiang eq. 34 read literally.
  double sleeve_coefficient = std::numeric_limits<double>::quiet_NaN();
  enum class TorqueBalance {
    kSolve,  ///< re-solve with the friction moment in the balance, to a fixed point (default)
    kBound,  ///< frictionless forces; the friction moment's ratio to T reported as a bound
  };
  TorqueBalance torque_balance = TorqueBalance::kSolve;  ///< deck: torque_balance = "solve" | "bound"
  /// Throws std::invalid_argument naming the key, the value and what is expected.
  void Validate(const geometry::PairParameters& pair) const;
};
const char* ToString(FrictionSettings::Model model);
// --- end of issue 14's block ----------------------------------------------------------------------

struct Deck {
  std::string name;  ///< file path, or "built-in default"
  CaseInfo info;
  geometry::PairParameters pair;
  geometry::Modification modification;
  geometry::ManufacturingErrors errors;        ///< [errors], optional, default none
  geometry::AssemblyErrors assembly;           ///< [errors] assembly keys, optional, default none
  geometry::GeometrySettings geometry;         ///< [geometry], optional, default analytic
  bool width_slices_given = false;             ///< [geometry] width_slices is in the deck
  std::vector<std::string> notes;              ///< keys given without effect (reported in Model().note)
  /// Where the tip relief ([modification] tip_truncation_mm, tip_rounding_radius_mm; issue 12)
  /// came from: "deck" (a key given, also when 0) or "none" (no relief is ever assumed, issue 26);
  /// the note says what sharp tips of a |d| >= 2 pair do (reported with the model).
  std::string tip_relief_source = "none";
  std::string tip_relief_note;
  contact::ContactSettings contact;            ///< [contact], optional, default hertz-line / signed
  SolverOptions solver;                        ///< [solver], optional, default bisection / linearised
  std::optional<contact::PinSupport> pins;    ///< [pins], optional: pin bending (issue 11)
  std::optional<SecondDisc> second_disc;       ///< [second_disc], optional: the two discs of an RV stage
  std::optional<contact::Material> material;  ///< required by the load commands
  std::optional<LoadCase> load;               ///< required by the load commands
  Sweep sweep;
  StiffnessSettings stiffness;                 ///< [stiffness], optional (ltca stiffness)
  std::optional<ToleranceSettings> tolerances; ///< [tolerances], optional (ltca tolerance, issue 15)
  std::optional<OperationSettings> operation;  ///< [operation], optional (ltca efficiency; issue 14)
  std::optional<FrictionSettings> friction;    ///< [friction], optional: without it no friction anywhere

  /// The pair as made: modification and [errors] applied once (geometry::RealPair); every
  /// command builds this one.
  geometry::RealPair MakeRealPair() const { return {pair, modification, errors, assembly}; }
  /// The pair as the contact layer sees it (the real pair, geometry mode, the slices it needs).
  contact::MeshModel MakeModel() const { return contact::MeshModel(MakeRealPair(), geometry, SlicesForced()); }
  /// The second disc as made, and as the contact layer sees it (nullptr without [second_disc]).
  geometry::RealPair MakeSecondRealPair() const;
  std::shared_ptr<const contact::MeshModel> MakeSecondModel() const;
  int disc_count() const { return second_disc ? 2 : 1; }
  /// Pin bending's coupling of the model's points ([pins]: every pin a Timoshenko beam of the
  /// nominal pin radius and the pin material), checked once for the problems of a sweep; the
  /// matrix is nullptr without [pins].
  solvers::LoadProblem::CheckedCoupling MakeCoupling(const contact::MeshModel& model) const;
  /// The load problem of this deck at a crank on the model (its coupling applied).
  /// With two discs ([second_disc]) the problem of both: `second` from MakeSecondModel().
  solvers::LoadProblem MakeProblem(const std::shared_ptr<const contact::MeshModel>& model, double crank,
                                   contact::ContactKinematics kinematics,
                                   const std::shared_ptr<const contact::MeshModel>& second = nullptr) const;
  /// The unloaded state of every contact point at a crank: one disc, or both
  /// (contact::EvaluateTwoDiscs); `second` as for MakeProblem.
  contact::MeshState EvaluateDiscs(const contact::MeshModel& model, const contact::MeshModel* second, double crank) const;

  /// The model that runs for this deck, named in every output (issues 9, 11): "plane" (one slice
  /// over the face width: nothing varies along it) or "slices" (width_slices slices: something
  /// varies along the width), the surface (analytic or elements), and a note when width_slices was
  /// given without need.
  struct ModelInfo {
    std::string name;     ///< "plane" | "slices" | "slices+pin-bending"
    int slices = 1;
    std::string surface;  ///< "analytic" or "elements"
    std::string note;     ///< empty, or why a given slice count or key was not used
    geometry::TipRelief tip_relief;  ///< the relief that runs (issue 12)
    std::string tip_relief_source;   ///< "deck" | "none"
    std::string tip_relief_note;     ///< how a default was chosen, or why there is none
    int discs = 1;                   ///< 2 with [second_disc] (name ends in "+two-discs")
  };
  ModelInfo Model() const;

  /// The slice model is forced on every disc: pin bending couples the slices; with two discs one
  /// that varies along the width makes both run it (one point layout per position).
  bool SlicesForced() const;

  /// Throws std::invalid_argument naming the deck and the missing section.
  const contact::Material& RequireMaterial() const;
  const LoadCase& RequireLoad() const;
};

/// Parses and validates a deck, including the geometry (an undercut profile is rejected).
/// overrides: "section.key=value" (the CLI's --set), each value read as a TOML value (a bare
/// word that is not TOML is a string), applied to the parsed text before the sections are read,
/// so that an override is checked like the key in the file; a missing section is created.
/// Text larger than DeckLimits::kMaxFileBytes or nested deeper than DeckLimits::kMaxNesting is
/// rejected before the TOML parser sees it.
/// directory: where relative paths in the deck ([errors] profile_measured_csv) are read from;
/// empty: the current directory (LoadDeck passes the deck file's directory).
/// Throws std::invalid_argument with a message that starts with the deck name.
Deck ParseDeck(std::string_view toml_text, const std::string& name, const std::vector<std::string>& overrides = {},
               const std::filesystem::path& directory = {});
/// The same for a file, which must be a regular file (not a directory, FIFO or device) of at
/// most DeckLimits::kMaxFileBytes; it is read with a bounded read.
Deck LoadDeck(const std::filesystem::path& path, const std::vector<std::string>& overrides = {});

/// The built-in default case: Liu 2021 Table 1 (the text of cases/liu2021_table1.toml).
std::string_view DefaultDeckText();
Deck DefaultDeck(const std::vector<std::string>& overrides = {});

}  // namespace ltca::app
