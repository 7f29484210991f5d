#pragma once
// The slice-count study: how the figures of the slice model converge with the number of
// face-width slices, and what each slice count costs. `ltca-bench` reports the times beside the
// errors (docs/performance.md); `ltca validate` reports the convergence (docs/validation.md).
// Not a timed test.
#include <string>
#include <vector>

#include "ltca/analysis/stage.hpp"
#include "ltca/contact/unloaded.hpp"

namespace ltca::analysis {

struct SliceStudyRow {
  int slices = 0;
  double seconds_per_position = 0.0;  ///< the whole sweep (mesh states included), fastest of the repeats
  double mean_te_arcsec = 0.0, pp_te_arcsec = 0.0;
  double mean_backlash_arcsec = 0.0, pp_backlash_arcsec = 0.0;  ///< linearised unloaded TCA
  bool succeeded = false;  ///< every position solved
};

/// The stage (which must run the slice model: something varies along the width, or [pins]) at
/// the cranks (rad) and the torque (N*mm), solved with `options` under linearised kinematics at
/// every slice count, `repeats` times each; the time per position includes building the stage.
std::vector<SliceStudyRow> RunSliceStudy(const StageDesign& design, const std::vector<double>& cranks, double torque,
                                         const SolverOptions& options, const std::vector<int>& slice_counts,
                                         int repeats);

/// The unloaded figures of a misaligned deck from its face edges alone: the plane pair
/// with the cycloid centre where the tilted axis puts it at face B, and the one at the far face
/// (AssemblyErrors::SliceShift at z = 0 and z = B added to the centre offset); at each crank the
/// first contact both ways is the nearer of the two. The gap of a tilted axis is linear along the
/// face, so this is the value every slice count must give (a closed period's repeated state weighs
/// once). Throws std::invalid_argument for a deck without misalignment.
struct FaceEdgeBacklash {
  double mean_arcsec = 0.0, pp_arcsec = 0.0;
};
FaceEdgeBacklash FaceEdgeUnloaded(const StageDesign& design, const std::vector<double>& cranks,
                                  contact::ContactKinematics kinematics = contact::ContactKinematics::kLinearised);

/// Least-squares slope of log(time) against log(slices) over the rows with lo <= slices <= hi:
/// the cost exponent (1: linear).
double CostExponent(const std::vector<SliceStudyRow>& rows, int lo, int hi);

}  // namespace ltca::analysis
