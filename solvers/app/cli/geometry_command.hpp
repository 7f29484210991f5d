#pragma once
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "ltca/app/deck.hpp"
#include "output.hpp"

namespace ltca::cli {

struct GeometryOptions {
  std::string json_path;  ///< "" none, "-" stdout
  std::string csv_path;
  std::string svg_path;
  double crank_deg = 0.0;
  int samples_per_flank = 60;
};

/// `ltca geometry`: the derived geometry of the deck's pair, its profile and a drawing.
void RunGeometry(const app::Deck& deck, const GeometryOptions& options, const Streams& streams);

/// The summary document of `ltca geometry --json` (the default job nests it).
nlohmann::json GeometryJson(const app::Deck& deck);

}  // namespace ltca::cli
