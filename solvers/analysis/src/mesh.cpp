#include "ltca/analysis/mesh.hpp"

#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::analysis {

MeshResult MeshAt(const contact::MeshModel& model, double crank_deg) {
  const double crank = units::DegToRad(crank_deg);
  MeshResult result;
  result.crank_deg = crank_deg;
  result.slices = model.slice_count();
  result.state = model.Evaluate(crank);
  // A preloaded pair's negative clearances are its overlaps: tabulated as they are.
  return result;
}

}  // namespace ltca::analysis
