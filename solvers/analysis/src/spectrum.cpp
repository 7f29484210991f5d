#include "ltca/analysis/spectrum.hpp"

#include <algorithm>
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
double SpectrumResult::ShortestModifiedHours() const { return Shortest(modified_hours); }
double SpectrumResult::ShortestLoadZoneModifiedHours() const { return Shortest(load_zone_modified_hours); }
std::pair<double, int> SpectrumResult::SmallestStaticSafety() const {
  std::pair<double, int> out{std::numeric_limits<double>::quiet_NaN(), -1};
  for (std::size_t k = 0; k < static_safety.size(); ++k) {
    if (!std::isnan(static_safety[k]) && (std::isnan(out.first) || static_safety[k] < out.first)) out = {static_safety[k], static_safety_bin[k]};
  }
  return out;
}
std::pair<double, int> SpectrumResult::LargestRollerStress() const {
  std::pair<double, int> out{std::numeric_limits<double>::quiet_NaN(), -1};
  for (std::size_t k = 0; k < max_roller_stress.size(); ++k) {
    if (!std::isnan(max_roller_stress[k]) && (std::isnan(out.first) || max_roller_stress[k] > out.first)) {
      out = {max_roller_stress[k], max_roller_stress_bin[k]};
    }
  }
  return out;
}
double SpectrumResult::SmallestContactSafety() const { return Shortest(contact_safety); }
bool SpectrumResult::modified() const {
  return !bins.empty() && bins.front().summary.bearing_life && bins.front().summary.bearing_life->modified;
}

double SpectrumContactSafety(const std::vector<SpectrumContactLoad>& loads, contact::LifeCurve curve, double sigma_hlim) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (!(sigma_hlim > 0.0)) return kNaN;
  double largest = 0.0;
  for (const SpectrumContactLoad& l : loads) {
    if (std::isnan(l.cycles) || std::isnan(l.stress)) return kNaN;
    if (l.cycles > 0.0 && l.stress > 0.0) largest = std::max(largest, l.stress);
  }
  if (largest == 0.0) return std::numeric_limits<double>::infinity();
  // Miner's damage over the required life with every stress times s: non-decreasing in s, zero
  // while every scaled stress is at or below the curve's floor (contact::CyclesToPitting). The
  // answer lies between the factors that put the largest stress on the floor and on the static
  // value: beyond it the damage stays finite (ISO 6336-6's extended line) but the flank's static
  // strength is exceeded, and ISO 6336-2's Z_NT is flat there, so the safety stops at it.
  const auto damage = [&](double s) {
    double d = 0.0;
    for (const SpectrumContactLoad& l : loads) {
      if (l.cycles > 0.0 && l.stress > 0.0) d += l.cycles / contact::CyclesToPitting(curve, sigma_hlim, s * l.stress);
    }
    return d;
  };
  double lo = contact::LifeFactor(curve, std::numeric_limits<double>::infinity()) * sigma_hlim / largest;  // damage 0
  double hi = contact::LifeFactor(curve, 0.0) * sigma_hlim / largest;
  if (damage(hi) <= 1.0) return hi;
  for (int i = 0; i < 200 && hi - lo > 4.0 * std::numeric_limits<double>::epsilon() * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (damage(mid) <= 1.0 ? lo : hi) = mid;
  }
  return lo;
}

SpectrumResult CombineSpectrum(std::vector<SpectrumBinResult> bins) {
  SpectrumResult r;
  r.l10_hours = Combined(bins, [](const BearingLife& l) -> const std::vector<double>& { return l.hours; });
  r.load_zone_hours = Combined(bins, [](const BearingLife& l) -> const std::vector<double>& { return l.load_zone_hours; });
  // Each bin's modified life at its own kappa (its speed's nu_1) and loads, then Miner.
  if (!bins.empty() && bins.front().summary.bearing_life && bins.front().summary.bearing_life->modified) {
    r.modified_hours = Combined(bins, [](const BearingLife& l) -> const std::vector<double>& { return l.modified_hours; });
    r.load_zone_modified_hours =
        Combined(bins, [](const BearingLife& l) -> const std::vector<double>& { return l.load_zone_modified_hours; });
  }
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
  // The pitting safety over the spectrum at the required life (the same for every bin: the deck's).
  const auto* first = !bins.empty() && bins.front().summary.contact_fatigue ? &*bins.front().summary.contact_fatigue : nullptr;
  if (first != nullptr && std::isfinite(first->required_hours)) {
    r.required_contact_hours = first->required_hours;
    for (std::size_t k = 0; k < 2 * discs; ++k) {
      std::vector<SpectrumContactLoad> loads;
      for (const SpectrumBinResult& b : bins) {
        const auto& f = b.summary.contact_fatigue;
        if (!f || k / 2 >= f->discs.size()) {
          loads.push_back({std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()});
          continue;
        }
        const ContactFatigueDisc& d = f->discs[k / 2];
        const double per_turn = k % 2 == 0 ? d.pin_cycles_per_turn : d.tooth_cycles_per_turn;
        loads.push_back({per_turn * 60.0 * f->crank_rpm * b.bin.time_share * first->required_hours, d.max_stress});
      }
      r.contact_safety.push_back(SpectrumContactSafety(loads, first->curve, first->fatigue_limit));
    }
  }
  // The static figures: the worst bin's, per bearing (a bin without the figure makes it NaN).
  std::size_t bearings = 0;
  for (const SpectrumBinResult& b : bins) {
    if (b.summary.bearing_life) bearings = std::max(bearings, b.summary.bearing_life->static_safety.size());
  }
  for (std::size_t k = 0; k < bearings; ++k) {
    double s0 = std::numeric_limits<double>::infinity(), stress = -1.0;
    int s0_bin = -1, stress_bin = -1;
    for (std::size_t i = 0; i < bins.size(); ++i) {
      const auto& l = bins[i].summary.bearing_life;
      double a = l && k < l->static_safety.size() ? l->static_safety[k] : std::numeric_limits<double>::quiet_NaN();
      // A bin that loads the bearing not at all (an idle bin: P_0,max = 0) sets no static safety.
      const auto& g = bins[i].summary.reducer;
      if (std::isnan(a) && g && k < g->bearing_max_load.size() && g->bearing_max_load[k] == 0.0) a = std::numeric_limits<double>::infinity();
      const double b = l && k < l->max_roller_stress.size() ? l->max_roller_stress[k] : std::numeric_limits<double>::quiet_NaN();
      if (std::isnan(a) || s0_bin == -2) {
        s0_bin = -2;
      } else if (s0_bin == -1 || a < s0) {
        s0 = a, s0_bin = static_cast<int>(i);
      }
      if (std::isnan(b) || stress_bin == -2) {
        stress_bin = -2;
      } else if (stress_bin == -1 || b > stress) {
        stress = b, stress_bin = static_cast<int>(i);
      }
    }
    r.static_safety.push_back(s0_bin >= 0 ? s0 : std::numeric_limits<double>::quiet_NaN());
    r.static_safety_bin.push_back(std::max(s0_bin, -1));
    r.max_roller_stress.push_back(stress_bin >= 0 ? stress : std::numeric_limits<double>::quiet_NaN());
    r.max_roller_stress_bin.push_back(std::max(stress_bin, -1));
  }
  // The largest tooth-contact stress over every bin (a bin that solved no position has none: NaN).
  for (std::size_t i = 0; i < bins.size(); ++i) {
    const double s = bins[i].summary.max_contact_stress;
    if (std::isnan(s)) {
      r.max_contact_stress = std::numeric_limits<double>::quiet_NaN();
      r.max_contact_stress_bin = -1;
      break;
    }
    if (r.max_contact_stress_bin < 0 || s > r.max_contact_stress) r.max_contact_stress = s, r.max_contact_stress_bin = static_cast<int>(i);
  }
  r.bins = std::move(bins);
  return r;
}

}  // namespace ltca::analysis
