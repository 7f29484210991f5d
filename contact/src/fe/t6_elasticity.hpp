#pragma once
// Plane linear elasticity over 6-node quadratic triangles (isoparametric T6): the constitutive
// matrix of plane strain or plane stress, the element stiffness by Gauss quadrature, consistent
// edge loads, and the global model (assembled once, factorised once by CHOLMOD, solved for any
// number of load cases). Zienkiewicz, Taylor and Zhu, The Finite Element Method: Its Basis and
// Fundamentals, 6th ed., 2005: ch. 6 (plane stress and plane strain: D, B, K = int B^T D B t dA),
// ch. 4 (the quadratic triangle's shape functions in area coordinates) and ch. 5 (isoparametric
// mapping, numerical integration on triangles). Units: mm, N, MPa.
#include <array>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "fe/disc_mesh.hpp"
#include "ltca/contact/disc_body.hpp"

namespace ltca::contact::fe {

struct Elasticity {
  PlaneModel plane = PlaneModel::kStrain;
  double young_modulus_mpa = 206000.0;
  double poisson_ratio = 0.3;
  double thickness_mm = 1.0;

  /// sigma = D epsilon, (xx, yy, xy) with engineering shear strain, MPa.
  Eigen::Matrix3d D() const;
};

using T6Coordinates = std::array<Eigen::Vector2d, 6>;
using T6Matrix = Eigen::Matrix<double, 12, 12>;

/// The element stiffness, dofs (u0, v0, u1, v1, ..., u5, v5), N/mm: K = int B^T D B t |J| over
/// the reference triangle by the 6-point rule exact to degree 4 (Strang and Fix; Dunavant 1985),
/// exact for a straight-sided element (degree 2) and accurate for the curved ones at a boundary.
/// Throws std::runtime_error for a non-positive Jacobian.
T6Matrix T6Stiffness(const T6Coordinates& x, const Eigen::Matrix3d& d, double thickness_mm);

/// Consistent nodal forces of a traction t(x) (force per area, N/mm^2) over the boundary edges
/// accepted by `take`: f = int N^T t B ds on each 3-node edge (5-point Gauss-Legendre). Length 2 *
/// nodes.
Eigen::VectorXd EdgeLoad(const T6Mesh& mesh, double thickness_mm,
                         const std::function<bool(const BoundaryEdge&)>& take,
                         const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& traction);

/// A unit force along `direction` spread uniformly over the boundary within `half_width_mm` of
/// the boundary point nearest to `point` (the edges accepted by `take`, and of the same boundary
/// part as the nearest): f = int N^T d / L ds over the patch, L its length, so sum f = d exactly.
/// Throws std::invalid_argument when no edge is accepted.
Eigen::VectorXd PatchLoad(const T6Mesh& mesh, const std::function<bool(const BoundaryEdge&)>& take,
                          const Eigen::Vector2d& point, const Eigen::Vector2d& direction,
                          double half_width_mm);

/// The assembled model with some dofs prescribed (dof 2 n + 0 is node n's x, 2 n + 1 its y).
class ElasticModel {
 public:
  /// Assembles K and factorises its free block once (CHOLMOD, supernodal Cholesky). Throws
  /// std::runtime_error when the free block is not positive definite (a mechanism).
  ElasticModel(const T6Mesh& mesh, const Elasticity& elasticity, const std::vector<int>& prescribed_dofs);
  ~ElasticModel();
  ElasticModel(const ElasticModel&) = delete;
  ElasticModel& operator=(const ElasticModel&) = delete;

  int dofs() const;
  int free_dofs() const;

  /// Displacements (every dof, one column per case) under the nodal forces `loads` (dofs x m) with
  /// the prescribed dofs at `prescribed` (dofs x m; only their rows are read; empty: zero). The
  /// forces at prescribed dofs are ignored (they are reactions).
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& loads, const Eigen::MatrixXd& prescribed = {}) const;

  /// The condensed compliance F^T K_ff^-1 F of sparse load columns (dofs x n, the prescribed dofs
  /// held at zero and their rows ignored, as Solve does), symmetric positive semidefinite and
  /// exactly symmetric. With the factorisation P K_ff P^T = L L^T it is Y^T Y, Y = L^-1 P F: only
  /// forward solves, each over the supernodes its column reaches (the path from its nonzeros to the
  /// root of the supernodal elimination tree; Y is zero elsewhere), and the Gram products of those
  /// sparse columns (T. A. Davis, Direct Methods for Sparse Linear Systems, SIAM, 2006, sec. 3.2:
  /// the nonzeros of L^-1 b are the reach of b's in L's graph; sec. 4.1: for a Cholesky factor,
  /// the paths from them up the elimination tree). Where
  /// F^T Solve(F) costs a forward and a backward solve over the whole factor for every column and
  /// a dofs x n product, this costs the reached supernodes' dense blocks (Eigen's products). The
  /// same numbers as F^T Solve(F) to round-off (test "contact: the T6 model's sparse
  /// condensation ...").
  Eigen::MatrixXd Condense(const Eigen::SparseMatrix<double>& loads) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ltca::contact::fe
