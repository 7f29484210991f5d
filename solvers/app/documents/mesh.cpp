#include "documents/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <fmt/format.h>

#include "documents/common.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::app::documents {

using units::RadToDeg;

nlohmann::json Json(const Deck& deck, const analysis::MeshResult& mesh) {
  const bool sliced = mesh.slices > 1;
  nlohmann::json pins = nlohmann::json::array();
  for (const auto& c : mesh.state.pins) {
    nlohmann::json row = {{"pin", c.pin + 1},
                          {"pin_angle_deg", RadToDeg(c.angle)},
                          {"clearance_um", units::MmToUm(c.clearance)},
                          {"arm_mm", c.arm},
                          {"cycloid_curvature_radius_mm", FiniteOrNull(c.cycloid_curvature == 0.0 ? INFINITY : 1.0 / c.cycloid_curvature)},
                          {"pin_radius_mm", c.pin_radius},
                          {"cycloid_point_mm", {c.cycloid_point.x(), c.cycloid_point.y()}},
                          {"pin_point_mm", {c.pin_point.x(), c.pin_point.y()}},
                          {"normal", {c.normal.x(), c.normal.y()}},
                          {"edge_contact", c.edge}};
    if (sliced) {
      row["slice"] = c.slice + 1;
      row["z_mm"] = c.z;
    }
    pins.push_back(std::move(row));
  }
  return {{"case", CaseJson(deck)}, {"crank_deg", mesh.crank_deg}, {"model", ModelJson(deck.Model())}, {"pins", pins}};
}

Table Columns(const analysis::MeshResult& mesh) {
  Table t;
  for (const auto& c : mesh.state.pins) {
    t.Add("pin", c.pin + 1.0);
    t.Add("pin_angle_deg", RadToDeg(c.angle));
    t.Add("clearance_um", units::MmToUm(c.clearance));
    t.Add("arm_mm", c.arm);
    t.Add("cycloid_curvature_radius_mm", c.cycloid_curvature == 0.0 ? INFINITY : 1.0 / c.cycloid_curvature);
    t.Add("pin_radius_mm", c.pin_radius);
    t.Add("cycloid_point_mm", std::vector<double>{c.cycloid_point.x(), c.cycloid_point.y()});
    t.Add("pin_point_mm", std::vector<double>{c.pin_point.x(), c.pin_point.y()});
    t.Add("normal", std::vector<double>{c.normal.x(), c.normal.y()});
    if (mesh.slices > 1) {
      t.Add("slice", c.slice + 1.0);
      t.Add("z_mm", c.z);
    }
  }
  return t;
}

std::string Text(const Deck& deck, const analysis::MeshResult& mesh) {
  std::string text = CaseLines(deck);
  text += fmt::format("mesh state at crank {:g} deg (unloaded pose)\n", mesh.crank_deg);
  if (deck.disc_count() == 2) text += "note      [second_disc]: the first disc's mesh only\n";
  // The slice model has a row per pin and slice: the slice and its z are named.
  const bool sliced = mesh.slices > 1;
  text += ModelLine(deck);
  text += fmt::format("{:>4} {}{:>9} {:>12} {:>10} {:>12} {:>8} {:>11} {:>11} {:>5}\n", "pin",
                      sliced ? fmt::format("{:>5} {:>7} ", "slice", "z_mm") : std::string(), "angle_deg", "c_um", "L_mm",
                      "rho_c_mm", "rho_p_mm", "x_mm", "y_mm", "edge");
  for (const auto& c : mesh.state.pins) {
    text += fmt::format("{:>4} {}{:>9.3f} {:>12.4f} {:>10.4f} {:>12.4f} {:>8.4f} {:>11.5f} {:>11.5f} {:>5}\n", c.pin + 1,
                        sliced ? fmt::format("{:>5} {:>7.3f} ", c.slice + 1, c.z) : std::string(), RadToDeg(c.angle),
                        units::MmToUm(c.clearance), c.arm, c.cycloid_curvature == 0.0 ? INFINITY : 1.0 / c.cycloid_curvature,
                        c.pin_radius, c.cycloid_point.x(), c.cycloid_point.y(), c.edge ? "yes" : "");
  }
  return text;
}

plots::Figure Figure(const Deck& deck, const analysis::MeshResult& mesh) {
  const int pin_count = deck.pair.pin_count;
  const double crank_deg = mesh.crank_deg;
  std::vector<double> pin, clearance(static_cast<std::size_t>(pin_count), INFINITY), arm(static_cast<std::size_t>(pin_count), NAN);
  for (const auto& c : mesh.state.pins) {  // the slice model: per pin, the slice of least clearance
    const auto j = static_cast<std::size_t>(c.pin);
    if (c.disc != 0 || j >= clearance.size()) continue;
    if (units::MmToUm(c.clearance) < clearance[j]) clearance[j] = units::MmToUm(c.clearance), arm[j] = c.arm;
  }
  // A log axis when the clearances span more than two decades (microns in the mesh, millimetres
  // away from it); a contact (below floor_um) is then drawn at floor_um.
  const double floor_um = 1e-3;
  double least = INFINITY, most = -INFINITY;
  int least_pin = 0;
  for (int j = 0; j < pin_count; ++j) {
    pin.push_back(j + 1);
    const double c = clearance[static_cast<std::size_t>(j)];
    if (c < least) least = c, least_pin = j + 1;
    if (std::isfinite(c)) most = std::max(most, c);
  }
  const bool log = most > 100.0 * std::max(least, floor_um);
  if (log) {
    for (double& c : clearance) c = std::max(c, floor_um);
  }
  plots::Figure figure;
  figure.title = fmt::format("{}: mesh state at crank {:g} deg (unloaded)", CaseTitle(deck), crank_deg);
  figure.caption = FigureCaption(deck, fmt::format("model {}; pins numbered from +x_f counter-clockwise{}{}",
                                                   deck.Model().name,
                                                   log ? fmt::format("; clearance on a log scale, below {:g} um (contact) drawn at {:g} um",
                                                                     floor_um, floor_um)
                                                       : "",
                                                   deck.disc_count() == 2 ? "; [second_disc]: the first disc's mesh" : ""));
  figure.columns = 2;
  figure.width = 1300;
  figure.height = 520;
  plots::Panel c;
  c.title = fmt::format("least clearance {:.4g} um at pin {}", least, least_pin);
  c.x_label = "pin number";
  c.y_label = "clearance (um)";
  c.log_y = log;
  c.series.push_back({"clearance", pin, clearance, plots::Style::kLineMarkers});
  c.x_min = 0.0, c.x_max = pin_count + 1.0;
  figure.panels.push_back(std::move(c));
  plots::Panel a;
  a.title = "moment arm of the contact normal about O_c";
  a.x_label = "pin number";
  a.y_label = "arm L_i (mm)";
  plots::Series arms{"arm", pin, arm, plots::Style::kBars};
  arms.colour = 2;
  a.series.push_back(std::move(arms));
  a.x_min = 0.0, a.x_max = pin_count + 1.0;
  figure.panels.push_back(std::move(a));
  return figure;
}

}  // namespace ltca::app::documents
