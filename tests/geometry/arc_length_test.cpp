// Arc length along the real profile against the closed form of arc_length_closed_form.hpp (the
// equidistant's length from the elliptic integral of the locus and its tangent's turning angle).
#include <cmath>
#include <stdexcept>

#include <doctest/doctest.h>

#include "arc_length_closed_form.hpp"
#include "ltca/geometry/arc_length.hpp"
#include "pairs.hpp"

using ltca::geometry::CycloidProfile;
using ltca::geometry::Modification;
using ltca::geometry::ProfileArcLength;
using ltca::test::ClosedFormArcLength;

TEST_CASE("geometry: the arc length along the profile matches the elliptic-integral closed form") {
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    for (const Modification& mod : {Modification{}, ltca::test::Mod(-4, -17), ltca::test::Mod(10, 20)}) {
      const CycloidProfile profile(pair, mod);
      const ProfileArcLength arc(profile);
      const double phi = profile.phi_max();
      const double flank = ClosedFormArcLength(pair, mod, phi);
      CAPTURE(name);
      CHECK(flank > 0.0);
      CHECK(std::abs(arc.end() - flank) <= 1e-12 * flank);
      CHECK(std::abs(arc.begin() + flank) <= 1e-12 * flank);
      for (int i = -20; i <= 20; ++i) {
        const double u = phi * (i + (i > -20 && i < 20 ? 0.31 : 0.0)) / 20.0;
        CAPTURE(u);
        CHECK(std::abs(arc.At(u) - ClosedFormArcLength(pair, mod, u)) <= 1e-12 * flank);
      }
      CHECK(arc.At(0.0) == 0.0);
    }
  }
}

TEST_CASE("geometry: the parameter of an arc length inverts the arc length to a few ulp") {
  for (const auto& [name, pair] : ltca::test::AllPairs()) {
    const CycloidProfile profile(pair, ltca::test::Mod(-4, -17));
    const ProfileArcLength arc(profile);
    const double phi = profile.phi_max();
    CAPTURE(name);
    for (int i = -50; i <= 50; ++i) {
      const double u = phi * i / 50.0 * 0.999;
      CHECK(std::abs(arc.ParameterAt(arc.At(u)) - u) <= 1e-14 * phi);
      // s -> u -> s, at arc lengths spread evenly along the flank.
      const double s = arc.begin() + (arc.end() - arc.begin()) * (i + 50.5) / 101.0;
      CHECK(std::abs(arc.At(arc.ParameterAt(s)) - s) <= 1e-13 * arc.end());
    }
    CHECK(arc.ParameterAt(arc.end()) == phi);
    CHECK(arc.ParameterAt(arc.begin()) == -phi);
    CHECK_THROWS_AS(arc.At(1.01 * phi), std::out_of_range);
    CHECK_THROWS_AS(arc.ParameterAt(1.01 * arc.end()), std::out_of_range);
  }
}
