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

// Splits `intervals` intervals from point `from` into `runs` runs (at least one, at most one per
// interval): their first points, and `from + intervals` last.
std::vector<int> RunEnds(int from, int intervals, int runs) {
  runs = std::clamp(runs, 1, std::max(1, intervals));
  std::vector<int> ends;
  for (int r = 0; r <= runs; ++r) ends.push_back(from + static_cast<int>(static_cast<long long>(r) * intervals / runs));
  return ends;
}

// The outline polygon: straight lines for a short polygon, else splines through runs of its
// points (a profile sampled every few micrometres would otherwise force an element per sample);
// no run crosses a corner (its splines end there).
std::vector<int> AddOutline(GmshLibrary& gmsh, const std::vector<Eigen::Vector2d>& outline, double size,
                            std::vector<int> corners) {
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
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  if (!corners.empty()) {
    // Each piece between two corners its own runs, about as many as its share of the points.
    for (std::size_t c = 0; c < corners.size(); ++c) {
      const int from = corners[c];
      const int to = c + 1 < corners.size() ? corners[c + 1] : corners.front() + n;
      if (from < 0 || from >= n) throw std::invalid_argument("disc outline: a corner index outside the outline");
      const std::vector<int> ends =
          RunEnds(from, to - from, static_cast<int>(std::lround(static_cast<double>(to - from) * runs / n)));
      for (std::size_t r = 0; r + 1 < ends.size(); ++r) {
        std::vector<int> run;
        for (int i = ends[r]; i <= ends[r + 1]; ++i) run.push_back(points[i % n]);
        curves.push_back(gmsh.geo_add_spline(run.data(), run.size(), -1, &ierr));
        gmsh.Check(ierr, "addSpline");
      }
    }
    return curves;
  }
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

// Sizes from the background field only (the geometry's points, curvature and boundary do not add
// their own), capped at the target element size; one thread, a fixed seed.
void SetOptions(GmshLibrary& gmsh, double element_size) {
  int ierr = 0;
  gmsh.clear(&ierr);
  gmsh.Check(ierr, "clear");
  gmsh.model_add("ltca_disc", &ierr);
  gmsh.Check(ierr, "model add");
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"Mesh.MeshSizeFromPoints", 0.0}, {"Mesh.MeshSizeFromCurvature", 0.0},
        {"Mesh.MeshSizeExtendFromBoundary", 0.0}, {"Mesh.MeshSizeMax", element_size},
        {"Mesh.MeshSizeMin", 0.0}, {"Mesh.Algorithm", 6.0} /* Frontal-Delaunay */,
        {"Mesh.SecondOrderLinear", 0.0} /* mid-side nodes on the curves */,
        {"Mesh.HighOrderOptimize", 0.0}, {"General.NumThreads", 1.0}, {"Mesh.RandomSeed", 1.0}}) {
    gmsh.option_set_number(name, value, &ierr);
    gmsh.Check(ierr, name);
  }
}

// Refinement: size = refined at distance 0 from the nearest refinement point, growing linearly to
// element_size at refine_radius (gmsh's Distance and Threshold fields). Synchronizes the geometry.
void Refine(GmshLibrary& gmsh, const std::vector<Eigen::Vector2d>& near, double refined, double size, double radius) {
  int ierr = 0;
  std::vector<double> refine_tags;
  for (const Eigen::Vector2d& p : near) {
    refine_tags.push_back(gmsh.geo_add_point(p.x(), p.y(), 0.0, size, -1, &ierr));
    gmsh.Check(ierr, "addPoint");
  }
  gmsh.geo_synchronize(&ierr);
  gmsh.Check(ierr, "synchronize");
  if (refine_tags.empty() || !(refined < size)) return;
  const int distance = gmsh.field_add("Distance", -1, &ierr);
  gmsh.Check(ierr, "field Distance");
  // gmsh 4.8 names the Distance field's points NodesList (PointsList from 4.9 on).
  gmsh.field_set_numbers(distance, "NodesList", refine_tags.data(), refine_tags.size(), &ierr);
  if (ierr != 0) gmsh.field_set_numbers(distance, "PointsList", refine_tags.data(), refine_tags.size(), &ierr);
  gmsh.Check(ierr, "Distance points");
  const int threshold = gmsh.field_add("Threshold", -1, &ierr);
  gmsh.Check(ierr, "field Threshold");
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"InField", static_cast<double>(distance)}, {"SizeMin", refined},
        {"SizeMax", size}, {"DistMin", 0.0}, {"DistMax", radius}}) {
    gmsh.field_set_number(threshold, name, value, &ierr);
    gmsh.Check(ierr, name);
  }
  gmsh.field_set_as_background_mesh(threshold, &ierr);
  gmsh.Check(ierr, "background field");
}

// The meshed surface's T6 (renumbered from 0, the refinement points' lone nodes dropped) and the
// 3-node boundary edges of the given curves. `tag_of`, when given, receives gmsh's tag of each node.
struct Curves {
  std::vector<int> tags;
  Boundary boundary = Boundary::kOutline;
  int hole = -1;
};
T6Mesh Extract(GmshLibrary& gmsh, int surface, const std::vector<Curves>& curves, std::vector<std::size_t>* tag_of = nullptr) {
  int ierr = 0;
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
      if (tag_of != nullptr) tag_of->push_back(tag);
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
  for (const Curves& set : curves) {
    for (const int curve : set.tags) {
      GmshArray<std::size_t> elements{gmsh};
      GmshArray<std::size_t> element_nodes{gmsh};
      gmsh.mesh_get_elements_by_type(kLine3, &elements.data, &elements.size, &element_nodes.data,
                                     &element_nodes.size, curve, 0, 1, &ierr);
      gmsh.Check(ierr, "getElementsByType (line 3)");
      for (std::size_t e = 0; e < elements.size; ++e) {
        BoundaryEdge edge;
        for (int k = 0; k < 3; ++k) edge.nodes[k] = node(element_nodes.data[3 * e + k]);
        edge.boundary = set.boundary;
        edge.hole = set.hole;
        mesh.edges.push_back(edge);
      }
    }
  }
  return mesh;
}

}  // namespace

T6Mesh MeshDisc(const DiscBodyDesign& design) {
  design.Validate();
  GmshLibrary& gmsh = GmshLibrary::Get();
  const auto lock = gmsh.Lock();
  int ierr = 0;
  SetOptions(gmsh, design.element_size_mm);
  const double size = design.element_size_mm;
  std::vector<int> outer = design.outline_mm.empty()
                               ? AddCircle(gmsh, Eigen::Vector2d::Zero(), design.outer_radius_mm, size)
                               : AddOutline(gmsh, design.outline_mm, size, design.outline_corners);
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
  Refine(gmsh, design.refine_near_mm, design.refined_size_mm, size, design.refine_radius_mm);
  gmsh.mesh_generate(2, &ierr);
  gmsh.Check(ierr, "mesh generate");
  gmsh.mesh_set_order(2, &ierr);
  gmsh.Check(ierr, "mesh set order 2");
  std::vector<Curves> curves{{outer, Boundary::kOutline, -1}, {bore, Boundary::kBore, -1}};
  for (std::size_t h = 0; h < holes.size(); ++h) curves.push_back({holes[h], Boundary::kHole, static_cast<int>(h)});
  T6Mesh mesh = Extract(gmsh, surface, curves);
  gmsh.clear(&ierr);
  gmsh.Check(ierr, "clear");
  return mesh;
}

T6Mesh MeshDiscSector(const DiscSector& sector) {
  const std::vector<Eigen::Vector2d>& outline = sector.outline_mm;
  const int n = static_cast<int>(outline.size());
  if (n < 3 || sector.copies < 2) throw std::invalid_argument("disc sector: at least 3 outline points and 2 copies");
  const double size = sector.element_size_mm, refined = std::min(sector.refined_size_mm, size);
  if (!(size > 0.0) || !(refined > 0.0) || !(sector.bore_radius_mm > 0.0)) {
    throw std::invalid_argument("disc sector: sizes and the bore radius must be positive");
  }
  const Eigen::Vector2d start = outline.front(), end = outline.back();
  const double turn = std::remainder(std::atan2(end.y(), end.x()) - std::atan2(start.y(), start.x()), 2.0 * std::numbers::pi);
  if (std::abs(std::abs(turn) - 2.0 * std::numbers::pi / sector.copies) > 1e-9 ||
      std::abs(turn - sector.angle_rad) > 1e-9 || std::abs(start.norm() - end.norm()) > 1e-9 * start.norm()) {
    throw std::invalid_argument("disc sector: the outline's ends are not one turn of 2 pi / copies apart");
  }
  const double cut = start.norm() - sector.bore_radius_mm;
  if (!(cut > 2.0 * size)) throw std::invalid_argument("disc sector: the bore reaches within two elements of the outline");
  // The cuts: graded from `refined` at the outline by a ratio of 1.25 up to the element size (at
  // most half the cut), then even.
  constexpr double kRatio = 1.25;
  int graded = 0;
  double graded_length = 0.0;
  for (double h = refined; h < size && graded_length + h <= 0.5 * cut; h *= kRatio) graded_length += h, ++graded;
  graded = std::max(graded, 1);
  if (graded_length <= 0.0) graded_length = std::min(refined, 0.5 * cut);
  const int even = std::max(1, static_cast<int>(std::ceil((cut - graded_length) / size)));

  GmshLibrary& gmsh = GmshLibrary::Get();
  const auto lock = gmsh.Lock();
  int ierr = 0;
  SetOptions(gmsh, size);
  std::vector<int> points(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    points[static_cast<std::size_t>(i)] = gmsh.geo_add_point(outline[i].x(), outline[i].y(), 0.0, size, -1, &ierr);
    gmsh.Check(ierr, "addPoint");
  }
  std::vector<int> outer;
  const int runs = std::max(1, std::min(16, (n - 1) / 8));
  if (sector.corners.empty()) {
    for (int r = 0; r < runs; ++r) {
      const int first = r * (n - 1) / runs, last = (r + 1) * (n - 1) / runs;
      std::vector<int> run(points.begin() + first, points.begin() + last + 1);
      outer.push_back(gmsh.geo_add_spline(run.data(), run.size(), -1, &ierr));
      gmsh.Check(ierr, "addSpline");
    }
  } else {
    // The pieces between corners, each its own runs (about its share of the points): no spline
    // runs across a corner.
    std::vector<int> stops{0};
    for (const int c : sector.corners) {
      if (c <= 0 || c >= n - 1) throw std::invalid_argument("disc sector: a corner index not inside the outline");
      stops.push_back(c);
    }
    stops.push_back(n - 1);
    std::sort(stops.begin(), stops.end());
    stops.erase(std::unique(stops.begin(), stops.end()), stops.end());
    for (std::size_t c = 0; c + 1 < stops.size(); ++c) {
      const int span = stops[c + 1] - stops[c];
      const std::vector<int> ends =
          RunEnds(stops[c], span, static_cast<int>(std::lround(static_cast<double>(span) * runs / (n - 1))));
      for (std::size_t r = 0; r + 1 < ends.size(); ++r) {
        std::vector<int> run(points.begin() + ends[r], points.begin() + ends[r + 1] + 1);
        outer.push_back(gmsh.geo_add_spline(run.data(), run.size(), -1, &ierr));
        gmsh.Check(ierr, "addSpline");
      }
    }
  }
  const auto point = [&](const Eigen::Vector2d& p) {
    const int tag = gmsh.geo_add_point(p.x(), p.y(), 0.0, size, -1, &ierr);
    gmsh.Check(ierr, "addPoint");
    return tag;
  };
  const int centre = point(Eigen::Vector2d::Zero());
  // Each cut: outline point -> inner point (graded) -> bore point (even), oriented alike.
  const auto add_cut = [&](int outline_tag, const Eigen::Vector2d& at, std::array<int, 2>* segments) {
    const Eigen::Vector2d unit = at.normalized();
    const int inner = point(at - graded_length * unit);
    const int bore = point(sector.bore_radius_mm * unit);
    (*segments)[0] = gmsh.geo_add_line(outline_tag, inner, -1, &ierr);
    gmsh.Check(ierr, "addLine");
    (*segments)[1] = gmsh.geo_add_line(inner, bore, -1, &ierr);
    gmsh.Check(ierr, "addLine");
    gmsh.geo_mesh_set_transfinite_curve((*segments)[0], graded + 1, "Progression", kRatio, &ierr);
    gmsh.Check(ierr, "setTransfiniteCurve");
    gmsh.geo_mesh_set_transfinite_curve((*segments)[1], even + 1, "Progression", 1.0, &ierr);
    gmsh.Check(ierr, "setTransfiniteCurve");
    return bore;
  };
  std::array<int, 2> start_cut{}, end_cut{};
  const int start_bore = add_cut(points.front(), start, &start_cut);
  const int end_bore = add_cut(points.back(), end, &end_cut);
  const int arc = gmsh.geo_add_circle_arc(end_bore, centre, start_bore, -1, 0.0, 0.0, 0.0, &ierr);
  gmsh.Check(ierr, "addCircleArc");
  std::vector<int> loop_curves = outer;
  loop_curves.push_back(end_cut[0]);
  loop_curves.push_back(end_cut[1]);
  loop_curves.push_back(arc);
  loop_curves.push_back(-start_cut[1]);
  loop_curves.push_back(-start_cut[0]);
  const int loop = gmsh.geo_add_curve_loop(loop_curves.data(), loop_curves.size(), -1, 1, &ierr);
  gmsh.Check(ierr, "addCurveLoop");
  std::vector<int> loops{loop};
  const int surface = gmsh.geo_add_plane_surface(loops.data(), loops.size(), -1, &ierr);
  gmsh.Check(ierr, "addPlaneSurface");
  Refine(gmsh, outline, refined, size, sector.refine_radius_mm);
  gmsh.mesh_generate(2, &ierr);
  gmsh.Check(ierr, "mesh generate");
  gmsh.mesh_set_order(2, &ierr);
  gmsh.Check(ierr, "mesh set order 2");
  std::vector<std::size_t> tag_of;
  const T6Mesh one = Extract(gmsh, surface, {{outer, Boundary::kOutline, -1}, {{arc}, Boundary::kBore, -1}}, &tag_of);
  // The nodes of each cut (both segments, their ends included), by distance from the centre.
  std::vector<int> local_of_tag;
  for (std::size_t i = 0; i < tag_of.size(); ++i) {
    if (tag_of[i] >= local_of_tag.size()) local_of_tag.resize(tag_of[i] + 1, -1);
    local_of_tag[tag_of[i]] = static_cast<int>(i);
  }
  const auto cut_nodes = [&](const std::array<int, 2>& segments) {
    std::vector<int> nodes;
    for (const int segment : segments) {
      GmshArray<std::size_t> tags{gmsh};
      GmshArray<double> coords{gmsh};
      GmshArray<double> parametric{gmsh};
      gmsh.mesh_get_nodes(&tags.data, &tags.size, &coords.data, &coords.size, &parametric.data, &parametric.size, 1,
                          segment, 1, 0, &ierr);
      gmsh.Check(ierr, "getNodes (cut)");
      for (std::size_t i = 0; i < tags.size; ++i) {
        const std::size_t tag = tags.data[i];
        if (tag >= local_of_tag.size() || local_of_tag[tag] < 0) throw std::runtime_error("gmsh: a cut's node is in no element");
        nodes.push_back(local_of_tag[tag]);
      }
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    std::sort(nodes.begin(), nodes.end(), [&](int a, int b) { return one.nodes[a].norm() < one.nodes[b].norm(); });
    return nodes;
  };
  const std::vector<int> first_cut = cut_nodes(start_cut), last_cut = cut_nodes(end_cut);
  gmsh.clear(&ierr);
  gmsh.Check(ierr, "clear");
  if (first_cut.size() != last_cut.size()) throw std::runtime_error("disc sector: the two cuts' meshes differ");
  for (std::size_t m = 0; m < first_cut.size(); ++m) {
    if (std::abs(one.nodes[first_cut[m]].norm() - one.nodes[last_cut[m]].norm()) > 1e-9 * start.norm()) {
      throw std::runtime_error("disc sector: the two cuts' nodes do not pair");
    }
  }
  // The copies: copy c is the sector turned through c * angle; its start cut is copy c - 1's end
  // cut (copy 0's that of the last copy).
  const std::size_t local = one.nodes.size();
  std::vector<int> start_slot(local, -1), end_slot(local, -1);
  for (std::size_t m = 0; m < first_cut.size(); ++m) start_slot[first_cut[m]] = static_cast<int>(m), end_slot[last_cut[m]] = static_cast<int>(m);
  T6Mesh mesh;
  std::vector<int> first_start(first_cut.size(), -1), previous_end(first_cut.size(), -1);
  for (int c = 0; c < sector.copies; ++c) {
    const double a = c * sector.angle_rad;
    const Eigen::Matrix2d turn_by{{std::cos(a), -std::sin(a)}, {std::sin(a), std::cos(a)}};
    std::vector<int> id(local, -1);
    std::vector<int> this_end(first_cut.size(), -1);
    for (std::size_t i = 0; i < local; ++i) {
      if (start_slot[i] >= 0 && c > 0) {
        id[i] = previous_end[static_cast<std::size_t>(start_slot[i])];
      } else if (end_slot[i] >= 0 && c + 1 == sector.copies) {
        id[i] = first_start[static_cast<std::size_t>(end_slot[i])];
      }
      if (id[i] < 0) {
        id[i] = static_cast<int>(mesh.nodes.size());
        mesh.nodes.push_back(turn_by * one.nodes[i]);
      }
      if (start_slot[i] >= 0 && c == 0) first_start[static_cast<std::size_t>(start_slot[i])] = id[i];
      if (end_slot[i] >= 0) this_end[static_cast<std::size_t>(end_slot[i])] = id[i];
    }
    previous_end = this_end;
    for (const std::array<int, 6>& t : one.triangles) {
      std::array<int, 6> u{};
      for (int k = 0; k < 6; ++k) u[k] = id[static_cast<std::size_t>(t[k])];
      mesh.triangles.push_back(u);
    }
    for (const BoundaryEdge& e : one.edges) {
      BoundaryEdge f = e;
      for (int k = 0; k < 3; ++k) f.nodes[k] = id[static_cast<std::size_t>(e.nodes[k])];
      mesh.edges.push_back(f);
    }
  }
  return mesh;
}

}  // namespace ltca::contact::fe
