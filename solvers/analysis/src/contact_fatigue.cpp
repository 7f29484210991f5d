#include "ltca/analysis/contact_fatigue.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "ltca/analysis/sweep.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::analysis {
namespace contact_fatigue_detail {

constexpr double kNoFigure = std::numeric_limits<double>::quiet_NaN();
/// A run below this fraction of its disc's largest pressure is not a load cycle (Finish).
constexpr double kMinorRun = 0.1;

/// The whole number nearest x when x is one to rounding (relative 1e-9), else 0.
double Whole(double x) {
  const double n = std::round(x);
  return n >= 1.0 && std::abs(x - n) <= 1e-9 * n ? n : 0.0;
}

}  // namespace contact_fatigue_detail
using contact_fatigue_detail::kMinorRun;
using contact_fatigue_detail::kNoFigure;
using contact_fatigue_detail::Whole;

void ContactCycleCounter::Add(const std::vector<double>& stress) {
  if (pins_.empty()) pins_.resize(stress.size());
  if (stress.size() != pins_.size()) {  // not one stage's positions: no basis
    failed_ = true;
    return;
  }
  for (std::size_t j = 0; j < stress.size(); ++j) {
    Pin& p = pins_[j];
    const double s = stress[j];
    const bool loaded = s > 0.0;
    p.largest = std::max(p.largest, s);
    if (positions_ == 0) {
      p.loaded_first = p.first_open = loaded;
      p.first_peak = loaded ? s : 0.0;
    } else if (loaded && p.first_open) {
      p.first_peak = std::max(p.first_peak, s);
    } else if (loaded && p.loaded) {
      p.peak = std::max(p.peak, s);
    } else if (loaded && p.gap == 1 && !p.peaks.empty()) {
      // A run one unloaded position after the last: the sweep does not resolve that gap (a load
      // handed over and back between neighbouring positions), so it is the same engagement.
      p.peak = std::max(p.peaks.back(), s);
      p.peaks.pop_back();
    } else if (loaded && p.gap == 1 && p.loaded_first && p.peaks.empty()) {
      p.first_open = true;  // the same, after the run that began at the first position
      p.first_peak = std::max(p.first_peak, s);
    } else if (loaded) {
      p.peak = s;
      if (p.first_start < 0 && !p.loaded_first) p.first_start = positions_;
    } else if (p.first_open) {
      p.first_open = false;
    } else if (p.loaded) {
      p.peaks.push_back(p.peak);
    }
    p.gap = loaded ? 0 : p.gap + 1;
    p.loaded = loaded;
  }
  if (positions_ == 0) first_stress_ = stress;
  last_stress_ = stress;
  ++positions_;
}

int ContactCycleCounter::PeriodShift(int disc, int pin_count, double largest) const {
  // The last position of a repeating mesh period is the first turned by one pin pitch: the
  // pressures at the last equal the first's of the pins s further on (s = 1 or pin_count - 1 by
  // the sense of rotation; any s is tried), to rounding of the solves.
  const auto at = [&](const std::vector<double>& v, int j) { return v[static_cast<std::size_t>(disc * pin_count + j)]; };
  // Compared as squares (a Hertz line contact's load goes with the pressure squared): a load at
  // the solves' rounding, 1e-10 of the largest, shows as a pressure of 1e-5 of the largest.
  const double tolerance = 1e-6 * largest * largest;
  for (int s = 1; s < pin_count; ++s) {
    bool same = true;
    for (int j = 0; j < pin_count && same; ++j) {
      const double a = at(last_stress_, j), b = at(first_stress_, (j + s) % pin_count);
      same = std::abs(a * a - b * b) <= tolerance;
    }
    if (same) return s;
  }
  return -1;
}

ContactCycles ContactCycleCounter::Finish(const Sweep& sweep, bool closed_period, int discs) const {
  ContactCycles out;
  out.discs = std::max(1, discs);
  const int pin_count = static_cast<int>(pins_.size()) / out.discs;
  if (failed_ || positions_ < 2 || pin_count <= 0 || pins_.size() != static_cast<std::size_t>(out.discs * pin_count)) {
    out.basis = failed_ ? "not rated: a position failed, so a load cycle's peak may be missing"
                        : "not rated: the sweep has fewer than two positions";
    return out;
  }
  const double swept = std::abs(sweep.crank_end - sweep.crank_start);
  const double n = static_cast<double>(positions_);
  const double turns_repeating = Whole(swept / (2.0 * units::kPi));                // the last repeats the first
  const double turns_covering = Whole(swept * n / (n - 1.0) / (2.0 * units::kPi));  // evenly around, no repeat
  const double turns = turns_repeating > 0.0 ? turns_repeating : turns_covering;
  // A run whose peak is below kMinorRun of its disc's largest pressure is the load handed over and
  // back between neighbouring positions, not an engagement (e.g. 160 MPa beside 1500 for one
  // position at a pin's handover): it does no damage (far below the curve's floor) and is not counted.
  std::vector<double> floor(static_cast<std::size_t>(out.discs), 0.0);
  for (std::size_t j = 0; j < pins_.size(); ++j) {
    double& f = floor[j / static_cast<std::size_t>(pin_count)];
    f = std::max(f, kMinorRun * pins_[j].largest);
  }
  const auto counted = [&](std::size_t j, double peak) { return peak >= floor[j / static_cast<std::size_t>(pin_count)]; };
  if (turns > 0.0) {
    out.crank_turns = turns;
    out.basis = fmt::format("{:g} whole crank turn{}: every pin's loaded runs, one cycle each at its largest pressure", turns,
                            turns == 1.0 ? "" : "s");
    for (std::size_t j = 0; j < pins_.size(); ++j) {
      const Pin& p = pins_[j];
      std::vector<double> peaks = p.peaks;
      if (p.first_open) {
        peaks.push_back(p.first_peak);  // loaded over the whole sweep: one cycle a turn at most
      } else if (p.loaded && p.loaded_first) {
        peaks.push_back(std::max(p.peak, p.first_peak));  // the run across the end joins the first
      } else if (p.loaded && p.first_start == 1 && !peaks.empty()) {
        peaks.front() = std::max(peaks.front(), p.peak);  // one unloaded position across the end: the same engagement
      } else {
        if (p.loaded_first) peaks.push_back(p.first_peak);
        if (p.loaded) peaks.push_back(p.peak);
      }
      std::erase_if(peaks, [&](double peak) { return !counted(j, peak); });
      out.peaks.push_back(std::move(peaks));
    }
    return out;
  }
  const double periods = Whole(swept * pin_count / (2.0 * units::kPi));
  if (closed_period && periods > 0.0) {
    out.crank_turns = periods;  // z_p pins share a period, so a pin sees a period's starts a turn
    out.basis = fmt::format("{:g} mesh period{} repeating over the crank turn (every pin alike): the pins' run starts in {} "
                            "are a pin's cycles a crank turn, each at the disc's largest pressure",
                            periods, periods == 1.0 ? "" : "s", periods == 1.0 ? "it" : "them");
    for (int d = 0; d < out.discs; ++d) {
      int starts = 0;
      double largest = 0.0;
      for (int j = 0; j < pin_count; ++j) largest = std::max(largest, pins_[static_cast<std::size_t>(d * pin_count + j)].largest);
      const int shift = PeriodShift(d, pin_count, largest);
      const auto pin = [&](int j) -> const Pin& { return pins_[static_cast<std::size_t>(d * pin_count + j)]; };
      const auto counts = [&](double peak) { return counted(static_cast<std::size_t>(d * pin_count), peak); };
      if (shift > 0) {
        // A pin's history over the crank turn is its period followed by the period of the pin s
        // further on, and so on (pin j at a period later is pin j + s now): walk that chain twice
        // round, joining a run cut by a period's end to the run that goes on at the next's start,
        // and count the runs of the second lap. So a run that begins or ends exactly at the
        // period's ends (a few MPa there) is one engagement with its real peak, not a handover.
        std::optional<double> open;  // the run carried over a period's end, its peak so far
        for (int lap = 0; lap < 2; ++lap) {
          for (int i = 0, j = 0; i < pin_count; ++i, j = (j + shift) % pin_count) {
            const Pin& p = pin(j);
            const bool count = lap == 1;
            if (p.first_open) {  // loaded over the whole period: the carried run goes on
              open = std::max(open.value_or(0.0), p.first_peak);
              continue;
            }
            if (p.loaded_first || open) {
              const double peak = std::max(open.value_or(0.0), p.loaded_first ? p.first_peak : 0.0);
              if (count && counts(peak)) ++starts;
              open.reset();
            }
            if (count) starts += static_cast<int>(std::count_if(p.peaks.begin(), p.peaks.end(), counts));
            if (p.loaded) open = p.peak;
          }
        }
        if (starts == 0 && open) starts = 1;  // loaded all the way round: one cycle a turn
      } else {
        for (int j = 0; j < pin_count; ++j) {
          const Pin& p = pin(j);
          // The runs begun after the first position: the closed ones and the one still open.
          starts += static_cast<int>(std::count_if(p.peaks.begin(), p.peaks.end(), counts));
          if (p.loaded && !p.first_open && counts(p.peak)) ++starts;
        }
      }
      for (int j = 0; j < pin_count; ++j) out.peaks.emplace_back(static_cast<std::size_t>(starts), largest);
    }
    return out;
  }
  out.basis = fmt::format("not rated: the swept {:.6g} deg is neither whole crank turns nor a repeating mesh period "
                          "(sweep crank_end_deg = crank_start_deg + 360)",
                          units::RadToDeg(swept));
  return out;
}

/// The least of a figure of the pins and the teeth over the discs; NaN when none is rated.
template <class Pins, class Teeth>
double Least(const std::vector<ContactFatigueDisc>& discs, Pins pins, Teeth teeth) {
  double out = kNoFigure;
  for (const ContactFatigueDisc& d : discs) {
    for (const double v : {pins(d), teeth(d)}) {
      if (!std::isnan(v) && !(v >= out)) out = v;
    }
  }
  return out;
}

double ContactFatigue::ShortestHours() const {
  return Least(discs, [](const ContactFatigueDisc& d) { return d.pin_life_hours; },
               [](const ContactFatigueDisc& d) { return d.tooth_life_hours; });
}

double ContactFatigue::SmallestSafety() const {
  return Least(discs, [](const ContactFatigueDisc& d) { return d.pin_safety; },
               [](const ContactFatigueDisc& d) { return d.tooth_safety; });
}

ContactFatigue RateContactFatigue(const ContactCycles& cycles, const contact::Material& material, int tooth_count,
                                  double crank_speed, std::optional<double> required_hours) {
  ContactFatigue out;
  out.basis = cycles.basis;
  out.curve = material.life_curve;
  out.fatigue_limit = material.contact_fatigue_limit;
  out.crank_rpm = std::isfinite(crank_speed) ? std::abs(units::RadPerSToRpm(crank_speed)) : kNoFigure;
  out.required_hours = required_hours.value_or(kNoFigure);
  if (!cycles.counted() || cycles.peaks.empty() || tooth_count <= 0) return out;
  const double turns_per_hour = 60.0 * out.crank_rpm;
  const auto hours = [&](double damage_per_turn) {
    if (std::isnan(turns_per_hour)) return kNoFigure;
    return damage_per_turn > 0.0 ? 1.0 / (damage_per_turn * turns_per_hour) : std::numeric_limits<double>::infinity();
  };
  const auto safety = [&](double cycles_per_turn, double stress) {
    if (std::isnan(out.required_hours) || std::isnan(turns_per_hour) || !(stress > 0.0)) return kNoFigure;
    const double n = cycles_per_turn * turns_per_hour * out.required_hours;
    return out.fatigue_limit * contact::LifeFactor(out.curve, n) / stress;
  };
  const std::size_t pins = cycles.peaks.size() / static_cast<std::size_t>(cycles.discs);
  for (int d = 0; d < cycles.discs; ++d) {
    ContactFatigueDisc r;
    double ring_damage = 0.0, ring_cycles = 0.0, worst_damage = -1.0, worst_cycles = -1.0, largest = 0.0;
    for (std::size_t j = 0; j < pins; ++j) {
      const std::vector<double>& peaks = cycles.peaks[static_cast<std::size_t>(d) * pins + j];
      double damage = 0.0;
      for (const double s : peaks) {
        damage += 1.0 / contact::CyclesToPitting(out.curve, out.fatigue_limit, s);
        largest = std::max(largest, s);
      }
      const double count = static_cast<double>(peaks.size());
      ring_damage += damage;
      ring_cycles += count;
      if (damage > worst_damage || (damage == worst_damage && count > worst_cycles)) {
        worst_damage = damage;
        worst_cycles = count;
        r.worst_pin = static_cast<int>(j);
      }
    }
    r.max_stress = largest;
    r.pin_cycles_per_turn = worst_cycles / cycles.crank_turns;
    r.pin_damage_per_turn = worst_damage / cycles.crank_turns;
    r.tooth_cycles_per_turn = ring_cycles / cycles.crank_turns / tooth_count;
    r.tooth_damage_per_turn = ring_damage / cycles.crank_turns / tooth_count;
    r.pin_life_hours = hours(r.pin_damage_per_turn);
    r.tooth_life_hours = hours(r.tooth_damage_per_turn);
    r.pin_safety = safety(r.pin_cycles_per_turn, largest);
    r.tooth_safety = safety(r.tooth_cycles_per_turn, largest);
    out.discs.push_back(r);
  }
  return out;
}

}  // namespace ltca::analysis
