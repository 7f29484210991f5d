#include "fe/t6_elasticity.hpp"

#include "cholmod_lazy.hpp"  // before Eigen/CholmodSupport: CHOLMOD, loaded on its first call
#include <Eigen/CholmodSupport>
#include <Eigen/LU>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

namespace ltca::contact::fe {
namespace {

// Reference triangle (xi, eta), area coordinates L1 = 1 - xi - eta, L2 = xi, L3 = eta; shape
// functions of the quadratic triangle (Zienkiewicz, Taylor and Zhu 2005, ch. 4, area
// coordinates): corners L(2L - 1), mid-sides 4 Li Lj, gmsh's node order.
struct ShapeDerivatives {
  Eigen::Matrix<double, 2, 6> d;  // row 0: dN/dxi, row 1: dN/deta
};

ShapeDerivatives T6Derivatives(double xi, double eta) {
  const double l1 = 1.0 - xi - eta, l2 = xi, l3 = eta;
  ShapeDerivatives s;
  // d/dxi: dL1 = -1, dL2 = 1, dL3 = 0; d/deta: dL1 = -1, dL2 = 0, dL3 = 1.
  const double dl[2][3] = {{-1.0, 1.0, 0.0}, {-1.0, 0.0, 1.0}};
  for (int r = 0; r < 2; ++r) {
    s.d(r, 0) = (4.0 * l1 - 1.0) * dl[r][0];
    s.d(r, 1) = (4.0 * l2 - 1.0) * dl[r][1];
    s.d(r, 2) = (4.0 * l3 - 1.0) * dl[r][2];
    s.d(r, 3) = 4.0 * (dl[r][0] * l2 + l1 * dl[r][1]);
    s.d(r, 4) = 4.0 * (dl[r][1] * l3 + l2 * dl[r][2]);
    s.d(r, 5) = 4.0 * (dl[r][2] * l1 + l3 * dl[r][0]);
  }
  return s;
}

// The symmetric 6-point rule of degree 4 on the triangle (Strang and Fix 1973; Dunavant, Int. J.
// Numer. Meth. Eng. 21, 1985, table for p = 4), weights summing to the reference area 1/2.
struct TrianglePoint {
  double xi, eta, weight;
};
constexpr double kA = 0.445948490915965, kWA = 0.223381589678011 / 2.0;
constexpr double kB = 0.091576213509771, kWB = 0.109951743655322 / 2.0;
constexpr TrianglePoint kTriangleRule[6] = {
    {kA, kA, kWA}, {1.0 - 2.0 * kA, kA, kWA}, {kA, 1.0 - 2.0 * kA, kWA},
    {kB, kB, kWB}, {1.0 - 2.0 * kB, kB, kWB}, {kB, 1.0 - 2.0 * kB, kWB}};

// 5-point Gauss-Legendre on [-1, 1].
constexpr double kGaussX[5] = {-0.906179845938664, -0.538469310105683, 0.0, 0.538469310105683,
                               0.906179845938664};
constexpr double kGaussW[5] = {0.236926885056189, 0.478628670499366, 0.568888888888889,
                               0.478628670499366, 0.236926885056189};

// The 3-node edge, s in [-1, 1]: nodes 0 at s = -1, 1 at s = +1, 2 (mid) at s = 0.
Eigen::Vector3d EdgeShape(double s) { return {0.5 * s * (s - 1.0), 0.5 * s * (s + 1.0), 1.0 - s * s}; }
Eigen::Vector3d EdgeShapeDerivative(double s) { return {s - 0.5, s + 0.5, -2.0 * s}; }

Eigen::Vector2d EdgePoint(const T6Mesh& mesh, const BoundaryEdge& edge, double s) {
  const Eigen::Vector3d n = EdgeShape(s);
  return n[0] * mesh.nodes[edge.nodes[0]] + n[1] * mesh.nodes[edge.nodes[1]] + n[2] * mesh.nodes[edge.nodes[2]];
}
double EdgeJacobian(const T6Mesh& mesh, const BoundaryEdge& edge, double s) {
  const Eigen::Vector3d n = EdgeShapeDerivative(s);
  return (n[0] * mesh.nodes[edge.nodes[0]] + n[1] * mesh.nodes[edge.nodes[1]] + n[2] * mesh.nodes[edge.nodes[2]])
      .norm();
}

// Adds int_{a}^{b} N^T g(x) |x'| ds over one edge by 5-point Gauss; returns the length.
double IntegrateEdge(const T6Mesh& mesh, const BoundaryEdge& edge, double a, double b,
                     const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& g, Eigen::VectorXd& f) {
  double length = 0.0;
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  for (int q = 0; q < 5; ++q) {
    const double s = mid + half * kGaussX[q];
    const double w = kGaussW[q] * half * EdgeJacobian(mesh, edge, s);
    length += w;
    const Eigen::Vector2d t = g(EdgePoint(mesh, edge, s));
    const Eigen::Vector3d n = EdgeShape(s);
    for (int k = 0; k < 3; ++k) {
      f[2 * edge.nodes[k]] += w * n[k] * t.x();
      f[2 * edge.nodes[k] + 1] += w * n[k] * t.y();
    }
  }
  return length;
}

}  // namespace

Eigen::Matrix3d Elasticity::D() const {
  const double e = young_modulus_mpa, nu = poisson_ratio;
  Eigen::Matrix3d d = Eigen::Matrix3d::Zero();
  if (plane == PlaneModel::kStress) {
    const double c = e / (1.0 - nu * nu);
    d << c, c * nu, 0.0, c * nu, c, 0.0, 0.0, 0.0, c * (1.0 - nu) / 2.0;
  } else {
    const double c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
    d << c * (1.0 - nu), c * nu, 0.0, c * nu, c * (1.0 - nu), 0.0, 0.0, 0.0, c * (1.0 - 2.0 * nu) / 2.0;
  }
  return d;
}

T6Matrix T6Stiffness(const T6Coordinates& x, const Eigen::Matrix3d& d, double thickness_mm) {
  Eigen::Matrix<double, 6, 2> xy;
  for (int k = 0; k < 6; ++k) xy.row(k) = x[k].transpose();
  T6Matrix k = T6Matrix::Zero();
  for (const TrianglePoint& p : kTriangleRule) {
    const ShapeDerivatives s = T6Derivatives(p.xi, p.eta);
    const Eigen::Matrix2d j = s.d * xy;  // J(r, c) = d x_c / d xi_r
    const double det = j.determinant();
    if (!(det > 0.0)) throw std::runtime_error("T6 element with a non-positive Jacobian (inverted or degenerate)");
    const Eigen::Matrix<double, 2, 6> dn = j.inverse() * s.d;  // dN/dx, dN/dy
    Eigen::Matrix<double, 3, 12> b = Eigen::Matrix<double, 3, 12>::Zero();
    for (int n = 0; n < 6; ++n) {
      b(0, 2 * n) = dn(0, n);
      b(1, 2 * n + 1) = dn(1, n);
      b(2, 2 * n) = dn(1, n);
      b(2, 2 * n + 1) = dn(0, n);
    }
    k.noalias() += (p.weight * det * thickness_mm) * (b.transpose() * d * b);
  }
  return k;
}

Eigen::VectorXd EdgeLoad(const T6Mesh& mesh, double thickness_mm,
                         const std::function<bool(const BoundaryEdge&)>& take,
                         const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& traction) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(2 * static_cast<Eigen::Index>(mesh.nodes.size()));
  const auto force = [&](const Eigen::Vector2d& x) -> Eigen::Vector2d { return thickness_mm * traction(x); };
  for (const BoundaryEdge& edge : mesh.edges) {
    if (take(edge)) IntegrateEdge(mesh, edge, -1.0, 1.0, force, f);
  }
  return f;
}

Eigen::VectorXd PatchLoad(const T6Mesh& mesh, const std::function<bool(const BoundaryEdge&)>& take,
                          const Eigen::Vector2d& point, const Eigen::Vector2d& direction, double half_width_mm) {
  if (!(half_width_mm > 0.0) || !std::isfinite(half_width_mm)) {
    throw std::invalid_argument("a load patch's half_width_mm must be finite and positive");
  }
  if (!(direction.norm() > 0.0) || !direction.allFinite()) {
    throw std::invalid_argument("a load point's direction must be a finite non-zero vector");
  }
  // The nearest boundary point: 16 samples per edge, then a golden-section search about the best.
  // Only the edges that can hold it are sampled: a point of an edge is no nearer than its nearest
  // node less the edge's span, and no farther than the nearest node of all.
  const BoundaryEdge* nearest = nullptr;
  double best_s = 0.0, best = std::numeric_limits<double>::infinity();
  constexpr int kSamples = 16;
  const auto node_distance = [&](const BoundaryEdge& edge) {
    double d = std::numeric_limits<double>::infinity();
    for (const int n : edge.nodes) d = std::min(d, (mesh.nodes[n] - point).norm());
    return d;
  };
  const auto span = [&](const BoundaryEdge& edge) {
    return std::max({(mesh.nodes[edge.nodes[0]] - mesh.nodes[edge.nodes[1]]).norm(),
                     (mesh.nodes[edge.nodes[0]] - mesh.nodes[edge.nodes[2]]).norm(),
                     (mesh.nodes[edge.nodes[1]] - mesh.nodes[edge.nodes[2]]).norm()});
  };
  double nearest_node = std::numeric_limits<double>::infinity();
  for (const BoundaryEdge& edge : mesh.edges) {
    if (take(edge)) nearest_node = std::min(nearest_node, node_distance(edge));
  }
  for (const BoundaryEdge& edge : mesh.edges) {
    if (!take(edge)) continue;
    if (node_distance(edge) - span(edge) > nearest_node) continue;
    for (int i = 0; i <= kSamples; ++i) {
      const double s = -1.0 + 2.0 * i / kSamples;
      const double dist = (EdgePoint(mesh, edge, s) - point).norm();
      if (dist < best) best = dist, best_s = s, nearest = &edge;
    }
  }
  if (nearest == nullptr) throw std::invalid_argument("no boundary edge to load");
  {
    double lo = std::max(-1.0, best_s - 2.0 / kSamples), hi = std::min(1.0, best_s + 2.0 / kSamples);
    const double golden = (std::sqrt(5.0) - 1.0) / 2.0;
    for (int it = 0; it < 40; ++it) {
      const double a = hi - golden * (hi - lo), b = lo + golden * (hi - lo);
      if ((EdgePoint(mesh, *nearest, a) - point).norm() < (EdgePoint(mesh, *nearest, b) - point).norm()) {
        hi = b;
      } else {
        lo = a;
      }
    }
    best_s = 0.5 * (lo + hi);
  }
  const Eigen::Vector2d centre = EdgePoint(mesh, *nearest, best_s);
  const Eigen::Vector2d unit = direction.normalized();
  // The patch: the boundary of the nearest edge's part within half_width of the centre, each edge
  // cut at the crossings of |x(s) - centre| = half_width (32 sub-intervals, then bisection).
  Eigen::VectorXd f = Eigen::VectorXd::Zero(2 * static_cast<Eigen::Index>(mesh.nodes.size()));
  const auto one = [](const Eigen::Vector2d&) -> Eigen::Vector2d { return Eigen::Vector2d(1.0, 0.0); };
  double length = 0.0;
  for (const BoundaryEdge& edge : mesh.edges) {
    if (!take(edge) || edge.boundary != nearest->boundary || edge.hole != nearest->hole) continue;
    const auto inside = [&](double s) { return (EdgePoint(mesh, edge, s) - centre).norm() - half_width_mm; };
    if ((mesh.nodes[edge.nodes[0]] - centre).norm() > half_width_mm + (mesh.nodes[edge.nodes[0]] - mesh.nodes[edge.nodes[1]]).norm() * 2.0) {
      continue;  // far from the patch
    }
    constexpr int kCuts = 32;
    for (int i = 0; i < kCuts; ++i) {
      double a = -1.0 + 2.0 * i / kCuts, b = -1.0 + 2.0 * (i + 1) / kCuts;
      const double ga = inside(a), gb = inside(b);
      if (ga > 0.0 && gb > 0.0) continue;
      if ((ga > 0.0) != (gb > 0.0)) {
        double lo = a, hi = b;  // inside(lo) and inside(hi) of opposite signs
        for (int it = 0; it < 60; ++it) {
          const double m = 0.5 * (lo + hi);
          ((inside(m) > 0.0) == (inside(lo) > 0.0) ? lo : hi) = m;
        }
        (ga > 0.0 ? a : b) = 0.5 * (lo + hi);
      }
      length += IntegrateEdge(mesh, edge, a, b, one, f);
    }
  }
  if (!(length > 0.0)) throw std::invalid_argument("a load patch of zero length");
  // f holds int N ds in its x entries; spread the unit force along the direction.
  for (Eigen::Index n = 0; n < f.size() / 2; ++n) {
    const double weight = f[2 * n] / length;
    f[2 * n] = weight * unit.x();
    f[2 * n + 1] = weight * unit.y();
  }
  return f;
}

namespace {

/// Eigen's supernodal LL^T with CHOLMOD's factor readable (the supernodes' blocks, for
/// ElasticModel::Condense's forward solves). Eigen keeps the factor supernodal and LL^T
/// (final_asis, CHOLMOD_SUPERNODAL).
class SupernodalLLT : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  const cholmod_factor* factor() const { return m_cholmodFactor; }
};

}  // namespace

struct ElasticModel::Impl {
  int dofs = 0;
  std::vector<int> free_index;  // dof -> free row, -1 when prescribed
  std::vector<int> free_dofs, prescribed_dofs;
  Eigen::SparseMatrix<double> k_fp;  // free x prescribed
  SupernodalLLT cholesky;
};

ElasticModel::ElasticModel(const T6Mesh& mesh, const Elasticity& elasticity,
                           const std::vector<int>& prescribed_dofs)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.dofs = 2 * static_cast<int>(mesh.nodes.size());
  m.free_index.assign(m.dofs, 0);
  for (const int dof : prescribed_dofs) {
    if (dof < 0 || dof >= m.dofs) throw std::invalid_argument("a prescribed dof outside the mesh");
    m.free_index[dof] = -1;
  }
  for (int dof = 0; dof < m.dofs; ++dof) {
    if (m.free_index[dof] < 0) {
      m.prescribed_dofs.push_back(dof);
    } else {
      m.free_index[dof] = static_cast<int>(m.free_dofs.size());
      m.free_dofs.push_back(dof);
    }
  }
  std::vector<int> prescribed_index(m.dofs, -1);
  for (std::size_t i = 0; i < m.prescribed_dofs.size(); ++i) prescribed_index[m.prescribed_dofs[i]] = static_cast<int>(i);
  const Eigen::Matrix3d d = elasticity.D();
  std::vector<Eigen::Triplet<double>> ff, fp;
  ff.reserve(mesh.triangles.size() * 78);
  for (const auto& t : mesh.triangles) {
    T6Coordinates x;
    for (int k = 0; k < 6; ++k) x[k] = mesh.nodes[t[k]];
    const T6Matrix ke = T6Stiffness(x, d, elasticity.thickness_mm);
    for (int a = 0; a < 12; ++a) {
      const int row = m.free_index[2 * t[a / 2] + a % 2];
      if (row < 0) continue;
      for (int b = 0; b < 12; ++b) {
        const int dof = 2 * t[b / 2] + b % 2;
        const int col = m.free_index[dof];
        if (col < 0) {
          fp.emplace_back(row, prescribed_index[dof], ke(a, b));
        } else if (col <= row) {
          ff.emplace_back(row, col, ke(a, b));  // the lower triangle, CHOLMOD's
        }
      }
    }
  }
  const int nf = static_cast<int>(m.free_dofs.size());
  Eigen::SparseMatrix<double> k_ff(nf, nf);
  k_ff.setFromTriplets(ff.begin(), ff.end());
  m.k_fp.resize(nf, static_cast<int>(m.prescribed_dofs.size()));
  m.k_fp.setFromTriplets(fp.begin(), fp.end());
  m.cholesky.compute(k_ff);
  if (m.cholesky.info() != Eigen::Success) {
    throw std::runtime_error("the disc's stiffness is not positive definite: a rigid-body mode is not held");
  }
}

ElasticModel::~ElasticModel() = default;

int ElasticModel::dofs() const { return impl_->dofs; }
int ElasticModel::free_dofs() const { return static_cast<int>(impl_->free_dofs.size()); }

Eigen::MatrixXd ElasticModel::Solve(const Eigen::MatrixXd& loads, const Eigen::MatrixXd& prescribed) const {
  const Impl& m = *impl_;
  if (loads.rows() != m.dofs) throw std::invalid_argument("loads: one row per dof");
  if (prescribed.size() != 0 && (prescribed.rows() != m.dofs || prescribed.cols() != loads.cols())) {
    throw std::invalid_argument("prescribed: one row per dof, one column per load case");
  }
  const Eigen::Index cases = loads.cols();
  const Eigen::Index nf = static_cast<Eigen::Index>(m.free_dofs.size());
  const Eigen::Index np = static_cast<Eigen::Index>(m.prescribed_dofs.size());
  Eigen::MatrixXd rhs(nf, cases), up = Eigen::MatrixXd::Zero(np, cases);
  for (Eigen::Index i = 0; i < nf; ++i) rhs.row(i) = loads.row(m.free_dofs[i]);
  if (prescribed.size() != 0) {
    for (Eigen::Index i = 0; i < np; ++i) up.row(i) = prescribed.row(m.prescribed_dofs[i]);
    rhs -= m.k_fp * up;
  }
  const Eigen::MatrixXd uf = m.cholesky.solve(rhs);
  Eigen::MatrixXd u(m.dofs, cases);
  for (Eigen::Index i = 0; i < nf; ++i) u.row(m.free_dofs[i]) = uf.row(i);
  for (Eigen::Index i = 0; i < np; ++i) u.row(m.prescribed_dofs[i]) = up.row(i);
  return u;
}

Eigen::MatrixXd ElasticModel::Condense(const Eigen::SparseMatrix<double>& loads) const {
  const Impl& m = *impl_;
  if (loads.rows() != m.dofs) throw std::invalid_argument("loads: one row per dof");
  const cholmod_factor* factor = m.cholesky.factor();
  if (factor == nullptr || !factor->is_super || !factor->is_ll || factor->itype != CHOLMOD_INT ||
      factor->xtype != CHOLMOD_REAL || factor->dtype != CHOLMOD_DOUBLE) {
    throw std::logic_error("ElasticModel::Condense: the factor is not CHOLMOD's supernodal LL' of doubles");
  }
  const auto n = static_cast<int>(factor->n);
  const auto nsuper = static_cast<int>(factor->nsuper);
  const int* super = static_cast<const int*>(factor->super);  // first column of each supernode
  const int* pi = static_cast<const int*>(factor->pi);        // its row indices' start in s
  const int* px = static_cast<const int*>(factor->px);        // its values' start in x
  const int* rows = static_cast<const int*>(factor->s);
  const int* perm = static_cast<const int*>(factor->Perm);    // row k of P K P^T is free row perm[k]
  const double* values = static_cast<const double*>(factor->x);
  const auto cols = static_cast<int>(loads.cols());
  // Supernode of each column and the supernodal elimination tree: the parent of supernode s is the
  // supernode of its first row below the diagonal block (every row below it is an ancestor's).
  std::vector<int> column_super(static_cast<std::size_t>(n));
  std::vector<int> parent(static_cast<std::size_t>(nsuper), -1);
  for (int s = 0; s < nsuper; ++s) {
    for (int k = super[s]; k < super[s + 1]; ++k) column_super[static_cast<std::size_t>(k)] = s;
  }
  for (int s = 0; s < nsuper; ++s) {
    const int width = super[s + 1] - super[s];
    if (pi[s + 1] - pi[s] > width) parent[static_cast<std::size_t>(s)] = column_super[static_cast<std::size_t>(rows[pi[s] + width])];
  }
  std::vector<int> permuted(static_cast<std::size_t>(n));  // free row -> row of P K P^T
  for (int k = 0; k < n; ++k) permuted[static_cast<std::size_t>(perm != nullptr ? perm[k] : k)] = k;
  // The load columns over the factor's rows (prescribed dofs dropped, as Solve ignores them).
  Eigen::SparseMatrix<double> f = loads;  // compressed, column-major
  f.makeCompressed();
  // members[s]: the load columns whose forward solve reaches supernode s (ascending): the union of
  // the paths from their nonzeros' supernodes to the root.
  std::vector<std::vector<int>> members(static_cast<std::size_t>(nsuper));
  std::vector<int> mark(static_cast<std::size_t>(nsuper), -1);
  for (int g = 0; g < cols; ++g) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(f, g); it; ++it) {
      const int free = m.free_index[static_cast<std::size_t>(it.row())];
      if (free < 0 || it.value() == 0.0) continue;
      for (int s = column_super[static_cast<std::size_t>(permuted[static_cast<std::size_t>(free)])];
           s >= 0 && mark[static_cast<std::size_t>(s)] != g; s = parent[static_cast<std::size_t>(s)]) {
        mark[static_cast<std::size_t>(s)] = g;
        members[static_cast<std::size_t>(s)].push_back(g);
      }
    }
  }
  // Y's rows of each supernode over its members, P F scattered in.
  std::vector<Eigen::MatrixXd> y(static_cast<std::size_t>(nsuper));
  for (int s = 0; s < nsuper; ++s) {
    const auto& j = members[static_cast<std::size_t>(s)];
    if (!j.empty()) y[static_cast<std::size_t>(s)].setZero(super[s + 1] - super[s], static_cast<Eigen::Index>(j.size()));
  }
  for (int g = 0; g < cols; ++g) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(f, g); it; ++it) {
      const int free = m.free_index[static_cast<std::size_t>(it.row())];
      if (free < 0 || it.value() == 0.0) continue;
      const int k = permuted[static_cast<std::size_t>(free)];
      const int s = column_super[static_cast<std::size_t>(k)];
      const auto& j = members[static_cast<std::size_t>(s)];
      const auto at = std::lower_bound(j.begin(), j.end(), g) - j.begin();
      y[static_cast<std::size_t>(s)](k - super[s], at) += it.value();
    }
  }
  // The forward solve, supernode by supernode in the factor's order (a descendant before its
  // ancestors): Y_s = L_ss^-1 Y_s, then the rows below take -L_bs Y_s (CHOLMOD's supernodal
  // forward solve, cholmod_super_lsolve, over the reached supernodes and their members only).
  std::vector<Eigen::Index> position;
  for (int s = 0; s < nsuper; ++s) {
    const auto& j = members[static_cast<std::size_t>(s)];
    if (j.empty()) continue;
    Eigen::MatrixXd& ys = y[static_cast<std::size_t>(s)];
    const int width = super[s + 1] - super[s];
    const int height = pi[s + 1] - pi[s];
    const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> block(values + px[s], height, width,
                                                                          Eigen::OuterStride<>(height));
    block.topRows(width).triangularView<Eigen::Lower>().solveInPlace(ys);
    if (height == width) continue;
    const Eigen::MatrixXd below = block.bottomRows(height - width) * ys;
    const int* below_rows = rows + pi[s] + width;
    for (int r = 0; r < height - width;) {
      const int t = column_super[static_cast<std::size_t>(below_rows[r])];
      int end = r + 1;
      while (end < height - width && column_super[static_cast<std::size_t>(below_rows[end])] == t) ++end;
      // s's members among t's (a subset: t is an ancestor of s).
      const auto& jt = members[static_cast<std::size_t>(t)];
      position.resize(j.size());
      std::size_t q = 0;
      for (std::size_t c = 0; c < j.size(); ++c) {
        while (q < jt.size() && jt[q] < j[c]) ++q;
        if (q == jt.size() || jt[q] != j[c]) throw std::logic_error("ElasticModel::Condense: a row below a supernode is not an ancestor's");
        position[c] = static_cast<Eigen::Index>(q);
      }
      Eigen::MatrixXd& yt = y[static_cast<std::size_t>(t)];
      for (std::size_t c = 0; c < j.size(); ++c) {
        for (int i = r; i < end; ++i) yt(below_rows[i] - super[t], position[c]) -= below(i, static_cast<Eigen::Index>(c));
      }
      r = end;
    }
  }
  // C = Y^T Y: the supernodes of one member set stacked, one symmetric rank update each (lower
  // triangle), scattered into C's rows and columns of those members; then C's upper triangle is
  // its lower's (exactly symmetric).
  std::map<std::vector<int>, std::vector<int>> groups;
  for (int s = 0; s < nsuper; ++s) {
    if (!members[static_cast<std::size_t>(s)].empty()) groups[members[static_cast<std::size_t>(s)]].push_back(s);
  }
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(cols, cols);
  for (const auto& [j, supernodes] : groups) {
    Eigen::Index height = 0;
    for (const int s : supernodes) height += y[static_cast<std::size_t>(s)].rows();
    Eigen::MatrixXd stacked(height, static_cast<Eigen::Index>(j.size()));
    height = 0;
    for (const int s : supernodes) {
      Eigen::MatrixXd& ys = y[static_cast<std::size_t>(s)];
      stacked.middleRows(height, ys.rows()) = ys;
      height += ys.rows();
      ys.resize(0, 0);
    }
    if (static_cast<int>(j.size()) == cols) {
      c.selfadjointView<Eigen::Lower>().rankUpdate(stacked.transpose());
      continue;
    }
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(j.size()), static_cast<Eigen::Index>(j.size()));
    gram.selfadjointView<Eigen::Lower>().rankUpdate(stacked.transpose());
    for (std::size_t b = 0; b < j.size(); ++b) {
      for (std::size_t a = b; a < j.size(); ++a) c(j[a], j[b]) += gram(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
    }
  }
  for (Eigen::Index b = 1; b < cols; ++b) {
    for (Eigen::Index a = 0; a < b; ++a) c(a, b) = c(b, a);
  }
  return c;
}

}  // namespace ltca::contact::fe
