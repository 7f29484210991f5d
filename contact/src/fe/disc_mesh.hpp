#pragma once
// The disc's T6 mesh from gmsh: nodes, 6-node triangles and the 3-node boundary edges of each
// boundary part (the outline, the bore, each hole). Node order as gmsh's (element types 9 and 8):
// a triangle's vertices 0, 1, 2, then the mid-side nodes of edges 0-1, 1-2, 2-0; an edge's ends
// 0, 1, then its mid-side node 2.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "ltca/contact/disc_body.hpp"

namespace ltca::contact::fe {

/// Which boundary an edge lies on.
enum class Boundary { kOutline, kBore, kHole };

struct BoundaryEdge {
  std::array<int, 3> nodes{};
  Boundary boundary = Boundary::kOutline;
  int hole = -1;  ///< The hole's index for Boundary::kHole.
};

struct T6Mesh {
  std::vector<Eigen::Vector2d> nodes;        ///< mm
  std::vector<std::array<int, 6>> triangles;
  std::vector<BoundaryEdge> edges;
};

/// Meshes the design's outline (or its circle), bore and holes with gmsh (second order, the
/// mid-side nodes on the curved boundaries), sized by element_size_mm and refined near
/// refine_near_mm. Validates the design. Throws std::runtime_error when gmsh cannot be loaded or
/// fails.
T6Mesh MeshDisc(const DiscBodyDesign& design);

/// A cyclically symmetric disc (no holes): one sector meshed, then copied `copies` times by the
/// rotation through `angle_rad` that takes its start cut to its end cut, the copies sharing their
/// common cuts' nodes, so that the mesh is the same after a turn through 2 pi / copies. The sector:
/// `outline_mm` from the start cut's outline point to the end cut's (an open polyline, both ends
/// included; |angle between them| = 2 pi / copies), the bore's arc between the cuts, and the two
/// radial cuts meshed alike (transfinite: graded from the outline's refined size, then even at the
/// element size). Refined near the sector's outline points. Throws std::invalid_argument for an
/// inconsistent sector, std::runtime_error when gmsh fails or the cuts' nodes do not pair.
struct DiscSector {
  std::vector<Eigen::Vector2d> outline_mm;
  /// Interior indices of `outline_mm` where a spline must end (a tip relief's junctions and its
  /// segment's ends: corners or jumps of curvature). Empty: none.
  std::vector<int> corners;
  int copies = 0;
  double angle_rad = 0.0;
  double bore_radius_mm = 0.0;
  double element_size_mm = 3.0;
  double refined_size_mm = 0.2;
  double refine_radius_mm = 6.0;
};
T6Mesh MeshDiscSector(const DiscSector& sector);

}  // namespace ltca::contact::fe
