#pragma once
// Results against allowables: one rule for every front-end. A figure passes its allowable when
// it is finite and min <= value <= max (either bound may be open); its margin is the distance to
// the nearer bound in the figure's own unit, positive inside. The tolerance study counts a sample
// as within its limits by the same rule (AllowableRange::Holds), so the verdict on the nominal
// design and the Monte Carlo's pass fraction never disagree on what "within" means.
#include <limits>
#include <optional>
#include <string>
#include <vector>

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

}  // namespace ltca::analysis
