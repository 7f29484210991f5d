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

std::vector<Eigen::Vector2d> DiscOutline(const geometry::CycloidProfile& profile, int points_per_space) {
  if (profile.tip_cap().active()) throw std::invalid_argument("disc outline: a tip relief's caps are not sampled");
  if (profile.tooth_difference() < 0) throw std::invalid_argument("disc outline: the cycloid is the outer member (d < 0)");
  if (points_per_space < 8) throw std::invalid_argument("disc outline: at least 8 points per tooth space");
  const int spaces = profile.pair().tooth_count;
  const double phi = profile.phi_max();
  const int step = OutlineStep(profile);
  std::vector<Eigen::Vector2d> outline;
  outline.reserve(static_cast<std::size_t>(spaces) * points_per_space);
  for (int i = 0, k = 0; i < spaces; ++i, k = (k + step) % spaces) {
    for (int j = 0; j < points_per_space; ++j) {
      outline.push_back(profile.Position(-phi + 2.0 * phi * j / points_per_space, k));
    }
  }
  double twice_area = 0.0;  // shoelace
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const Eigen::Vector2d& a = outline[i];
    const Eigen::Vector2d& b = outline[(i + 1) % outline.size()];
    twice_area += a.x() * b.y() - a.y() * b.x();
  }
  if (twice_area < 0.0) std::reverse(outline.begin(), outline.end());
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
  flank_points_ = spaces_ * m;
  hole_count_ = static_cast<int>(body.holes.size());
  const int n = flank_points_ + hole_count_ * hp;
  // The grid evenly in arc length over a tooth space (the same u in every space): uniform in u it
  // is coarsest near the root, where the flank turns fastest (the trapezoidal arc length of 64
  // sub-intervals per grid interval).
  {
    constexpr int kFine = 64;
    const int steps = kFine * m;
    std::vector<double> arc(static_cast<std::size_t>(steps) + 1, 0.0);
    const auto speed = [&](int i) { return profile.Evaluate(-phi_max_ + 2.0 * phi_max_ * i / steps, 0).d1.norm(); };
    double previous = speed(0);
    for (int i = 1; i <= steps; ++i) {
      const double next = speed(i);
      arc[static_cast<std::size_t>(i)] = arc[static_cast<std::size_t>(i) - 1] + 0.5 * (previous + next) * (2.0 * phi_max_ / steps);
      previous = next;
    }
    grid_u_.assign(static_cast<std::size_t>(m) + 1, 0.0);
    for (int j = 0; j <= m; ++j) {
      const double target = arc.back() * j / m;
      const auto it = std::lower_bound(arc.begin(), arc.end(), target);
      const std::size_t i = std::clamp<std::size_t>(static_cast<std::size_t>(it - arc.begin()), 1, arc.size() - 1);
      const double f = (target - arc[i - 1]) / (arc[i] - arc[i - 1]);
      grid_u_[static_cast<std::size_t>(j)] = -phi_max_ + 2.0 * phi_max_ * (static_cast<double>(i - 1) + f) / steps;
    }
    grid_u_.front() = -phi_max_;
    grid_u_.back() = phi_max_;
  }
  points_.resize(2, n);
  normals_.resize(2, n);
  for (int k = 0; k < spaces_; ++k) {
    for (int j = 0; j < m; ++j) {
      const geometry::ProfilePoint p = profile.Evaluate(grid_u_[static_cast<std::size_t>(j)], k);
      points_.col(k * m + j) = p.position;
      normals_.col(k * m + j) = -p.normal;  // into the material: the direction a pin pushes
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
  body.outline_mm = DiscOutline(profile, 2 * m);
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
    for (int j = 0; j <= 2 * m; ++j) sector.outline_mm.push_back(profile.Position(-phi_max_ + phi_max_ * j / m, 0));
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
  // Cyclic: only space 0's m columns are solved for (K between spaces a and b is K between a - b
  // and 0), in full: F^T K_fe^-1 F_0.
  const int solved = m;
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
  // K(a m + i, b m + j) = columns(((a - b) mod z_c) m + i, j), so K is block-circulant and so is
  // (K + K^T) / 2: its generator (space 0's columns) holds, entry by entry, the same sum of the
  // same two numbers as the whole symmetrised K did.
  k_.resize(n, m);
  for (int j = 0; j < m; ++j) {
    for (int a = 0; a < spaces_; ++a) {
      const int mirror = (spaces_ - a) % spaces_;  // K(j, a m + i) = columns(((0 - a) mod z_c) m + j, i)
      for (int i = 0; i < m; ++i) k_(a * m + i, j) = 0.5 * (columns(a * m + i, j) + columns(mirror * m + j, i));
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
  const int m = grid_.points_per_space;
  const int k = ((tooth_space % spaces_) + spaces_) % spaces_;
  const auto it = std::upper_bound(grid_u_.begin(), grid_u_.end(), u);
  const int j = std::clamp(static_cast<int>(it - grid_u_.begin()) - 1, 0, m - 1);
  const double lo = grid_u_[static_cast<std::size_t>(j)], hi = grid_u_[static_cast<std::size_t>(j) + 1];
  *t = std::clamp((u - lo) / (hi - lo), 0.0, 1.0);
  *first = k * m + j;
  *second = j + 1 < m ? k * m + j + 1 : ((k + step_) % spaces_) * m;
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
    if (p.edge || p.part != geometry::SurfacePart::kFlank || !(p.length > 0.0) || p.disc != 0) {
      on[k] = 0;
      continue;
    }
    Neighbours(p.tooth_space, p.u, &a[k], &b[k], &t[k]);
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
  const int m = grid_.points_per_space;
  const auto slot = [m](int g) { return Slot{g, g / m, g % m}; };
  for (std::size_t i = 0; i < points.size(); ++i) {
    const PinContact& p = points[i];
    if (p.edge || p.part != geometry::SurfacePart::kFlank || !(p.length > 0.0)) continue;
    on[i] = 1;
    int first = 0, second = 0;
    Neighbours(p.tooth_space, p.u, &first, &second, &t[i]);
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
