#include "ltca/contact/disc_body.hpp"

#include <algorithm>
#include <chrono>
#include <numbers>
#include <memory>
#include <mutex>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/SparseCore>

#include <fmt/format.h>

#include "fe/disc_mesh.hpp"
#include "fe/t6_elasticity.hpp"

namespace ltca::contact {
namespace {

void RequirePositive(double value, const char* name) {
  if (!std::isfinite(value) || !(value > 0.0)) {
    throw std::invalid_argument(std::string("disc body: ") + name + " must be finite and positive");
  }
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

/// The model with every node of the bore clamped (both components): the support.
std::unique_ptr<fe::ElasticModel> ClampedAtBore(const fe::T6Mesh& mesh, const DiscBodyDesign& design) {
  std::vector<char> on_bore(mesh.nodes.size(), 0);
  for (const fe::BoundaryEdge& edge : mesh.edges) {
    if (edge.boundary == fe::Boundary::kBore) {
      for (const int n : edge.nodes) on_bore[n] = 1;
    }
  }
  std::vector<int> clamped;
  for (std::size_t n = 0; n < mesh.nodes.size(); ++n) {
    if (on_bore[n]) {
      clamped.push_back(2 * static_cast<int>(n));
      clamped.push_back(2 * static_cast<int>(n) + 1);
    }
  }
  const fe::Elasticity elasticity{design.plane, design.young_modulus_mpa, design.poisson_ratio, design.thickness_mm};
  return std::make_unique<fe::ElasticModel>(mesh, elasticity, clamped);
}

/// The step between consecutive tooth spaces along the outline: space k's end (u = phi_max) meets
/// the start (u = -phi_max) of space k + 1 or of space k - 1 (1 or z_c - 1).
int OutlineStep(const geometry::CycloidProfile& profile) {
  const int spaces = profile.pair().tooth_count;
  const double phi = profile.phi_max();
  const Eigen::Vector2d end = profile.Position(phi, 0);
  return (end - profile.Position(-phi, 1)).norm() <= (end - profile.Position(-phi, spaces - 1)).norm() ? 1 : spaces - 1;
}

/// A tip relief's cap (geometry::TipCap) sampled from its apex (w = 0) to its junction with the flank
/// (w = 1), in TipCap::Point's w (uniform in arc length): the truncation segment's half (if any) in
/// intervals at most `spacing` long (at least one), then the rounding arc's (if any) at most `spacing`
/// long and at most 0.1 rad (at least two). `transition` receives the index of the segment's end,
/// where the arc starts (its curvature jumps there), or -1 without both pieces.
std::vector<double> HalfCapW(const geometry::TipCap& cap, double spacing, int* transition) {
  const double half = 0.5 * cap.length();
  const double land = cap.land_half_width();
  const double rho = cap.relief().rounding_radius;
  const double arc = half - land;
  const int line_steps = land > 0.0 ? std::max(1, static_cast<int>(std::ceil(land / spacing))) : 0;
  const int arc_steps = rho > 0.0 && arc > 0.0
                            ? std::max({2, static_cast<int>(std::ceil(arc / spacing)), static_cast<int>(std::ceil(arc / rho / 0.1))})
                            : 0;
  std::vector<double> w{0.0};
  for (int i = 1; i <= line_steps; ++i) w.push_back(land * i / line_steps / half);
  for (int i = 1; i <= arc_steps; ++i) w.push_back((land + arc * i / arc_steps) / half);
  w.back() = 1.0;
  *transition = line_steps > 0 && arc_steps > 0 ? line_steps : -1;
  return w;
}

/// The flank's length from u = -u_end to u_end of a tooth space, mm (the chords of `intervals` even steps in u).
double FlankChordLength(const geometry::CycloidProfile& profile, double u_end, int intervals) {
  double length = 0.0;
  Eigen::Vector2d previous = profile.Position(-u_end, 0);
  for (int j = 1; j <= intervals; ++j) {
    const Eigen::Vector2d next = profile.Position(-u_end + 2.0 * u_end * j / intervals, 0);
    length += (next - previous).norm();
    previous = next;
  }
  return length;
}

/// Appends cap `tip`'s points at the given w's (TipCap::Point), marking as corners of the curve the
/// junctions (|w| = 1) and the segment's ends (|w| = the half list's `transition` entry).
void AppendCap(const geometry::TipCap& cap, int tip, const std::vector<double>& ws, double transition_w,
               std::vector<Eigen::Vector2d>* points, std::vector<int>* corners) {
  for (const double w : ws) {
    if (std::abs(w) == 1.0 || std::abs(w) == transition_w) corners->push_back(static_cast<int>(points->size()));
    points->push_back(cap.Point(w, tip).point);
  }
}

}  // namespace

void DiscBodyDesign::Validate() const {
  if (outline_mm.empty()) {
    RequirePositive(outer_radius_mm, "outer_radius_mm");
  } else {
    if (outline_mm.size() < 3) throw std::invalid_argument("disc body: the outline needs at least 3 points");
    for (const Eigen::Vector2d& p : outline_mm) {
      if (!p.allFinite()) throw std::invalid_argument("disc body: an outline point is not finite");
    }
  }
  RequirePositive(bore_radius_mm, "bore_radius_mm");
  RequirePositive(young_modulus_mpa, "young_modulus_mpa");
  RequirePositive(thickness_mm, "thickness_mm");
  RequirePositive(element_size_mm, "element_size_mm");
  RequirePositive(refined_size_mm, "refined_size_mm");
  RequirePositive(refine_radius_mm, "refine_radius_mm");
  if (!(poisson_ratio >= 0.0 && poisson_ratio < 0.5)) {
    throw std::invalid_argument("disc body: poisson_ratio must be in [0, 0.5)");
  }
  if (refined_size_mm > element_size_mm) {
    throw std::invalid_argument("disc body: refined_size_mm must not exceed element_size_mm");
  }
  for (const DiscHole& hole : holes) {
    RequirePositive(hole.radius_mm, "a hole's radius_mm");
    if (!hole.centre_mm.allFinite()) throw std::invalid_argument("disc body: a hole's centre is not finite");
    if (hole.centre_mm.norm() - hole.radius_mm <= bore_radius_mm) {
      throw std::invalid_argument("disc body: a hole meets the bore");
    }
  }
  for (const Eigen::Vector2d& p : refine_near_mm) {
    if (!p.allFinite()) throw std::invalid_argument("disc body: a refinement point is not finite");
  }
}

std::vector<Eigen::Vector2d> DiscOutline(const geometry::CycloidProfile& profile, int points_per_space,
                                         std::vector<int>* corners) {
  if (profile.tooth_difference() < 0) throw std::invalid_argument("disc outline: the cycloid is the outer member (d < 0)");
  if (points_per_space < 8) throw std::invalid_argument("disc outline: at least 8 points per tooth space");
  const int spaces = profile.pair().tooth_count;
  const double phi = profile.phi_max();
  const int step = OutlineStep(profile);
  const geometry::TipCap& cap = profile.tip_cap();
  std::vector<Eigen::Vector2d> outline;
  std::vector<int> breaks;
  if (!cap.active()) {
    outline.reserve(static_cast<std::size_t>(spaces) * points_per_space);
    for (int i = 0, k = 0; i < spaces; ++i, k = (k + step) % spaces) {
      for (int j = 0; j < points_per_space; ++j) {
        outline.push_back(profile.Position(-phi + 2.0 * phi * j / points_per_space, k));
      }
    }
  } else {
    // d > 0: tooth space k's flank over [-u_j, u_j], then tip k's cap from its junction with space
    // k (w = 1) over the tip to its junction with space k + 1 (w = -1, space k + 1's first point).
    if (step != 1) throw std::invalid_argument("disc outline: a tip relief's caps on a profile whose spaces do not follow in order");
    const double uj = cap.junction();
    int transition = -1;
    const std::vector<double> half = HalfCapW(cap, FlankChordLength(profile, uj, points_per_space) / points_per_space, &transition);
    std::vector<double> ws(half.rbegin(), half.rend());                        // 1 ... 0
    for (std::size_t i = 1; i + 1 < half.size(); ++i) ws.push_back(-half[i]);  // ... down to, not at, -1
    const double transition_w = transition >= 0 ? half[static_cast<std::size_t>(transition)] : -1.0;
    for (int k = 0; k < spaces; ++k) {
      breaks.push_back(static_cast<int>(outline.size()));  // the junction with tip k - 1's cap
      for (int j = 0; j < points_per_space; ++j) outline.push_back(profile.Position(-uj + 2.0 * uj * j / points_per_space, k));
      AppendCap(cap, k, ws, transition_w, &outline, &breaks);
    }
  }
  double twice_area = 0.0;  // shoelace
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const Eigen::Vector2d& a = outline[i];
    const Eigen::Vector2d& b = outline[(i + 1) % outline.size()];
    twice_area += a.x() * b.y() - a.y() * b.x();
  }
  if (twice_area < 0.0) {
    std::reverse(outline.begin(), outline.end());
    for (int& c : breaks) c = static_cast<int>(outline.size()) - 1 - c;
    std::sort(breaks.begin(), breaks.end());
  }
  if (corners != nullptr) *corners = std::move(breaks);
  return outline;
}

struct DiscBody::Impl {
  fe::T6Mesh mesh;
  std::unique_ptr<fe::ElasticModel> model;
  double mesh_seconds = 0.0;
  double factorisation_seconds = 0.0;
  /// CHOLMOD's workspace (Eigen's wrapper keeps it mutable inside the factorisation) is one per
  /// body: the solves of concurrent Condense calls on the body or its copies take turns.
  mutable std::mutex solving;
};

DiscBody::DiscBody(const DiscBodyDesign& design) {
  auto impl = std::make_shared<Impl>();
  const auto start = std::chrono::steady_clock::now();
  impl->mesh = fe::MeshDisc(design);
  impl->mesh_seconds = Seconds(start);
  const auto solve_start = std::chrono::steady_clock::now();
  impl->model = ClampedAtBore(impl->mesh, design);
  impl->factorisation_seconds = Seconds(solve_start);
  impl_ = std::move(impl);
}

DiscBody::~DiscBody() = default;
DiscBody::DiscBody(const DiscBody&) = default;
DiscBody& DiscBody::operator=(const DiscBody&) = default;

DiscCompliance DiscBody::Condense(const std::vector<DiscLoadPoint>& points) const {
  const Impl& body = *impl_;
  DiscCompliance result;
  result.nodes = static_cast<int>(body.mesh.nodes.size());
  result.elements = static_cast<int>(body.mesh.triangles.size());
  result.mesh_seconds = body.mesh_seconds;
  const auto start = std::chrono::steady_clock::now();
  // One unit-force patch per point (not on the bore); C = F^T K^-1 F.
  const auto loadable = [](const fe::BoundaryEdge& edge) { return edge.boundary != fe::Boundary::kBore; };
  Eigen::MatrixXd loads(body.model->dofs(), static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].point_mm.allFinite()) throw std::invalid_argument("disc body: a load point is not finite");
    loads.col(static_cast<Eigen::Index>(i)) =
        fe::PatchLoad(body.mesh, loadable, points[i].point_mm, points[i].direction, points[i].half_width_mm);
  }
  Eigen::MatrixXd u;
  {
    const std::lock_guard<std::mutex> lock(body.solving);
    u = body.model->Solve(loads);
  }
  result.compliance_mm_per_n = loads.transpose() * u;
  result.solve_seconds = body.factorisation_seconds + Seconds(start);
  return result;
}

DiscCompliance CondenseDiscCompliance(const DiscBodyDesign& design, const std::vector<DiscLoadPoint>& points) {
  return DiscBody(design).Condense(points);
}

const char* ToString(DiscBodySettings::Body body) {
  return body == DiscBodySettings::Body::kElastic ? "elastic" : "rigid";
}

const char* ToString(PlaneModel plane) { return plane == PlaneModel::kStress ? "stress" : "strain"; }

void DiscBodySettings::Validate(double root_radius) const {
  if (!elastic()) return;
  const auto fail = [](const char* key, double value, const std::string& expected) {
    throw std::invalid_argument(fmt::format("[disc] {} = {}: expected {}", key, value, expected));
  };
  if (!(element_size >= 0.1 && element_size <= 20.0)) fail("element_size_mm", element_size, "a length from 0.1 to 20 mm");
  const double limit = root_radius - 2.0 * element_size;
  if (!(bore_radius > 0.0) || !std::isfinite(bore_radius) || !(bore_radius < limit)) {
    fail("bore_radius_mm", bore_radius,
         fmt::format("a radius above 0 and below {:g} mm (the root circle {:g} mm less two element sizes) with body = "
                     "\"elastic\"",
                     limit, root_radius));
  }
  if (grid.points_per_space < 8 || grid.points_per_space > 256) {
    fail("grid_points_per_space", grid.points_per_space, "an integer from 8 to 256");
  }
  const double w = grid.patch_half_width_mm;
  if (!(w >= 0.01 && w <= 2.0) || !(w < element_size)) {
    fail("patch_half_width_mm", w, fmt::format("a length from 0.01 to 2 mm and below element_size_mm = {:g}", element_size));
  }
}

DiscFlankCompliance::DiscFlankCompliance(const geometry::CycloidProfile& profile, DiscBodyDesign body,
                                         DiscFlankGrid grid)
    : grid_(grid),
      spaces_(profile.pair().tooth_count),
      step_(OutlineStep(profile)),
      phi_max_(profile.phi_max()),
      thickness_(body.thickness_mm) {
  const auto start = std::chrono::steady_clock::now();
  if (grid.points_per_space < 8) throw std::invalid_argument("disc flank: at least 8 grid points per tooth space");
  RequirePositive(grid.patch_half_width_mm, "patch_half_width_mm");
  if (grid.points_per_hole < 8) throw std::invalid_argument("disc flank: at least 8 grid points per hole");
  const int m = grid.points_per_space;
  const int hp = grid.points_per_hole;
  hole_count_ = static_cast<int>(body.holes.size());
  // A tip relief (d > 0): each space's flank ends at +-u_j, and tip k's cap joins space k's u_j (w =
  // 1) to space k + 1's -u_j (w = -1).
  const geometry::TipCap& cap = profile.tip_cap();
  caps_ = cap.active();
  if (caps_ && (profile.tooth_difference() < 0 || step_ != 1)) {
    throw std::invalid_argument("disc flank: a tip relief's caps are built for d > 0 only");
  }
  const double u_end = caps_ ? cap.junction() : phi_max_;
  // The grid evenly in arc length over a tooth space (the same u in every space): uniform in u it
  // is coarsest near the root, where the flank turns fastest (the trapezoidal arc length of 64
  // sub-intervals per grid interval). With caps the space's m points are shared between the flank
  // and its cap by their lengths (at least 2 intervals each).
  int flank_intervals = m;
  {
    constexpr int kFine = 64;
    const int steps = kFine * m;
    std::vector<double> arc(static_cast<std::size_t>(steps) + 1, 0.0);
    const auto speed = [&](int i) { return profile.Evaluate(-u_end + 2.0 * u_end * i / steps, 0).d1.norm(); };
    double previous = speed(0);
    for (int i = 1; i <= steps; ++i) {
      const double next = speed(i);
      arc[static_cast<std::size_t>(i)] = arc[static_cast<std::size_t>(i) - 1] + 0.5 * (previous + next) * (2.0 * u_end / steps);
      previous = next;
    }
    if (caps_) {
      // The flank keeps its share of m by length; the cap has at least its share, at most w0 and
      // pi / 16 of its turn between points: a tip is a thin wedge whose coefficients change over
      // the rounding's length (on the d = 2 pair's 0.5 mm rounding: 2 intervals by length gave
      // 4.6 % between grid points against a direct condensation, docs/fe_disc.md).
      const double flank = arc.back();
      flank_intervals = std::clamp(static_cast<int>(std::lround(m * flank / (flank + cap.length()))), 2, m - 2);
      const double turn = std::acos(std::clamp(cap.Point(1.0, 0).normal.dot(cap.Point(-1.0, 0).normal), -1.0, 1.0));
      cap_intervals_ = std::max({m - flank_intervals, static_cast<int>(std::ceil(cap.length() / grid.patch_half_width_mm)),
                                 static_cast<int>(std::ceil(turn / (std::numbers::pi / 16.0)))});
    }
    grid_u_.assign(static_cast<std::size_t>(flank_intervals) + 1, 0.0);
    for (int j = 0; j <= flank_intervals; ++j) {
      const double target = arc.back() * j / flank_intervals;
      const auto it = std::lower_bound(arc.begin(), arc.end(), target);
      const std::size_t i = std::clamp<std::size_t>(static_cast<std::size_t>(it - arc.begin()), 1, arc.size() - 1);
      const double f = (target - arc[i - 1]) / (arc[i] - arc[i - 1]);
      grid_u_[static_cast<std::size_t>(j)] = -u_end + 2.0 * u_end * (static_cast<double>(i - 1) + f) / steps;
    }
    grid_u_.front() = -u_end;
    grid_u_.back() = u_end;
  }
  // A space's grid points: without caps its m flank points over [-phi_max, phi_max) (the next
  // space's first closes it); with caps the flank's over [-u_j, u_j], both ends included, then tip
  // k's cap at w = 1 - 2 i / m_c. With a rounding the junction is smooth (the normal continuous): the
  // cap's ends are the flanks' end points (the cap's interior points i = 1 ... m_c - 1 follow). With
  // the segment alone (rho = 0) the junction is a corner: the cap has its own end points (i = 0 ...
  // m_c, the segment's normal), so that no interpolation straddles the corner.
  const bool cap_ends = caps_ && !(cap.relief().rounding_radius > 0.0);
  per_space_ = !caps_ ? m : cap_ends ? flank_intervals + cap_intervals_ + 2 : flank_intervals + cap_intervals_;
  std::vector<double> station_w;  // the cap's w of each of a space's cap points, from local index flank_intervals + 1
  if (caps_) {
    cap_slots_.assign(static_cast<std::size_t>(cap_intervals_) + 1, 0);
    for (int i = 0; i <= cap_intervals_; ++i) {
      int slot = 0;
      if (cap_ends) {
        slot = flank_intervals + 1 + i;
      } else {
        slot = i == 0 ? flank_intervals : i == cap_intervals_ ? per_space_ : flank_intervals + i;
      }
      cap_slots_[static_cast<std::size_t>(i)] = slot;
      if (slot > flank_intervals && slot < per_space_) station_w.push_back(1.0 - 2.0 * i / cap_intervals_);
    }
  }
  flank_points_ = spaces_ * per_space_;
  const int n = flank_points_ + hole_count_ * hp;
  points_.resize(2, n);
  normals_.resize(2, n);
  for (int k = 0; k < spaces_; ++k) {
    for (int j = 0; j < per_space_; ++j) {
      if (j <= flank_intervals) {
        const geometry::ProfilePoint p = profile.Evaluate(grid_u_[static_cast<std::size_t>(j)], k);
        points_.col(k * per_space_ + j) = p.position;
        normals_.col(k * per_space_ + j) = -p.normal;  // into the material: the direction a pin pushes
      } else {
        const geometry::CapFoot c = cap.Point(station_w[static_cast<std::size_t>(j - flank_intervals - 1)], k);
        points_.col(k * per_space_ + j) = c.point;
        normals_.col(k * per_space_ + j) = -c.normal;
      }
    }
  }
  // Each hole's ring: evenly in angle from the hole's +x, along the outward normal (into the
  // material, the direction an output pin or a crank bearing pushes the wall).
  for (int h = 0; h < hole_count_; ++h) {
    const DiscHole& hole = body.holes[static_cast<std::size_t>(h)];
    for (int j = 0; j < hp; ++j) {
      const double a = 2.0 * std::numbers::pi * j / hp;
      const Eigen::Vector2d d(std::cos(a), std::sin(a));
      points_.col(flank_points_ + h * hp + j) = hole.centre_mm + hole.radius_mm * d;
      normals_.col(flank_points_ + h * hp + j) = d;
    }
  }
  // The outline at twice the grid's density, meshed at w0 along all of it. Without holes the body
  // is cyclically symmetric: one tooth space's sector is meshed and turned z_c times (a mesh that
  // a turn through 2 pi / z_c leaves the same), and only that space's grid points are solved for:
  // K between spaces a and b is K between spaces a - b and 0.
  body.outline_mm = DiscOutline(profile, 2 * m, &body.outline_corners);
  body.refine_near_mm = body.outline_mm;
  for (const DiscHole& hole : body.holes) {  // the holes' walls meshed at w0 too
    for (int j = 0; j < 2 * hp; ++j) {
      const double a = std::numbers::pi * j / hp;
      body.refine_near_mm.emplace_back(hole.centre_mm + hole.radius_mm * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
  }
  body.refined_size_mm = std::min(grid.patch_half_width_mm, body.element_size_mm);
  body.Validate();
  cyclic_ = body.holes.empty();
  fe::T6Mesh mesh;
  if (cyclic_) {
    fe::DiscSector sector;
    if (!caps_) {
      for (int j = 0; j <= 2 * m; ++j) sector.outline_mm.push_back(profile.Position(-phi_max_ + phi_max_ * j / m, 0));
    } else {
      // From tip z_c - 1's apex (on its axis, w = 0) over its cap's half to space 0's flank, the
      // flank, then tip 0's cap to its apex: the cuts run along the tooth axes through the apexes,
      // sampled as DiscOutline samples them (2 m points over the flank).
      int transition = -1;
      const std::vector<double> half = HalfCapW(cap, FlankChordLength(profile, u_end, 2 * m) / (2 * m), &transition);
      const double transition_w = transition >= 0 ? half[static_cast<std::size_t>(transition)] : -1.0;
      std::vector<double> before;  // 0 ... down to, not at, -1 (space 0's flank starts there)
      for (std::size_t i = 0; i + 1 < half.size(); ++i) before.push_back(-half[i]);
      before.front() = 0.0;
      AppendCap(cap, spaces_ - 1, before, transition_w, &sector.outline_mm, &sector.corners);
      sector.corners.push_back(static_cast<int>(sector.outline_mm.size()));  // the junction
      for (int j = 0; j < 2 * m; ++j) sector.outline_mm.push_back(profile.Position(-u_end + u_end * j / m, 0));
      const std::vector<double> after(half.rbegin(), half.rend());  // 1 ... 0
      AppendCap(cap, 0, after, transition_w, &sector.outline_mm, &sector.corners);
      sector.corners.erase(std::remove_if(sector.corners.begin(), sector.corners.end(),
                                          [&](int c) { return c <= 0 || c + 1 >= static_cast<int>(sector.outline_mm.size()); }),
                           sector.corners.end());
    }
    sector.copies = spaces_;
    const Eigen::Vector2d& a = sector.outline_mm.front();
    const Eigen::Vector2d& b = sector.outline_mm.back();
    sector.angle_rad = std::remainder(std::atan2(b.y(), b.x()) - std::atan2(a.y(), a.x()), 2.0 * std::numbers::pi);
    sector.bore_radius_mm = body.bore_radius_mm;
    sector.element_size_mm = body.element_size_mm;
    sector.refined_size_mm = body.refined_size_mm;
    sector.refine_radius_mm = body.refine_radius_mm;
    mesh = fe::MeshDiscSector(sector);
  } else {
    mesh = fe::MeshDisc(body);
  }
  nodes_ = static_cast<int>(mesh.nodes.size());
  elements_ = static_cast<int>(mesh.triangles.size());
  const std::unique_ptr<fe::ElasticModel> model = ClampedAtBore(mesh, body);
  // The grid's patch loads (sparse: each touches a few edges), then K = L^T K_fe^-1 L, solved in
  // blocks of columns so that no dense dofs x n matrix is held.
  const auto loadable = [](const fe::BoundaryEdge& edge) { return edge.boundary != fe::Boundary::kBore; };
  std::vector<Eigen::Triplet<double>> entries;
  for (int g = 0; g < n; ++g) {
    const Eigen::VectorXd f = fe::PatchLoad(mesh, loadable, points_.col(g), normals_.col(g), grid.patch_half_width_mm);
    for (Eigen::Index i = 0; i < f.size(); ++i) {
      if (f[i] != 0.0) entries.emplace_back(static_cast<int>(i), g, f[i]);
    }
  }
  Eigen::SparseMatrix<double> loads(model->dofs(), n);
  loads.setFromTriplets(entries.begin(), entries.end());
  if (!cyclic_) {
    // A body with holes: K = F^T K_fe^-1 F of every grid point, by forward solves over the
    // elimination tree's paths from each patch only (ElasticModel::Condense: Y = L^-1 P F, K =
    // Y^T Y, exactly symmetric; Maxwell-Betti by construction). The full solves of the 1,632
    // columns (a forward and a backward solve over the whole factor each, then F^T U) took 61 % of
    // the cycloidal drive body's 15.8 s set-up in the reference BLAS.
    k_ = model->Condense(loads);
    setup_seconds_ = Seconds(start);
    return;
  }
  // Cyclic: only space 0's per_space_ columns are solved for (K between spaces a and b is K between
  // a - b and 0; n = spaces x per_space_), in full: F^T K_fe^-1 F_0.
  const int solved = per_space_;
  // Blocks of 16 columns: a block's dense arrays (dofs x 16) are reused by the allocator, where 64
  // columns' (above glibc's 32 MB mmap threshold) were mapped and faulted in anew for every block.
  // Each column's solve is the same arithmetic whatever the block (the reference BLAS's dgemm and
  // dtrsm treat the right-hand sides column by column): the same numbers.
  constexpr int kBlock = 16;
  Eigen::MatrixXd columns(n, solved);
  for (int first = 0; first < solved; first += kBlock) {
    const int cols = std::min(kBlock, solved - first);
    const Eigen::MatrixXd u = model->Solve(Eigen::MatrixXd(loads.middleCols(first, cols)));
    columns.middleCols(first, cols) = loads.transpose() * u;
  }
  // Maxwell-Betti holds to rounding; make it exact: the solved columns (space 0's) give
  // K(a m + i, b m + j) = columns(((a - b) mod z_c) m + i, j), m = per_space_, so K is
  // block-circulant and so is (K + K^T) / 2: its generator (space 0's columns) holds, entry by
  // entry, the same sum of the same two numbers as the whole symmetrised K did.
  const int ps = per_space_;
  k_.resize(n, ps);
  for (int j = 0; j < ps; ++j) {
    for (int a = 0; a < spaces_; ++a) {
      const int mirror = (spaces_ - a) % spaces_;  // K(j, a m + i) = columns(((0 - a) mod z_c) m + j, i)
      for (int i = 0; i < ps; ++i) k_(a * ps + i, j) = 0.5 * (columns(a * ps + i, j) + columns(mirror * ps + j, i));
    }
  }
  setup_seconds_ = Seconds(start);
}

Eigen::MatrixXd DiscFlankCompliance::grid_compliance() const {
  if (!cyclic_) return k_;
  const auto n = k_.rows();
  Eigen::MatrixXd k(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < n; ++i) k(i, j) = grid_compliance(static_cast<int>(i), static_cast<int>(j));
  }
  return k;
}

double DiscFlankCompliance::cycloid_log_radius_mm() const {
  return grid_.patch_half_width_mm / std::sqrt(std::numbers::e);
}

void DiscFlankCompliance::Neighbours(int tooth_space, double u, int* first, int* second, double* t) const {
  const int m = per_space_;
  const int intervals = static_cast<int>(grid_u_.size()) - 1;  // m without caps; the flank's m_f with them
  const int k = ((tooth_space % spaces_) + spaces_) % spaces_;
  const auto it = std::upper_bound(grid_u_.begin(), grid_u_.end(), u);
  const int j = std::clamp(static_cast<int>(it - grid_u_.begin()) - 1, 0, intervals - 1);
  const double lo = grid_u_[static_cast<std::size_t>(j)], hi = grid_u_[static_cast<std::size_t>(j) + 1];
  *t = std::clamp((u - lo) / (hi - lo), 0.0, 1.0);
  *first = k * m + j;
  *second = j + 1 < m ? k * m + j + 1 : ((k + step_) % spaces_) * m;
}

void DiscFlankCompliance::CapNeighbours(int tooth_space, double u, double w, int* first, int* second, double* t) const {
  // The cap of tip k joins space k's u_j (w = 1) to space k + 1's -u_j (w = -1): a point on its half
  // next to space k' is on tip k' (u > 0) or k' - 1 (u < 0). Its grid points are evenly in w from 1.
  const int m = per_space_;
  const int k = (((u > 0.0 ? tooth_space : tooth_space - 1) % spaces_) + spaces_) % spaces_;
  const double s = 0.5 * (1.0 - std::clamp(w, -1.0, 1.0)) * cap_intervals_;
  const int i = std::clamp(static_cast<int>(std::floor(s)), 0, cap_intervals_ - 1);
  *t = std::clamp(s - i, 0.0, 1.0);
  const auto global = [&](int slot) { return slot < m ? k * m + slot : ((k + 1) % spaces_) * m + (slot - m); };
  *first = global(cap_slots_[static_cast<std::size_t>(i)]);
  *second = global(cap_slots_[static_cast<std::size_t>(i) + 1]);
}

bool DiscFlankCompliance::OnGrid(const PinContact& p, int* first, int* second, double* t) const {
  if (p.edge || !(p.length > 0.0)) return false;
  if (p.part == geometry::SurfacePart::kFlank) {
    Neighbours(p.tooth_space, p.u, first, second, t);
    return true;
  }
  if (caps_ && (p.part == geometry::SurfacePart::kTipRounding || p.part == geometry::SurfacePart::kTipTruncation)) {
    CapNeighbours(p.tooth_space, p.u, p.cap_w, first, second, t);
    return true;
  }
  return false;
}

void DiscFlankCompliance::HoleNeighbours(int h, const Eigen::Vector2d& direction, int* first, int* second,
                                         double* t) const {
  if (h < 0 || h >= hole_count_) {
    throw std::invalid_argument(fmt::format("disc flank: hole {} of a body with {} holes", h, hole_count_));
  }
  const int hp = grid_.points_per_hole;
  double a = std::atan2(direction.y(), direction.x()) / (2.0 * std::numbers::pi) * hp;  // in grid steps
  if (a < 0.0) a += hp;
  const int j = std::clamp(static_cast<int>(std::floor(a)), 0, hp - 1);
  *t = std::clamp(a - j, 0.0, 1.0);
  *first = hole_grid_start(h) + j;
  *second = hole_grid_start(h) + (j + 1) % hp;
}

Eigen::MatrixXd DiscFlankCompliance::Coupling(const std::vector<PinContact>& points,
                                              const std::vector<DiscHoleContact>& holes) const {
  const auto n = static_cast<Eigen::Index>(points.size());
  const auto h = static_cast<Eigen::Index>(holes.size());
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n + h, n + h);
  c.topLeftCorner(n, n) = Coupling(points);
  // Every entry's two neighbours and weight: the flank's points (on: loaded flank points), then the holes'.
  std::vector<int> a(static_cast<std::size_t>(n + h)), b(static_cast<std::size_t>(n + h));
  std::vector<double> t(static_cast<std::size_t>(n + h));
  std::vector<char> on(static_cast<std::size_t>(n + h), 1);
  for (Eigen::Index i = 0; i < n; ++i) {
    const PinContact& p = points[static_cast<std::size_t>(i)];
    const auto k = static_cast<std::size_t>(i);
    if (p.disc != 0 || !OnGrid(p, &a[k], &b[k], &t[k])) on[k] = 0;
  }
  for (Eigen::Index i = 0; i < h; ++i) {
    const auto k = static_cast<std::size_t>(n + i);
    HoleNeighbours(holes[static_cast<std::size_t>(i)].hole, holes[static_cast<std::size_t>(i)].direction, &a[k], &b[k], &t[k]);
  }
  const auto k = [this](int i, int j) { return grid_compliance(i, j); };
  const auto product = [&](std::size_t i, std::size_t j) {
    const double ti = t[i], si = 1.0 - ti, tj = t[j], sj = 1.0 - tj;
    return si * (sj * k(a[i], a[j]) + tj * k(a[i], b[j])) + ti * (sj * k(b[i], a[j]) + tj * k(b[i], b[j]));
  };
  for (Eigen::Index x = n; x < n + h; ++x) {
    const auto i = static_cast<std::size_t>(x);
    c(x, x) = (1.0 - t[i]) * k(a[i], a[i]) + t[i] * k(b[i], b[i]);
    for (Eigen::Index y = 0; y < x; ++y) {
      const auto j = static_cast<std::size_t>(y);
      if (!on[j]) continue;
      c(x, y) = c(y, x) = product(i, j);
    }
  }
  return c;
}

Eigen::MatrixXd DiscFlankCompliance::Coupling(const std::vector<PinContact>& points) const {
  const Eigen::Index n = static_cast<Eigen::Index>(points.size());
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n, n);
  // Each loaded flank point's two grid neighbours as (index, tooth space, index in the space): K's
  // entries are then read without a division (grid_compliance(i, j) divides by points_per_space;
  // a pose of 40 points reads K 3,300 times).
  struct Slot {
    int full = 0, space = 0, local = 0;
  };
  std::vector<Slot> a(points.size()), b(points.size());
  std::vector<double> t(points.size());
  std::vector<char> on(points.size(), 0);
  const int m = per_space_;
  const auto slot = [m](int g) { return Slot{g, g / m, g % m}; };
  for (std::size_t i = 0; i < points.size(); ++i) {
    int first = 0, second = 0;
    if (!OnGrid(points[i], &first, &second, &t[i])) continue;
    on[i] = 1;
    a[i] = slot(first), b[i] = slot(second);
  }
  const double* g = k_.data();
  const Eigen::Index stride = k_.rows();  // column-major
  const int spaces = spaces_;
  const bool cyclic = cyclic_;
  const auto k = [&](const Slot& x, const Slot& y) {  // K(x, y), as grid_compliance(x.full, y.full)
    if (!cyclic) return g[x.full + y.full * stride];
    const int shift = x.space >= y.space ? x.space - y.space : x.space - y.space + spaces;
    return g[shift * m + x.local + y.local * stride];
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!on[i]) continue;
    const double scale = thickness_ / points[i].length;  // a slice: a section of its own thickness
    const double ti = t[i], si = 1.0 - ti;
    for (std::size_t j = i; j < points.size(); ++j) {
      if (!on[j] || points[j].slice != points[i].slice || points[j].disc != points[i].disc) continue;
      double v = 0.0;
      if (i == j) {
        v = si * k(a[i], a[i]) + ti * k(b[i], b[i]);
      } else {
        const double tj = t[j], sj = 1.0 - tj;
        v = si * (sj * k(a[i], a[j]) + tj * k(a[i], b[j])) + ti * (sj * k(b[i], a[j]) + tj * k(b[i], b[j]));
      }
      c(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = scale * v;
      c(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(i)) = scale * v;
    }
  }
  return c;
}

}  // namespace ltca::contact
