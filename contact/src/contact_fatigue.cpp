#include "ltca/contact/contact_fatigue.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <span>

namespace ltca::contact {
namespace {

struct Point {
  double cycles;
  double factor;
};

/// The points of each curve (ISO 6336-2:2006, the life-factor table of method B); between
/// them Z_NT is a straight line in log N and log Z_NT (e.g. Z_NT = (5e7 / N)^0.0756 from 1e5 to 5e7
/// on kSteel), flat before the first and after the last.
std::span<const Point> Points(LifeCurve curve) {
  static constexpr std::array<Point, 3> kSteel{{{1e5, 1.6}, {5e7, 1.0}, {1e10, 0.85}}};
  static constexpr std::array<Point, 4> kLimited{{{6e5, 1.6}, {1e7, 1.3}, {1e9, 1.0}, {1e10, 0.85}}};
  static constexpr std::array<Point, 3> kNitrided{{{1e5, 1.3}, {2e6, 1.0}, {1e10, 0.85}}};
  static constexpr std::array<Point, 3> kNitrocarburized{{{1e5, 1.1}, {2e6, 1.0}, {1e10, 0.85}}};
  switch (curve) {
    case LifeCurve::kSteelLimitedPitting: return kLimited;
    case LifeCurve::kNitrided: return kNitrided;
    case LifeCurve::kNitrocarburized: return kNitrocarburized;
    case LifeCurve::kSteel: break;
  }
  return kSteel;
}

}  // namespace

const char* ToString(LifeCurve curve) {
  switch (curve) {
    case LifeCurve::kSteelLimitedPitting: return "steel-limited-pitting";
    case LifeCurve::kNitrided: return "nitrided";
    case LifeCurve::kNitrocarburized: return "nitrocarburized";
    case LifeCurve::kSteel: break;
  }
  return "steel";
}

double LifeFactor(LifeCurve curve, double cycles) {
  const std::span<const Point> p = Points(curve);
  if (!(cycles > p.front().cycles)) return p.front().factor;
  for (std::size_t k = 1; k < p.size(); ++k) {
    if (cycles <= p[k].cycles) {
      const double t = std::log(cycles / p[k - 1].cycles) / std::log(p[k].cycles / p[k - 1].cycles);
      return p[k - 1].factor * std::pow(p[k].factor / p[k - 1].factor, t);
    }
  }
  return p.back().factor;
}

double CyclesToPitting(LifeCurve curve, double sigma_hlim, double stress) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::span<const Point> p = Points(curve);
  if (!(stress > 0.0)) return kInf;
  const double z = stress / sigma_hlim;  // the life factor the stress needs
  if (z <= p.back().factor) return kInf;
  // Above the static value the loop's first segment is extended (ISO 6336-6:2019 Annex C).
  for (std::size_t k = 1; k < p.size(); ++k) {
    if (z >= p[k].factor) {
      if (p[k].factor == p[k - 1].factor) return p[k].cycles;  // a flat step (none in the table)
      const double t = std::log(z / p[k - 1].factor) / std::log(p[k].factor / p[k - 1].factor);
      return p[k - 1].cycles * std::pow(p[k].cycles / p[k - 1].cycles, t);
    }
  }
  return kInf;
}

}  // namespace ltca::contact
