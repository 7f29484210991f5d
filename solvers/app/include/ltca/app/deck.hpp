#pragma once
// Case decks: TOML files whose keys carry their unit (docs/decks.md). One small struct per
// section, each with its own validation; unknown sections and keys and missing required keys
// are errors that name the key. Values are converted to the internal units (mm, N, MPa, N*mm,
// rad) on reading.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "ltca/contact/laws.hpp"
#include "ltca/contact/material.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/contact/pin_bending.hpp"
#include "ltca/geometry/discrete_profile.hpp"
#include "ltca/geometry/errors.hpp"
#include "ltca/geometry/pair.hpp"
#include "ltca/analysis/efficiency.hpp"
#include "ltca/analysis/friction.hpp"
#include "ltca/analysis/allowables.hpp"
#include "ltca/analysis/spectrum.hpp"
#include "ltca/analysis/inspection.hpp"
#include "ltca/analysis/keys.hpp"
#include "ltca/analysis/optimise.hpp"
#include "ltca/analysis/slice_study.hpp"
#include "ltca/analysis/stage.hpp"
#include "ltca/analysis/stiffness.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/analysis/tolerance.hpp"
#include "ltca/solvers/load_problem.hpp"
#include "ltca/solvers/load_solver.hpp"

namespace ltca::app {

// The solvers' vocabulary, which every deck speaks; the analyses' types are named analysis::X.
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
  static constexpr int kMaxPositions = analysis::Sweep::kMaxPositions;  ///< [sweep] positions
  static constexpr double kMaxCrankDeg = analysis::kMaxCrankDeg;  ///< any crank angle; a sweep's own: analysis::MaxCrankDeg
  /// Modifications and manufacturing errors (lengths) larger than this fraction of the pin
  /// radius look like absolute values (a radius, not a change of it) and are rejected.
  static constexpr double kMaxDeviationFraction = analysis::DeckKey::kMaxDeviationFraction;
  /// [errors] profile_measured_csv: the trace file, read with a bounded read (a trace of a
  /// measuring centre has a few hundred to a few thousand rows).
  static constexpr std::uintmax_t kMaxProfileCsvBytes = 4u << 20;
};

/// Files a deck reads that a front-end holds in memory, by the name the deck gives them (Python's
/// Deck.with_measured_profile): [errors] profile_measured_csv = "name" is read from here before the
/// disk, with the same checks and messages as a file's. The command line has none.
using MemoryFiles = std::map<std::string, std::string>;

/// A case deck: the stage's data (analysis::StageDesign: [pair], [modification], [errors],
/// [geometry], [contact], [material], [pins], [second_disc], [solver] kinematics) and the settings of
/// the analyses.
struct Deck : analysis::StageDesign {
  analysis::CaseInfo info;
  /// Where the deck came from, as read: its TOML text (before the overrides), the --set
  /// overrides, the folder its relative paths are read from, and every file the reading opened
  /// (the deck itself, measured traces). WriteDeck edits the text; the command line refuses an
  /// output that is one of the files. `memory`: the in-memory files the deck was read with (none:
  /// null); they are not in `files`.
  struct Source {
    std::string text;
    std::vector<std::string> overrides;
    std::filesystem::path directory;
    std::vector<std::filesystem::path> files;
    std::shared_ptr<const MemoryFiles> memory;
  };
  Source source;
  bool width_slices_given = false;             ///< [geometry] width_slices is in the deck
  std::vector<std::string> notes;              ///< keys given without effect (reported in Model().note)
  /// Every key the deck text gives (after the overrides), in its order: section, key and the
  /// value as TOML writes it (the report's inputs table).
  struct GivenKey {
    std::string section, key, value;
  };
  std::vector<GivenKey> given;
  /// Where the tip relief ([modification] tip_truncation_mm, tip_rounding_radius_mm)
  /// came from: "deck" (a key given, also when 0) or "none" (no relief is ever assumed);
  /// the note says what sharp tips of a |d| >= 2 pair do (reported with the model).
  std::string tip_relief_source = "none";
  std::string tip_relief_note;
  SolverOptions solver;                        ///< [solver], optional, default bisection
  std::optional<analysis::LoadCase> load;               ///< required by the load commands
  analysis::Sweep sweep;
  analysis::StiffnessSettings stiffness;                 ///< [stiffness], optional (ltca stiffness)
  std::optional<analysis::ToleranceSettings> tolerances; ///< [tolerances], optional (ltca tolerance)
  std::optional<analysis::OperationSettings> operation;  ///< [operation], optional (ltca efficiency)
  std::optional<analysis::FrictionSettings> friction;    ///< [friction], optional: without it no friction anywhere
  std::optional<analysis::OptimiseSettings> optimise;    ///< [optimise], optional (ltca optimise)
  analysis::InspectionSettings inspection;               ///< [inspection], optional (ltca geometry)
  analysis::AllowablesSettings allowables;               ///< [allowables], optional (the stage's bearing targets)
  /// [[load_spectrum]], optional: the duty cycle's bins (ltca solve rates every life over them).
  std::vector<analysis::LoadBin> load_spectrum;
  /// [operation] gave motor_speed_rpm (the crank speed derived through the first stage).
  bool speed_from_motor = false;

  /// The stage of this deck checked at its sweep's cranks (or the given ones), for the commands
  /// that load it: requires [material] (std::invalid_argument naming the deck).
  analysis::Stage MakeStage() const { return MakeStage(sweep.CrankAngles()); }
  analysis::Stage MakeStage(std::vector<double> cranks) const;
  /// The deck as the tolerance study's nominal case: requires [material] and [load].
  analysis::ToleranceCase MakeToleranceCase() const;

  /// The model that runs for this deck, named in every output: the stage's model
  /// (analysis::ModelInfo), with a note when a key was given without effect, and the tip relief.
  struct ModelInfo : analysis::ModelInfo {
    std::string note;     ///< empty, or why a given slice count or key was not used
    geometry::TipRelief tip_relief;  ///< the relief that runs
    std::string tip_relief_source;   ///< "deck" | "none"
    std::string tip_relief_note;     ///< why there is none
  };
  ModelInfo Model() const;

  /// The analyses' settings together: [friction] model = "jiang-mixed" needs [operation] (the film
  /// thickness); the stage's friction is not modelled ([friction] with [output]); [tolerances]
  /// profile_random_per_sample needs [errors] profile_random_zone_um > 0. Throws
  /// std::invalid_argument naming the sections and keys.
  void ValidateSettings() const;

  /// Throws std::invalid_argument naming the deck and the missing section.
  const contact::Material& RequireMaterial() const;
  const analysis::LoadCase& RequireLoad() const;
  const analysis::FrictionSettings& RequireFriction() const;    ///< [friction], with an example in the message
  const analysis::OperationSettings& RequireOperation() const;  ///< [operation], with an example in the message
};

/// The deck's sweep: its stage at its [sweep] cranks (under the deck's kinematics), solved at its
/// [load] torque with `options`; the summary's wall time includes building the stage (the mesh
/// state of every position). For a reducer stage the summary carries its bearings' lives
/// (SweepSummary::bearing_life, at [operation] input_speed_rpm; no hours without it). Requires
/// [material] and [load].
analysis::SweepResult SolveDeckSweep(const Deck& deck, const SolverOptions& options, const analysis::SweepCallbacks& callbacks = {});
/// The deck's [[load_spectrum]]: each bin solved as the deck's sweep at the bin's torque and crank
/// speed (what --set load.torque_nm / operation.input_speed_rpm would give), the lives combined by
/// Miner's rule over the time shares (analysis::CombineSpectrum). Empty without a spectrum.
analysis::SpectrumResult SolveDeckSpectrum(const Deck& deck, const SolverOptions& options);
/// The deck's efficiency over its [[load_spectrum]]: each bin's efficiency run over the deck's
/// sweep at the bin's torque and crank speed, combined over the time shares
/// (analysis::CombineEfficiency). Requires [material], [friction] and [operation] as `ltca
/// efficiency` does; empty without a spectrum.
analysis::EfficiencySpectrum EfficiencyDeckSpectrum(const Deck& deck, const SolverOptions& options);

/// The deck with a front-end's kinematics by name (contact::ParseKinematics; "" keeps the deck's
/// [solver] kinematics).
Deck DeckFor(const Deck& deck, const std::string& kinematics);
/// The deck's [solver] options with a front-end's solver by name ("" keeps the deck's).
SolverOptions SolverFor(const Deck& deck, const std::string& name);

/// Parses and validates a deck, including the geometry (an undercut profile is rejected).
/// overrides: "section.key=value" (the CLI's --set), each value read as a TOML value (a bare
/// word that is not TOML is a string), applied to the parsed text before the sections are read,
/// so that an override is checked like the key in the file; a missing section is created. An
/// override "-section" or "-section.key" (the CLI's --unset) removes that section or key, which
/// the deck must have. They apply in order.
/// Text larger than DeckLimits::kMaxFileBytes or nested deeper than DeckLimits::kMaxNesting is
/// rejected before the TOML parser sees it.
/// directory: where relative paths in the deck ([errors] profile_measured_csv) are read from;
/// empty: the current directory (LoadDeck passes the deck file's directory).
/// Throws std::invalid_argument with a message that starts with the deck name.
Deck ParseDeck(std::string_view toml_text, const std::string& name, const std::vector<std::string>& overrides = {},
               const std::filesystem::path& directory = {});
/// A deck's text parsed once, to read decks from it with different overrides: the TOML parse is
/// most of the cost of reading a deck (about 1 ms for a short one), and a sweep of decks built in
/// Python changes a key or two of the same text. Read(overrides) is
/// ParseDeck(text, name, overrides, directory), the same checks and messages. Immutable; shared
/// between copies.
class DeckSource {
 public:
  /// Parses the text (std::invalid_argument naming the deck for bad TOML or shape).
  DeckSource(std::string_view toml_text, std::string name, std::filesystem::path directory = {});
  Deck Read(const std::vector<std::string>& overrides = {}) const;
  const std::string& name() const;
  /// The same text with one more in-memory file (MemoryFiles), `text` under `name`, replacing a
  /// file of that name; this source is unchanged.
  DeckSource WithFile(const std::string& name, std::string text) const;

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
};

/// The same for a file, which must be a regular file (not a directory, FIFO or device) of at
/// most DeckLimits::kMaxFileBytes; it is read with a bounded read.
Deck LoadDeck(const std::filesystem::path& path, const std::vector<std::string>& overrides = {});

/// One key written into a deck: `[section] key = value`, the value as TOML text; `comment` (without
/// the '#') is put after a key the deck did not have. With `remove` the key is taken out instead.
struct DeckEdit {
  std::string section, key, value, comment;
  bool remove = false;
};

/// The deck as a file that reads back as this deck: its own text (comments, order, empty sections
/// such as an identical [second_disc], kept) with the --set and --unset overrides and then `edits` written into
/// it, the sections `drop` left out, and `header` (comment lines) first. The one deck writer
/// (`ltca optimise --write-deck`). The text is read back before it is returned: every key it
/// gives must be the deck's (after the edits, without the dropped sections) with the same value,
/// and the disc count and the stage must be the deck's; std::invalid_argument naming the key
/// otherwise.
std::string WriteDeck(const Deck& deck, const std::vector<DeckEdit>& edits, const std::vector<std::string>& drop = {},
                      const std::string& header = {});

/// A value of a deck as a front-end hands it over (Python's Deck.from_dict and Deck.set): a
/// boolean, an integer, a float, a string, an array or a table (its keys in their order).
struct TomlEntry;
struct TomlValue {
  using Array = std::vector<TomlValue>;
  /// A table's keys in order (a struct, not std::pair: a pair of the type being defined is
  /// incomplete inside its definition, which clang's libstdc++ checks refuse).
  using Table = std::vector<TomlEntry>;
  std::variant<bool, std::int64_t, double, std::string, Array, Table> value;
};
struct TomlEntry {
  std::string key;
  TomlValue value;
};

/// The deck writer's TOML text of a value, on one line (TOML 1.0): a float always as a float (100.0
/// not 100; nan, inf, -inf) in the shortest text that reads back the same double, a string as a
/// basic string (quotes, backslashes and control characters escaped, other UTF-8 as it is), an
/// array as [a, b], a table inline as { key = value, ... }.
std::string TomlText(const TomlValue& value);
/// A key as the deck writer writes it: bare when it is only A-Z a-z 0-9 _ -, else a basic string.
std::string TomlKeyText(const std::string& key);
/// A deck's text from its sections: "[section]", a "key = value" line per key, an empty line after
/// each section.
std::string TomlDeckText(const std::vector<std::pair<std::string, TomlValue::Table>>& sections);

/// The built-in default case: Liu 2021 Table 1 (the text of cases/liu2021_table1.toml).
std::string_view DefaultDeckText();
Deck DefaultDeck(const std::vector<std::string>& overrides = {});

}  // namespace ltca::app
