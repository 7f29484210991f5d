// Liu 2021's discrete tooth surface (the elements geometry mode) against the analytic profile.
#include <cmath>

#include <doctest/doctest.h>

#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/discrete_profile.hpp"
#include "pairs.hpp"

using ltca::contact::MeshModel;
using ltca::geometry::DiscreteProfile;
using ltca::geometry::GeometrySettings;

TEST_CASE("contact: Liu's elements have equal arc length (eq. 3) and lie on the profile") {
  // Control points at equal arc length S / n: the chord between neighbours equals the spacing to
  // 1e-3 (chord against arc on elements of 0.06 mm); each lies on the analytic curve (1e-12 mm).
  // The polynomial of eq. 3 alone would miss: its fit error is reported (> 1e-4 rad at order 9),
  // which is why it only seeds the placement.
  const ltca::geometry::CycloidProfile profile(ltca::test::LiuPair(), ltca::test::Mod(-4, -17));
  const DiscreteProfile discrete(profile, 200, 1);
  CHECK(discrete.fit_error() > 1e-4);
  const double spacing = discrete.arc_length() / 200;
  for (int j = 1; j < discrete.element_count(); ++j) {
    const auto& a = discrete.elements()[static_cast<std::size_t>(j - 1)];
    const auto& b = discrete.elements()[static_cast<std::size_t>(j)];
    CHECK((b.position - a.position).norm() == doctest::Approx(spacing).epsilon(1e-3));
    CHECK((profile.Position(b.u) - b.position).norm() < 1e-12);
  }
}

TEST_CASE("contact: element-mode clearances converge to the analytic ones as elements are added") {
  // The element gap uses the osculating cylinder of the nearest control point: its error falls
  // with the element size (at least 10 times from 50 to 800 elements) and is below 1e-6 mm at
  // Liu's 800 elements.
  const auto pair = ltca::test::LiuPair();
  const MeshModel analytic(pair, ltca::test::Mod(-4, -17));
  double previous = 1e300;
  for (const int elements : {50, 200, 800}) {
    GeometrySettings g;
    g.mode = GeometrySettings::Mode::kElements;
    g.profile_elements = elements;
    g.width_slices = 1;
    const MeshModel model(pair, ltca::test::Mod(-4, -17), {}, g);
    double worst = 0;
    for (const double crank : {0.0, 0.07}) {
      const auto a = analytic.Evaluate(crank), b = model.Evaluate(crank);
      for (std::size_t i = 0; i < a.pins.size(); ++i) {
        worst = std::max(worst, std::abs(a.pins[i].clearance - b.pins[i].clearance));
        if (a.pins[i].arm > 5.0) CHECK(b.pins[i].arm == doctest::Approx(a.pins[i].arm).epsilon(2e-2));
      }
    }
    CAPTURE(elements);
    CHECK(worst < previous);
    if (elements == 800) CHECK(worst < 1e-6);
    if (elements == 800) CHECK(worst < previous / 10.0);
    previous = worst;
  }
}
