#include "ltca/contact/disc_body.hpp"

#include <algorithm>
#include <chrono>
#include <memory>
#include <mutex>
#include <cmath>
#include <stdexcept>
#include <string>

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
  // Space k's end (u = phi_max) meets the start (u = -phi_max) of space k + 1 or of space k - 1.
  const Eigen::Vector2d end = profile.Position(phi, 0);
  const int step =
      (end - profile.Position(-phi, 1)).norm() <= (end - profile.Position(-phi, spaces - 1)).norm() ? 1 : spaces - 1;
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
  // The support: every node of the bore clamped (both components).
  std::vector<char> on_bore(impl->mesh.nodes.size(), 0);
  for (const fe::BoundaryEdge& edge : impl->mesh.edges) {
    if (edge.boundary == fe::Boundary::kBore) {
      for (const int n : edge.nodes) on_bore[n] = 1;
    }
  }
  std::vector<int> clamped;
  for (std::size_t n = 0; n < impl->mesh.nodes.size(); ++n) {
    if (on_bore[n]) {
      clamped.push_back(2 * static_cast<int>(n));
      clamped.push_back(2 * static_cast<int>(n) + 1);
    }
  }
  const fe::Elasticity elasticity{design.plane, design.young_modulus_mpa, design.poisson_ratio, design.thickness_mm};
  impl->model = std::make_unique<fe::ElasticModel>(impl->mesh, elasticity, clamped);
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

}  // namespace ltca::contact
