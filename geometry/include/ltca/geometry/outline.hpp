#pragma once
// The closed outline of the cycloid as made (modification, profile layer and tip relief applied)
// as a polyline for CAD: vertices on the analytic curve, spaced by its curvature so that no chord
// strays from the curve by more than a given sagitta (docs/export.md).
#include <vector>

#include <Eigen/Core>

#include "ltca/geometry/profile.hpp"

namespace ltca::geometry {

/// The outline, body frame (mm, disc centre at the origin), counter-clockwise, tooth space by
/// tooth space as `ltca geometry --csv` runs (space k's flank, then the cap of its tip), each vertex
/// once (the polyline closes from the last back to the first). Every chord's sagitta is at most
/// `sagitta` (mm, > 0): on a flank the step in u is h / |x'(u)| with h = sqrt(8 rho sagitta / 2),
/// rho the least |radius of curvature| at the step's two ends and its middle (the chord sagitta
/// h^2 / (8 rho), kept at half the bound for the curvature's change over the step); a cap is cut
/// evenly in arc length by the same rule on its rounding radius (one chord on a straight land).
/// Corners (sharp tips, junctions) are vertices.
std::vector<Eigen::Vector2d> OutlinePolyline(const CycloidProfile& profile, double sagitta);

/// The same outline in its smooth pieces, in the same order: each tooth space's flank (two for a
/// ring with a tip relief) and each tip relief's cap, a piece's last point the next one's first
/// (the last piece's the first's). The joints are where the curve may have a corner (a sharp tip,
/// a junction); OutlinePolyline is their concatenation. For CAD curves fitted piece by piece (the
/// STEP solid's B-splines, docs/export.md).
std::vector<std::vector<Eigen::Vector2d>> OutlineSegments(const CycloidProfile& profile, double sagitta);

}  // namespace ltca::geometry
