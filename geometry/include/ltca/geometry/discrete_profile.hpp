#pragma once
// Liu 2021 section 2: the cycloid tooth surface discretised into elements of equal arc length along
// the profile (eq. 3: the profile parameter as a fitted polynomial of arc length) and into slices
// across the face width. Each element is an equivalent cylinder: control point, unit normal
// (eq. 10), signed radius of curvature (eq. 8), and a profile deviation (eq. 4, delta^{n i j}; zero
// here, the slot the manufacturing-error work fills). Built from the analytic profile, so the two
// geometry modes share one curve; only the representation differs.
#include <vector>

#include <Eigen/Core>

#include "ltca/geometry/profile.hpp"

namespace ltca::geometry {

/// The [geometry] section: how the cycloid surface is represented.
struct GeometrySettings {
  enum class Mode { kAnalytic, kElements };
  Mode mode = Mode::kAnalytic;
  int profile_elements = 800;  ///< elements along one tooth space (Liu: 800)
  int width_slices = 100;      ///< slices across the face width (Liu: 100)
  /// Limits (docs/decks.md): the cost of one pin evaluation grows with elements x slices (Liu's
  /// 800 x 100 takes about 1.2 s per position), so the product is capped at 12.5 times Liu's.
  static constexpr int kMaxProfileElements = 100'000;
  static constexpr int kMaxWidthSlices = 1'000;
  static constexpr long long kMaxElementsTimesSlices = 1'000'000;
  /// Throws std::invalid_argument naming the key: in elements mode fewer than 2 elements or 1
  /// slice; in any mode a value above its limit.
  void Validate() const;
};

struct ProfileElement {
  double u = 0.0;                     ///< profile parameter of the control point (from eq. 3)
  Eigen::Vector2d position;           ///< control point, body frame (reference tooth space), mm
  Eigen::Vector2d normal;             ///< unit, out of the material
  double curvature = 0.0;             ///< 1/mm, signed (+ convex), Liu eq. 8
  double deviation = 0.0;             ///< profile deviation of the element, mm (+ adds material)
};

class DiscreteProfile {
 public:
  /// elements: per tooth space (Liu: 800); slices: across the face width (Liu: 100);
  /// polynomial_order: N of eq. 3.
  DiscreteProfile(const CycloidProfile& profile, int elements, int slices, int polynomial_order = 9);

  const CycloidProfile& profile() const { return profile_; }
  int slices() const { return slices_; }
  double arc_length() const { return arc_length_; }  ///< S_c of one tooth space, mm
  /// Largest |u_fit(s) - u(s)| at the fitting samples, rad: the error of Liu's eq. 3 polynomial
  /// (it only seeds the exact placement of the control points, see the .cpp).
  double fit_error() const { return fit_error_; }
  /// Elements of the reference tooth space (u from -phi_max to phi_max); the same in every slice
  /// until deviations are set.
  const std::vector<ProfileElement>& elements() const { return elements_; }
  /// Element j of tooth space k, in the body frame.
  ProfileElement Element(int j, int tooth_space) const;
  int element_count() const { return static_cast<int>(elements_.size()); }

 private:
  CycloidProfile profile_;  // a copy: the discrete profile stays valid on its own
  int slices_;
  double arc_length_ = 0.0;
  double fit_error_ = 0.0;
  std::vector<ProfileElement> elements_;
};

}  // namespace ltca::geometry
