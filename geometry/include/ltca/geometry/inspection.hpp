#pragma once
// The figures an inspector measures on the cycloid as made (modification, profile layer and tip
// relief applied; the profile deviation along the profile is not): the root and tip diameters and
// the dimension over two rollers. Body frame, mm (docs/export.md).
//
// Root and tip: the root circle runs through the bottoms of the tooth spaces, the tip circle
// through the tips of the teeth. For d > 0 (an external disc) they are the least and the largest
// diameter of the profile, 2 (R' - e - r') and, without relief, 2 |x(phi_max)| (2 (R' + e - r')
// for |d| = 1); for d < 0 (a ring, whose teeth point inward) the root is the largest diameter
// and the tip the least.
//
// A roller of diameter D_M seated in a tooth space: its centre on the space's symmetry axis at the
// radius s where, pushed along the axis into the space (toward the centre for d > 0, outward for a
// ring), it first touches the profile:
//   d > 0: s = max over profile points (x, y) with |y| <= D_M / 2 of x + sqrt((D_M/2)^2 - y^2),
//   d < 0: s = min over them of x - sqrt((D_M/2)^2 - y^2),
// with x along the axis and y across it. It touches both flanks at +-u (or rests on the root when
// D_M / 2 is at most the root's concave radius of curvature: so does every roller no larger than
// the generating pin, 2 r'; with D_M = 2 r' on the unmodified profile s = R_p - e exactly, the
// pin's centre on the pin circle at the mesh). The dimension over rollers, two rollers in the
// spaces nearest to opposite (gear metrology's M_d, ISO 21771 / DIN 3960):
//   z_c even: M = 2 s + D_M  (d > 0), 2 s - D_M (a ring: between the rollers);
//   z_c odd:  M = 2 s cos(pi / (2 z_c)) +- D_M, the spaces pi (1 - 1/z_c) apart, measured along
//             the line through the two roller centres (the chord 2 s sin(pi (1 - 1/z_c) / 2)).
#include <optional>

#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/tip_relief.hpp"

namespace ltca::geometry {

/// Diameter of the root circle, through the bottoms of the tooth spaces, mm.
double RootDiameter(const CycloidProfile& profile);
/// Diameter of the tip circle, through the tips of the teeth (the relieved tips when there is a
/// relief: the largest diameter of the cap for d > 0, the least for a ring), mm.
double TipDiameter(const CycloidProfile& profile);

/// Where a seated roller touches the profile.
enum class RollerContact : unsigned char {
  kFlanks,  ///< both working flanks at +-u, strictly between root and tip: a valid measurement
  kRoot,    ///< the bottom of the space (the roller is no larger than the root's concave radius)
  kTips,    ///< the tips or their relief (the roller is too large for the space)
};
/// "flanks", "root", "tips".
const char* RollerContactName(RollerContact contact);

/// A roller seated in tooth space 0 and the dimension over two rollers.
struct RollerMeasurement {
  double roller_diameter = 0.0;  ///< D_M, mm
  double centre_radius = 0.0;    ///< s: roller centre from the disc centre, on the space's axis, mm
  RollerContact contact = RollerContact::kFlanks;
  double contact_u = 0.0;        ///< |u| of the contact on the flank, rad (0 or phi_max: root; on a cap: NaN)
  double contact_diameter = 0.0; ///< diameter of the circle through the contact points, mm
  double dimension = 0.0;        ///< M over (d > 0) or between (d < 0) the two rollers, mm
  /// Both contact points on the working flanks (contact == kFlanks).
  bool OnWorkingFlanks() const { return contact == RollerContact::kFlanks; }
};

/// Seats a roller of diameter `roller_diameter` (mm, > 0 and finite: std::invalid_argument naming
/// [inspection] roller_diameter_mm otherwise) and measures over two (the header's equations).
RollerMeasurement MeasureOverRollers(const CycloidProfile& profile, double roller_diameter);

}  // namespace ltca::geometry
