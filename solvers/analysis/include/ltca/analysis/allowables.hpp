#pragma once
// Results against allowables: one rule for every front-end. A figure passes its allowable when
// it is finite and min <= value <= max (either bound may be open); its margin is the distance to
// the nearer bound in the figure's own unit, positive inside. The tolerance study counts a sample
// as within its limits by the same rule (AllowableRange::Holds), so the verdict on the nominal
// design and the Monte Carlo's pass fraction never disagree on what "within" means.
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ltca/analysis/tolerance.hpp"

namespace ltca::analysis {

/// The allowable range of one figure: min <= value <= max; an infinite bound is open.
struct AllowableRange {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  /// Whether either bound is finite (an allowable is given).
  bool Given() const;
  /// Whether value is finite and within [min, max].
  bool Holds(double value) const;
  /// min(max - value, value - min) over the finite bounds: positive inside, negative outside, in
  /// the figure's unit; NaN when value is not finite or no bound is given.
  double Margin(double value) const;
};

enum class AllowableVerdict {
  kPass,         ///< within its allowable
  kFail,         ///< outside its allowable
  kNoAllowable,  ///< computed, but the deck gives no allowable
  kNotComputed,  ///< no analysis that ran gives the figure (or its run failed): no value to judge
};

/// "pass", "FAIL", "no allowable", "n/a".
const char* ToString(AllowableVerdict verdict);

/// One row of the check: a figure of the nominal design with its allowable and verdict.
struct AllowableRow {
  std::string figure;  ///< the figure's key, e.g. "pp_te_arcsec" (its unit in its name)
  std::string name;    ///< how a reader names it where the key does not say it well; empty: the key's
  double value = std::numeric_limits<double>::quiet_NaN();  ///< the nominal value; NaN: not computed
  std::string basis;                                        ///< the analysis (and model) the value is from
  AllowableRange range;
  double margin = std::numeric_limits<double>::quiet_NaN();  ///< AllowableRange::Margin(value)
  AllowableVerdict verdict = AllowableVerdict::kNotComputed;
  std::optional<double> pass_fraction;  ///< the Monte Carlo's fraction of samples within range, when it ran
};

/// The row of one figure: its margin and verdict by the rule above.
AllowableRow Judge(std::string figure, double value, std::string basis, AllowableRange range = {},
                   std::optional<double> pass_fraction = std::nullopt);

struct BacklashResult;
struct EfficiencySummary;
struct StiffnessResult;
struct SweepSummary;
struct ToleranceResult;

/// The results of the nominal design the check reads; nullptr where that analysis did not run.
struct NominalResults {
  bool reducer = false;        ///< the design has a reducer stage (its free play is the backlash)
  bool output_pins = false;    ///< the stage's output is pins in holes (it has an output-pin force)
  const SweepSummary* solve = nullptr;            ///< the loaded sweep (required)
  const BacklashResult* backlash = nullptr;       ///< the pin ring's unloaded backlash over the sweep
  const StiffnessResult* stiffness = nullptr;     ///< the torque-twist loop at crank 0
  const EfficiencySummary* efficiency = nullptr;  ///< the sweep's efficiency
  /// The tolerance study (rank 0's result): its worst case's nominal figures and its limits' pass
  /// fractions; `study` names the figures it ran.
  const ToleranceStudy* study = nullptr;
  const ToleranceResult* tolerance = nullptr;
};

/// [allowables] (docs/stage.md, issue 50): the targets of a stage's bearing ratings; absent: none.
struct AllowablesSettings {
  /// h: the life every bearing must reach, its load-zone life and its basic L10 alike (and, with
  /// the oil's viscosity, their modified lives a_ISO L).
  std::optional<double> bearing_life_hours;
  /// The least static safety s_0 = C_0 / P_0,max of every bearing (ISO 76).
  std::optional<double> min_static_safety;
  /// h: the pitting life the pins and the disc's teeth must reach; their S_H is rated at it.
  std::optional<double> contact_life_hours;
  /// The least pitting safety S_H of the pins and teeth at contact_life_hours (ISO 6336-2).
  std::optional<double> min_contact_safety;
  /// Throws std::invalid_argument naming the `[allowables]` key, its value and what is expected:
  /// each given value finite and > 0.
  void Validate() const;
};

/// The allowables of a design: the largest contact stress (MPa, infinite: none), the limits
/// of [tolerances] (each a figure of ToleranceSettings::FigureNames with its range) and the
/// targets of [allowables].
struct Allowables {
  double contact_stress_limit = std::numeric_limits<double>::infinity();
  std::vector<ToleranceLimit> limits;
  AllowablesSettings targets;
};

struct BearingLife;
/// A stage's bearing ratings against their targets, one rule for every front-end (the solve's
/// JSON and text, the report): "stage.shortest_l10_hours" and
/// "stage.shortest_load_zone_life_hours" against [allowables] bearing_life_hours (min), with the
/// oil's viscosity also "stage.shortest_modified_life_hours" and
/// "stage.shortest_load_zone_modified_life_hours" (ISO 281's a_ISO L) against it,
/// "stage.smallest_static_safety" against min_static_safety, and
/// "stage.largest_roller_contact_stress_mpa" against ISO 76's 4,000 MPa (max, always given).
std::vector<AllowableRow> BearingRatingRows(const BearingLife& life, const AllowablesSettings& targets);

struct ContactFatigue;
/// The pin-cycloid contact's pitting rating against its targets: "contact.shortest_life_hours"
/// against [allowables] contact_life_hours (min; an infinite life, no damage, passes it: value and
/// margin +inf) and "contact.smallest_safety" against min_contact_safety (min).
std::vector<AllowableRow> ContactFatigueRows(const ContactFatigue& fatigue, const AllowablesSettings& targets);

struct SpectrumResult;
/// A load spectrum's figures against their targets, one rule for every front-end (the solve's
/// JSON and text, the report), each figure the spectrum's: the lives by Miner's rule over the bins
/// ("spectrum.shortest_l10_hours", "spectrum.shortest_load_zone_life_hours", with the oil's
/// viscosity the two modified lives, against bearing_life_hours; "spectrum.shortest_pitting_life_hours"
/// against contact_life_hours), the pitting safety over the spectrum ("spectrum.smallest_pitting_safety",
/// SpectrumContactSafety) against min_contact_safety, and the static figures of the worst bin:
/// "spectrum.smallest_static_safety" against min_static_safety, "spectrum.largest_roller_contact_stress_mpa"
/// against ISO 76's 4,000 MPa and "spectrum.max_contact_stress_mpa" against contact_stress_limit
/// (MPa, [material] contact_stress_limit_mpa). A static row's basis names the bin (1-based) that sets it.
/// Rows of a stage's bearings only when the bins rated bearings (`reducer`).
std::vector<AllowableRow> SpectrumRatingRows(const SpectrumResult& spectrum, const AllowablesSettings& targets,
                                             double contact_stress_limit, bool reducer);

/// A figure of the nominal design (a name of ToleranceSettings::FigureNames) and the analysis it
/// is taken from: the tolerance study's nominal run when it ran its worst case, else the analysis
/// that reports it. For a reducer stage the backlash is the stage's free play (the loop's width at
/// zero torque, x 60 in arcsec), never the pin ring's unloaded analysis, and its loads and lives
/// are the loaded sweep's stage summary. NaN and "not computed" when nothing that ran gives it.
std::pair<double, std::string> NominalFigure(const NominalResults& results, const std::string& figure);

/// The check, in the order a reviewer signs it: the largest contact stress against its limit;
/// every limit with its nominal value and Monte Carlo pass fraction; then, without an allowable
/// unless a limit named them, pp TE and the mean backlash, the loop's lost motion and rigidity
/// (arcmin, N*m/arcmin), the efficiency and a stage's shortest bearing L10 (h, key
/// "stage.shortest_l10_hours").
std::vector<AllowableRow> CheckAllowables(const NominalResults& results, const Allowables& allowables);

}  // namespace ltca::analysis
