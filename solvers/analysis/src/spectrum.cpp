#include "ltca/analysis/spectrum.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "ltca/analysis/friction.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::analysis {
namespace {

double Shortest(const std::vector<double>& v) {
  double out = std::numeric_limits<double>::quiet_NaN();
  for (const double x : v) {
    if (!std::isnan(x) && (std::isnan(out) || x < out)) out = x;
  }
  return out;
}

/// Per bearing, Miner over the bins of the lives `pick` gives.
template <class Pick>
std::vector<double> Combined(const std::vector<SpectrumBinResult>& bins, Pick pick) {
  std::size_t n = 0;
  for (const SpectrumBinResult& b : bins) {
    if (b.summary.bearing_life) n = std::max(n, pick(*b.summary.bearing_life).size());
  }
  std::vector<double> shares;
  for (const SpectrumBinResult& b : bins) shares.push_back(b.bin.time_share);
  std::vector<double> out;
  for (std::size_t k = 0; k < n; ++k) {
    std::vector<double> hours;
    for (const SpectrumBinResult& b : bins) {
      const std::vector<double>* v = b.summary.bearing_life ? &pick(*b.summary.bearing_life) : nullptr;
      hours.push_back(v != nullptr && k < v->size() ? (*v)[k] : std::numeric_limits<double>::quiet_NaN());
    }
    out.push_back(MinerHours(hours, shares));
  }
  return out;
}

}  // namespace

void ValidateSpectrum(const std::vector<LoadBin>& bins) {
  double sum = 0.0;
  for (std::size_t i = 0; i < bins.size(); ++i) {
    const LoadBin& b = bins[i];
    const std::string entry = fmt::format("[[load_spectrum]] #{}", i + 1);
    if (!std::isfinite(b.torque)) {
      throw std::invalid_argument(fmt::format("{} torque_nm = {}: expected a finite torque in N*m", entry, units::NmmToNm(b.torque)));
    }
    const double rpm = units::RadPerSToRpm(b.input_speed);
    if (!std::isfinite(rpm) || rpm <= 0.0 || rpm > OperationSettings::kMaxSpeedRpm) {
      throw std::invalid_argument(fmt::format("{} speed_rpm = {}: expected a crank speed > 0 and <= {} rpm", entry, rpm,
                                              OperationSettings::kMaxSpeedRpm));
    }
    if (!std::isfinite(b.time_share) || b.time_share <= 0.0 || b.time_share > 1.0) {
      throw std::invalid_argument(fmt::format("{} time_share = {}: expected a share of the time > 0 and <= 1", entry, b.time_share));
    }
    sum += b.time_share;
  }
  if (!bins.empty() && std::abs(sum - 1.0) > kTimeShareTolerance) {
    throw std::invalid_argument(fmt::format("[[load_spectrum]] time_share: the shares add to {:.12g}: expected 1 (within {:g}); "
                                            "they are not normalised",
                                            sum, kTimeShareTolerance));
  }
}

double MinerHours(const std::vector<double>& hours, const std::vector<double>& shares) {
  double damage_per_hour = 0.0;
  for (std::size_t i = 0; i < hours.size() && i < shares.size(); ++i) {
    if (std::isnan(hours[i])) return std::numeric_limits<double>::quiet_NaN();
    if (std::isinf(hours[i])) continue;
    damage_per_hour += shares[i] / hours[i];
  }
  return damage_per_hour > 0.0 ? 1.0 / damage_per_hour : std::numeric_limits<double>::infinity();
}

bool SpectrumResult::all_succeeded() const {
  for (const SpectrumBinResult& b : bins) {
    if (!b.summary.all_succeeded()) return false;
  }
  return true;
}

double SpectrumResult::ShortestL10Hours() const { return Shortest(l10_hours); }
double SpectrumResult::ShortestLoadZoneHours() const { return Shortest(load_zone_hours); }
double SpectrumResult::ShortestContactHours() const { return Shortest(contact_life_hours); }

SpectrumResult CombineSpectrum(std::vector<SpectrumBinResult> bins) {
  SpectrumResult r;
  r.l10_hours = Combined(bins, [](const BearingLife& l) -> const std::vector<double>& { return l.hours; });
  r.load_zone_hours = Combined(bins, [](const BearingLife& l) -> const std::vector<double>& { return l.load_zone_hours; });
  // The pitting lives: per disc the pins' and the teeth's, each bin's at its speed.
  std::vector<double> shares;
  std::size_t discs = 0;
  for (const SpectrumBinResult& b : bins) {
    shares.push_back(b.bin.time_share);
    if (b.summary.contact_fatigue) discs = std::max(discs, b.summary.contact_fatigue->discs.size());
  }
  for (std::size_t k = 0; k < 2 * discs; ++k) {
    std::vector<double> hours;
    for (const SpectrumBinResult& b : bins) {
      const auto& f = b.summary.contact_fatigue;
      hours.push_back(f && k / 2 < f->discs.size()
                          ? (k % 2 == 0 ? f->discs[k / 2].pin_life_hours : f->discs[k / 2].tooth_life_hours)
                          : std::numeric_limits<double>::quiet_NaN());
    }
    r.contact_life_hours.push_back(MinerHours(hours, shares));
  }
  r.bins = std::move(bins);
  return r;
}

}  // namespace ltca::analysis
