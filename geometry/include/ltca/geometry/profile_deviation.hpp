#pragma once
// A cycloid profile deviation that varies along the profile (Liu 2021 eq. 4, delta^{n_c i_c j_c};
// docs/contact.md, "Profile deviation along the profile"): a normal deviation delta(k, u), mm,
// of tooth space k at profile parameter u. delta > 0 adds material: the flank as made is at
//   x(u) + delta(k, u) n(u)      (n = ProfilePoint::normal, out of the material, toward the pin),
// the same sign as the uniform [errors] cycloid_profile_layer_mm. It is a function on the smooth
// analytic profile, not a displaced element surface. A random deviation with Liu's 800 elements
// changes by up to the zone within one element (14.5 um of arc on Liu Table 1), far faster than
// the gap to a pin opens away from the foot point: the clearance is then the minimum over u near
// the foot point of (gap(u) - delta(k, u)), as Liu's minimum over elements, not delta at the
// smooth foot point (docs/contact.md, "Profile deviation along the profile").
//
// Two sources, and their sum:
//  - random: Liu section 5.2, each element of each tooth space deviates at random within a
//    tolerance zone (uniform or truncated normal), from counter-based random numbers;
//  - measured: one trace of a gear measuring centre (CSV), applied to every tooth space.
// Both are tabulated once, at construction, against the CycloidProfile they are built for (pass
// the profile as made, RealPair::profile()); At() is then a binary search and one linear
// interpolation. Immutable; copies share the tables.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ltca/geometry/profile.hpp"

namespace ltca::geometry {

/// How the random value of an element is drawn within the zone of width `zone`.
enum class ProfileRandomDistribution {
  kUniform,  ///< U(-zone/2, zone/2): standard deviation zone / sqrt(12)
  kNormal,   ///< N(0, (zone/6)^2) truncated to [-zone/2, zone/2] (+-3 sigma) by rejection
};
/// "uniform" | "normal"; otherwise std::invalid_argument naming [errors] profile_random_distribution.
ProfileRandomDistribution ParseProfileRandomDistribution(const std::string& text);

/// Where the elements of a tooth space sit along the flank.
enum class ProfileElementSpacing {
  kArcLength,  ///< equal arc length (Liu eq. 3): element j is centred at s = S (j + 1/2) / n from
               ///< the flank's start, as DiscreteProfile's control points are
  kParameter,  ///< equal intervals of u in [-phi_max, phi_max]
};
/// "arc_length" | "parameter"; otherwise std::invalid_argument naming [errors] profile_random_spacing.
ProfileElementSpacing ParseProfileElementSpacing(const std::string& text);

/// The random per-element deviation (deck keys in brackets, [errors] section).
struct RandomProfileDeviation {
  double zone = 0.0;        ///< mm, full width of the tolerance zone, centred on the nominal
                            ///< profile (profile_random_zone_um); 0: no random deviation.
  int elements = 800;       ///< per tooth space (profile_random_elements; Liu: 800)
  std::uint64_t seed = 0;   ///< profile_random_seed
  ProfileRandomDistribution distribution = ProfileRandomDistribution::kUniform;  ///< profile_random_distribution
  ProfileElementSpacing spacing = ProfileElementSpacing::kArcLength;            ///< profile_random_spacing

  static constexpr int kMaxElements = 100'000;             ///< as [geometry] profile_elements
  static constexpr long long kMaxValues = 10'000'000;      ///< tooth_count x elements (80 MB)
  /// Throws std::invalid_argument naming the key, the value and what is expected: zone not finite
  /// or < 0, elements outside 1 .. kMaxElements, tooth_count x elements above kMaxValues.
  void Validate(int tooth_count) const;
};

/// Counter layout of the random deviation (docs/contact.md, "Profile deviation along the
/// profile"). Fixed: changing it changes the deviation every seed gives. The draw of element e
/// of tooth space k, attempt a, is at
///   stream = kRandomProfileStream + k,  index = e * kRandomProfileAttempts + a
/// under the seed. Uniform: zone (Uniform01 - 1/2) at attempt 0. Normal: the first attempt with
/// |StandardNormal| <= 3 gives zone / 6 * z; should all kRandomProfileAttempts attempts fail
/// (probability 0.0027^64 per element) the last is clipped to +-3.
inline constexpr std::uint64_t kRandomProfileStream = std::uint64_t{1} << 32;
inline constexpr std::uint64_t kRandomProfileAttempts = 64;

/// A measured profile trace as read from its CSV (ParseMeasuredProfile), internal units.
struct MeasuredProfile {
  enum class Abscissa {
    kProfileAngle,  ///< the profile parameter u, rad (CSV column profile_angle_deg)
    kArcLength,     ///< arc length from the root centre u = 0, signed, + toward u > 0, mm (arc_length_mm)
  };
  std::string source;              ///< for messages: the file name
  Abscissa abscissa = Abscissa::kProfileAngle;
  std::vector<double> x;           ///< abscissae, strictly increasing, rad or mm
  std::vector<double> deviation;   ///< normal deviation, mm (+ adds material)
  std::vector<int> line;           ///< 1-based line of each row in the source
};

/// Parses the CSV a gear measuring centre exports, given as text (the app reads the file):
///   # comment lines and blank lines are skipped anywhere
///   profile_angle_deg, deviation_um        <- header: the abscissa, then deviation_um
///   -4.5, 1.2                              <- rows: abscissa, normal deviation in um
/// The abscissa is profile_angle_deg (the profile parameter u in degrees) or arc_length_mm (arc
/// length along the flank from the root centre u = 0, signed, + toward u > 0). Fields are
/// separated by a comma or by whitespace; at least 2 rows; every value finite; abscissae strictly
/// increasing. Throws std::invalid_argument "<source>: line <n>: <what is wrong>, expected ...".
MeasuredProfile ParseMeasuredProfile(const std::string& text, const std::string& source_name);

class ProfileDeviation {
 public:
  /// No deviation.
  ProfileDeviation() = default;

  /// Liu section 5.2: element e of tooth space k deviates by its own draw (the counter layout
  /// above). delta is piecewise linear in u between the element centres and constant beyond the
  /// outer centres, so it is continuous in u and stays within the zone. Validates `random`
  /// against the profile's tooth count. A zero zone gives no deviation.
  static ProfileDeviation Random(const RandomProfileDeviation& random, const CycloidProfile& profile);
  /// The measured trace on every tooth space: linear in u between the measured points, constant
  /// beyond the first and the last. Arc-length abscissae are converted to u once, here, along
  /// `profile`. Every point must lie on the flank, |u| <= phi_max, or beyond an end by at most
  /// 1e-3 of the half flank (rounding in the file: an angle is kept as it is, an arc length is
  /// continued beyond the end at the end's speed); otherwise std::invalid_argument naming the
  /// source, the line and the range.
  static ProfileDeviation Measured(const MeasuredProfile& trace, const CycloidProfile& profile);
  /// a + b (both built for the same profile; std::invalid_argument if their tooth counts differ).
  static ProfileDeviation Sum(const ProfileDeviation& a, const ProfileDeviation& b);

  /// True when At is 0 everywhere.
  bool IsZero() const { return terms_.empty(); }
  /// delta(k, u), mm (> 0 adds material). Any tooth space k (taken modulo the tooth count, as
  /// CycloidProfile does); any u (constant beyond the tabulated ends). 0 when IsZero().
  double At(int tooth_space, double u) const;
  /// An upper bound of |At| over all k and u, mm (exact for a single source).
  double MaxAbs() const;
  /// Tooth count of the profile it was built for (0 when IsZero()).
  int tooth_count() const { return tooth_count_; }
  /// Appends to `nodes` the abscissae u in the open interval (lo, hi) where delta has a kink
  /// (the knots of every source: the same on every tooth space), sorted and without repeats.
  /// Between two consecutive nodes delta is linear in u on every tooth space: a smooth function
  /// minus delta has its minimum there at a node or where its derivative vanishes.
  void NodesIn(double lo, double hi, std::vector<double>* nodes) const;

 private:
  struct Table {
    std::vector<double> knots;   // u, strictly increasing
    std::vector<double> values;  // knots.size() values per tooth space (or one shared row)
    bool per_tooth_space = false;
  };
  static double Interpolate(const Table& table, int row, double u);

  std::vector<std::shared_ptr<const Table>> terms_;
  int tooth_count_ = 0;
};

}  // namespace ltca::geometry
