#pragma once
// The disc as made as the plain data of the STEP solid (docs/export.md): the outline in smooth
// pieces of points on the analytic curve (modification, profile layer and tip relief applied), the
// check points between them, the holes through the disc, the face width. The STEP file itself is
// written by the module ltca_step.so (solvers/app/step), which alone links OpenCASCADE; this part
// knows nothing of it.
#include <string>
#include <vector>

#include "ltca/app/deck.hpp"
#include "ltca/geometry/real_pair.hpp"

namespace ltca::app::documents {

/// The largest deviation of the solid's B-splines from the analytic profile allowed, mm: 0.1 um.
inline constexpr double kStepTolerance = 1e-4;
/// The chord sagitta of the points the B-splines interpolate, mm: a cubic through points this
/// dense strays from the curve by far less than kStepTolerance (measured at the check points).
inline constexpr double kStepNodeSagitta = 1e-3;
/// The check points' chord sagitta, mm (16 times finer: about 4 check points a node interval).
inline constexpr double kStepCheckSagitta = kStepNodeSagitta / 16.0;

struct StepDisc {
  std::vector<int> piece_offsets;   ///< pieces + 1 offsets into points (in points)
  std::vector<double> points_xy;    ///< the points the B-splines interpolate, body frame, mm
  std::vector<int> check_offsets;   ///< pieces + 1 offsets into check_xy
  std::vector<double> check_xy;     ///< analytic points between them, mm
  std::vector<double> holes_xyr;    ///< centre x, y and radius of each hole: the bore, the output pins' holes
  double width_mm = 0.0;            ///< the face width B_c
  std::string description;          ///< the STEP header's description: ltca, the deck, what the file holds
  std::vector<std::string> notes;   ///< what the solid leaves out (the crank holes without a radius)
};

/// The deck's first disc as made, ready for ltca_step_write.
StepDisc MakeStepDisc(const Deck& deck, const geometry::RealPair& real);

}  // namespace ltca::app::documents
