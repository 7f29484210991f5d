#include "fe/disc_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "fe/gmsh_library.hpp"

namespace ltca::contact::fe {
namespace {

// gmsh element types (gmsh reference manual, "MSH file format"): 8 the 3-node line, 9 the 6-node
// triangle.
constexpr int kLine3 = 8;
constexpr int kTriangle6 = 9;

// Owns an array gmsh allocated (gmshFree).
template <typename T>
struct GmshArray {
  GmshLibrary& gmsh;
  T* data = nullptr;
  std::size_t size = 0;
  ~GmshArray() {
    if (data != nullptr) gmsh.free(data);
  }
};

// A circle of 4 arcs (gmsh's arcs must be strictly smaller than pi), points on the axes first:
// returns the curve tags, counterclockwise.
std::vector<int> AddCircle(GmshLibrary& gmsh, const Eigen::Vector2d& centre, double radius, double size) {
  int ierr = 0;
  const int c = gmsh.geo_add_point(centre.x(), centre.y(), 0.0, size, -1, &ierr);
  gmsh.Check(ierr, "addPoint");
  std::array<int, 4> p{};
  for (int k = 0; k < 4; ++k) {
    const double angle = k * std::numbers::pi / 2.0;
    p[k] = gmsh.geo_add_point(centre.x() + radius * std::cos(angle), centre.y() + radius * std::sin(angle),
                              0.0, size, -1, &ierr);
    gmsh.Check(ierr, "addPoint");
  }
  std::vector<int> curves;
  for (int k = 0; k < 4; ++k) {
    curves.push_back(gmsh.geo_add_circle_arc(p[k], c, p[(k + 1) % 4], -1, 0.0, 0.0, 0.0, &ierr));
    gmsh.Check(ierr, "addCircleArc");
  }
  return curves;
}

// The outline polygon: straight lines for a short polygon, else splines through runs of its
// points (a profile sampled every few micrometres would otherwise force an element per sample).
std::vector<int> AddOutline(GmshLibrary& gmsh, const std::vector<Eigen::Vector2d>& outline, double size) {
  int ierr = 0;
  const int n = static_cast<int>(outline.size());
  std::vector<int> points(n);
  for (int i = 0; i < n; ++i) {
    points[i] = gmsh.geo_add_point(outline[i].x(), outline[i].y(), 0.0, size, -1, &ierr);
    gmsh.Check(ierr, "addPoint");
  }
  std::vector<int> curves;
  constexpr int kLinesUpTo = 200;  // points of a polygon meshed as straight lines
  if (n <= kLinesUpTo) {
    for (int i = 0; i < n; ++i) {
      curves.push_back(gmsh.geo_add_line(points[i], points[(i + 1) % n], -1, &ierr));
      gmsh.Check(ierr, "addLine");
    }
    return curves;
  }
  // Runs of about n/64 points (at least 8), each a spline through its points, sharing ends.
  const int runs = std::max(4, std::min(64, n / 8));
  for (int r = 0; r < runs; ++r) {
    const int first = static_cast<int>(static_cast<long long>(r) * n / runs);
    const int last = static_cast<int>(static_cast<long long>(r + 1) * n / runs);  // n: back to 0
    std::vector<int> run;
    for (int i = first; i <= last; ++i) run.push_back(points[i % n]);
    curves.push_back(gmsh.geo_add_spline(run.data(), run.size(), -1, &ierr));
    gmsh.Check(ierr, "addSpline");
  }
  return curves;
}

int AddLoop(GmshLibrary& gmsh, std::vector<int> curves) {
  int ierr = 0;
  const int loop = gmsh.geo_add_curve_loop(curves.data(), curves.size(), -1, 1, &ierr);
  gmsh.Check(ierr, "addCurveLoop");
  return loop;
}

}  // namespace

T6Mesh MeshDisc(const DiscBodyDesign& design) {
  design.Validate();
  GmshLibrary& gmsh = GmshLibrary::Get();
  const auto lock = gmsh.Lock();
  int ierr = 0;
  gmsh.clear(&ierr);
  gmsh.Check(ierr, "clear");
  gmsh.model_add("ltca_disc", &ierr);
  gmsh.Check(ierr, "model add");
  // Sizes from the background field only (the geometry's points, curvature and boundary do not
  // add their own), capped at the target element size.
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"Mesh.MeshSizeFromPoints", 0.0}, {"Mesh.MeshSizeFromCurvature", 0.0},
        {"Mesh.MeshSizeExtendFromBoundary", 0.0}, {"Mesh.MeshSizeMax", design.element_size_mm},
        {"Mesh.MeshSizeMin", 0.0}, {"Mesh.Algorithm", 6.0} /* Frontal-Delaunay */,
        {"Mesh.SecondOrderLinear", 0.0} /* mid-side nodes on the curves */,
        {"Mesh.HighOrderOptimize", 0.0}, {"General.NumThreads", 1.0}, {"Mesh.RandomSeed", 1.0}}) {
    gmsh.option_set_number(name, value, &ierr);
    gmsh.Check(ierr, name);
  }

  const double size = design.element_size_mm;
  std::vector<int> outer = design.outline_mm.empty()
                               ? AddCircle(gmsh, Eigen::Vector2d::Zero(), design.outer_radius_mm, size)
                               : AddOutline(gmsh, design.outline_mm, size);
  std::vector<int> loops{AddLoop(gmsh, outer)};
  std::vector<int> bore;
  if (design.bore_radius_mm > 0.0) {
    bore = AddCircle(gmsh, Eigen::Vector2d::Zero(), design.bore_radius_mm, size);
    loops.push_back(AddLoop(gmsh, bore));
  }
  std::vector<std::vector<int>> holes;
  for (const DiscHole& hole : design.holes) {
    holes.push_back(AddCircle(gmsh, hole.centre_mm, hole.radius_mm, size));
    loops.push_back(AddLoop(gmsh, holes.back()));
  }
  const int surface = gmsh.geo_add_plane_surface(loops.data(), loops.size(), -1, &ierr);
  gmsh.Check(ierr, "addPlaneSurface");

  // Refinement: size = refined at distance 0 from the nearest refinement point, growing linearly
  // to element_size at refine_radius (gmsh's Distance and Threshold fields).
  std::vector<double> refine_tags;
  for (const Eigen::Vector2d& p : design.refine_near_mm) {
    refine_tags.push_back(gmsh.geo_add_point(p.x(), p.y(), 0.0, size, -1, &ierr));
    gmsh.Check(ierr, "addPoint");
  }
  gmsh.geo_synchronize(&ierr);
  gmsh.Check(ierr, "synchronize");
  if (!refine_tags.empty() && design.refined_size_mm < design.element_size_mm) {
    const int distance = gmsh.field_add("Distance", -1, &ierr);
    gmsh.Check(ierr, "field Distance");
    // gmsh 4.8 names the Distance field's points NodesList (PointsList from 4.9 on).
    gmsh.field_set_numbers(distance, "NodesList", refine_tags.data(), refine_tags.size(), &ierr);
    if (ierr != 0) gmsh.field_set_numbers(distance, "PointsList", refine_tags.data(), refine_tags.size(), &ierr);
    gmsh.Check(ierr, "Distance points");
    const int threshold = gmsh.field_add("Threshold", -1, &ierr);
    gmsh.Check(ierr, "field Threshold");
    for (const auto& [name, value] :
         {std::pair<const char*, double>{"InField", static_cast<double>(distance)},
          {"SizeMin", design.refined_size_mm}, {"SizeMax", design.element_size_mm}, {"DistMin", 0.0},
          {"DistMax", design.refine_radius_mm}}) {
      gmsh.field_set_number(threshold, name, value, &ierr);
      gmsh.Check(ierr, name);
    }
    gmsh.field_set_as_background_mesh(threshold, &ierr);
    gmsh.Check(ierr, "background field");
  }
  gmsh.mesh_generate(2, &ierr);
  gmsh.Check(ierr, "mesh generate");
  gmsh.mesh_set_order(2, &ierr);
  gmsh.Check(ierr, "mesh set order 2");

  // Every node (gmsh's tags), then the surface's T6 and each curve's 3-node lines; the nodes the
  // triangles use, renumbered from 0 (the refinement points' lone nodes dropped).
  T6Mesh mesh;
  GmshArray<std::size_t> tags{gmsh};
  GmshArray<double> coords{gmsh};
  GmshArray<double> parametric{gmsh};
  gmsh.mesh_get_nodes(&tags.data, &tags.size, &coords.data, &coords.size, &parametric.data,
                      &parametric.size, -1, -1, 0, 0, &ierr);
  gmsh.Check(ierr, "getNodes");
  std::size_t max_tag = 0;
  for (std::size_t i = 0; i < tags.size; ++i) max_tag = std::max(max_tag, tags.data[i]);
  std::vector<long> position(max_tag + 1, -1);
  for (std::size_t i = 0; i < tags.size; ++i) position[tags.data[i]] = static_cast<long>(i);
  std::vector<int> index(max_tag + 1, -1);
  const auto node = [&](std::size_t tag) {
    if (tag > max_tag || position[tag] < 0) throw std::runtime_error("gmsh: an element names an unknown node");
    if (index[tag] < 0) {
      index[tag] = static_cast<int>(mesh.nodes.size());
      const std::size_t at = 3 * static_cast<std::size_t>(position[tag]);
      mesh.nodes.emplace_back(coords.data[at], coords.data[at + 1]);
    }
    return index[tag];
  };
  {
    GmshArray<std::size_t> elements{gmsh};
    GmshArray<std::size_t> element_nodes{gmsh};
    gmsh.mesh_get_elements_by_type(kTriangle6, &elements.data, &elements.size, &element_nodes.data,
                                   &element_nodes.size, surface, 0, 1, &ierr);
    gmsh.Check(ierr, "getElementsByType (T6)");
    if (elements.size == 0 || element_nodes.size != 6 * elements.size) {
      throw std::runtime_error("gmsh: the disc's mesh has no 6-node triangles");
    }
    for (std::size_t e = 0; e < elements.size; ++e) {
      std::array<int, 6> t{};
      for (int k = 0; k < 6; ++k) t[k] = node(element_nodes.data[6 * e + k]);
      mesh.triangles.push_back(t);
    }
  }
  const auto add_edges = [&](const std::vector<int>& curves, Boundary boundary, int hole) {
    for (const int curve : curves) {
      GmshArray<std::size_t> elements{gmsh};
      GmshArray<std::size_t> element_nodes{gmsh};
      gmsh.mesh_get_elements_by_type(kLine3, &elements.data, &elements.size, &element_nodes.data,
                                     &element_nodes.size, curve, 0, 1, &ierr);
      gmsh.Check(ierr, "getElementsByType (line 3)");
      for (std::size_t e = 0; e < elements.size; ++e) {
        BoundaryEdge edge;
        for (int k = 0; k < 3; ++k) edge.nodes[k] = node(element_nodes.data[3 * e + k]);
        edge.boundary = boundary;
        edge.hole = hole;
        mesh.edges.push_back(edge);
      }
    }
  };
  add_edges(outer, Boundary::kOutline, -1);
  add_edges(bore, Boundary::kBore, -1);
  for (std::size_t h = 0; h < holes.size(); ++h) add_edges(holes[h], Boundary::kHole, static_cast<int>(h));
  gmsh.clear(&ierr);
  gmsh.Check(ierr, "clear");
  return mesh;
}

}  // namespace ltca::contact::fe
