#include "ltca/app/tip_relief_default.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "ltca/solvers/registry.hpp"
#include "ltca/solvers/workspace.hpp"

namespace ltca::app {
namespace {

/// Whether the solved position keeps every loaded contact on the relief within the law and the
/// stress limit.
bool ReliefContactsValid(const solvers::LoadProblem& problem, const LoadResult& result, solvers::Workspace& workspace,
                         double stress_limit) {
  std::vector<contact::ContactLaw> scratch;
  const std::vector<solvers::LoadProblem::PinAt> at = problem.At(result.rotation, workspace, &scratch);
  const bool exact = problem.kinematics() == contact::ContactKinematics::kExact;
  for (std::size_t i = 0; i < at.size(); ++i) {
    const double f = result.force[i];
    if (!(f > 0.0)) continue;
    const contact::PinContact& base = problem.base_state().pins[i];
    const geometry::SurfacePart part = exact ? problem.EvaluatePin(base, result.rotation).part : base.part;
    if (part == geometry::SurfacePart::kFlank) continue;
    const contact::ContactLaw* law = at[i].law;
    if (law == nullptr || law->HalfWidth(f) > law->valid_half_width() || law->MaxPressure(f) > stress_limit) {
      return false;
    }
  }
  return true;
}

}  // namespace

double DefaultTipRoundingCandidate(int i) {
  static constexpr std::array<double, 10> kR10 = {1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0};
  return 0.01 * kR10[static_cast<std::size_t>(i % 10)] * std::pow(10.0, i / 10);
}

void ChooseDefaultTipRelief(Deck& deck) {
  deck.tip_relief_source = "none";
  if (!deck.load || !deck.material) {
    deck.tip_relief_note = "sharp tips: the default tip relief is chosen for the deck's load, and the deck has no [load] "
                           "and [material]";
    return;
  }
  if (deck.load->torque == 0.0) {
    deck.tip_relief_note = "sharp tips: zero torque loads no contact to choose a tip relief for";
    return;
  }
  if (deck.geometry.mode == geometry::GeometrySettings::Mode::kElements || deck.errors.HasProfileDeviation()) {
    deck.tip_relief_note = "sharp tips: a tip relief needs the analytic surface without a profile deviation";
    return;
  }
  std::vector<double> cranks = deck.sweep.CrankAngles();
  std::string sampled;
  if (cranks.size() > static_cast<std::size_t>(kTipReliefChoicePositions)) {
    std::vector<double> every;
    for (int i = 0; i < kTipReliefChoicePositions; ++i) {
      every.push_back(cranks[cranks.size() * static_cast<std::size_t>(i) / kTipReliefChoicePositions]);
    }
    cranks = std::move(every);
    sampled = fmt::format(", sampled evenly from the deck's {}", deck.sweep.positions);
  }
  // Judged under both kinematics: the command line may choose either for the same deck.
  constexpr std::array<contact::ContactKinematics, 2> kBoth = {contact::ContactKinematics::kLinearised,
                                                               contact::ContactKinematics::kExact};
  SolverOptions options = deck.solver;
  options.name = "compatibility";
  const auto solver = solvers::MakeSolver(options.name);
  const contact::Material& material = *deck.material;
  const std::string rule = fmt::format(
      "the smallest of 0.01 mm x R10 (no truncation) for which all {} positions{} solve on both flanks (+-T; compatibility, linearised and exact kinematics) with "
      "every loaded contact on the arc within the law's half-width bound and contact_stress_limit_mpa = {:g}",
      cranks.size(), sampled, material.contact_stress_limit);
  std::string stop;
  for (int i = 0; DefaultTipRoundingCandidate(i) <= deck.pair.pin_radius; ++i) {
    const double rho = DefaultTipRoundingCandidate(i);
    Deck trial = deck;
    trial.modification.tip_relief = {0.0, rho};
    std::shared_ptr<const contact::MeshModel> model;
    solvers::LoadProblem::CheckedCoupling coupling;
    try {
      model = std::make_shared<const contact::MeshModel>(trial.MakeModel());
      coupling = trial.MakeCoupling(*model);
    } catch (const std::invalid_argument& e) {
      stop = fmt::format("; at {:g} mm the relief no longer fits the tooth", rho);
      break;
    }
    bool ok = true;
    // Both flanks (+-T): `ltca stiffness` loads the coast flank too, and with errors its tips differ.
    for (int i = 0; ok && i < 4; ++i) {
      // Linearised on both flanks first: a radius that fails, fails there and cheaply.
      const contact::ContactKinematics kinematics = kBoth[static_cast<std::size_t>(i / 2)];
      const double torque = i % 2 == 0 ? trial.load->torque : -trial.load->torque;
      solvers::Workspace workspace;
      options.kinematics = kinematics;
      for (const double crank : cranks) {
        solvers::LoadProblem problem(model, crank, trial.contact, material, torque, kinematics);
        if (trial.pins) problem = problem.WithCoupling(coupling);
        const LoadResult r = solver->Solve(problem, options, workspace);
        ok = r.status == SolverStatus::kSuccess && ReliefContactsValid(problem, r, workspace, material.contact_stress_limit);
        if (!ok) break;
      }
    }
    if (ok) {
      deck.modification.tip_relief = trial.modification.tip_relief;
      deck.tip_relief_source = "default";
      deck.tip_relief_note = fmt::format(
          "rounding radius {:g} mm chosen for this load: {}; set tip_rounding_radius_mm or tip_truncation_mm to choose "
          "(both 0: sharp tips)",
          rho, rule);
      return;
    }
  }
  deck.tip_relief_note =
      fmt::format("sharp tips: no radius up to the pin radius meets the default rule ({}){}", rule, stop);
}

}  // namespace ltca::app
