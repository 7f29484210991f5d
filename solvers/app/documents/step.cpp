#include "documents/step.hpp"

#include <cmath>

#include <fmt/format.h>

#include "ltca/contact/holes.hpp"
#include "ltca/geometry/outline.hpp"
#include "ltca/solvers/reducer.hpp"

namespace ltca::app::documents {
namespace step_pieces {

void Flatten(const std::vector<std::vector<Eigen::Vector2d>>& pieces, std::vector<int>& offsets, std::vector<double>& xy) {
  offsets.assign(1, 0);
  for (const std::vector<Eigen::Vector2d>& piece : pieces) {
    for (const Eigen::Vector2d& p : piece) {
      xy.push_back(p.x());
      xy.push_back(p.y());
    }
    offsets.push_back(static_cast<int>(xy.size() / 2));
  }
}

}  // namespace step_pieces

StepDisc MakeStepDisc(const Deck& deck, const geometry::RealPair& real) {
  StepDisc disc;
  step_pieces::Flatten(geometry::OutlineSegments(real.profile(), kStepNodeSagitta), disc.piece_offsets, disc.points_xy);
  step_pieces::Flatten(geometry::OutlineSegments(real.profile(), kStepCheckSagitta), disc.check_offsets, disc.check_xy);
  disc.width_mm = real.nominal().face_width;
  if (deck.disc.bore_radius > 0.0) disc.holes_xyr.insert(disc.holes_xyr.end(), {0.0, 0.0, deck.disc.bore_radius});
  if (deck.reducer) {
    const solvers::ReducerSettings& reducer = *deck.reducer;
    if (reducer.kind == solvers::OutputKind::kPins) {
      const contact::OutputPins& w = reducer.pins;
      for (const Eigen::Vector2d& hole : contact::HolesInDisc(w.circle_radius, w.count, w.phase, w.hole_deviation)) {
        disc.holes_xyr.insert(disc.holes_xyr.end(), {hole.x(), hole.y(), w.hole_radius});
      }
    } else {
      disc.notes.push_back(fmt::format("the {} crank holes are not cut: the deck gives their centres, not their radius",
                                       reducer.cranks.count));
    }
  }
  disc.description = fmt::format("ltca {} geometry: the cycloid disc as made of deck '{}' ({}), extruded over {} mm",
                                 LTCA_VERSION, deck.name, CaseTitle(deck, 200), disc.width_mm);
  return disc;
}

}  // namespace ltca::app::documents
