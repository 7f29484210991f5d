#pragma once
#include <ostream>
#include <string>

#include "ltca/app/deck.hpp"
#include "output.hpp"

namespace ltca::cli {

struct GeometryOptions {
  std::string json_path;  ///< "" none, "-" stdout
  std::string csv_path;
  std::string svg_path;
  std::string dxf_path;   ///< the disc as a DXF drawing (docs/export.md)
  std::string step_path;  ///< the disc as a STEP solid, written by the module ltca_step.so (docs/export.md)
  std::string deviation_csv_path;  ///< the deviation chart of [errors] profile_measured_csv as CSV
  std::string deviation_svg_path;  ///< and as a figure
  double crank_deg = 0.0;
  int samples_per_flank = 60;
};

/// `ltca geometry`: the derived geometry of the deck's pair, its profile and a drawing.
/// Returns the exit code: kExitNotSucceeded, nothing written, when --step is asked and the STEP
/// writer module cannot be loaded.
int RunGeometry(const app::Deck& deck, const GeometryOptions& options, const Streams& streams);

}  // namespace ltca::cli
