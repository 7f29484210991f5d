// Pin bending (issue 11): the Timoshenko beam's Green's function and slice compliance against
// textbook closed forms (Roark's Formulas for Stress and Strain, 7th ed., Table 8.1 cases 1a, 1e,
// 2a, 2e for the bending; the shear deflection of a Timoshenko beam, Timoshenko & Gere, Mechanics
// of Materials, sec. 10.10) and, for the clamped beam under an off-centre load, where the end
// moments depend on the shear stiffness, against an independent finite-element solution with the
// two-node Timoshenko element of Przemieniecki (Theory of Matrix Structural Analysis, 1968,
// eq. 5.118), which is exact at the nodes for nodal loads. Tolerance 1e-9 relative throughout
// (the formulas are evaluated in double precision; 1e-9 leaves room for rounding only).
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <doctest/doctest.h>

#include "ltca/contact/laws.hpp"
#include "ltca/contact/pin_bending.hpp"

using ltca::contact::Material;
using ltca::contact::PinBeam;
using ltca::contact::PinContact;
using ltca::contact::PinSupport;
using ltca::contact::PinSupportKind;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadius = 3.0;  // mm, Liu Table 1's pin
constexpr double kSpan = 20.0;   // mm

Material Steel() {
  Material m;
  m.pin_young_modulus = 206000.0;
  m.pin_poisson_ratio = 0.3;
  return m;
}

PinSupport Support(PinSupportKind kind, double span = kSpan, double offset = 0.0) {
  PinSupport s;
  s.span = span;
  s.support = kind;
  s.face_offset = offset;
  return s;
}

// Section and material figures computed here from their definitions, not from PinBeam.
struct Section {
  double ei, kga;
};
Section Figures(const Material& m = Steel(), double r = kRadius) {
  const double e = m.pin_young_modulus, nu = m.pin_poisson_ratio;
  const double kappa = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu);  // Cowper 1966, solid circle
  return {e * kPi * std::pow(r, 4) / 4.0, kappa * e / (2.0 * (1.0 + nu)) * kPi * r * r};
}

double Relative(double got, double want) { return std::abs(got - want) / std::abs(want); }

// Composite Simpson with `panels` (even) panels.
template <typename F>
double Simpson(double lo, double hi, int panels, F&& f) {
  const double h = (hi - lo) / panels;
  double s = f(lo) + f(hi);
  for (int k = 1; k < panels; ++k) s += (k % 2 == 1 ? 4.0 : 2.0) * f(lo + k * h);
  return s * h / 3.0;
}

// Timoshenko beam by finite elements (Przemieniecki's two-node element, exact at the nodes):
// nodes at the given sorted positions, unit load at node `load`, deflection at node `at`.
double FiniteElementDeflection(const std::vector<double>& nodes, std::size_t load, std::size_t at, PinSupportKind kind,
                               const Section& s) {
  const auto n = static_cast<Eigen::Index>(nodes.size());
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(2 * n, 2 * n);  // dofs (v, theta) per node
  for (Eigen::Index e = 0; e + 1 < n; ++e) {
    const double l = nodes[static_cast<std::size_t>(e + 1)] - nodes[static_cast<std::size_t>(e)];
    const double phi = 12.0 * s.ei / (s.kga * l * l);
    Eigen::Matrix4d ke;
    ke << 12, 6 * l, -12, 6 * l,  //
        6 * l, (4 + phi) * l * l, -6 * l, (2 - phi) * l * l,  //
        -12, -6 * l, 12, -6 * l,  //
        6 * l, (2 - phi) * l * l, -6 * l, (4 + phi) * l * l;
    ke *= s.ei / ((1 + phi) * l * l * l);
    k.block(2 * e, 2 * e, 4, 4) += ke;
  }
  std::vector<Eigen::Index> fixed = {0, 2 * (n - 1)};
  if (kind == PinSupportKind::kClamped) fixed = {0, 1, 2 * (n - 1), 2 * (n - 1) + 1};
  std::vector<Eigen::Index> free;
  for (Eigen::Index d = 0; d < 2 * n; ++d) {
    if (std::find(fixed.begin(), fixed.end(), d) == fixed.end()) free.push_back(d);
  }
  const auto m = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd kff(m, m);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    for (Eigen::Index j = 0; j < m; ++j) kff(i, j) = k(free[static_cast<std::size_t>(i)], free[static_cast<std::size_t>(j)]);
    if (free[static_cast<std::size_t>(i)] == 2 * static_cast<Eigen::Index>(load)) f(i) = 1.0;
  }
  const Eigen::VectorXd u = kff.ldlt().solve(f);
  for (Eigen::Index i = 0; i < m; ++i) {
    if (free[static_cast<std::size_t>(i)] == 2 * static_cast<Eigen::Index>(at)) return u(i);
  }
  return 0.0;
}

}  // namespace

TEST_CASE("contact: pin bending - central point load on both supports matches the textbook closed forms") {
  const Section s = Figures();
  const double l = kSpan;
  const PinBeam simple(Support(PinSupportKind::kSimplySupported), Steel(), kRadius);
  const PinBeam clamped(Support(PinSupportKind::kClamped), Steel(), kRadius);
  // P L^3 / (48 EI) + P L / (4 kappa G A) and P L^3 / (192 EI) + P L / (4 kappa G A), P = 1 N.
  CHECK(Relative(simple.Deflection(l / 2, l / 2), l * l * l / (48 * s.ei) + l / (4 * s.kga)) < 1e-9);
  CHECK(Relative(clamped.Deflection(l / 2, l / 2), l * l * l / (192 * s.ei) + l / (4 * s.kga)) < 1e-9);
  CHECK(Relative(simple.bending_stiffness(), s.ei) < 1e-12);
  CHECK(Relative(simple.shear_stiffness(), s.kga) < 1e-12);
  // Shear matters for a stubby pin: at L / r = 6.7 it is 17 % of the simply supported deflection.
  CHECK(l / (4 * s.kga) > 0.15 * simple.Deflection(l / 2, l / 2));
}

TEST_CASE("contact: pin bending - off-centre point load on a simply supported pin matches the closed form") {
  const Section s = Figures();
  const double l = kSpan, a = 0.7 * l, b = l - a;
  const PinBeam simple(Support(PinSupportKind::kSimplySupported), Steel(), kRadius);
  // Left of the load: P b x (L^2 - b^2 - x^2) / (6 EI L) + P b x / (L kappa G A).
  for (const double x : {0.1 * l, 0.3 * l, 0.5 * l, a}) {
    CAPTURE(x);
    CHECK(Relative(simple.Deflection(x, a), b * x * (l * l - b * b - x * x) / (6 * s.ei * l) + b * x / (l * s.kga)) < 1e-9);
  }
  // Right of the load: P a (L - x) (2 L x - a^2 - x^2) / (6 EI L) + P a (L - x) / (L kappa G A).
  for (const double x : {0.8 * l, 0.95 * l}) {
    CAPTURE(x);
    CHECK(Relative(simple.Deflection(x, a),
                   a * (l - x) * (2 * l * x - a * a - x * x) / (6 * s.ei * l) + a * (l - x) / (l * s.kga)) < 1e-9);
  }
  CHECK(simple.Deflection(0.0, a) == 0.0);
  CHECK(std::abs(simple.Deflection(l, a)) < 1e-20);
}

TEST_CASE("contact: pin bending - off-centre loads on both supports match a Timoshenko finite-element solution") {
  // The clamped end moments depend on the shear stiffness (derived in PinBeam::Deflection): checked
  // against an independent method, at several load and field points, on a stubby and a slender pin.
  for (const double radius : {3.0, 0.8}) {
    const Section s = Figures(Steel(), radius);
    for (const auto kind : {PinSupportKind::kClamped, PinSupportKind::kSimplySupported}) {
      const PinBeam beam(Support(kind), Steel(), radius);
      for (const double a : {0.15, 0.4, 0.5, 0.83}) {
        for (const double x : {0.05, 0.3, 0.5, 0.61, 0.9}) {
          CAPTURE(radius);
          CAPTURE(static_cast<int>(kind));
          CAPTURE(a);
          CAPTURE(x);
          std::vector<double> nodes = {0.0, kSpan};
          for (const double p : {a, x, 0.37}) {
            if (std::find(nodes.begin(), nodes.end(), p * kSpan) == nodes.end()) nodes.push_back(p * kSpan);
          }
          std::sort(nodes.begin(), nodes.end());
          const auto index = [&](double p) {
            return static_cast<std::size_t>(std::find(nodes.begin(), nodes.end(), p * kSpan) - nodes.begin());
          };
          const double fe = FiniteElementDeflection(nodes, index(a), index(x), kind, s);
          CHECK(Relative(beam.Deflection(x * kSpan, a * kSpan), fe) < 1e-9);
        }
      }
    }
  }
}

TEST_CASE("contact: pin bending - uniform load over the span: midspan deflection and slice means match the closed forms") {
  const Section s = Figures();
  const double l = kSpan, q = 1.0;  // N/mm
  for (const auto kind : {PinSupportKind::kSimplySupported, PinSupportKind::kClamped}) {
    CAPTURE(static_cast<int>(kind));
    const PinBeam beam(Support(kind), Steel(), kRadius);
    const bool clamped = kind == PinSupportKind::kClamped;
    // Midspan: 5 q L^4 / (384 EI) + q L^2 / (8 kappa G A), clamped q L^4 / (384 EI) + the same shear.
    const double midspan = (clamped ? 1.0 : 5.0) * q * std::pow(l, 4) / (384 * s.ei) + q * l * l / (8 * s.kga);
    // The Green's function integrated over the load (Simpson, the kink at a panel boundary).
    const auto at_mid = [&](double a) { return q * beam.Deflection(l / 2, a); };
    const double integrated = Simpson(0.0, l / 2, 200, at_mid) + Simpson(l / 2, l, 200, at_mid);
    CHECK(Relative(integrated, midspan) < 1e-9);
    // The deflection curve: q x (L^3 - 2 L x^2 + x^3) / (24 EI) simply supported,
    // q x^2 (L - x)^2 / (24 EI) clamped, plus q x (L - x) / (2 kappa G A).
    const auto curve = [&](double x) {
      const double bending = clamped ? q * x * x * (l - x) * (l - x) / (24 * s.ei)
                                     : q * x * (l * l * l - 2 * l * x * x + x * x * x) / (24 * s.ei);
      return bending + q * x * (l - x) / (2 * s.kga);
    };
    CHECK(Relative(curve(l / 2), midspan) < 1e-12);
    // SliceCompliance with the face over the whole span: sum_j C_ij q w is the mean of the curve
    // over slice i (its mean by Simpson, independently).
    for (const int n : {1, 3, 8}) {
      CAPTURE(n);
      const Eigen::MatrixXd c = beam.SliceCompliance(l, n);
      const double w = l / n;
      for (int i = 0; i < n; ++i) {
        CAPTURE(i);
        const double mean = Simpson(i * w, (i + 1) * w, 2000, curve) / w;
        CHECK(Relative(c.row(i).sum() * q * w, mean) < 1e-9);
      }
    }
  }
}

TEST_CASE("contact: pin bending - the slice compliance is symmetric, positive definite and reciprocal (Maxwell)") {
  for (const auto kind : {PinSupportKind::kSimplySupported, PinSupportKind::kClamped}) {
    CAPTURE(static_cast<int>(kind));
    const PinBeam beam(Support(kind, 30.0, 7.0), Steel(), kRadius);  // face 12 mm from 7 to 19 mm
    // Maxwell: deflection at x under a load at a equals deflection at a under a load at x.
    for (const double x : {0.7, 7.3, 15.0, 29.1}) {
      for (const double a : {2.2, 9.9, 15.0, 26.0}) {
        CAPTURE(x);
        CAPTURE(a);
        CHECK(std::abs(beam.Deflection(x, a) - beam.Deflection(a, x)) <= 1e-12 * beam.Deflection(15.0, 15.0));
      }
    }
    for (const int n : {1, 2, 5, 20}) {
      CAPTURE(n);
      const Eigen::MatrixXd c = beam.SliceCompliance(12.0, n);
      CHECK(c.rows() == n);
      CHECK((c - c.transpose()).cwiseAbs().maxCoeff() == 0.0);
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(c);
      CHECK(eig.eigenvalues().minCoeff() > 0.0);
      // One slice: the mean over the face of the deflection under its uniform load, by double Simpson.
      if (n == 1) {
        const double mean = Simpson(7.0, 19.0, 400, [&](double x) {
                              return Simpson(7.0, x, 200, [&](double a) { return beam.Deflection(x, a); }) +
                                     Simpson(x, 19.0, 200, [&](double a) { return beam.Deflection(x, a); });
                            }) /
                            (12.0 * 12.0);
        CHECK(Relative(c(0, 0), mean) < 1e-9);
      }
      // The face sits off the middle (7 to 19 of 30 mm): the slice nearer midspan bends more.
      if (n == 20) CHECK(c(19, 19) > c(0, 0));
    }
  }
}

TEST_CASE("contact: pin bending - a stiff pin's compliance vanishes beside the contact compliance") {
  // E x 1e6: the beam compliance scales with 1 / E; beside the hertz-line law's compliance of a
  // 0.6 mm slice at 100 N it is below 1e-5 of it (here it is about 2e-7).
  Material stiff = Steel();
  stiff.pin_young_modulus *= 1e6;
  const PinBeam soft(Support(PinSupportKind::kClamped, 14.0, 1.0), Steel(), kRadius);
  const PinBeam rigid(Support(PinSupportKind::kClamped, 14.0, 1.0), stiff, kRadius);
  const Eigen::MatrixXd c_soft = soft.SliceCompliance(12.0, 20), c_rigid = rigid.SliceCompliance(12.0, 20);
  CHECK(Relative(c_rigid.maxCoeff(), c_soft.maxCoeff() * 1e-6) < 1e-9);
  const ltca::contact::ContactLaw law({}, Steel(), 1.0 / 5.0, kRadius, 12.0 / 20, 64.0);
  const double contact_compliance = law.Approach(100.0) / 100.0;
  CHECK(c_rigid.maxCoeff() < 1e-5 * contact_compliance);
  CHECK(c_soft.maxCoeff() > 1e-2 * contact_compliance);  // while a steel pin's is not negligible
}

TEST_CASE("contact: pin bending - bad settings are rejected naming the key, the value and what is expected") {
  const auto rejects = [](const PinSupport& s, double face, const char* key) {
    CAPTURE(key);
    CHECK_THROWS_WITH_AS(
        {
          const PinBeam beam(s, Steel(), kRadius);
          (void)beam.SliceCompliance(face, 4);
        },
        doctest::Contains(key), std::invalid_argument);
  };
  rejects(Support(PinSupportKind::kClamped, 0.0), 12.0, "[pins] span_mm = 0");
  rejects(Support(PinSupportKind::kClamped, -5.0), 12.0, "span_mm = -5");
  rejects(Support(PinSupportKind::kClamped, NAN), 12.0, "span_mm");
  rejects(Support(PinSupportKind::kClamped, 20.0, -1.0), 12.0, "[pins] face_offset_mm = -1");
  rejects(Support(PinSupportKind::kClamped, 20.0, 9.0), 12.0, "face_offset_mm + face width <= span_mm = 20");
  rejects(Support(static_cast<PinSupportKind>(7), 20.0), 12.0, "[pins] support");
  CHECK_THROWS_WITH_AS(ltca::contact::ParsePinSupport("pinned"),
                       doctest::Contains("[pins] support = \"pinned\": expected \"simply-supported\" or \"clamped\""),
                       std::invalid_argument);
  CHECK(ltca::contact::ParsePinSupport("clamped") == PinSupportKind::kClamped);
  CHECK(ltca::contact::ParsePinSupport("simply-supported") == PinSupportKind::kSimplySupported);
  CHECK(std::string(ltca::contact::ToString(PinSupportKind::kClamped)) == "clamped");
  // The face exactly between the supports is accepted.
  CHECK(PinBeam(Support(PinSupportKind::kClamped, 20.0, 8.0), Steel(), kRadius).SliceCompliance(12.0, 3).rows() == 3);
}

TEST_CASE("contact: pin bending - the coupling is block diagonal over the points of each pin, in any order") {
  const PinBeam beam(Support(PinSupportKind::kClamped, 16.0, 2.0), Steel(), kRadius);
  const double face = 12.0;
  // Two pins of three slices and one of a single slice (the plane model), shuffled.
  std::vector<PinContact> points;
  const std::vector<std::pair<int, int>> order = {{1, 2}, {0, 0}, {4, 0}, {1, 0}, {0, 2}, {1, 1}, {0, 1}};
  for (const auto& [pin, slice] : order) {
    PinContact p;
    p.cycloid_point = p.pin_point = p.normal = Eigen::Vector2d::Zero();
    p.pin = pin;
    p.slice = slice;
    p.length = pin == 4 ? face : face / 3;
    points.push_back(p);
  }
  const Eigen::MatrixXd c = Eigen::MatrixXd(ltca::contact::PinBendingCoupling(points, beam, face));
  const Eigen::MatrixXd three = beam.SliceCompliance(face, 3), one = beam.SliceCompliance(face, 1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (std::size_t j = 0; j < points.size(); ++j) {
      CAPTURE(i);
      CAPTURE(j);
      const auto ii = static_cast<Eigen::Index>(i), jj = static_cast<Eigen::Index>(j);
      if (points[i].pin != points[j].pin) {
        CHECK(c(ii, jj) == 0.0);
      } else if (points[i].pin == 4) {
        CHECK(c(ii, jj) == one(0, 0));
      } else {
        CHECK(c(ii, jj) == three(points[i].slice, points[j].slice));
      }
    }
  }
  // A missing or repeated slice, or a length that is not B / n, is rejected.
  std::vector<PinContact> repeated = points;
  repeated[0].slice = 1;
  CHECK_THROWS_WITH_AS(ltca::contact::PinBendingCoupling(repeated, beam, face), doctest::Contains("pin 2"),
                       std::invalid_argument);
  std::vector<PinContact> wrong_length = points;
  wrong_length[1].length = 5.0;
  CHECK_THROWS_WITH_AS(ltca::contact::PinBendingCoupling(wrong_length, beam, face),
                       doctest::Contains("contact length 5 mm"), std::invalid_argument);
}

TEST_CASE("contact: pin bending - the factored form B K^-1 B^T + E equals the slice compliance (issue 11)") {
  // K: Przemieniecki's exact Timoshenko element between the supports, face B, the slice
  // boundaries and the far face; B: consistent loads of 1 N over each slice; E: each slice's
  // fixed-fixed particular solution. Exact, so equal to SliceCompliance to rounding.
  double worst = 0.0;
  for (const PinSupportKind kind : {PinSupportKind::kSimplySupported, PinSupportKind::kClamped}) {
    for (const auto& [span, offset, face] : std::vector<std::array<double, 3>>{
             {16.0, 2.0, 12.0}, {20.0, 0.0, 20.0}, {20.0, 0.0, 14.0}, {20.0, 6.0, 14.0}, {30.0, 1.5, 9.0}}) {
      const PinBeam beam(Support(kind, span, offset), Steel(), kRadius);
      for (const int n : {1, 2, 3, 5, 10, 20, 37}) {
        CAPTURE(ToString(kind));
        CAPTURE(span);
        CAPTURE(offset);
        CAPTURE(n);
        const PinBeam::SliceBeam m = beam.SliceBeamModel(face, n);
        const Eigen::MatrixXd k = Eigen::MatrixXd(m.stiffness), b = Eigen::MatrixXd(m.loads);
        const Eigen::MatrixXd c = b * k.ldlt().solve(b.transpose()) + Eigen::MatrixXd(m.local.asDiagonal());
        const Eigen::MatrixXd exact = beam.SliceCompliance(face, n);
        const double error = (c - exact).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff();
        worst = std::max(worst, error);
        CHECK(error < 1e-10);
        CHECK(Eigen::MatrixXd(m.stiffness) .isApprox(Eigen::MatrixXd(m.stiffness).transpose()));
      }
    }
  }
  MESSAGE("factored pin bending: largest relative difference " << worst);
  // The coupling of shuffled points of pins with different slice counts.
  const PinBeam beam(Support(PinSupportKind::kClamped, 16.0, 2.0), Steel(), kRadius);
  const double face = 12.0;
  std::vector<PinContact> points;
  const std::vector<std::pair<int, int>> order = {{1, 2}, {0, 0}, {4, 0}, {1, 0}, {0, 2}, {1, 1}, {0, 1}};
  for (const auto& [pin, slice] : order) {
    PinContact p;
    p.cycloid_point = p.pin_point = p.normal = Eigen::Vector2d::Zero();
    p.pin = pin;
    p.slice = slice;
    p.length = pin == 4 ? face : face / 3;
    points.push_back(p);
  }
  const Eigen::MatrixXd c = Eigen::MatrixXd(ltca::contact::PinBendingCoupling(points, beam, face));
  const ltca::contact::FactoredPinBending f = ltca::contact::PinBendingFactors(points, beam, face);
  const Eigen::MatrixXd k = Eigen::MatrixXd(f.stiffness), b = Eigen::MatrixXd(f.loads);
  const Eigen::MatrixXd factored = b * k.ldlt().solve(b.transpose()) + Eigen::MatrixXd(f.local.asDiagonal());
  CHECK((factored - c).cwiseAbs().maxCoeff() < 1e-10 * c.cwiseAbs().maxCoeff());
}
