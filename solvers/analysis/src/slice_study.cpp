#include "ltca/analysis/slice_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/analysis/sweep.hpp"
#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::analysis {

std::vector<SliceStudyRow> RunSliceStudy(const StageDesign& design, const std::vector<double>& cranks, double torque,
                                         const SolverOptions& options, const std::vector<int>& slice_counts,
                                         int repeats) {
  using Clock = std::chrono::steady_clock;
  std::vector<SliceStudyRow> rows;
  for (const int n : slice_counts) {
    StageDesign d = design;
    d.geometry.width_slices = n;
    d.kinematics = contact::ContactKinematics::kLinearised;
    if (d.Model().slices != n) {
      throw std::invalid_argument(fmt::format("slice study: deck '{}' runs the {} model, not {} slices", design.name,
                                              d.Model().name, n));
    }
    SliceStudyRow row;
    row.slices = n;
    row.seconds_per_position = std::numeric_limits<double>::infinity();
    for (int r = 0; r < std::max(repeats, 1); ++r) {
      const auto start = Clock::now();
      const Stage stage(d, cranks);
      const SweepResult sweep = SolveSweep(stage, options, torque);
      const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
      row.seconds_per_position = std::min(row.seconds_per_position, seconds / static_cast<double>(sweep.summary.positions()));
      row.succeeded = sweep.summary.all_succeeded();
      row.mean_te_arcsec = units::RadToArcsec(sweep.summary.mean_te);
      row.pp_te_arcsec = units::RadToArcsec(sweep.summary.pp_te);
    }
    const auto backlash = contact::AnalyseUnloadedSweep(d.MakeModel(), cranks, contact::ContactKinematics::kLinearised);
    row.mean_backlash_arcsec = units::RadToArcsec(backlash.mean_backlash);
    row.pp_backlash_arcsec = units::RadToArcsec(backlash.pp_backlash);
    rows.push_back(row);
  }
  return rows;
}

FaceEdgeBacklash FaceEdgeUnloaded(const StageDesign& deck, const std::vector<double>& cranks,
                                  contact::ContactKinematics kinematics) {
  if (!deck.assembly.VariesAlongWidth()) {
    throw std::invalid_argument(fmt::format("deck '{}': the face-edge backlash needs a misalignment", deck.name));
  }
  StageDesign edge[2] = {deck, deck};
  const double width = deck.pair.face_width;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d shift = deck.assembly.SliceShift(k == 0 ? 0.0 : width, width);
    edge[k].assembly.misalignment_xz = edge[k].assembly.misalignment_yz = 0.0;
    edge[k].assembly.centre_dx += shift.x();
    edge[k].assembly.centre_dy += shift.y();
    edge[k].geometry.width_slices = 1;
  }
  const contact::MeshModel at_b = edge[0].MakeModel(), at_far = edge[1].MakeModel();
  const contact::MeshModel tilted = deck.MakeModel();
  const bool closed = cranks.size() > 1 && contact::SameMesh(tilted.Evaluate(cranks.front()), tilted.Evaluate(cranks.back()));
  double sum = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < cranks.size(); ++i) {
    const auto p = contact::AnalyseUnloaded(at_b, cranks[i], kinematics);
    const auto q = contact::AnalyseUnloaded(at_far, cranks[i], kinematics);
    const double b = std::min(p.theta_c1, q.theta_c1) - std::max(p.theta_c2, q.theta_c2);
    if (!(closed && i + 1 == cranks.size())) sum += b;
    lo = std::min(lo, b), hi = std::max(hi, b);
  }
  return {units::RadToArcsec(sum / static_cast<double>(cranks.size() - (closed ? 1 : 0))), units::RadToArcsec(hi - lo)};
}

double CostExponent(const std::vector<SliceStudyRow>& rows, int lo, int hi) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int m = 0;
  for (const auto& r : rows) {
    if (r.slices < lo || r.slices > hi) continue;
    const double x = std::log(r.slices), y = std::log(r.seconds_per_position);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
    ++m;
  }
  if (m < 2) return std::numeric_limits<double>::quiet_NaN();
  return (m * sxy - sx * sy) / (m * sxx - sx * sx);
}

}  // namespace ltca::analysis
