#include "compare_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "contact_commands.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/sweep.hpp"
#include "output.hpp"

namespace ltca::cli {

void RunCompare(const solvers::Deck& deck, const CompareOptions& options, std::ostream& out) {
  const std::vector<std::string> names = options.solvers.empty() ? solvers::SolverNames() : options.solvers;
  std::vector<solvers::SweepResult> runs;
  for (const auto& name : names) {
    solvers::SolverOptions o = deck.solver;
    o.name = name;
    if (!options.kinematics.empty()) o.kinematics = ParseKinematics(options.kinematics);
    runs.push_back(solvers::SolveSweep(deck, o));
  }
  const auto& ref = runs.front();
  fmt::print(out, "case      {}\n", deck.info.title);
  fmt::print(out, "{} positions, {} kinematics, law {} / {}; differences against {}\n", ref.positions.size(),
             ref.options.kinematics == contact::ContactKinematics::kExact ? "exact" : "linearised",
             contact::ToString(deck.contact.law), contact::ToString(deck.contact.rho_convention), ref.solver);
  fmt::print(out, "{:<14} {:<18} {:>12} {:>10} {:>7} {:>11} {:>11} {:>12} {:>12} {:>9} {:>9}\n", "solver", "status",
             "mean_te_as", "pp_te_as", "pins", "max_F_N", "max_p_MPa", "d_te_as", "d_F_N", "d_pins", "time_s");
  nlohmann::json doc = {{"case", {{"title", deck.info.title}, {"deck", deck.name}}}, {"reference", ref.solver},
                        {"solvers", nlohmann::json::array()}};
  for (const auto& run : runs) {
    double d_te = 0.0, d_force = 0.0;
    int d_pins = 0;
    for (std::size_t i = 0; i < run.positions.size(); ++i) {
      const auto& a = run.positions[i];
      const auto& b = ref.positions[i];
      d_te = std::max(d_te, std::abs(units::RadToArcsec(a.result.te - b.result.te)));
      for (std::size_t k = 0; k < a.result.force.size(); ++k) {
        d_force = std::max(d_force, std::abs(a.result.force[k] - b.result.force[k]));
      }
      d_pins = std::max(d_pins, std::abs(a.contacts - b.contacts));
    }
    const auto& s = run.summary;
    fmt::print(out, "{:<14} {:<18} {:>12.6f} {:>10.6f} {:>3}-{:<3} {:>11.3f} {:>11.3f} {:>12.3g} {:>12.3g} {:>9} {:>9.4f}\n",
               run.solver, solvers::ToString(s.status), units::RadToArcsec(s.mean_te), units::RadToArcsec(s.pp_te),
               s.contacts_min, s.contacts_max, s.max_pin_force, s.max_contact_stress, d_te, d_force, d_pins,
               s.wall_seconds);
    doc["solvers"].push_back({{"name", run.solver},
                              {"status", solvers::ToString(s.status)},
                              {"mean_te_arcsec", units::RadToArcsec(s.mean_te)},
                              {"pp_te_arcsec", units::RadToArcsec(s.pp_te)},
                              {"contacts_min", s.contacts_min},
                              {"contacts_max", s.contacts_max},
                              {"max_pin_force_n", s.max_pin_force},
                              {"max_contact_stress_mpa", s.max_contact_stress},
                              {"wall_seconds", s.wall_seconds},
                              {"max_te_difference_arcsec", d_te},
                              {"max_pin_force_difference_n", d_force},
                              {"max_contact_count_difference", d_pins}});
  }
  if (!options.json_path.empty()) {
    WriteTo(options.json_path, out, [&](std::ostream& os) { os << doc.dump(2) << '\n'; });
  }
}

}  // namespace ltca::cli
