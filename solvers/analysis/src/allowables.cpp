#include "ltca/analysis/allowables.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace ltca::analysis {

bool AllowableRange::Given() const { return std::isfinite(min) || std::isfinite(max); }

bool AllowableRange::Holds(double value) const { return std::isfinite(value) && value >= min && value <= max; }

double AllowableRange::Margin(double value) const {
  if (!std::isfinite(value) || !Given()) return std::numeric_limits<double>::quiet_NaN();
  double m = std::numeric_limits<double>::infinity();
  if (std::isfinite(max)) m = std::min(m, max - value);
  if (std::isfinite(min)) m = std::min(m, value - min);
  return m;
}

const char* ToString(AllowableVerdict verdict) {
  switch (verdict) {
    case AllowableVerdict::kPass: return "pass";
    case AllowableVerdict::kFail: return "FAIL";
    case AllowableVerdict::kNoAllowable: return "no allowable";
    case AllowableVerdict::kNotComputed: return "n/a";
  }
  return "n/a";
}

AllowableRow Judge(std::string figure, double value, std::string basis, AllowableRange range, std::optional<double> pass_fraction) {
  AllowableRow row;
  row.figure = std::move(figure);
  row.value = value;
  row.basis = std::move(basis);
  row.range = range;
  row.pass_fraction = pass_fraction;
  row.margin = range.Margin(value);
  row.verdict = !std::isfinite(value) ? AllowableVerdict::kNotComputed
                : !range.Given()      ? AllowableVerdict::kNoAllowable
                : range.Holds(value)  ? AllowableVerdict::kPass
                                      : AllowableVerdict::kFail;
  return row;
}

}  // namespace ltca::analysis
