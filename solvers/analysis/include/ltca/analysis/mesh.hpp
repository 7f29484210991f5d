#pragma once
// The unloaded mesh state of a pair at one crank: every pin's (and slice's) clearance, moment arm,
// curvatures and contact point in the unloaded pose. `ltca mesh`, the report and the Python module
// build their documents from it.
#include "ltca/contact/mesh_state.hpp"

namespace ltca::analysis {

/// The mesh state at one crank and what ran.
struct MeshResult {
  double crank_deg = 0.0;    ///< the crank as asked, deg (the documents give it as asked, not via rad)
  int slices = 1;            ///< the model's face-width slices: more than one, a row per pin and slice
  contact::MeshState state;  ///< the model's contacts at the crank, unloaded (mm, rad)
};

/// The state of `model` (a disc's mesh: [second_disc] is not in it) at `crank_deg`, unloaded at
/// the theoretical position: a preloaded pair's negative clearances are its overlaps.
MeshResult MeshAt(const contact::MeshModel& model, double crank_deg);

}  // namespace ltca::analysis
