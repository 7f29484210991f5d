#pragma once
// Arc length along the real cycloid profile of one tooth space, measured from the root centre
// u = 0 and signed (+ toward u > 0):  s(u) = integral_0^u |x'(v)| dv, with x' = Evaluate(v).d1.
// The same in every tooth space (a tooth space is a rotated copy of the reference one).
//
// Accuracy: s is tabulated at 64 equal panels of [-phi_max, phi_max] (u = 0 is a panel edge);
// each panel and each partial panel is integrated by adaptive 8-point Gauss-Legendre (a panel is
// halved until two halves agree with the whole to 1e-14 relative), so s(u) is good to about 1e-13
// of the flank length. The inverse u(s) is a safeguarded Newton iteration (ds/du = |x'(u)| > 0)
// inside the panel found from the table, to a few ulp of u.
#include <vector>

#include "ltca/geometry/profile.hpp"

namespace ltca::geometry {

class ProfileArcLength {
 public:
  explicit ProfileArcLength(const CycloidProfile& profile);

  double phi_max() const { return profile_.phi_max(); }
  /// s(-phi_max) (< 0) and s(phi_max) (> 0), mm: the ends of the flank.
  double begin() const { return node_s_.front(); }
  double end() const { return node_s_.back(); }
  /// |x'(u)| = ds/du, mm/rad.
  double Speed(double u) const;
  /// s(u), mm, for |u| <= phi_max; throws std::out_of_range outside (not user input: callers
  /// check their ranges with their own message).
  double At(double u) const;
  /// The inverse: u with s(u) = s, for begin() <= s <= end(); throws std::out_of_range outside.
  double ParameterAt(double s) const;

 private:
  double FromNode(int panel, double u) const;  // s(u) for u in the panel

  CycloidProfile profile_;
  double h_ = 0.0;             // panel width in u
  std::vector<double> node_s_;  // s at the panel edges -phi_max + i h
};

}  // namespace ltca::geometry
