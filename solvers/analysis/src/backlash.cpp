#include "ltca/analysis/backlash.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::analysis {

BacklashPosition UnloadedBacklashAt(const Stage& stage, double crank, contact::ContactKinematics kinematics) {
  BacklashPosition p;
  contact::UnloadedContact& r = p.contact;
  r = contact::AnalyseUnloaded(stage.model(), crank, kinematics);
  if (stage.disc_count() == 2) {
    const contact::UnloadedContact r2 = contact::AnalyseUnloaded(stage.model(1), crank + contact::kSecondDiscCrankOffset, kinematics);
    if (r2.theta_c1 < r.theta_c1) r.theta_c1 = r2.theta_c1, r.first_pin_c1 = r2.first_pin_c1, p.disc_c1 = 2;
    if (r2.theta_c2 > r.theta_c2) r.theta_c2 = r2.theta_c2, r.first_pin_c2 = r2.first_pin_c2, p.disc_c2 = 2;
    const double rounding = stage.interference_tolerance() / stage.model().pair().pin_circle_radius;
    const bool overlapping = r.theta_c2 - r.theta_c1 > rounding;  // as contact::AnalyseUnloaded
    r.backlash = overlapping ? 0.0 : r.theta_c1 - r.theta_c2;
    r.interference = overlapping ? r.theta_c2 - r.theta_c1 : 0.0;
    p.second_clearance = r2.clearance;
  }
  if (r.interference > 0.0 && stage.design().material && std::isfinite(r.theta_c1) && std::isfinite(r.theta_c2)) {
    // The moment the other flank still carries where the last pin of one flank opens (LoadProblem's
    // frame: psi = direction * physical rotation).
    p.unload_torque_nmm = std::max(0.0, stage.Problem(crank, 1.0).OutputTorque(r.theta_c2));
    p.unload_torque_reverse_nmm = std::max(0.0, stage.Problem(crank, -1.0).OutputTorque(-r.theta_c1));
  }
  // No pin closes its gap within the rotation window on a flank (a degenerate pair, e.g. an
  // eccentricity far below the pin's clearance): no backlash, a failed position.
  p.ok = std::isfinite(r.theta_c1) && std::isfinite(r.theta_c2) && r.first_pin_c1 >= 0 && r.first_pin_c2 >= 0;
  if (!p.ok) {
    p.failure = fmt::format("no pin closes its gap {} within a quarter tooth pitch of the theoretical position",
                            std::isfinite(r.theta_c1) ? "against the load direction" : "in the load direction");
  }
  return p;
}

void BacklashSummary::Add(const BacklashPosition& p, bool repeated_state) {
  ++positions_;
  if (!p.ok) {
    if (first_failure_.empty()) first_failure_ = fmt::format("crank {:.6g} deg: {}", units::RadToDeg(p.contact.crank), p.failure);
    return;
  }
  ++succeeded_;
  if (p.contact.interference > 0.0) {
    ++preloaded_;
    max_interference_ = std::max(max_interference_, p.contact.interference);
    for (const double t : {p.unload_torque_nmm, p.unload_torque_reverse_nmm}) {
      if (std::isfinite(t)) min_unload_ = std::isfinite(min_unload_) ? std::min(min_unload_, t) : t;
    }
  }
  const double b = p.contact.backlash;
  if (!repeated_state) sum_ += b, ++in_mean_;
  lo_ = std::min(lo_, b);
  hi_ = std::max(hi_, b);
}

double BacklashSummary::mean() const {
  // A sweep's only success may be its repeated last state.
  if (in_mean_ > 0) return sum_ / static_cast<double>(in_mean_);
  return succeeded_ > 0 ? lo_ : std::numeric_limits<double>::quiet_NaN();
}

double BacklashSummary::pp() const { return succeeded_ > 0 ? hi_ - lo_ : std::numeric_limits<double>::quiet_NaN(); }

BacklashResult Backlash(const Stage& stage, contact::ContactKinematics kinematics, const BacklashSink& sink) {
  const auto start = std::chrono::steady_clock::now();
  BacklashResult result;
  result.kinematics = kinematics;
  result.discs = stage.disc_count();
  result.closed_period = stage.closed_period();
  const std::vector<double>& cranks = stage.cranks();
  result.positions = cranks.size();
  for (std::size_t i = 0; i < cranks.size(); ++i) {
    const BacklashPosition p = UnloadedBacklashAt(stage, cranks[i], kinematics);
    result.summary.Add(p, result.closed_period && i + 1 == cranks.size());
    if (sink) sink(p);
  }
  if (std::string note = stage.SamplingNote(); !note.empty()) result.notes.push_back(std::move(note));
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace ltca::analysis
