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
  double crank_deg = 0.0;
  int samples_per_flank = 60;
};

/// `ltca geometry`: the derived geometry of the deck's pair, its profile and a drawing.
void RunGeometry(const app::Deck& deck, const GeometryOptions& options, const Streams& streams);

}  // namespace ltca::cli
