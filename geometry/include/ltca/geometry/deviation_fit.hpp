#pragma once
// The deviation chart of a measured profile trace (docs/export.md, "Deviation chart"): the normal
// deviation of a profile from the design along the profile parameter u, and the generating
// modification (offset dR_p, isometric dR_rp, rotation) that best explains a trace.
//
// Normal deviation. The design profile x(u), n(u) its unit normal out of the material (toward
// the pin). A profile made with the design's modification plus dm deviates at u by the t with
//   x_dm(u') = x(u) + t n(u)
// for some u' (the point where the design's normal line at u meets the other profile; Newton in
// (u', t) from (u, 0)); t > 0 adds material, the sign of [errors] profile_measured_csv
// (geometry/profile_deviation.hpp). An isometric dm_rp alone gives t = -dm_rp exactly (the profile
// is the equidistant of the pin-centre locus at r_rp + dR_rp).
//
// The fit. Least squares of the trace's values delta_i at u_i against t(u_i; dm) over
// dm = (dR_p, dR_rp, rotation), solved by Gauss-Newton: each step the linear least-squares
// problem of the Jacobian (central differences of t, 1e-5 mm and 1e-7 rad) by Eigen's
// column-pivoting Householder QR, until the step is below 1e-12 mm (rotation times R_p); a trace
// made from a modification returns it (no linearisation error). The trace must cover both flanks
// (otherwise offset, isometric and rotation are not told apart: std::invalid_argument).
#include <vector>

#include "ltca/geometry/profile.hpp"

namespace ltca::geometry {

/// Normal deviation t(u) of tooth space 0 of `design` made with its modification plus `delta`
/// (dR_p, dR_rp, rotation; the tip relief of `design` kept), mm, + adds material.
double ModificationDeviation(const CycloidProfile& design, const Modification& delta, double u);

/// The fitted modification and how well it explains the trace.
struct DeviationFit {
  double offset = 0.0;         ///< dR_p, mm (the offset modification's change)
  double isometric = 0.0;      ///< dR_rp, mm (the isometric modification's change)
  double rotation = 0.0;       ///< rad
  double rms_residual = 0.0;   ///< mm, of trace minus fit at the trace's points
  double max_residual = 0.0;   ///< mm, largest |trace - fit|
  int iterations = 0;          ///< Gauss-Newton steps
  Modification AsModification() const;
};

/// Fits dm to the trace (u_i rad on the flank of tooth space 0, delta_i mm). std::invalid_argument
/// when the sizes differ, there are fewer than 3 points, or the points do not lie on both flanks
/// (some u_i < 0 and some > 0 for d > 0; both sides of a tip for a ring).
DeviationFit FitModification(const CycloidProfile& design, const std::vector<double>& u, const std::vector<double>& delta);

}  // namespace ltca::geometry
