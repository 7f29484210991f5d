#include "ltca/contact/pin_bending.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "ltca/geometry/units.hpp"

namespace ltca::contact {
namespace {

using units::kPi;

// 6-point Gauss-Legendre on [-1, 1]: exact for polynomials of degree <= 11.
constexpr std::array<double, 6> kGaussX = {-0.9324695142031521, -0.6612093864662645, -0.2386191860831969,
                                           0.2386191860831969,  0.6612093864662645,  0.9324695142031521};
constexpr std::array<double, 6> kGaussW = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
                                           0.4679139345726910, 0.3607615730481386, 0.1713244923791704};

// int_lo^hi f(t) dt by the 6-point rule.
template <typename F>
double Gauss(double lo, double hi, F&& f) {
  const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  double sum = 0.0;
  for (std::size_t k = 0; k < kGaussX.size(); ++k) sum += kGaussW[k] * f(mid + half * kGaussX[k]);
  return half * sum;
}

}  // namespace

PinSupportKind ParsePinSupport(const std::string& text) {
  if (text == "simply-supported") return PinSupportKind::kSimplySupported;
  if (text == "clamped") return PinSupportKind::kClamped;
  throw std::invalid_argument(
      fmt::format("[pins] support = \"{}\": expected \"simply-supported\" or \"clamped\"", text));
}

const char* ToString(PinSupportKind kind) {
  switch (kind) {
    case PinSupportKind::kSimplySupported: return "simply-supported";
    case PinSupportKind::kClamped: return "clamped";
  }
  return "?";
}

void PinSupport::Validate(double face_width) const {
  if (!(std::isfinite(span) && span > 0.0 && span <= kMaxSpan)) {
    throw std::invalid_argument(fmt::format(
        "[pins] span_mm = {}: expected a finite distance between the pin supports > 0 and at most {:g} mm", span, kMaxSpan));
  }
  if (!(std::isfinite(face_offset) && face_offset >= 0.0)) {
    throw std::invalid_argument(fmt::format(
        "[pins] face_offset_mm = {}: expected a finite distance >= 0 mm from the first support to the cycloid face",
        face_offset));
  }
  if (support != PinSupportKind::kSimplySupported && support != PinSupportKind::kClamped) {
    throw std::invalid_argument(fmt::format("[pins] support = {}: expected \"simply-supported\" or \"clamped\"",
                                            static_cast<int>(support)));
  }
  if (face_width > 0.0 && face_offset + face_width > span * (1.0 + 1e-12)) {
    throw std::invalid_argument(fmt::format(
        "[pins] face_offset_mm = {}: the face (width {} mm) must lie between the supports: expected "
        "face_offset_mm + face width <= span_mm = {}",
        face_offset, face_width, span));
  }
}

double PinBeam::ShearCoefficient(double poisson_ratio) {
  return 6.0 * (1.0 + poisson_ratio) / (7.0 + 6.0 * poisson_ratio);  // Cowper 1966, solid circle
}

PinBeam::PinBeam(const PinSupport& support, const Material& material, double pin_radius) : support_(support) {
  support_.Validate();
  if (!(std::isfinite(pin_radius) && pin_radius > 0.0)) {
    throw std::invalid_argument(fmt::format("pin bending: pin radius {} mm: expected a finite radius > 0", pin_radius));
  }
  const double e = material.pin_young_modulus, nu = material.pin_poisson_ratio;
  if (!(std::isfinite(e) && e > 0.0)) {
    throw std::invalid_argument(fmt::format("[material] pin_young_modulus_mpa = {}: expected a finite modulus > 0", e));
  }
  if (!(nu >= 0.0 && nu < 0.5)) {
    throw std::invalid_argument(fmt::format("[material] pin_poisson_ratio = {}: expected a Poisson ratio in [0, 0.5)", nu));
  }
  const double r2 = pin_radius * pin_radius;
  ei_ = e * kPi * r2 * r2 / 4.0;
  kga_ = ShearCoefficient(nu) * e / (2.0 * (1.0 + nu)) * kPi * r2;
}

double PinBeam::Deflection(double x, double a) const {
  const double l = support_.span;
  if (!(x >= 0.0 && x <= l && a >= 0.0 && a <= l)) {
    throw std::invalid_argument(
        fmt::format("pin bending: deflection at x = {} mm under a load at a = {} mm: both must lie in [0, span_mm = {}]",
                    x, a, l));
  }
  const double b = l - a;
  double v = 0.0;
  // Simply supported: bending (Euler-Bernoulli) and shear (V / (kappa G A), V = b / L left of the load).
  if (x <= a) {
    v = b * x * (l * l - b * b - x * x) / (6.0 * ei_ * l) + x * b / (l * kga_);
  } else {
    const double xr = l - x;
    v = a * xr * (l * l - a * a - xr * xr) / (6.0 * ei_ * l) + a * xr / (l * kga_);
  }
  if (support_.support == PinSupportKind::kClamped) {
    // Redundant end moments from zero section rotation at both ends (unit-load method with the
    // shear's complementary energy): M_A + M_B = -a b / L, M_B - M_A = a b (b - a) / (L^2 + 12 phi).
    const double phi = ei_ / kga_;
    const double sum = -a * b / l, diff = a * b * (b - a) / (l * l + 12.0 * phi);
    const double m_a = 0.5 * (sum - diff), m_b = 0.5 * (sum + diff);
    v += x * (l - x) * (m_a * (2.0 * l - x) + m_b * (l + x)) / (6.0 * ei_ * l);
  }
  return v;
}

void PinBeam::ValidateSlices(double face_width, int n_slices) const {
  if (!(std::isfinite(face_width) && face_width > 0.0)) {
    throw std::invalid_argument(fmt::format("pin bending: face width {} mm: expected a finite width > 0", face_width));
  }
  if (n_slices < 1) {
    throw std::invalid_argument(fmt::format("pin bending: {} slices: expected at least 1", n_slices));
  }
  support_.Validate(face_width);
}

Eigen::MatrixXd PinBeam::SliceCompliance(double face_width, int n_slices) const {
  ValidateSlices(face_width, n_slices);
  const double w = face_width / n_slices;
  const double l = support_.span;
  const auto start = [&](int k) { return std::min(support_.face_offset + k * w, l); };
  Eigen::MatrixXd c(n_slices, n_slices);
  for (int i = 0; i < n_slices; ++i) {
    const double xi0 = start(i), xi1 = start(i + 1);
    for (int j = i; j < n_slices; ++j) {
      const double aj0 = start(j), aj1 = start(j + 1);
      double integral = 0.0;
      if (i == j) {
        // The kink at x = a: integrate a over [x0, x] and [x, x1] separately (each a polynomial).
        integral = Gauss(xi0, xi1, [&](double x) {
          return Gauss(xi0, x, [&](double a) { return Deflection(x, a); }) +
                 Gauss(x, xi1, [&](double a) { return Deflection(x, a); });
        });
      } else {
        integral = Gauss(xi0, xi1, [&](double x) { return Gauss(aj0, aj1, [&](double a) { return Deflection(x, a); }); });
      }
      c(i, j) = c(j, i) = integral / (w * w);
    }
  }
  return c;
}

PinBeam::SliceBeam PinBeam::SliceBeamModel(double face_width, int n_slices) const {
  ValidateSlices(face_width, n_slices);
  const double w = face_width / n_slices;
  const double span = support_.span;
  // Nodes: first support, face B, the slice boundaries, the far face, the second support.
  std::vector<double> nodes;
  const double tiny = 1e-12 * span;
  if (support_.face_offset > tiny) nodes.push_back(0.0);
  const int first_slice_node = static_cast<int>(nodes.size());
  for (int k = 0; k <= n_slices; ++k) nodes.push_back(std::min(support_.face_offset + k * w, span));
  if (span - nodes.back() > tiny) {
    nodes.push_back(span);
  } else {
    nodes.back() = span;
  }
  if (first_slice_node == 0) nodes.front() = 0.0;
  const int count = static_cast<int>(nodes.size());
  // Dofs (w, theta) per node, the fixed ones removed.
  std::vector<int> dof(static_cast<std::size_t>(2 * count), -1);
  const bool clamped = support_.support == PinSupportKind::kClamped;
  int dofs = 0;
  for (int k = 0; k < count; ++k) {
    const bool end = k == 0 || k == count - 1;
    if (!end) dof[static_cast<std::size_t>(2 * k)] = dofs++;
    if (!end || !clamped) dof[static_cast<std::size_t>(2 * k + 1)] = dofs++;
  }
  std::vector<Eigen::Triplet<double>> kt, bt;
  for (int e = 0; e + 1 < count; ++e) {
    const double l = nodes[static_cast<std::size_t>(e + 1)] - nodes[static_cast<std::size_t>(e)];
    const double phi = 12.0 * ei_ / (kga_ * l * l);
    Eigen::Matrix4d ke;
    ke << 12, 6 * l, -12, 6 * l,  //
        6 * l, (4 + phi) * l * l, -6 * l, (2 - phi) * l * l,  //
        -12, -6 * l, 12, -6 * l,  //
        6 * l, (2 - phi) * l * l, -6 * l, (4 + phi) * l * l;
    ke *= ei_ / ((1 + phi) * l * l * l);
    const std::array<int, 4> at = {dof[static_cast<std::size_t>(2 * e)], dof[static_cast<std::size_t>(2 * e + 1)],
                                   dof[static_cast<std::size_t>(2 * e + 2)], dof[static_cast<std::size_t>(2 * e + 3)]};
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) {
        if (at[static_cast<std::size_t>(r)] >= 0 && at[static_cast<std::size_t>(c)] >= 0) {
          kt.emplace_back(at[static_cast<std::size_t>(r)], at[static_cast<std::size_t>(c)], ke(r, c));
        }
      }
    }
    const int slice = e - first_slice_node;
    if (slice < 0 || slice >= n_slices) continue;
    const std::array<double, 4> mean = {0.5, l / 12.0, 0.5, -l / 12.0};
    for (int r = 0; r < 4; ++r) {
      if (at[static_cast<std::size_t>(r)] >= 0) bt.emplace_back(slice, at[static_cast<std::size_t>(r)], mean[static_cast<std::size_t>(r)]);
    }
  }
  SliceBeam out;
  out.stiffness.resize(dofs, dofs);
  out.stiffness.setFromTriplets(kt.begin(), kt.end());
  out.loads.resize(n_slices, dofs);
  out.loads.setFromTriplets(bt.begin(), bt.end());
  out.local = Eigen::VectorXd::Constant(n_slices, w * w * w / (720.0 * ei_) + w / (12.0 * kga_));
  return out;
}

namespace {

// The points grouped by pin: (slice, point index), slices sorted and checked to be 0 .. n - 1 of length B / n.
std::map<int, std::vector<std::pair<int, int>>> GroupPinSlices(const std::vector<PinContact>& points, double face_width) {
  std::map<int, std::vector<std::pair<int, int>>> pins;
  for (std::size_t k = 0; k < points.size(); ++k) pins[points[k].pin].emplace_back(points[k].slice, static_cast<int>(k));
  for (auto& [pin, slices] : pins) {
    std::sort(slices.begin(), slices.end());
    const int n = static_cast<int>(slices.size());
    for (int k = 0; k < n; ++k) {
      if (slices[static_cast<std::size_t>(k)].first != k) {
        throw std::invalid_argument(fmt::format(
            "pin bending: pin {} has {} contact points whose slices are not 0 .. {} each once (slice {} found)",
            pin + 1, n, n - 1, slices[static_cast<std::size_t>(k)].first));
      }
      const double length = points[static_cast<std::size_t>(slices[static_cast<std::size_t>(k)].second)].length;
      if (!(std::abs(length - face_width / n) <= 1e-9 * face_width)) {
        throw std::invalid_argument(fmt::format(
            "pin bending: pin {}, slice {} has contact length {} mm: expected the face width {} mm / {} slices",
            pin + 1, k, length, face_width, n));
      }
    }
  }
  return pins;
}

}  // namespace

FactoredPinBending PinBendingFactors(const std::vector<PinContact>& points, const PinBeam& beam, double face_width) {
  const auto pins = GroupPinSlices(points, face_width);
  std::map<int, PinBeam::SliceBeam> models;  // by slice count
  std::vector<Eigen::Triplet<double>> kt, bt;
  FactoredPinBending out;
  out.local = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(points.size()));
  int offset = 0;
  for (const auto& [pin, slices] : pins) {
    const int n = static_cast<int>(slices.size());
    auto it = models.find(n);
    if (it == models.end()) it = models.emplace(n, beam.SliceBeamModel(face_width, n)).first;
    const PinBeam::SliceBeam& m = it->second;
    for (int k = 0; k < m.stiffness.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator e(m.stiffness, k); e; ++e) {
        kt.emplace_back(offset + static_cast<int>(e.row()), offset + static_cast<int>(e.col()), e.value());
      }
    }
    const Eigen::SparseMatrix<double, Eigen::RowMajor> rows = m.loads;
    for (int s = 0; s < n; ++s) {
      const int point = slices[static_cast<std::size_t>(s)].second;
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator e(rows, s); e; ++e) {
        bt.emplace_back(point, offset + static_cast<int>(e.col()), e.value());
      }
      out.local(point) = m.local(s);
    }
    offset += static_cast<int>(m.stiffness.rows());
  }
  out.stiffness.resize(offset, offset);
  out.stiffness.setFromTriplets(kt.begin(), kt.end());
  out.loads.resize(static_cast<Eigen::Index>(points.size()), offset);
  out.loads.setFromTriplets(bt.begin(), bt.end());
  return out;
}

Eigen::SparseMatrix<double> PinBendingCoupling(const std::vector<PinContact>& points, const PinBeam& beam,
                                               double face_width) {
  const auto pins = GroupPinSlices(points, face_width);
  std::map<int, Eigen::MatrixXd> blocks;  // by slice count
  // Built column by column (compressed, rows ascending): a pin's points in point order.
  const auto size = static_cast<Eigen::Index>(points.size());
  std::vector<const Eigen::MatrixXd*> block_of(points.size(), nullptr);
  std::vector<const std::vector<std::pair<int, int>>*> pin_of(points.size(), nullptr);
  std::map<int, std::vector<std::pair<int, int>>> by_point;  // per pin: (point, slice), point ascending
  Eigen::Index nnz = 0;
  for (const auto& [pin, slices] : pins) {
    const int n = static_cast<int>(slices.size());
    auto it = blocks.find(n);
    if (it == blocks.end()) it = blocks.emplace(n, beam.SliceCompliance(face_width, n)).first;
    std::vector<std::pair<int, int>>& order = by_point[pin];
    for (const auto& [slice, point] : slices) order.emplace_back(point, slice);
    std::sort(order.begin(), order.end());
    for (const auto& [slice, point] : slices) {
      block_of[static_cast<std::size_t>(point)] = &it->second;
      pin_of[static_cast<std::size_t>(point)] = &order;
    }
    nnz += static_cast<Eigen::Index>(n) * n;
  }
  Eigen::SparseMatrix<double> out(size, size);
  out.resizeNonZeros(nnz);
  auto* outer = out.outerIndexPtr();
  auto* inner = out.innerIndexPtr();
  auto* value = out.valuePtr();
  Eigen::Index p = 0;
  for (Eigen::Index j = 0; j < size; ++j) {
    outer[j] = static_cast<int>(p);
    const Eigen::MatrixXd& c = *block_of[static_cast<std::size_t>(j)];
    const int sj = points[static_cast<std::size_t>(j)].slice;
    for (const auto& [point, slice] : *pin_of[static_cast<std::size_t>(j)]) {
      inner[p] = point;
      value[p++] = c(slice, sj);
    }
  }
  outer[size] = static_cast<int>(p);
  return out;
}

}  // namespace ltca::contact
