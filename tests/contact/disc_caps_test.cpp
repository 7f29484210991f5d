// Issue 48: the elastic disc body with a tip relief's caps (contact/disc_body.hpp, docs/fe_disc.md
// "A tip relief's caps"): the outline follows the relieved tip, the mesh follows the outline, and
// the grid's cap points give a cap contact its coefficient.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "fe/disc_mesh.hpp"
#include "geometry/tip_relief_closed_form.hpp"
#include "ltca/contact/disc_body.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "pairs.hpp"

namespace disc_caps_test {

using ltca::contact::DiscBodyDesign;
using ltca::contact::DiscLoadPoint;
using ltca::geometry::SurfacePart;
namespace fe = ltca::contact::fe;

constexpr double kPi = std::numbers::pi;

/// The d = 2 pair of cases/hard/d2_loaded.toml (24 pins, 22 teeth, r_rp 7, R_p 90, e 4, B 20 mm):
/// its sharp tips carry load, so a relief's cap does.
ltca::geometry::PairParameters D2Pair() { return {24, 22, 7.0, 90.0, 4.0, 20.0}; }

ltca::geometry::CycloidProfile Relieved(double truncation, double rounding) {
  ltca::geometry::Modification m;
  m.tip_relief.truncation = truncation;
  m.tip_relief.rounding_radius = rounding;
  return ltca::geometry::CycloidProfile(D2Pair(), m);
}

/// Angle of p from tip k's axis (the unrelieved tip corner's direction: rotation modification 0).
double FromAxis(const ltca::geometry::CycloidProfile& profile, const Eigen::Vector2d& p, int tip) {
  const Eigen::Vector2d corner = profile.Position(profile.phi_max(), tip);
  return std::abs(std::remainder(std::atan2(p.y(), p.x()) - std::atan2(corner.y(), corner.x()), 2.0 * kPi));
}

/// The nearest tip to p by polar angle.
int NearestTip(const ltca::geometry::CycloidProfile& profile, const Eigen::Vector2d& p) {
  int best = 0;
  for (int k = 1; k < profile.pair().tooth_count; ++k) {
    if (FromAxis(profile, p, k) < FromAxis(profile, p, best)) best = k;
  }
  return best;
}

/// Whether two segments ab and cd cross (proper intersection).
bool Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c, const Eigen::Vector2d& d) {
  const auto orient = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
    const Eigen::Vector2d u = q - p, v = r - p;
    return u.x() * v.y() - u.y() * v.x();
  };
  return orient(a, b, c) * orient(a, b, d) < 0.0 && orient(c, d, a) * orient(c, d, b) < 0.0;
}

double TwiceArea(const std::vector<Eigen::Vector2d>& polygon) {
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return twice;
}

/// The distance of a point near tip k from the analytic cap of a relief given by one piece alone:
/// the rounding arc (rho > 0, no truncation: the circle of radius rho centred on the axis at the
/// flank's distance rho, found from the flank alone, tests/geometry/tip_relief_closed_form.hpp) or
/// the truncation line (rho = 0: the line across the axis t below the sharp corner). *on_cap: the
/// point lies within the cap's angular extent (between the junctions, as seen from the centre).
struct CapPiece {
  bool arc = true;
  Eigen::Vector2d centre;  // the arc's
  double rho = 0.0;
  Eigen::Vector2d axis;    // unit, out of the tooth
  double line = 0.0;       // the line's distance from the body centre along the axis
};
CapPiece AnalyticCap(const ltca::geometry::CycloidProfile& profile, int tip, double truncation, double rounding) {
  CapPiece piece;
  const Eigen::Vector2d corner = profile.Position(profile.phi_max(), tip);
  piece.axis = corner.normalized();
  if (rounding > 0.0) {
    piece.centre = ltca::test::RoundingCentre(profile, tip, rounding);
    piece.rho = rounding;
  } else {
    piece.arc = false;
    piece.line = corner.norm() - truncation;
  }
  return piece;
}
double DistanceFromPiece(const CapPiece& piece, const Eigen::Vector2d& p) {
  return piece.arc ? std::abs((p - piece.centre).norm() - piece.rho) : std::abs(p.dot(piece.axis) - piece.line);
}

TEST_CASE("contact: the disc outline with a tip relief's caps lies on the analytic caps to 1e-9 mm and is closed, simple and counterclockwise") {
  // The d = 2 pair's sharp tips relieved (a) by a rounding of 0.5 mm alone and (b) by a truncation of
  // 0.3 mm alone, its outline at 16 points a flank: every point inside a junction's angle from a tip
  // axis (a cap point) lies on that tip's analytic cap (computed from the flank alone, not from
  // geometry::TipCap) to 1e-9 mm; every other point on the unrelieved flank (the nearest sample of
  // Position within 1e-9 mm: it is one of them); the corners are the junctions; the polygon is closed
  // (no edge longer than 3 flank spacings), simple (no two edges cross) and counterclockwise, and
  // its area is below the unrelieved outline's (the caps take material away).
  const int per_space = 16;
  const ltca::geometry::CycloidProfile sharp = Relieved(0.0, 0.0);
  const std::vector<Eigen::Vector2d> unrelieved = ltca::contact::DiscOutline(sharp, per_space);
  for (const auto& [truncation, rounding] : {std::pair{0.0, 0.5}, std::pair{0.3, 0.0}, std::pair{0.2, 0.4}}) {
    CAPTURE(truncation);
    CAPTURE(rounding);
    const ltca::geometry::CycloidProfile profile = Relieved(truncation, rounding);
    const ltca::geometry::TipCap& cap = profile.tip_cap();
    REQUIRE(cap.active());
    std::vector<int> corners;
    const std::vector<Eigen::Vector2d> outline = ltca::contact::DiscOutline(profile, per_space, &corners);
    const int z = profile.pair().tooth_count;
    // The junction's angle from the axis (both junctions of a tip are mirror images).
    const double junction_angle = FromAxis(profile, profile.Position(cap.junction(), 0), 0);
    int on_cap = 0;
    double worst_cap = 0.0, worst_flank = 0.0;
    for (const Eigen::Vector2d& p : outline) {
      const int tip = NearestTip(profile, p);
      if (FromAxis(profile, p, tip) < junction_angle - 1e-12) {
        ++on_cap;
        if (truncation == 0.0 || rounding == 0.0) {
          worst_cap = std::max(worst_cap, DistanceFromPiece(AnalyticCap(profile, tip, truncation, rounding), p));
        } else {
          // Both pieces: the truncation line t below the corner, or the arc of radius rho tangent to
          // it and to the flank: its centre rho below the line and rho from the flank, found here by
          // bisection along that parallel (the flank's half next to tip k is space k's u in [0,
          // phi_max]; the other half's centre is its mirror image in the axis).
          const CapPiece line = AnalyticCap(profile, tip, truncation, 0.0);
          const Eigen::Vector2d corner = profile.Position(profile.phi_max(), tip);
          Eigen::Vector2d across = profile.Position(0.9 * profile.phi_max(), tip) - corner;
          across = (across - across.dot(line.axis) * line.axis).normalized();
          const auto centre_at = [&](double s) { return Eigen::Vector2d((line.line - rounding) * line.axis + s * across); };
          // The distance to the flank falls as s grows from the axis until the centre crosses the
          // flank: the first s within rho, scanned in 10 um steps, then bisection.
          double lo = 0.0, hi = 0.0;
          while (hi < 5.0 && ltca::test::DistanceToFlank(profile, tip, centre_at(hi)) > rounding) lo = hi, hi += 0.01;
          for (int it = 0; it < 200; ++it) {
            const double mid = 0.5 * (lo + hi);
            if (ltca::test::DistanceToFlank(profile, tip, centre_at(mid)) > rounding) lo = mid; else hi = mid;
          }
          const Eigen::Vector2d plus = centre_at(0.5 * (lo + hi));
          const Eigen::Vector2d minus = 2.0 * plus.dot(line.axis) * line.axis - plus;
          const double dd = std::min({DistanceFromPiece(line, p), std::abs((p - plus).norm() - rounding),
                                                    std::abs((p - minus).norm() - rounding)});
          worst_cap = std::max(worst_cap, dd);
        }
      } else {
        worst_flank = std::max(worst_flank, ltca::test::DistanceToProfile(profile, p));
      }
    }
    MESSAGE("cap points " << on_cap << ", largest distance from the analytic cap " << worst_cap << " mm");
    CHECK(on_cap >= z);  // (the segment alone: its apex; the rounding: several a tip)
    CHECK(worst_cap <= 1e-9);
    MESSAGE("largest distance of a flank point from the flank " << worst_flank << " mm");
    CHECK(worst_flank <= 1e-9);
    // The corners: every junction (2 a tip), at the flank's ends, and with both pieces the arc's ends.
    CHECK(static_cast<int>(corners.size()) == (truncation > 0.0 && rounding > 0.0 ? 4 : 2) * z);
    int junctions = 0;
    for (const int c : corners) {
      REQUIRE(c >= 0);
      REQUIRE(c < static_cast<int>(outline.size()));
      const Eigen::Vector2d& p = outline[static_cast<std::size_t>(c)];
      const int tip = NearestTip(profile, p);
      if (std::abs(FromAxis(profile, p, tip) - junction_angle) < 1e-9) ++junctions;
    }
    CHECK(junctions == 2 * z);
    // Closed, simple, counterclockwise, smaller.
    double longest = 0.0, spacing = 0.0;
    for (std::size_t i = 0; i < outline.size(); ++i) {
      const double edge = (outline[(i + 1) % outline.size()] - outline[i]).norm();
      longest = std::max(longest, edge);
      spacing += edge;
    }
    spacing /= static_cast<double>(outline.size());
    CHECK(longest <= 3.0 * spacing);
    int crossings = 0;
    const std::size_t n = outline.size();
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = i + 2; j < n; ++j) {
        if (i == 0 && j == n - 1) continue;
        if (Cross(outline[i], outline[i + 1], outline[j], outline[(j + 1) % n])) ++crossings;
      }
    }
    CHECK(crossings == 0);
    CHECK(TwiceArea(outline) > 0.0);
    CHECK(TwiceArea(outline) < TwiceArea(unrelieved));
  }
}

TEST_CASE("contact: a cap foot point's w is where TipCap::Point puts it (the contact's place on the cap)") {
  // geometry::CapFoot::w, which the body's grid interpolates a cap contact in (PinContact::cap_w):
  // a point 0.3 mm outside the cap along its normal at TipCap::Point(w) has its nearest cap point
  // there, with the same w to 1e-9, on the rounding, the segment and both (the d = 2 pair).
  for (const auto& [truncation, rounding] : {std::pair{0.0, 0.5}, std::pair{0.3, 0.0}, std::pair{0.2, 0.4}}) {
    CAPTURE(truncation);
    CAPTURE(rounding);
    const ltca::geometry::CycloidProfile profile = Relieved(truncation, rounding);
    const ltca::geometry::TipCap& cap = profile.tip_cap();
    REQUIRE(cap.active());
    for (const int tip : {0, 7}) {
      for (int i = -20; i <= 20; ++i) {
        const double w = 0.999 * i / 20.0;
        const ltca::geometry::CapFoot at = cap.Point(w, tip);
        const ltca::geometry::CapFoot foot = cap.Nearest(at.point + 0.3 * at.normal, tip);
        CAPTURE(w);
        CHECK(std::abs(foot.w - w) < 1e-9);
        CHECK((foot.point - at.point).norm() < 1e-9);
      }
    }
  }
}

TEST_CASE("contact: the mesh of a relieved disc follows its caps: every boundary node at a tip within 1e-8 mm of the analytic cap") {
  // The d = 2 pair with a rounding of 0.5 mm, meshed whole (fe::MeshDisc: its outline as splines that
  // end at the corners DiscOutline gives), refined to 0.1 mm at the outline: every node of an outline
  // edge (vertices and mid-side nodes) between a tip's junctions is within 1e-8 mm of the analytic arc
  // (the splines through points at most 0.1 rad apart on it; measured 6.9e-10 mm).
  const double rounding = 0.5;
  const ltca::geometry::CycloidProfile profile = Relieved(0.0, rounding);
  const ltca::geometry::TipCap& cap = profile.tip_cap();
  DiscBodyDesign d;
  d.outline_mm = ltca::contact::DiscOutline(profile, 64, &d.outline_corners);
  d.bore_radius_mm = 30.0;
  d.element_size_mm = 8.0;
  d.refined_size_mm = 0.1;
  d.refine_radius_mm = 3.0;
  // Refine at the tips only (a short mesh): the points of every cap.
  for (int k = 0; k < profile.pair().tooth_count; ++k) {
    for (int i = -4; i <= 4; ++i) d.refine_near_mm.push_back(cap.Point(0.25 * i, k).point);
  }
  const double junction_angle = FromAxis(profile, profile.Position(cap.junction(), 0), 0);
  const auto worst_on_caps = [&](const fe::T6Mesh& mesh, int* count) {
    double worst = 0.0;
    *count = 0;
    std::vector<char> seen(mesh.nodes.size(), 0);
    for (const fe::BoundaryEdge& e : mesh.edges) {
      if (e.boundary != fe::Boundary::kOutline) continue;
      for (const int n : e.nodes) {
        if (seen[static_cast<std::size_t>(n)]) continue;
        seen[static_cast<std::size_t>(n)] = 1;
        const Eigen::Vector2d& p = mesh.nodes[static_cast<std::size_t>(n)];
        const int tip = NearestTip(profile, p);
        if (!(FromAxis(profile, p, tip) < junction_angle)) continue;
        ++*count;
        worst = std::max(worst, DistanceFromPiece(AnalyticCap(profile, tip, 0.0, rounding), p));
      }
    }
    return worst;
  };
  int count = 0;
  const double worst = worst_on_caps(fe::MeshDisc(d), &count);
  MESSAGE("cap nodes " << count << ", largest distance from the analytic arc " << worst << " mm");
  CHECK(count >= 5 * profile.pair().tooth_count);
  CHECK(worst <= 1e-8);
}

TEST_CASE("contact: the relieved elastic body's cap grid is K at its grid points and interpolates a direct condensation within 2 %") {
  // The d = 2 pair with a rounding of 0.5 mm (its cap carries load), the elastic body of its relieved
  // profile (30 mm bore, plane strain, 4 mm elements, the default grid: 32 points a space shared by
  // the flank and the cap by length, w0 = 0.2 mm), meshed cyclically: (1) a contact at a cap grid
  // point has K's entries exactly (1e-12); (2) contacts on the cap half-way between cap grid points,
  // and a pose's loaded contacts on the flank and on the cap, couple within 2 % of a direct
  // condensation of the whole disc meshed at 0.1 mm at those very points (diagonal and every pair,
  // relative to sqrt(C_ii C_jj): the flank's bound, docs/fe_disc.md); (3) every pose's coupling over
  // a mesh period, cap contacts included, is positive semidefinite; (4) far from the tips the
  // relief changes the flank's coefficients by less than 1 % (the unrelieved body at the same
  // contact points; two meshes of one outline differ by about 0.5 %). Labelled slow.
  const double rounding = 0.5;
  const ltca::geometry::PairParameters pair = D2Pair();
  ltca::geometry::Modification relief;
  relief.tip_relief.rounding_radius = rounding;
  const ltca::contact::MeshModel model{ltca::geometry::RealPair(pair, relief)};
  const ltca::geometry::CycloidProfile& profile = model.real_pair().profile();
  const ltca::geometry::TipCap& cap = profile.tip_cap();
  DiscBodyDesign body;
  body.bore_radius_mm = 30.0;
  body.thickness_mm = pair.face_width;
  body.element_size_mm = 4.0;
  body.refine_radius_mm = 8.0;
  const ltca::contact::DiscFlankCompliance flank(profile, body);
  REQUIRE(flank.caps());
  REQUIRE(flank.cyclic());
  MESSAGE("relieved grid: " << flank.grid_points() << " points (" << flank.flank_intervals() << " flank and "
                            << flank.cap_intervals() << " cap intervals a space), " << flank.nodes() << " nodes, set-up "
                            << flank.setup_seconds() << " s");
  CHECK(flank.space_points() >= flank.grid().points_per_space);
  CHECK(flank.cap_intervals() >= 2);
  // A cap contact at (tip, w): its tooth space and u are the junction's on w's side.
  const auto on_cap = [&](int tip, double w) {
    ltca::contact::PinContact c;
    c.part = SurfacePart::kTipRounding;
    c.tooth_space = w >= 0.0 ? tip : (tip + 1) % pair.tooth_count;
    c.u = w >= 0.0 ? cap.junction() : -cap.junction();
    c.cap_w = w;
    c.length = pair.face_width;
    c.cycloid_point = c.pin_point = c.normal = Eigen::Vector2d::Zero();  // not read here; set, so a copy reads no indeterminate value
    return c;
  };
  const int mc = flank.cap_intervals();
  const auto grid_w = [mc](int i) { return 1.0 - 2.0 * i / mc; };
  // (1) K at the grid points (a cap point of tip 3, one of tip 5 and its flank's junction point).
  {
    const std::vector<ltca::contact::PinContact> at{on_cap(3, grid_w(1)), on_cap(5, grid_w(mc - 1)), on_cap(5, 1.0)};
    const Eigen::MatrixXd c = flank.Coupling(at);
    const int g0 = flank.cap_grid_point(3, 1), g1 = flank.cap_grid_point(5, mc - 1), g2 = flank.cap_grid_point(5, 0);
    CHECK(g2 == 5 * flank.space_points() + flank.flank_intervals());  // the junction is the flank's end point
    CHECK(c(0, 0) == doctest::Approx(flank.grid_compliance(g0, g0)).epsilon(1e-12));
    CHECK(c(1, 1) == doctest::Approx(flank.grid_compliance(g1, g1)).epsilon(1e-12));
    CHECK(c(0, 1) == doctest::Approx(flank.grid_compliance(g0, g1)).epsilon(1e-12));
    CHECK(c(1, 2) == doctest::Approx(flank.grid_compliance(g1, g2)).epsilon(1e-12));
    CHECK((flank.grid_point(g1) - cap.Point(grid_w(mc - 1), 5).point).norm() < 1e-12);
    CHECK(flank.grid_normal(g1).dot(-cap.Point(grid_w(mc - 1), 5).normal) == doctest::Approx(1.0).epsilon(1e-12));
  }
  // (2) Against a direct condensation: half-way cap points of tip 2, and the loaded side's contacts
  // (arm > 0) of poses with a pin on a cap.
  std::vector<ltca::contact::PinContact> points;
  for (int i = 0; i < mc; ++i) points.push_back(on_cap(2, 0.5 * (grid_w(i) + grid_w(i + 1))));
  int cap_contacts = 0;
  for (int step = 0; step < 12 && cap_contacts < 2; ++step) {
    const double crank = step * model.kinematics().MeshPeriod() / 12.0;
    const std::vector<ltca::contact::PinContact> pins = model.Evaluate(crank).pins;
    const bool has_cap = std::any_of(pins.begin(), pins.end(), [](const ltca::contact::PinContact& p) {
      return p.arm > 1e-6 && p.part == SurfacePart::kTipRounding && p.clearance < 0.05;
    });
    if (!has_cap) continue;
    for (const ltca::contact::PinContact& p : pins) {
      if (!(p.arm > 1e-6) || p.clearance > 0.05) continue;
      points.push_back(p);
      if (p.part == SurfacePart::kTipRounding) ++cap_contacts;
    }
    break;
  }
  MESSAGE("cap contacts of a pose compared: " << cap_contacts << " of " << points.size() - static_cast<std::size_t>(mc) << " loaded-side contacts");
  CHECK(cap_contacts >= 1);
  std::vector<DiscLoadPoint> loads;
  for (const ltca::contact::PinContact& p : points) {
    if (p.part == SurfacePart::kFlank) {
      const ltca::geometry::ProfilePoint at = profile.Evaluate(p.u, p.tooth_space);
      loads.push_back({at.position, -at.normal, 0.2});
    } else {
      const int tip = p.u > 0.0 ? p.tooth_space : (p.tooth_space + pair.tooth_count - 1) % pair.tooth_count;
      const ltca::geometry::CapFoot at = cap.Point(p.cap_w, tip);
      loads.push_back({at.point, -at.normal, 0.2});
    }
  }
  DiscBodyDesign direct = body;
  direct.outline_mm = ltca::contact::DiscOutline(profile, 64, &direct.outline_corners);
  direct.refine_near_mm = direct.outline_mm;
  direct.refined_size_mm = 0.1;
  const Eigen::MatrixXd reference = ltca::contact::CondenseDiscCompliance(direct, loads).compliance_mm_per_n;
  const Eigen::MatrixXd c = flank.Coupling(points);
  double worst = 0.0, worst_cap = 0.0;
  for (Eigen::Index i = 0; i < c.rows(); ++i) {
    for (Eigen::Index j = 0; j < c.rows(); ++j) {
      const double e = std::abs(c(i, j) - reference(i, j)) / std::sqrt(reference(i, i) * reference(j, j));
      worst = std::max(worst, e);
      if (points[static_cast<std::size_t>(i)].part != SurfacePart::kFlank) worst_cap = std::max(worst_cap, e);
    }
  }
  MESSAGE("largest relative difference from the direct condensation: " << worst << " (rows on a cap: " << worst_cap
                                                                        << "); a cap point's own " << reference(0, 0) * 1e6 << " nm/N");
  CHECK(worst < 0.02);
  // (3) Positive semidefinite over a mesh period, with the poses' cap contacts coupled.
  int coupled_caps = 0;
  for (int step = 0; step < 12; ++step) {
    const std::vector<ltca::contact::PinContact> pins = model.Evaluate(step * model.kinematics().MeshPeriod() / 12.0).pins;
    const Eigen::MatrixXd cp = flank.Coupling(pins);
    for (std::size_t i = 0; i < pins.size(); ++i) {
      if (pins[i].part == SurfacePart::kTipRounding && cp(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) > 0.0) ++coupled_caps;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cp);
    CHECK(eig.eigenvalues().minCoeff() >= -1e-12 * eig.eigenvalues().maxCoeff());
  }
  CHECK(coupled_caps > 0);
  // (4) Far from the tips: the middle half of the flank (|u| < u_j / 2) of two spaces, against the
  // unrelieved profile's body at the same contact points.
  const ltca::geometry::CycloidProfile plain(pair);
  const ltca::contact::DiscFlankCompliance unrelieved(plain, body);
  std::vector<ltca::contact::PinContact> middle;
  for (const int k : {4, 5}) {
    for (int i = -3; i <= 3; ++i) {
      ltca::contact::PinContact p;
      p.cycloid_point = p.pin_point = p.normal = Eigen::Vector2d::Zero();  // not read here (see on_cap)
      p.tooth_space = k;
      p.u = 0.5 * cap.junction() * i / 3.0;
      p.length = pair.face_width;
      middle.push_back(p);
    }
  }
  const Eigen::MatrixXd a = flank.Coupling(middle), b = unrelieved.Coupling(middle);
  double change = 0.0;
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    for (Eigen::Index j = 0; j < a.rows(); ++j) change = std::max(change, std::abs(a(i, j) - b(i, j)) / std::sqrt(b(i, i) * b(j, j)));
  }
  MESSAGE("the flank's middle half, relieved against unrelieved body: largest relative change " << change);
  CHECK(change < 0.01);
}

TEST_CASE("contact: a segment-only cap (its junctions corners) has grid points of its own at the corners, so no interpolation straddles one") {
  // The d = 2 pair's tips truncated 0.3 mm without a rounding: the segment meets each flank in a
  // corner (TipCap: an edge). The body's space then holds the flank's m_f + 1 points, both corners
  // included with the flank's normal, and the cap's m_c + 1 with the segment's (space_points() =
  // m_f + m_c + 2): at a corner the two grid points sit at one place with normals the corner's angle
  // apart; a segment contact at its end (w = 1) takes the cap's own point's K, a flank contact at
  // the junction the flank's; every pose's coupling over a mesh period is positive semidefinite and
  // couples its segment contacts. (30 mm bore, 6 mm elements, 16 points a space: a short set-up.)
  const ltca::geometry::PairParameters pair = D2Pair();
  ltca::geometry::Modification relief;
  relief.tip_relief.truncation = 0.3;
  const ltca::contact::MeshModel model{ltca::geometry::RealPair(pair, relief)};
  const ltca::geometry::CycloidProfile& profile = model.real_pair().profile();
  const ltca::geometry::TipCap& cap = profile.tip_cap();
  REQUIRE(cap.active());
  DiscBodyDesign body;
  body.bore_radius_mm = 30.0;
  body.thickness_mm = pair.face_width;
  body.element_size_mm = 6.0;
  body.refine_radius_mm = 8.0;
  ltca::contact::DiscFlankGrid grid;
  grid.points_per_space = 16;
  const ltca::contact::DiscFlankCompliance flank(profile, body, grid);
  REQUIRE(flank.caps());
  const int mf = flank.flank_intervals(), mc = flank.cap_intervals();
  CHECK(flank.space_points() == mf + mc + 2);
  const int k = 3;
  const int flank_end = k * flank.space_points() + mf, cap_start = flank.cap_grid_point(k, 0);
  const int cap_end = flank.cap_grid_point(k, mc), next_flank = ((k + 1) % pair.tooth_count) * flank.space_points();
  CHECK(cap_start == flank_end + 1);
  CHECK(cap_end != next_flank);
  CHECK((flank.grid_point(flank_end) - flank.grid_point(cap_start)).norm() < 1e-9);
  CHECK((flank.grid_point(cap_end) - flank.grid_point(next_flank)).norm() < 1e-9);
  CHECK(flank.grid_normal(flank_end).dot(flank.grid_normal(cap_start)) < 0.99);  // a corner between them
  CHECK(flank.grid_normal(cap_end).dot(flank.grid_normal(next_flank)) < 0.99);
  ltca::contact::PinContact on_segment, on_flank;
  on_segment.cycloid_point = on_segment.pin_point = on_segment.normal = Eigen::Vector2d::Zero();  // not read here (see on_cap)
  on_flank.cycloid_point = on_flank.pin_point = on_flank.normal = Eigen::Vector2d::Zero();
  on_segment.part = SurfacePart::kTipTruncation;
  on_segment.tooth_space = k;
  on_segment.u = cap.junction();
  on_segment.cap_w = 1.0;
  on_segment.length = on_flank.length = pair.face_width;
  on_flank.tooth_space = k;
  on_flank.u = cap.junction();
  const Eigen::MatrixXd c = flank.Coupling({on_segment, on_flank});
  CHECK(c(0, 0) == doctest::Approx(flank.grid_compliance(cap_start, cap_start)).epsilon(1e-12));
  CHECK(c(1, 1) == doctest::Approx(flank.grid_compliance(flank_end, flank_end)).epsilon(1e-12));
  CHECK(c(0, 1) == doctest::Approx(flank.grid_compliance(cap_start, flank_end)).epsilon(1e-12));
  int segment_contacts = 0;
  for (int step = 0; step < 24; ++step) {
    const std::vector<ltca::contact::PinContact> pins = model.Evaluate(step * model.kinematics().MeshPeriod() / 24.0).pins;
    const Eigen::MatrixXd cp = flank.Coupling(pins);
    for (std::size_t i = 0; i < pins.size(); ++i) {
      const auto d = static_cast<Eigen::Index>(i);
      if (pins[i].part == SurfacePart::kTipTruncation && cp(d, d) > 0.0) ++segment_contacts;
      if (pins[i].edge) CHECK(cp(d, d) == 0.0);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cp);
    CHECK(eig.eigenvalues().minCoeff() >= -1e-12 * eig.eigenvalues().maxCoeff());
  }
  MESSAGE("segment-only cap: " << mf << " flank and " << mc << " cap intervals, " << flank.space_points()
                               << " points a space; segment contacts coupled over a mesh period: " << segment_contacts);
}

}  // namespace disc_caps_test
