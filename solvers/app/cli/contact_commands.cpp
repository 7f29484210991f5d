#include "contact_commands.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/units.hpp"
#include "output.hpp"

namespace ltca::cli {
namespace {

using units::RadToArcsec;
using units::RadToDeg;

nlohmann::json Finite(double v) { return FiniteOrNull(v); }

}  // namespace

contact::ContactKinematics ParseKinematics(const std::string& text) {
  if (text == "exact") return contact::ContactKinematics::kExact;
  if (text == "linearised") return contact::ContactKinematics::kLinearised;
  throw std::invalid_argument(fmt::format("--kinematics {}: expected exact or linearised", text));
}

void RunBacklash(const app::Deck& deck, const BacklashOptions& options, const Streams& streams) {
  RequireOneStdout({{"--json", options.json_path}, {"--csv", options.csv_path}});
  Output json("--json", options.json_path, streams.out);  // checked before computing
  Output csv("--csv", options.csv_path, streams.out);
  std::ostream& out = streams.text;
  const contact::MeshModel model = deck.MakeModel();
  const std::vector<double> cranks = deck.sweep.CrankAngles();
  // Every crank is checked for interference before anything is computed or written.
  for (const double crank : cranks) contact::RequireNoInterference(model, crank);
  fmt::print(out, "case      {}\n", deck.info.title);
  fmt::print(out, "unloaded TCA, {} kinematics, {} positions from {:g} to {:g} deg crank\n",
             options.kinematics == contact::ContactKinematics::kExact ? "exact" : "linearised",
             cranks.size(), RadToDeg(deck.sweep.crank_start), RadToDeg(deck.sweep.crank_end));
  fmt::print(out, "{:>10} {:>14} {:>14} {:>14} {:>6}\n", "crank_deg", "theta_c1_as", "theta_c2_as",
             "backlash_as", "pin");
  // Streamed, one position at a time, so memory does not grow with the sweep (issue 10): the JSON
  // holds the positions, then the summary.
  if (json.enabled()) {
    json.stream() << "{\n\"case\": "
                  << Dump({{"title", deck.info.title}, {"source", deck.info.source}, {"deck", deck.name}}, -1)
                  << ",\n\"positions\": [";
  }
  if (csv.enabled()) csv.stream() << "crank_deg,theta_c1_arcsec,theta_c2_arcsec,backlash_arcsec,first_contact_pin\n";
  const std::size_t step = std::max<std::size_t>(1, cranks.size() / 10);
  double sum = 0.0, lo = INFINITY, hi = -INFINITY;
  for (std::size_t i = 0; i < cranks.size(); ++i) {
    const contact::UnloadedContact r = contact::AnalyseUnloaded(model, cranks[i], options.kinematics);
    sum += r.backlash;
    lo = std::min(lo, r.backlash);
    hi = std::max(hi, r.backlash);
    if (i % step == 0) {
      fmt::print(out, "{:>10.4f} {:>14.4f} {:>14.4f} {:>14.4f} {:>6}\n", RadToDeg(r.crank), RadToArcsec(r.theta_c1),
                 RadToArcsec(r.theta_c2), RadToArcsec(r.backlash), r.first_pin_c1 + 1);
    }
    if (json.enabled()) {
      nlohmann::json clearance = nlohmann::json::array(), after = nlohmann::json::array();
      for (const double c : r.clearance) clearance.push_back(units::MmToUm(c));
      for (const double c : r.clearance_at_c1) after.push_back(units::MmToUm(c));
      const nlohmann::json position = {{"crank_deg", RadToDeg(r.crank)},
                                       {"theta_c1_arcsec", Finite(RadToArcsec(r.theta_c1))},
                                       {"theta_c2_arcsec", Finite(RadToArcsec(r.theta_c2))},
                                       {"backlash_arcsec", Finite(RadToArcsec(r.backlash))},
                                       {"first_contact_pin", r.first_pin_c1 + 1},
                                       {"first_contact_pin_reverse", r.first_pin_c2 + 1},
                                       {"clearance_um", clearance},
                                       {"clearance_at_first_contact_um", after}};
      json.stream() << (i == 0 ? "\n" : ",\n") << Dump(position, -1);
    }
    if (csv.enabled()) {
      fmt::print(csv.stream(), "{:.9g},{:.9g},{:.9g},{:.9g},{}\n", RadToDeg(r.crank), RadToArcsec(r.theta_c1),
                 RadToArcsec(r.theta_c2), RadToArcsec(r.backlash), r.first_pin_c1 + 1);
    }
  }
  const double mean = sum / static_cast<double>(cranks.size()), pp = hi - lo;
  fmt::print(out, "mean backlash           {:.4f} arcsec   (Liu eq. 17)\n", RadToArcsec(mean));
  fmt::print(out, "peak-to-peak backlash   {:.4f} arcsec\n", RadToArcsec(pp));
  if (json.enabled()) {
    json.stream() << "\n],\n\"summary\": "
                  << Dump({{"mean_backlash_arcsec", Finite(RadToArcsec(mean))}, {"pp_backlash_arcsec", Finite(RadToArcsec(pp))}}, -1)
                  << "\n}\n";
    json.Commit();
  }
  if (csv.enabled()) csv.Commit();
}

void RunMesh(const app::Deck& deck, const MeshOptions& options, const Streams& streams) {
  Output json("--json", options.json_path, streams.out);  // checked before computing
  std::ostream& out = streams.text;
  const contact::MeshModel model = deck.MakeModel();
  const double crank = units::DegToRad(options.crank_deg);
  const contact::MeshState state = model.Evaluate(crank);
  // A table of an interfering pair would show negative clearances as if they were a mesh state.
  contact::RequireNoInterference(state, crank, model.interference_tolerance());
  fmt::print(out, "case      {}\n", deck.info.title);
  fmt::print(out, "mesh state at crank {:g} deg (unloaded pose)\n", options.crank_deg);
  // The slice model has a row per pin and slice (issue 11): the slice and its z are named.
  const bool sliced = model.slice_count() > 1;
  out << ModelLine(deck);
  fmt::print(out, "{:>4} {}{:>9} {:>12} {:>10} {:>12} {:>8} {:>11} {:>11} {:>5}\n", "pin",
             sliced ? fmt::format("{:>5} {:>7} ", "slice", "z_mm") : std::string(), "angle_deg", "c_um", "L_mm",
             "rho_c_mm", "rho_p_mm", "x_mm", "y_mm", "edge");
  for (const auto& c : state.pins) {
    fmt::print(out, "{:>4} {}{:>9.3f} {:>12.4f} {:>10.4f} {:>12.4f} {:>8.4f} {:>11.5f} {:>11.5f} {:>5}\n", c.pin + 1,
               sliced ? fmt::format("{:>5} {:>7.3f} ", c.slice + 1, c.z) : std::string(), RadToDeg(c.angle),
               units::MmToUm(c.clearance), c.arm,
               c.cycloid_curvature == 0.0 ? INFINITY : 1.0 / c.cycloid_curvature, c.pin_radius,
               c.cycloid_point.x(), c.cycloid_point.y(), c.edge ? "yes" : "");
  }
  if (json.enabled()) {
    {
      std::ostream& os = json.stream();
      nlohmann::json pins = nlohmann::json::array();
      for (const auto& c : state.pins) {
        nlohmann::json row = {{"pin", c.pin + 1},
                        {"pin_angle_deg", RadToDeg(c.angle)},
                        {"clearance_um", units::MmToUm(c.clearance)},
                        {"arm_mm", c.arm},
                        {"cycloid_curvature_radius_mm", Finite(c.cycloid_curvature == 0.0 ? INFINITY : 1.0 / c.cycloid_curvature)},
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
      os << Dump(nlohmann::json{{"case", {{"title", deck.info.title}, {"source", deck.info.source}, {"deck", deck.name}}},
                                {"crank_deg", options.crank_deg},
                                {"model", ModelJson(deck.Model())},
                                {"pins", pins}})
         << '\n';
    }
    json.Commit();
  }
}

}  // namespace ltca::cli
