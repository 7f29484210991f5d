// Issue 11: the face-width slices. Each slice of the slice model is a plane state; the
// independent references are plane models built through other code paths: a misaligned slice is
// the plane pair with its centre offset (the frame-fixed dx, dy of Liu eq. 7), a slice of a
// crowned or sloped pair is the plane pair with a uniform profile layer (generated with the pin
// radius r_rp + dR_rp - t, RealPair), an eccentricity deviation is a centre offset turning with
// the crank, and a pin's radial deviation is a pin-circle deviation of that pin.
#include <cmath>
#include <vector>

#include <doctest/doctest.h>

#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/units.hpp"
#include "pairs.hpp"

using ltca::contact::MeshModel;
using ltca::contact::PinContact;
using ltca::geometry::AssemblyErrors;
using ltca::geometry::GeometrySettings;
using ltca::geometry::ManufacturingErrors;
using ltca::geometry::RealPair;

namespace {

const auto kPair = ltca::test::LiuPair();
const auto kMod = ltca::test::Mod(-4.0, -17.0);

GeometrySettings Slices(int n) {
  GeometrySettings g;
  g.width_slices = n;
  return g;
}

// Two contact points agree: gap and arm to 1e-12 mm, the normal to 1e-12, curvature to 1e-9 relative.
void CheckSame(const PinContact& a, const PinContact& b) {
  CHECK(std::abs(a.clearance - b.clearance) <= 1e-12);
  CHECK(std::abs(a.arm - b.arm) <= 1e-12);
  CHECK((a.normal - b.normal).norm() <= 1e-12);
  CHECK((a.cycloid_point - b.cycloid_point).norm() <= 1e-11);
  CHECK(a.cycloid_curvature == doctest::Approx(b.cycloid_curvature).epsilon(1e-9));
}

}  // namespace

TEST_CASE("contact: the slice model runs only when something varies along the face width") {
  CHECK(MeshModel(RealPair(kPair, kMod), Slices(20)).slice_count() == 1);  // nothing varies: plane
  CHECK(MeshModel(RealPair(kPair, kMod), Slices(20), /*coupled_along_width=*/true).slice_count() == 20);
  AssemblyErrors tilt;
  tilt.misalignment_xz = ltca::units::DegToRad(0.02);
  const MeshModel misaligned(RealPair(kPair, kMod, {}, tilt), Slices(7));
  CHECK(misaligned.slice_count() == 7);
  CHECK(misaligned.point_count() == 7 * 40);
  const auto state = misaligned.Evaluate(0.3);
  REQUIRE(state.pins.size() == 280u);
  // Pin-major, slice centres at (k + 1/2) B / n, each B / n long.
  CHECK(state.pins[7 * 3 + 2].pin == 3);
  CHECK(state.pins[7 * 3 + 2].slice == 2);
  CHECK(state.pins[7 * 3 + 2].z == doctest::Approx(2.5 * 12.0 / 7));
  CHECK(state.pins[7 * 3 + 2].length == doctest::Approx(12.0 / 7));
  ManufacturingErrors crowned;
  crowned.lead_crowning = 0.005;
  CHECK(MeshModel(RealPair(kPair, kMod, crowned), Slices(4)).slice_count() == 4);
  ManufacturingErrors uniform;  // uniform along the width: the plane model
  uniform.profile_layer = 0.002;
  uniform.pin_radius_deviations.assign(40, 0.001);
  CHECK(MeshModel(RealPair(kPair, kMod, uniform), Slices(4)).slice_count() == 1);
}

TEST_CASE("contact: a misaligned slice is the plane pair with its centre offset by (z tan phi, z tan gamma)") {
  const double phi = ltca::units::DegToRad(0.02), gamma = ltca::units::DegToRad(-0.013);
  for (const auto pivot : {AssemblyErrors::Pivot::kFace, AssemblyErrors::Pivot::kMid}) {
    AssemblyErrors tilt;
    tilt.misalignment_xz = phi;
    tilt.misalignment_yz = gamma;
    tilt.pivot = pivot;
    tilt.centre_dx = 0.001;  // a bore offset on top
    const int n = 5;
    const MeshModel sliced(RealPair(kPair, kMod, {}, tilt), Slices(n));
    for (const int k : {0, 2, 4}) {
      const double z = (k + 0.5) * kPair.face_width / n;
      const double zz = pivot == AssemblyErrors::Pivot::kFace ? z : z - 0.5 * kPair.face_width;
      AssemblyErrors offset;
      offset.centre_dx = 0.001 + zz * std::tan(phi);
      offset.centre_dy = zz * std::tan(gamma);
      const MeshModel plane(RealPair(kPair, kMod, {}, offset));
      for (const double crank : {0.0, 0.4, 2.0}) {
        for (const int pin : {0, 5, 17, 33}) {
          CAPTURE(k);
          CAPTURE(pin);
          CheckSame(sliced.EvaluatePoint(pin, k, crank, 1e-4), plane.EvaluatePoint(pin, 0, crank, 1e-4));
        }
      }
    }
  }
}

TEST_CASE("contact: each slice of a crowned and sloped pair is the plane pair with the uniform layer of its z") {
  // Lead crowning c over the face width B: a circular arc with sagitta c at the faces (radius
  // R = ((B/2)^2 + c^2) / (2c)); the slope s adds s (z - B/2) / B.
  ManufacturingErrors lead;
  lead.lead_crowning = 0.008;
  lead.lead_slope = 0.003;
  const int n = 6;
  const MeshModel sliced(RealPair(kPair, kMod, lead), Slices(n));
  const double b = kPair.face_width, c = lead.lead_crowning;
  const double radius = (0.25 * b * b + c * c) / (2.0 * c);
  for (int k = 0; k < n; ++k) {
    const double z = (k + 0.5) * b / n, x = z - 0.5 * b;
    ManufacturingErrors layer;
    layer.profile_layer = -(radius - std::sqrt(radius * radius - x * x)) + lead.lead_slope * x / b;
    const MeshModel plane(RealPair(kPair, kMod, layer));
    for (const double crank : {0.1, 1.0}) {
      for (const int pin : {2, 10, 21}) {
        CAPTURE(k);
        CAPTURE(pin);
        CheckSame(sliced.EvaluatePoint(pin, k, crank), plane.EvaluatePoint(pin, 0, crank));
      }
    }
  }
}

TEST_CASE("contact: an eccentricity deviation is a centre offset turning with the crank, a pin's errors move only that pin") {
  AssemblyErrors ecc;
  ecc.eccentricity_deviation = 0.004;
  const MeshModel deviated(RealPair(kPair, kMod, {}, ecc));
  for (const double crank : {0.0, 0.7, 3.9}) {
    AssemblyErrors offset;
    offset.centre_dx = 0.004 * std::cos(crank);
    offset.centre_dy = 0.004 * std::sin(crank);
    const MeshModel plane(RealPair(kPair, kMod, {}, offset));
    for (const int pin : {1, 9, 30}) CheckSame(deviated.EvaluatePoint(pin, 0, crank), plane.EvaluatePoint(pin, 0, crank));
  }
  // Pin 12 (index 11) 3 um further out and 2 um thicker: its gap is that of the pair whose whole
  // pin circle is 3 um larger, less 2 um; every other pin is untouched.
  ManufacturingErrors pin_errors;
  pin_errors.pin_radial_deviations.assign(40, 0.0);
  pin_errors.pin_radius_deviations.assign(40, 0.0);
  pin_errors.pin_radial_deviations[11] = 0.003;
  pin_errors.pin_radius_deviations[11] = 0.002;
  ManufacturingErrors circle;
  circle.pin_circle_deviation = 0.003;
  const MeshModel one_pin(RealPair(kPair, kMod, pin_errors)), bigger(RealPair(kPair, kMod, circle)),
      nominal(RealPair(kPair, kMod));
  for (const double crank : {0.2, 1.5}) {
    const PinContact a = one_pin.EvaluatePoint(11, 0, crank), ref = bigger.EvaluatePoint(11, 0, crank);
    CHECK(std::abs(a.clearance - (ref.clearance - 0.002)) <= 1e-12);
    CHECK(std::abs(a.arm - ref.arm) <= 1e-12);
    CHECK(a.pin_radius == doctest::Approx(3.002).epsilon(1e-15));
    CheckSame(one_pin.EvaluatePoint(12, 0, crank), nominal.EvaluatePoint(12, 0, crank));
  }
}
