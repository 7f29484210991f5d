#pragma once
// The disc as made as a DXF drawing for CAD and the shop floor (docs/export.md): mm, the disc
// centre at the origin, its body frame at crank 0. Layers:
//   DISC_PROFILE  the modified profile (modification, profile layer, tip relief applied), one
//                 closed LWPOLYLINE whose chords stay within `sagitta` of the analytic curve
//                 (geometry::OutlinePolyline);
//   BORE          the central bore, a circle, when the deck gives one ([disc] bore_radius_mm);
//   HOLES         the holes of [output]: the output pins' holes (circles of r_h), or the crank
//                 holes' centres (points: the deck gives no crank-hole radius);
//   PIN_RING      the ring's pins as assembled, where they stand at crank 0 (circles of their radius);
//   OUTPUT_PINS   the output pins at crank 0 (circles of r_w), with [output] kind = "pins".
// Written with dxflib (DXF R2000, $INSUNITS = 4, millimetres); this part alone links it.
#include <string>

#include "ltca/app/deck.hpp"
#include "ltca/geometry/real_pair.hpp"

namespace ltca::app::documents {

/// The profile's default chord tolerance, mm: 0.1 um.
inline constexpr double kDxfSagitta = 1e-4;

/// The DXF text of the deck's first disc as made. `scratch_folder`: where dxflib (which writes
/// only to a named file) may put its private temporary, removed before this returns.
/// std::runtime_error when that cannot be written.
std::string Dxf(const Deck& deck, const geometry::RealPair& real, const std::string& scratch_folder,
                double sagitta = kDxfSagitta);

/// The profile's vertex count for the same tolerance (the text reports it).
std::size_t DxfProfileVertices(const geometry::RealPair& real, double sagitta = kDxfSagitta);

}  // namespace ltca::app::documents
