// analysis::Judge and AllowableRange: the verdict, margin and "within" rule of the allowables
// check, against values worked by hand (a figure of 5 against [2, 4], <= 6, >= 5.5, and none).
#include <cmath>
#include <limits>
#include <string>

#include <doctest/doctest.h>

#include "ltca/analysis/allowables.hpp"

namespace {
using ltca::analysis::AllowableRange;
using ltca::analysis::AllowableVerdict;
using ltca::analysis::Judge;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
}  // namespace

TEST_CASE("analysis: an allowable's margin is the distance to the nearer bound, positive inside") {
  const auto between = Judge("f", 3.5, "by hand", AllowableRange{2.0, 4.0});
  CHECK(between.verdict == AllowableVerdict::kPass);
  CHECK(between.margin == doctest::Approx(0.5));  // 4 - 3.5 < 3.5 - 2
  const auto above = Judge("f", 5.0, "by hand", AllowableRange{2.0, 4.0});
  CHECK(above.verdict == AllowableVerdict::kFail);
  CHECK(above.margin == doctest::Approx(-1.0));
  const auto at_max = Judge("f", 6.0, "by hand", AllowableRange{-kInf, 6.0});
  CHECK(at_max.verdict == AllowableVerdict::kPass);  // on the bound is within
  CHECK(at_max.margin == 0.0);
  const auto below_min = Judge("f", 5.0, "by hand", AllowableRange{5.5, kInf});
  CHECK(below_min.verdict == AllowableVerdict::kFail);
  CHECK(below_min.margin == doctest::Approx(-0.5));
}

TEST_CASE("analysis: a figure without a value is not computed, one without an allowable is listed") {
  const auto missing = Judge("f", kNan, "not computed", AllowableRange{0.0, 1.0});
  CHECK(missing.verdict == AllowableVerdict::kNotComputed);
  CHECK(std::isnan(missing.margin));
  CHECK(Judge("f", kInf, "diverged", AllowableRange{0.0, kInf}).verdict == AllowableVerdict::kNotComputed);
  const auto free = Judge("f", 2.0, "by hand");
  CHECK(free.verdict == AllowableVerdict::kNoAllowable);
  CHECK(std::isnan(free.margin));
  CHECK(std::string(ltca::analysis::ToString(free.verdict)) == "no allowable");
}

TEST_CASE("analysis: within an allowable is one rule for the verdict and the Monte Carlo's count") {
  const AllowableRange r{2.0, 4.0};
  for (const double v : {1.9, 2.0, 3.0, 4.0, 4.1, kNan, kInf, -kInf}) {
    CHECK(r.Holds(v) == (Judge("f", v, "", r).verdict == AllowableVerdict::kPass));
  }
  CHECK_FALSE(AllowableRange{}.Given());
  CHECK(AllowableRange{-kInf, 1.0}.Given());
}
