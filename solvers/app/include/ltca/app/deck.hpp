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

/// [load]: the torque carried by this cycloid gear.
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
  /// came from: "deck" (a key given, also when 0), "default" (chosen by ChooseDefaultTipRelief for
  /// |d| >= 2) or "none"; and why, when chosen or not (reported with the model).
  std::string tip_relief_source = "none";
  std::string tip_relief_note;
  contact::ContactSettings contact;            ///< [contact], optional, default hertz-line / signed
  SolverOptions solver;                        ///< [solver], optional, default bisection / linearised
  std::optional<contact::PinSupport> pins;    ///< [pins], optional: pin bending (issue 11)
  std::optional<contact::Material> material;  ///< required by the load commands
  std::optional<LoadCase> load;               ///< required by the load commands
  Sweep sweep;
  StiffnessSettings stiffness;                 ///< [stiffness], optional (ltca stiffness)

  /// The pair as made: modification and [errors] applied once (geometry::RealPair); every
  /// command builds this one.
  geometry::RealPair MakeRealPair() const { return {pair, modification, errors, assembly}; }
  /// The pair as the contact layer sees it (the real pair, geometry mode, the slices it needs).
  contact::MeshModel MakeModel() const { return contact::MeshModel(MakeRealPair(), geometry, pins.has_value()); }
  /// Pin bending's coupling of the model's points ([pins]: every pin a Timoshenko beam of the
  /// nominal pin radius and the pin material), checked once for the problems of a sweep; the
  /// matrix is nullptr without [pins].
  solvers::LoadProblem::CheckedCoupling MakeCoupling(const contact::MeshModel& model) const;
  /// The load problem of this deck at a crank on the model (its coupling applied).
  solvers::LoadProblem MakeProblem(const std::shared_ptr<const contact::MeshModel>& model, double crank,
                                   contact::ContactKinematics kinematics) const;

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
    std::string tip_relief_source;   ///< "deck" | "default" | "none"
    std::string tip_relief_note;     ///< how a default was chosen, or why there is none
  };
  ModelInfo Model() const;

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
